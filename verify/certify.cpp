#include "verify/certify.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "numeric/mpfi_ops.hpp"
#include "numeric/tiers.hpp"
#include "verify/lohner.hpp"
#include "verify/trace.hpp"

namespace rotleak {

namespace {

/// The Lohner enclosure's trace: collision by collision until the leak, t_max or the cap. Returns whether
/// it passed t_max (proven: the time after the last collision lies beyond it).
template <class On>
bool trace_lohner(const Model<Mpfi>& model, const InitialDraw& draw, std::size_t max_collisions, On&& on) {
  LohnerEnclosure set(model, draw);
  for (std::size_t k = 1; k <= max_collisions; ++k) {
    const EnclosedCollision e = set.step();
    if (e.t > model.t_max) return true;
    if (!on(e.k, e.t, e.in_leak, std::exp2(e.log2_width))) return false;
  }
  return false;
}

}  // namespace

Certificate certify_at(const Scene& scene, const InitialDraw& draw, long bits, std::size_t max_collisions,
                       Enclosure method) {
  Certificate c;
  c.bits = bits;
  MpfrPrecision precision(bits);
  const auto on = [&](std::size_t k, const Mpfi& t, bool in_leak, double width) {
    c.certified_collisions = k;
    c.last_width = width;
    c.last_time_lo = t.lo();
    if (in_leak) {
      c.escape_certified = true;
      c.escape_collision = k;
      c.escape_time_lo = t.lo();
      c.escape_time_hi = t.hi();
      return false;
    }
    return true;
  };
  try {
    if (method == Enclosure::lohner && !scene.on_table()) {
      c.survived = trace_lohner(model_of<Mpfi>(scene), draw, max_collisions, on);
    } else {  // plain MPFI: on any table (the Lohner sets use the stadium's Jacobian)
      const std::size_t n = with_model<Mpfi>(scene, [&](const auto& model) {
        return trace(model, draw, max_collisions,
                     [&](const auto& s) { return on(s.k, s.t, s.in_leak, std::max(s.q.x.width(), s.q.y.width())); });
      });
      // trace stops at the leak (on says so), at the cap, or where the time passed t_max
      c.survived = !c.escape_certified && n < max_collisions && n == c.certified_collisions;
    }
  } catch (const UncertainDecision&) {
    // the next decision could not be proven at these bits: certified_collisions says how far it got
  }
  return c;
}

std::vector<Certificate> certify(const Scene& scene, const InitialDraw& draw, long start_bits, long max_bits,
                                 std::size_t max_collisions, Enclosure method) {
  std::vector<Certificate> attempts;
  for (long bits = start_bits; bits <= max_bits; bits *= 2) {
    attempts.push_back(certify_at(scene, draw, bits, max_collisions, method));
    const Certificate& c = attempts.back();
    // done when proven, or when the trace ended by itself (t_max or the collision cap), not by doubt
    if (c.escape_certified || c.survived || c.certified_collisions == max_collisions) break;
  }
  return attempts;
}

}  // namespace rotleak

namespace rotleak {

std::vector<double> enclosure_log2_widths(const Scene& scene, const InitialDraw& draw, long bits,
                                          std::size_t max_collisions, Enclosure method) {
  MpfrPrecision precision(bits);
  std::vector<double> widths;
  const auto widest = [](const Vec2<Mpfi>& q, const Vec2<Mpfi>& v) {
    return std::max({log2_width(q.x), log2_width(q.y), log2_width(v.x), log2_width(v.y)});
  };
  try {
    if (method == Enclosure::lohner && !scene.on_table()) {
      Model<Mpfi> model = model_of<Mpfi>(scene);
      model.t_max = Mpfi(std::numeric_limits<double>::max());
      LohnerEnclosure set(model, draw);
      widths.push_back(set.log2_width());
      for (std::size_t k = 1; k <= max_collisions; ++k) widths.push_back(set.step().log2_width);
    } else {  // plain MPFI (on any table)
      with_model<Mpfi>(scene, [&](auto model) {
        model.t_max = Mpfi(std::numeric_limits<double>::max());
        const ParticleState<Mpfi> ps = initial_state(model, draw);
        widths.push_back(widest(ps.q, ps.v));
        trace_from(model, ps, max_collisions, [&](const auto& s) {
          widths.push_back(widest(s.q, s.v));
          return true;
        });
      });
    }
  } catch (const UncertainDecision&) {
    // the enclosure has become too wide to decide a branch: the widths so far are the answer
  }
  return widths;
}

}  // namespace rotleak
