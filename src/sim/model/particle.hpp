// One particle's life, generic over the tier: next_hit, leak test, reflect, until escape or t_max.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "geometry/formulas.hpp"
#include "geometry/stadium.hpp"
#include "geometry/table.hpp"
#include "leak/leak.hpp"
#include "leak/table_leak.hpp"
#include "numeric/binade.hpp"
#include "numeric/device.hpp"
#include "sim/model/fate.hpp"
#include "sim/model/initial.hpp"

namespace rotleak {

template <class R>
struct Model {
  Stadium<R> stadium;
  Leak<R> leak;
  R t_max;
  bool fast_forward = false;  ///< jump over bouncing-ball phases in closed form (see fast_forward())

  Model(const ExactReal& d, const ExactReal& r, const ExactReal& width, const ExactReal& start, const ExactReal& omega,
        double tmax)
      : stadium(d, r), leak(stadium, width, start, omega), t_max(R(tmax)) {}
  Model(const Stadium<R>& st, const ExactReal& width, const ExactReal& start, const ExactReal& omega, double tmax)
      : stadium(st), leak(stadium, width, start, omega), t_max(R(tmax)) {}

  /// The scene's billiard, leak, t_max and fast-forward, rounded once into R.
  static Model from(const Scene& s) { return from(s, Stadium<R>(s.d, s.r)); }
  /// The same, on the scene's stadium already rounded into R (a run's plan holds it).
  static Model from(const Scene& s, const Stadium<R>& st) {
    Model m(st, s.width, s.start, s.omega, s.t_max);
    m.fast_forward = s.fast_forward;
    return m;
  }

  // What the one collision step (advance) asks of a model; TableModel answers the same for any table.
  using real_type = R;
  using hit_type = Hit<R>;
  /// the stadium's convex shortcut: the straight edges decide first (formula::next_exit)
  ROTLEAK_HD hit_type next_hit(const Vec2<R>& q, const Vec2<R>& v) const { return stadium.next_hit(q, v); }
  ROTLEAK_HD static constexpr bool lost(const hit_type&) { return false; }  ///< the stadium's next hit is always found
  /// the leak that takes the hit at time t (0: the one leak), or -1
  ROTLEAK_HD int leak_of(const hit_type& h, const R& t) const { return leak.hit(h.piece, h.q, t) ? 0 : -1; }
  ROTLEAK_HD R s_of(const hit_type& h) const { return stadium.s_of(h.piece, h.q); }
  ROTLEAK_HD Vec2<R> reflect(const hit_type& h, const Vec2<R>& v) const { return stadium.reflect(h.piece, h.q, v); }
  /// a hit from which a bouncing-ball phase may start (fast_forward)
  ROTLEAK_HD bool jumps_from(const hit_type& h) const {
    return fast_forward && (h.piece == Piece::top || h.piece == Piece::bottom);
  }
};

/// Any table (geometry/table.hpp) with its list of leaks (leak/table_leak.hpp), for the same collision step: the
/// next hit over the table's pieces, the first leak that takes a hit, the table's reflection and s. On the stadium
/// built as a table it computes the stadium's bits (tests/test_table.cpp).
template <class R>
struct TableModel {
  Table<R> table;
  LeakList<R> leaks;
  R t_max;

  template <class Specs>
  TableModel(const TableSpec& spec, const Specs& leak_specs, double tmax)
      : table(spec), leaks(table, leak_specs), t_max(R(tmax)) {}

