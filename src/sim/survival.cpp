#include "sim/survival.hpp"

#include <algorithm>
#include <cmath>

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
  SurvivalCurve c;
  c.t = survival_times(scene);
  c.survivors = survivors_on_grid(scene, tally);
  c.particles = scene.particles;
  if (tally.weighted) {
    // exact cumulative sums, rounded once per grid point
    c.weighted = true;
    c.max_weight = 1 / scene.sampling.eps;
    const double n = static_cast<double>(scene.particles);
    FixedSum w = tally.total_w, w2 = tally.total_w2;
    c.P_w.push_back(w.value() / n);
    c.Q.push_back(w2.value() / n);
    for (std::size_t k = 0; k < tally.escaped_w.size(); ++k) {
      w = w.minus(tally.escaped_w[k]);
      w2 = w2.minus(tally.escaped_w2[k]);
      c.P_w.push_back(w.value() / n);
      c.Q.push_back(w2.value() / n);
    }
  }
  return c;
}

double SurvivalCurve::P_err(std::size_t i) const {
  const double n = static_cast<double>(particles), p = P(i);
  if (!weighted) return std::sqrt(p * (1 - p) / n);
  return std::sqrt(std::max(0.0, Q[i] - p * p) / n);
}

double SurvivalCurve::effective(std::size_t i) const {
  if (!weighted) return static_cast<double>(survivors[i]);
  return Q[i] > 0 ? static_cast<double>(particles) * P_w[i] * P_w[i] / Q[i] : 0.0;
}

double SurvivalCurve::log_cov(std::size_t i, std::size_t j) const {
  const std::size_t a = std::min(i, j), b = std::max(i, j);
  const double n = static_cast<double>(particles);
  if (!weighted) return (1 - P(a)) / (n * P(a));
  return (Q[b] - P_w[a] * P_w[b]) / (n * P_w[a] * P_w[b]);
}

}  // namespace rotleak
