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
    if (tally.split) alive += tally.born_per_bin[k] - tally.culled_per_bin[k];  // members: copies in, roulette out
    alive -= tally.escapes_per_bin[k];
    out[k + 1] = alive;
  }
  return out;
}

namespace {

/// The split run's P, R, G and lines alive from the exact line tallies.
void line_curve(const Scene& scene, const Tally& tally, SurvivalCurve& c) {
  c.weighted = c.lines = true;
  c.max_weight = scene.sampling.max_weight();
  const double n = static_cast<double>(scene.particles);
  FixedSum in, out, in2, out2;
  std::uint64_t ended = 0;
  double g = 0;
  for (std::size_t j = 0; j < tally.line_in.size(); ++j) {
    in.merge(tally.line_in[j]);
    out.merge(tally.line_out[j]);
    in2.merge(tally.line2_in[j]);
    out2.merge(tally.line2_out[j]);
    ended += tally.lines_ended[j];
    const FixedSum y = in.minus(out), y2 = in2.minus(out2);  // exact: sum Y_i(t_j), sum Y_i(t_j)^2
    c.P_w.push_back(y.value() / n);
    // R = N sum Y^2 / (sum Y)^2 from the scaled sums (sum Y^2 may lie far below the double range)
    const FixedSum::Scaled s1 = y.scaled(), s2 = y2.scaled();
    const double r = s1.m > 0 ? n * std::ldexp(s2.m / (s1.m * s1.m), static_cast<int>(s2.e - 2 * s1.e)) : 0.0;
    c.R.push_back(r);
    if (r > 0) g = std::max(g, (r - 1) / n);
    c.G.push_back(g);
    c.lines_alive.push_back(scene.particles - ended);
  }
}

}  // namespace

SurvivalCurve survival_curve(const Scene& scene, const Tally& tally) {
  SurvivalCurve c;
  c.t = survival_times(scene);
  c.survivors = survivors_on_grid(scene, tally);
  c.particles = scene.particles;
  if (tally.split) {
    line_curve(scene, tally, c);
  } else if (tally.weighted) {
    // exact cumulative sums, rounded once per grid point
    c.weighted = true;
    c.max_weight = scene.sampling.max_weight();
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
  if (lines) return p * std::sqrt(std::max(0.0, R[i] - 1) / n);
  return std::sqrt(std::max(0.0, Q[i] - p * p) / n);
}

double SurvivalCurve::effective(std::size_t i) const {
  if (!weighted) return static_cast<double>(survivors[i]);
  if (lines) return R[i] > 0 ? static_cast<double>(particles) / R[i] : 0.0;
  return Q[i] > 0 ? static_cast<double>(particles) * P_w[i] * P_w[i] / Q[i] : 0.0;
}

double SurvivalCurve::log_cov(std::size_t i, std::size_t j) const {
  const std::size_t a = std::min(i, j), b = std::max(i, j);
  const double n = static_cast<double>(particles);
  if (!weighted) return (1 - P(a)) / (n * P(a));
  if (lines) return G[a];
  return (Q[b] - P_w[a] * P_w[b]) / (n * P_w[a] * P_w[b]);
}

}  // namespace rotleak
