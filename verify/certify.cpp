#include "verify/certify.hpp"

#include <algorithm>

#include "numeric/tiers.hpp"
#include "verify/trace.hpp"

namespace rotleak {

Certificate certify_at(const Scene& scene, const InitialDraw& draw, long bits, std::size_t max_collisions) {
  Certificate c;
  c.bits = bits;
  MpfrPrecision precision(bits);
  try {
    const Model<Mpfi> model = model_of<Mpfi>(scene);
    trace(model, draw, max_collisions, [&](const TraceStep<Mpfi>& s) {
      c.certified_collisions = s.k;
      c.last_width = std::max(s.q.x.width(), s.q.y.width());
      if (s.in_leak) {
        c.escape_certified = true;
        c.escape_collision = s.k;
        c.escape_time_lo = s.t.lo();
        c.escape_time_hi = s.t.hi();
        return false;
      }
      return true;
    });
  } catch (const UncertainDecision&) {
    // the next decision could not be proven at these bits: certified_collisions says how far it got
  }
  return c;
}

std::vector<Certificate> certify(const Scene& scene, const InitialDraw& draw, long start_bits, long max_bits,
                                 std::size_t max_collisions) {
  std::vector<Certificate> attempts;
  for (long bits = start_bits; bits <= max_bits; bits *= 2) {
    attempts.push_back(certify_at(scene, draw, bits, max_collisions));
    const Certificate& c = attempts.back();
    // done when proven, or when the trace ended by itself (t_max or the collision cap), not by doubt
    if (c.escape_certified || c.certified_collisions == max_collisions) break;
  }
  return attempts;
}

}  // namespace rotleak