  using real_type = R;
  using hit_type = TableHit<R>;
  ROTLEAK_HD hit_type next_hit(const Vec2<R>& q, const Vec2<R>& v) const { return table.next_hit(q, v); }
  /// a flight that met no piece (through a gap that rounding opened at a corner): the particle is stuck there
  ROTLEAK_HD static bool lost(const hit_type& h) { return h.piece < 0; }
  ROTLEAK_HD int leak_of(const hit_type& h, const R& t) const { return leaks.hit(table, h.piece, h.q, t); }
  ROTLEAK_HD R s_of(const hit_type& h) const { return table.s_of(h.piece, h.q); }
  ROTLEAK_HD Vec2<R> reflect(const hit_type& h, const Vec2<R>& v) const { return table.reflect(h.piece, h.q, v); }
  ROTLEAK_HD static constexpr bool jumps_from(const hit_type&) { return false; }
};

/// One bounce of a fast-forwarded stretch, as an observer with a ball_run() method is shown it.
template <class R>
struct Bounce {
  Piece piece;
  Vec2<R> q;
  R t;
};

/// A fast-forwarded stretch of n bounces as fast_forward() computes them: bounce j (j = 1 .. n) at
/// x_j = x + j dx and t_j = t + j dt exactly (the sums stay in one binade: next_run), on the top edge
/// for even j when top_even, on the bottom edge otherwise.
template <class R>
struct Stretch {
  long n;
  R x, dx, t, dt;
  R r;  ///< the edges' |y|
  bool top_even;

  ROTLEAK_HD Piece piece(long j) const { return ((j % 2) == 0) == top_even ? Piece::top : Piece::bottom; }
  /// x_j, bit for bit: x + fl(j dx) rounds to the exact x + j dx, since x and x_j share a binade, so
  /// j dx = x_j - x lies below it and is rounded by at most a quarter of x_j's ulp (for j up to n)
  ROTLEAK_HD R x_at(long j) const { return x + R(static_cast<double>(j)) * dx; }
  ROTLEAK_HD R t_at(long j) const { return t + R(static_cast<double>(j)) * dt; }  ///< t_j, as x_j
  /// bounce j, any j in 0 .. n
  ROTLEAK_HD Bounce<R> operator()(long j) const {
    const Piece p = piece(j);
    return {p, Vec2<R>{x_at(j), p == Piece::top ? r : R(-r)}, t_at(j)};
  }
};

/// Consecutive stretches of one fast-forward, shown to an observer together: bounce j (1 .. n) of the
/// phase is bounce j - start(i) of the stretch i that holds it. Over the whole phase x and t stay
/// monotone in j (each stretch adds the same step rounded to its binade's grid), and bounces of one
/// parity stay on one edge, so an observer can search the phase as it would one stretch.
template <class R>
struct BallRun {
  static constexpr int kMax = 64;  ///< stretches held; a longer fast-forward is shown in parts
  Stretch<R> part[kMax];
  long end[kMax];  ///< bounces through stretch i
  int count = 0;
  long n = 0;

