#include "sim/survival.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

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

/// The allowance for unsplit lines a run has not drawn (docs/model.md "Deep tails", "Unsplit lines not
/// drawn"): past the last time t_r at which at least kUnsplitReliable unsplit lines are alive, their
/// share of P is taken to go on decaying at the rate it showed over [t_a, t_r] (t_a the last time with
/// 2 kUnsplitReliable of them), P_u(t) = P_u(t_r) exp(-gamma (t - t_r)), carried by lines of their
/// typical weight w = N sum w^2 / sum w at t_r: a Poisson number of such lines adds w P_u(t) / N to P's
/// variance, beyond what the unsplit lines still alive add to the lines' spread. R (hence P_err, the
/// effective lines and G) includes it.
void add_unsplit_allowance(SurvivalCurve& c) {
  const std::size_t points = c.t.size();
  if (points == 0 || c.unsplit_lines.size() != points) return;
  const double n = static_cast<double>(c.particles);
  std::size_t r = points, a = points;
  for (std::size_t j = points; j-- > 0;)
    if (c.unsplit_lines[j] >= kUnsplitReliable) {
      r = j;
      break;
    }
  if (r == points || r + 1 == points || !(c.unsplit_P[r] > 0)) return;
  for (std::size_t j = r + 1; j-- > 0;)
    if (c.unsplit_lines[j] >= 2 * kUnsplitReliable) {
      a = j;
      break;
    }
  double gamma = 0;
  if (a < r && c.unsplit_P[a] > c.unsplit_P[r]) gamma = std::log(c.unsplit_P[a] / c.unsplit_P[r]) / (c.t[r] - c.t[a]);
  const double w = n * c.unsplit_var[r] / c.unsplit_P[r];
  c.unsplit_model = {true, c.t[r], c.t[a < points ? a : r], gamma, w, std::nullopt};
  double g = r > 0 ? c.G[r - 1] : 0.0;
  for (std::size_t j = 0; j < points; ++j) {
    if (j > r && c.P_w[j] > 0) {
      const double expected = c.unsplit_P[r] * std::exp(-gamma * (c.t[j] - c.t[r]));
      const double extra = std::max(0.0, w * expected / n - c.unsplit_var[j]);
      const double own = c.P_w[j] * c.P_w[j] * std::max(0.0, c.R[j] - 1) / n;
      if (extra > own && !c.unsplit_model.dominates_from) c.unsplit_model.dominates_from = c.t[j];
      c.R[j] += n * extra / (c.P_w[j] * c.P_w[j]);
    }
    if (j >= r) {
      if (c.R[j] > 0) g = std::max(g, (c.R[j] - 1) / n);
      c.G[j] = g;
    }
  }
}

namespace {

/// The split run's P, R, G and lines alive from the exact line tallies.
void line_curve(const Scene& scene, const Tally& tally, SurvivalCurve& c) {
  c.weighted = c.lines = true;
  c.max_weight = scene.sampling.max_weight();
  const double n = static_cast<double>(scene.particles);
  FixedSum in, out, in2, out2, u = tally.w_start, u2 = tally.w2_start;
  std::uint64_t ended = 0, left = 0;
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
    if (j < tally.unsplit_out.size()) {
      u = u.minus(tally.unsplit_out[j]);
      u2 = u2.minus(tally.unsplit2_out[j]);
      left += tally.unsplit_left[j];
    }
    c.unsplit_lines.push_back(scene.particles - left);
    c.unsplit_P.push_back(u.value() / n);
    c.unsplit_var.push_back(u2.value() / (n * n));
  }
  add_unsplit_allowance(c);
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
