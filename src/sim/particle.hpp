// One particle's life, generic over the tier: next_hit, leak test, reflect, until escape or t_max.
#pragma once

#include <cmath>
#include <cstdint>

#include "geometry/stadium.hpp"
#include "leak/leak.hpp"
#include "sim/engine.hpp"
#include "sim/initial.hpp"

namespace rotleak {

template <class R>
struct Model {
  Stadium<R> stadium;
  Leak<R> leak;
  R t_max;

  Model(const ExactReal& d, const ExactReal& r, const ExactReal& width, const ExactReal& start,
        const ExactReal& omega, double tmax)
      : stadium(d, r), leak(stadium, width, start, omega), t_max(tmax) {}
};

/// What the particle loop reports to its observer at each collision; the default does nothing.
template <class R>
struct NoCollisionObserver {
  static constexpr bool active = false;
  void operator()(Piece, const Vec2<R>&, const R&) {}
};

struct ParticleEnd {
  Fate fate = Fate::survived;
  double t = 0, s = 0;
  std::uint64_t collisions = 0;
};

/// Flights of zero length in a row before a particle is declared stuck (a corner or exact graze
/// that rounding cannot leave); counted and reported, never silently dropped.
inline constexpr int kMaxZeroFlights = 64;

/// A particle in flight: its state and, once it has ended, how.
template <class R>
struct Flight {
  ParticleState<R> ps;
  ParticleEnd end;
  int zero_flights = 0;
};

/// One collision: next_hit, time check, leak test, reflect. Returns false once the particle has
/// ended (f.end says how). The engine interleaves several flights per thread with this.
template <class R, class Observer>
inline bool advance(const Model<R>& m, Flight<R>& f, Observer& observe) {
  const Hit<R> h = m.stadium.next_hit(f.ps.q, f.ps.v);
  f.ps.t += h.t;
  if (f.ps.t > m.t_max) {
    f.end.fate = Fate::survived;
    f.end.t = num_traits<R>::to_double(m.t_max);
    return false;
  }
  ++f.end.collisions;
  if constexpr (Observer::active) observe(h.piece, h.q, f.ps.t);
  if (m.leak.hit(h.piece, h.q, f.ps.t)) {
    f.end.fate = Fate::escaped;
    f.end.t = num_traits<R>::to_double(f.ps.t);
    f.end.s = num_traits<R>::to_double(m.stadium.s_of(h.piece, h.q));
    return false;
  }
  f.ps.v = m.stadium.reflect(h.piece, h.q, f.ps.v);
  f.ps.q = h.q;
  if (h.t > 0) {
    f.zero_flights = 0;
  } else if (++f.zero_flights > kMaxZeroFlights) {
    f.end.fate = Fate::stuck;
    f.end.t = num_traits<R>::to_double(f.ps.t);
    return false;
  }
  return true;
}

/// A whole life, one particle at a time (the reference loop; the engine's interleaved loop
/// performs exactly these operations per particle).
template <class R, class Observer>
ParticleEnd run_particle(const Model<R>& m, const ParticleState<R>& ps, Observer& observe) {
  Flight<R> f{ps, {}, 0};
  while (advance(m, f, observe)) {
  }
  return f.end;
}

}  // namespace rotleak
