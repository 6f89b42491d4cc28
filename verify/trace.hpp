// One particle followed collision by collision in any tier, without stopping at the leak: the shadow
// integrator compares these traces across tiers, and the certificate runs the same loop in MPFI.
#pragma once

#include <cstddef>
#include <utility>

#include "sim/model/particle.hpp"

namespace rotleak {

template <class R>
struct TraceStep {
  std::size_t k;  ///< collision number, from 1
  const R& t;     ///< its time
  Piece piece;
  const Vec2<R>& q;  ///< its point
  Vec2<R>& v;        ///< outgoing velocity (on() may perturb it: a test of the replays)
  bool in_leak;      ///< the escape test at this collision
};

/// Follows the particle from state ps through at most `max_collisions` collisions (or until t_max),
/// calling on(step) after each (its velocity may be changed there: a test's perturbation). Returns the
/// number of collisions traced.
template <class R, class On>
std::size_t trace_from(const Model<R>& model, ParticleState<R> ps, std::size_t max_collisions, On&& on) {
  for (std::size_t k = 1; k <= max_collisions; ++k) {
    const Hit<R> h = model.stadium.next_hit(ps.q, ps.v);
    ps.t += h.t;
    if (ps.t > model.t_max) return k - 1;
    const bool leak = model.leak.hit(h.piece, h.q, ps.t);
    ps.v = model.stadium.reflect(h.piece, h.q, ps.v);
    ps.q = h.q;
    if (!on(TraceStep<R>{k, ps.t, h.piece, ps.q, ps.v, leak})) return k;
  }
  return max_collisions;
}

/// The same from binary initial data `draw` (initial_state).
template <class R, class On>
std::size_t trace(const Model<R>& model, const InitialDraw& draw, std::size_t max_collisions, On&& on) {
  return trace_from(model, initial_state(model.stadium, draw), max_collisions, std::forward<On>(on));
}

template <class R>
Model<R> model_of(const Scene& s) {
  Model<R> m = Model<R>::from(s);
  m.fast_forward = false;  // a shadow compares collision by collision: it steps every bounce
  return m;
}

}  // namespace rotleak
