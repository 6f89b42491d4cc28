// One particle followed collision by collision in any tier, without stopping at the leak: the shadow
// integrator compares these traces across tiers, and the certificate runs the same loop in MPFI.
#pragma once

#include <cstddef>
#include <utility>

#include "sim/model/particle.hpp"

namespace rotleak {

template <class R, class P = Piece>
struct TraceStep {
  std::size_t k;     ///< collision number, from 1
  const R& t;        ///< its time
  P piece;           ///< the stadium's Piece, or a table's piece index
  const Vec2<R>& q;  ///< its point
  Vec2<R>& v;        ///< outgoing velocity (on() may perturb it: a test of the replays)
  bool in_leak;      ///< the escape test at this collision (a table's: any of its leaks)
};

/// Follows the particle from state ps through at most `max_collisions` collisions (or until t_max, or a flight
/// that meets no piece), calling on(step) after each (its velocity may be changed there: a test's perturbation):
/// the collision step's own flight and reflection (fly, bounce: sim/model/particle.hpp, as advance takes them) and
/// the model's leak test (Model: the stadium; TableModel: any table), without stopping at the leak. Returns the number
/// of collisions traced.
template <class M, class On>
std::size_t trace_from(const M& model, ParticleState<typename M::real_type> ps, std::size_t max_collisions, On&& on) {
  using R = typename M::real_type;
  using P = decltype(std::declval<typename M::hit_type>().piece);
  for (std::size_t k = 1; k <= max_collisions; ++k) {
    const Flown<M> f = fly(model, ps);
    if (f.end != FlightEnd::hit) return k - 1;
    const typename M::hit_type& h = f.h;
    const bool leak = model.leak_of(h, ps.t) >= 0;
    bounce(model, h, ps);
    if (!on(TraceStep<R, P>{k, ps.t, h.piece, ps.q, ps.v, leak})) return k;
  }
  return max_collisions;
}

/// The same from binary initial data `draw` (initial_state on the model's stadium or table).
template <class M, class On>
std::size_t trace(const M& model, const InitialDraw& draw, std::size_t max_collisions, On&& on) {
  return trace_from(model, initial_state(model, draw), max_collisions, std::forward<On>(on));
}

template <class R>
Model<R> model_of(const Scene& s) {
  Model<R> m = Model<R>::from(s);
  m.fast_forward = false;  // a shadow compares collision by collision: it steps every bounce
  return m;
}

/// The scene's table and leaks in tier R (a scene on another table, or with several leaks: Scene::on_table).
template <class R>
TableModel<R> table_model_of(const Scene& s) {
  return TableModel<R>(table_spec(s), leak_specs(s), s.t_max);
}

/// f(model) with the scene's model in tier R: TableModel on another table or with several leaks, else the
/// stadium's Model (model_of).
template <class R, class F>
decltype(auto) with_model(const Scene& s, F&& f) {
  if (s.on_table()) return f(table_model_of<R>(s));
  return f(model_of<R>(s));
}

}  // namespace rotleak
