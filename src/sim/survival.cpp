#include "sim/survival.hpp"

namespace rotleak {

std::vector<double> survival_times(const Scene& scene) {
  const std::size_t bins = scene.survival_bins();
  std::vector<double> t(bins + 1);
  for (std::size_t k = 0; k <= bins; ++k) {
    const double tk = static_cast<double>(k) * scene.survival_dt;
    t[k] = tk < scene.t_max ? tk : scene.t_max;
  }
  return t;
}

std::vector<std::uint64_t> survivors_on_grid(const Scene& scene, const Tally& tally) {
  std::vector<std::uint64_t> out(tally.escapes_per_bin.size() + 1);
  std::uint64_t alive = scene.particles;
  out[0] = alive;
  for (std::size_t k = 0; k < tally.escapes_per_bin.size(); ++k) {
    alive -= tally.escapes_per_bin[k];
    out[k + 1] = alive;
  }
  return out;
}

SurvivalCurve survival_curve(const Scene& scene, const Tally& tally) {
  return {survival_times(scene), survivors_on_grid(scene, tally), scene.particles};
}

}  // namespace rotleak