  bool full() const { return count == kMax; }
  void push(const Stretch<R>& s) {
    part[count] = s;
    n += s.n;
    end[count++] = n;
  }
  void clear() { count = 0, n = 0; }
  long start(int i) const { return i == 0 ? 0 : end[i - 1]; }
  /// the stretch that holds bounce j
  int index(long j) const {
    if (j <= end[0] || count == 1) return 0;  // the phase's ends: an observer's usual questions
    if (j > end[count - 2]) return count - 1;
    return static_cast<int>(std::lower_bound(end + 1, end + count - 1, j) - end);
  }
  Bounce<R> operator()(long j) const {
    const int i = index(j);
    return part[i](j - start(i));
  }
};

/// What the particle loop reports to its observer at each collision; the default does nothing.
/// An observer may also take a fast-forward's bounces whole: phase(const BallRun<R>&) in place of their
/// calls one by one (bounces of one parity lie on one straight edge, with x and t monotone in j); it
/// must count exactly what those calls would.
template <class R>
struct NoCollisionObserver {
  static constexpr bool active = false;
  ROTLEAK_HD void operator()(Piece, const Vec2<R>&, const R&) {}
};

struct ParticleEnd {
  Fate fate = Fate::survived;
  double t = 0, s = 0;
  std::uint64_t collisions = 0;
  /// Survived, double tier: the state at its last collision before t_max (or its creation), from
  /// which the flight that passes t_max starts -- where a split run continues a member.
  ParticleState<double> last{};
  /// The particle's sampling weight (1 unweighted), as its start carried it: what its tallies add.
  double weight = 1;
  /// Escaped: the leak that took it (its index in the table's list; 0 on the stadium's one leak).
  int leak = 0;
};

/// A particle in flight: its state and, once it has ended, how.
template <class R>
struct Flight {
  ParticleState<R> ps;
  ParticleEnd end;
  int zero_flights = 0;
};

/// The first i in [lo, hi) where pred holds (hi if none), for a pred that is false and then true over
/// [lo, hi): bisection, looking at both ends first.
template <class P>
ROTLEAK_HD long first_true(long lo, long hi, const P& pred) {
  if (lo >= hi || pred(lo)) return lo;
  if (!pred(hi - 1)) return hi;
  ++lo, --hi;  // pred(lo - 1) is false, pred(hi) is true: the answer lies in [lo, hi]
  while (lo < hi) {
    const long mid = lo + (hi - lo) / 2;
    if (pred(mid))
      hi = mid;
    else
      lo = mid + 1;
  }
  return lo;
}

/// Fewest bounces for which fast_forward() jumps (below it stepping is as cheap).
inline constexpr long kMinFastForwardBounces = 4;

/// The next stretch of the repeated rounded sum x <- fl(x + d): `len` additions that each add exactly
/// `inc`. Inside one binade the grid spacing is fixed, so fl(x + d) - x is the same for every grid
/// point (an exact tie aside, which a second step detects); the stretch ends where x would leave
/// its binade. IEEE binary types only.
template <class R>
struct SumRun {
  R inc;
  long len;
};

template <class R>
ROTLEAK_HD SumRun<R> next_run(R x, R d, long cap) {
  using std::abs;
  const R x1 = x + d;
  const R inc = x1 - x;
  if (inc == 0) return {R(0), cap};  // d below half an ulp of x: x never moves
  const R x2 = x1 + d;
  if (x2 - x1 != inc || x == 0 || x1 == 0) return {inc, 1};  // a tie or a binade edge: one step
  const int e = binade_of(x);
  const R lo = pow2<R>(e), hi = pow2<R>(e + 1);  // |x| in [lo, hi)
  const R ax = abs(x);
  const bool away = (x > 0) == (inc > 0);  // |x| grows
  const R ainc = abs(inc);
  long len;
  if (away) {
    const R room = (hi - ax) / ainc;  // steps j with ax + j ainc < hi
    len = room > R(cap) ? cap : static_cast<long>(std::ceil(room)) - 1;
  } else {
    const R room = (ax - lo) / ainc;  // steps j with ax - j ainc >= lo
    len = room > R(cap) ? cap : static_cast<long>(std::floor(room));
  }
  // the divisions were rounded: make sure the last point is still inside the binade
  while (len > 1) {
    const R last = std::fma(R(static_cast<double>(len)), inc, x);
    if (binade_of(last) == e && (last > 0) == (x > 0) && last != 0) break;
    --len;
  }
  return {inc, len < 1 ? 1 : len};
}

namespace fast_forward_steps {

/// The first bounce of the stretch s (1 .. J) that leaves the straight edges (why 1) or passes t_max
/// (why 2); {J + 1, 0}: none. x_j and t_j are monotone in j (a fixed increment, exact): so "left the
/// straight edges" and "past t_max" are false up to some j and true after, and bisection finds it.
template <class R>
ROTLEAK_HD std::pair<long, int> first_edge_or_time(const Model<R>& m, const Stretch<R>& s, long J) {
  const R half_d = m.stadium.half_d();
  const long j_arc = first_true(1, J + 1, [&](long j) {
    const R v = s.x_at(j);
    return !(v <= half_d && v >= -half_d);
  });
  const long j_time = first_true(1, J + 1, [&](long j) { return s.t_at(j) > m.t_max; });
  std::pair<long, int> stop{J + 1, 0};
  if (j_arc < stop.first) stop = {j_arc, 1};
  if (j_time < stop.first) stop = {j_time, 2};
  return stop;
}

/// The first bounce of the stretch s (1 .. J) inside a stationary leak's windows; J + 1: none. A
/// stationary leak is a fixed set of x windows per edge, and consecutive bounces alternate edges:
/// bounces of one parity meet one edge's windows, at monotone x, so the first bounce inside a window is
/// again a bisection -- no per-bounce test over millions of bounces.
template <class R>
ROTLEAK_HD long first_window_bounce(const Model<R>& m, const Stretch<R>& s, long J) {
  long stop = J + 1;
  for (int parity = 1; parity <= 2; ++parity) {
    const auto& pw = m.leak.windows(s.piece(parity));
    for (int w = 0; w < pw.n; ++w) {
      // x_j in [lo, hi] is an interval of j (monotone x_j); search it among j = parity, parity + 2, ...
      const R lo = pw[w].lo, hi = pw[w].hi;
      auto before = [&](long j) {  // x_j has not reached the window yet (in the direction of motion)
        const R v = s.x_at(j);
        return s.dx > 0 ? v < lo : v > hi;
      };
      // smallest j of this parity with !before(j)
      long a = 0, b = (J - parity) / 2;  // j = parity + 2 i, i in [0, b]
      if (b < 0 || before(parity + 2 * b)) continue;
      while (a < b) {
        const long mid = a + (b - a) / 2;
        if (before(parity + 2 * mid))
          a = mid + 1;
        else
          b = mid;
      }
      const long j = parity + 2 * a;
      const R v = s.x_at(j);
      if (v >= lo && v <= hi && j < stop) stop = j;
    }
  }
  return stop;
}

/// The first bounce of the stretch s (1 .. upto) that a moving leak covers; upto + 1: none. A moving
/// leak has no fixed windows: the phase at every bounce time is tested (no geometry, a few flops each).
template <class R>
ROTLEAK_HD long first_moving_leak_bounce(const Model<R>& m, const Stretch<R>& s, long upto) {
  for (long j = 1; j <= upto; ++j) {
    const Bounce<R> b = s(j);
    if (m.leak.hit(b.piece, b.q, b.t)) return j;
  }
  return upto + 1;
}

/// Bounces 1 .. s.n of the stretch shown to the observer: with the rest of the phase (observers that take
/// a BallRun) or one by one.
template <class R, class Observer, class PhaseHeld>
ROTLEAK_HD void show(Observer* observe, PhaseHeld& phase, const Stretch<R>& s) {
  if constexpr (Observer::active) {
    if (!observe) return;
    if constexpr (std::is_same_v<PhaseHeld, BallRun<R>>) {
      if (s.n > 0) {
        if (phase.full()) observe->ball_run(phase), phase.clear();
        phase.push(s);
      }
    } else {
      for (long j = 1; j <= s.n; ++j) {
        const Bounce<R> b = s(j);
        (*observe)(b.piece, b.q, b.t);
      }
    }
  }
}

/// The particle set on the phase's last bounce k (at x, t, on the top edge or not), moving away from that
/// edge, its k bounces counted. Returns false when that bounce is in the leak (an escape); otherwise the
/// next step meets the arc, or t > t_max, as stepping would.
template <class R>
ROTLEAK_HD bool land(const Model<R>& m, Flight<R>& f, long k, R x, R t, bool top) {
  const Stadium<R>& st = m.stadium;
  ParticleState<R>& ps = f.ps;
  const Piece piece = top ? Piece::top : Piece::bottom;
  ps.q = {x, top ? st.r() : R(-st.r())};
  ps.t = t;
  const R avy = ps.v.y > 0 ? ps.v.y : R(-ps.v.y);
  ps.v.y = top ? R(-avy) : avy;  // outgoing: away from the edge it is on
  f.end.collisions += static_cast<std::uint64_t>(k);
  if (!m.leak.hit(piece, ps.q, t)) return true;
  f.end.fate = Fate::escaped;
  f.end.t = num_traits<R>::to_double(t);
  f.end.s = num_traits<R>::to_double(st.s_of(piece, ps.q));
  return false;
}

}  // namespace fast_forward_steps

/// Closed-form bouncing-ball phase, bit-identical to stepping. Called after a reflection on a
/// straight edge: while the particle crosses to the opposite edge inside |x| <= d/2, stepping would
/// compute the same flight dt = 2r/|vy| and the same dx = fl(vx dt) at every bounce, and x, t by
/// repeated rounded additions; next_run() reproduces those sums a binade at a time. Jumps to the
/// bounce before the particle would reach an arc or pass t_max, or to the first bounce in the leak
/// (stationary: windows tested on exact bounce positions; moving: the phase at each bounce time, no
/// geometry). Skipped bounces count as collisions, and an active observer sees each of them (as
/// stepping would show them: f_c counts every collision). Returns false when the particle ended.
template <class R, class Observer = NoCollisionObserver<R>>
ROTLEAK_HD bool fast_forward(const Model<R>& m, Flight<R>& f, Observer* observe = nullptr) {
  if constexpr (!std::is_floating_point_v<R>) {
    return true;  // exact emulation needs IEEE binary arithmetic
  } else {
    namespace steps = fast_forward_steps;
    const Stadium<R>& st = m.stadium;
    ParticleState<R>& ps = f.ps;
    if (ps.v.y == 0) return true;
    // the flight and step of the first bounce, exactly as next_hit computes them
    const R dt = formula::line_flight(ps.v.y > 0 ? st.r() : R(-st.r()), ps.q.y, ps.v.y);
    const R dx = formula::displacement(ps.v.x, dt);
    // A short phase is cheaper to step; these estimates only choose, the jump itself is exact.
    constexpr R kMin = R(kMinFastForwardBounces);
    if (!formula::straight_run_at_least(ps.q.x, ps.v.x, ps.v.y, st.half_d(), st.r(), kMin) ||
        !((m.t_max - ps.t) / dt >= kMin))
      return true;
    const bool stationary = !m.leak.schedule().rotating();
    const bool on_top = ps.q.y > 0;  // edge of bounce 0
    auto edge_top = [&](long j) { return ((j % 2) == 0) == on_top; };
    R x = ps.q.x, t = ps.t;
    long k = 0;
    // Stretch by stretch: within one, both sums add a fixed increment each bounce (x and t stay in
    // their binades), so bounce j of the stretch is x + j inc exactly (Stretch::x_at gives it).
    constexpr bool whole = requires(Observer & o, const BallRun<R>& p) { o.ball_run(p); };
    struct NoBallRun {};
    std::conditional_t<whole, BallRun<R>, NoBallRun> phase;
    for (;;) {
      constexpr long kCap = 1L << 40;
      const SumRun<R> rx = next_run(x, dx, kCap), rt = next_run(t, dt, kCap);
      const long J = rx.len < rt.len ? rx.len : rt.len;
      Stretch<R> s{J, x, rx.inc, t, rt.inc, st.r(), edge_top(k)};
      // the first bounce j in 1..J that leaves the straight edges, passes t_max, or is in the leak
      auto [stop, why] = steps::first_edge_or_time(m, s, J);  // why: 1 arc, 2 time, 3 leak
      const long leak = stationary ? steps::first_window_bounce(m, s, J)
                                   : steps::first_moving_leak_bounce(m, s, stop <= J ? stop - 1 : J);
      if (leak < stop) stop = leak, why = 3;
      // bounces 1..n of this stretch are collisions, shown to the observer; then x, t move to bounce n.
      // Leaving the edges or passing t_max happens on the flight after bounce stop - 1, which the
      // caller's next step computes as stepping would; an escape happens at bounce stop itself.
      s.n = why == 0 ? J : why == 3 ? stop : stop - 1;
      steps::show(observe, phase, s);
      x = s.x_at(s.n), t = s.t_at(s.n), k += s.n;
      if (why != 0) break;
    }
    if constexpr (whole)
      if (observe && phase.count > 0) observe->ball_run(phase);
    return k == 0 || steps::land(m, f, k, x, t, edge_top(k));
  }
}

/// How the collision step's flight ends (fly).
enum class FlightEnd { lost, past_t_max, hit };

template <class M>
struct Flown {
  typename M::hit_type h;
  FlightEnd end;
};

/// The collision step's flight, in the order every scalar loop takes it (advance below; trace_from,
/// verify/trace.hpp): the model's next hit from ps; a flight that meets no piece ends `lost`, one that passes t_max
/// `past_t_max` (ps unchanged: the state stays at the last collision); else the clock moves to the hit (`hit`), where
/// the caller takes the leak test (M::leak_of) and the reflection (bounce).
template <class M>
[[gnu::always_inline]] ROTLEAK_HD inline Flown<M> fly(const M& m, ParticleState<typename M::real_type>& ps) {
  using R = typename M::real_type;
  Flown<M> f{m.next_hit(ps.q, ps.v), FlightEnd::hit};
  if (m.lost(f.h)) {
    f.end = FlightEnd::lost;
    return f;
  }
  const R t_hit = ps.t + f.h.t;
  if (t_hit > m.t_max) {
    f.end = FlightEnd::past_t_max;
    return f;
  }
  ps.t = t_hit;
  return f;
}

/// The collision's reflection: the outgoing velocity at hit h, and the particle at the hit.
template <class M>
[[gnu::always_inline]] ROTLEAK_HD inline void bounce(const M& m, const typename M::hit_type& h,
                                                     ParticleState<typename M::real_type>& ps) {
  ps.v = m.reflect(h, ps.v);
  ps.q = h.q;
}

/// One collision: fly (next hit, lost, t_max, clock), leak test, bounce. Returns false once the particle has
/// ended (f.end says how). Written once for every model (Model: the stadium, with its convex shortcut and the
/// fast-forward; TableModel: any table and its leaks). The scalar engine calls it for one particle after another
/// (interleaving flights measured slower there); the vectorised kernel performs the same operations per lane.
template <class M, class Observer>
ROTLEAK_HD inline bool advance(const M& m, Flight<typename M::real_type>& f, Observer& observe) {
  using R = typename M::real_type;
  const Flown<M> fl = fly(m, f.ps);
  const typename M::hit_type& h = fl.h;
  if (fl.end == FlightEnd::lost) {
    f.end.fate = Fate::stuck;
    f.end.t = num_traits<R>::to_double(f.ps.t);
    return false;
  }
  if (fl.end == FlightEnd::past_t_max) {  // the state stays at the last collision
    f.end.fate = Fate::survived;
    f.end.t = num_traits<R>::to_double(m.t_max);
    if constexpr (std::is_same_v<R, double>) f.end.last = f.ps;
    return false;
  }
  ++f.end.collisions;
  if constexpr (Observer::active) observe(h.piece, h.q, f.ps.t);
  if (const int leak = m.leak_of(h, f.ps.t); leak >= 0) {
    f.end.fate = Fate::escaped;
    f.end.leak = leak;
    f.end.t = num_traits<R>::to_double(f.ps.t);
    f.end.s = num_traits<R>::to_double(m.s_of(h));
    return false;
  }
  bounce(m, h, f.ps);
  if constexpr (requires { m.stadium; }) {
    if (m.jumps_from(h) && !fast_forward(m, f, &observe)) return false;
  }
  if (h.t > 0) {
    f.zero_flights = 0;
  } else if (++f.zero_flights > kMaxZeroFlights) {
    f.end.fate = Fate::stuck;
    f.end.t = num_traits<R>::to_double(f.ps.t);
    return false;
  }
  return true;
}

/// A whole life, one particle at a time: the reference loop, which the scalar engine runs and whose
/// operations the vectorised kernel performs per lane.
template <class M, class Observer>
ROTLEAK_HD ParticleEnd run_particle(const M& m, const ParticleState<typename M::real_type>& ps, Observer& observe) {
  Flight<typename M::real_type> f{ps, {}, 0};
  while (advance(m, f, observe)) {
  }
  return f.end;
}

/// A particle's start from binary initial data on the model's boundary: its stadium's (Model) or its table's
/// (TableModel). Every caller that starts a particle from its draw (the scalar engine, the trace, the enclosures)
/// takes it here.
template <class M>
ROTLEAK_HD ParticleState<typename M::real_type> initial_state(const M& model, const InitialDraw& draw) {
  if constexpr (requires { model.stadium; })
    return initial_state(model.stadium, draw);
  else
    return initial_state(model.table, draw);
}

}  // namespace rotleak
