// The survival curve of a run: survivors on the time grid t_k = k dt, built in one place from the
// engine's escape histogram (exact integer counts), for the fits, the files and the checks.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/engine.hpp"
#include "sim/scene.hpp"

namespace rotleak {

struct SurvivalCurve {
  std::vector<double> t;                 ///< grid times, increasing
  std::vector<std::uint64_t> survivors;  ///< survivors at each time
  std::uint64_t particles = 0;

  double P(std::size_t i) const { return static_cast<double>(survivors[i]) / static_cast<double>(particles); }
};

/// Grid times t_k = k dt for k = 0..bins, the last one clamped to t_max.
std::vector<double> survival_times(const Scene& scene);
/// Survivors at t_k (k = 0..bins, the last at t_max) from the escape histogram.
std::vector<std::uint64_t> survivors_on_grid(const Scene& scene, const Tally& tally);
/// Both together.
SurvivalCurve survival_curve(const Scene& scene, const Tally& tally);

}  // namespace rotleak
