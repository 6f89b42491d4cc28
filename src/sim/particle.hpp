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

template <class R, class Observer>
ParticleEnd run_particle(const Model<R>& m, ParticleState<R> ps, Observer& observe) {
  ParticleEnd end;
  int zero_flights = 0;
  for (;;) {
    const Hit<R> h = m.stadium.next_hit(ps.q, ps.v);
    ps.t += h.t;
    if (ps.t > m.t_max) {
      end.fate = Fate::survived;
      end.t = static_cast<double>(num_traits<R>::to_double(m.t_max));
      return end;
    }
    ++end.collisions;
    if constexpr (Observer::active) observe(h.piece, h.q, ps.t);
    if (m.leak.hit(h.piece, h.q, ps.t)) {
      end.fate = Fate::escaped;
      end.t = num_traits<R>::to_double(ps.t);
      end.s = num_traits<R>::to_double(m.stadium.s_of(h.piece, h.q));
      return end;
    }
    ps.v = m.stadium.reflect(h.piece, h.q, ps.v);
    ps.q = h.q;
    if (h.t > 0) {
      zero_flights = 0;
    } else if (++zero_flights > kMaxZeroFlights) {
      end.fate = Fate::stuck;
      end.t = num_traits<R>::to_double(ps.t);
      return end;
    }
  }
}

}  // namespace rotleak
