// Escape certificates: the particle's trajectory in MPFI interval arithmetic. Every branch of the
// core is a comparison, and an interval comparison answers only when the enclosures decide it, so a
// trace that reaches a collision inside the leak has proven the escape: the enclosure of the hit
// lies wholly inside the leak and every earlier one wholly outside.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "sim/model/initial.hpp"
#include "sim/model/scene.hpp"
#include "verify/lohner.hpp"

namespace rotleak {

struct Certificate {
  long bits = 0;
  std::size_t certified_collisions = 0;  ///< collisions whose every decision was proven
  bool escape_certified = false;
  std::size_t escape_collision = 0;
  double escape_time_lo = 0, escape_time_hi = 0;  ///< enclosure of the escape time
  double last_width = 0;                          ///< width of the last position enclosure
  double last_time_lo = 0;  ///< lower end of the last certified collision's time: alive until then, proven
  bool survived = false;    ///< passed t_max with every decision before it proven
};

/// One attempt at `bits` bits, at most max_collisions collisions.
Certificate certify_at(const Scene& scene, const InitialDraw& draw, long bits, std::size_t max_collisions,
                       Enclosure method = Enclosure::lohner);

/// Doubles the bits from start_bits until the escape is certified or max_bits is passed; returns
/// every attempt (the last one is the answer).
std::vector<Certificate> certify(const Scene& scene, const InitialDraw& draw, long start_bits, long max_bits,
                                 std::size_t max_collisions, Enclosure method = Enclosure::lohner);

/// log2 of the largest width of a trajectory's enclosure of (x, y, vx, vy): w[0] at the start, w[k] after
/// collision k, the leak and t_max ignored, until max_collisions or the first branch the enclosure cannot
/// decide. Their growth, (w[k] - w[0]) / k, is the bits a collision the method loses.
std::vector<double> enclosure_log2_widths(const Scene& scene, const InitialDraw& draw, long bits,
                                          std::size_t max_collisions, Enclosure method);

}  // namespace rotleak
