#include "sim/tally/survival.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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
  const auto* lines = tally.get_if<LinesEstimator>();
  for (std::size_t k = 0; k < tally.escapes_per_bin.size(); ++k) {
    if (lines) alive += lines->born_per_bin[k] - lines->culled_per_bin[k];  // members: copies in, roulette out
    alive -= tally.escapes_per_bin[k];
    out[k + 1] = alive;
  }
  return out;
}

namespace {
/// P's share carried by lines that have split (P less the unsplit lines' share).
double split_share(const SurvivalCurve& c, std::size_t j) {
  return j < c.unsplit_P.size() ? c.P_w[j] - c.unsplit_P[j] : c.P_w[j];
}
}  // namespace

/// The allowance for unsplit lines a run has not drawn (docs/model.md "Deep tails", "Unsplit lines not
/// drawn"), group by group: past the last time t_r at which at least kUnsplitReliable of a group's lines
/// are alive, its share of P is extrapolated as P_g(t) = P_g(t_r) max(exp(-gamma (t - t_r)),
/// S(t) / S(t_r)): gamma the group's own leaving rate by maximum likelihood from t_a on (t_a the last time
/// after the first split with 2 kUnsplitReliable of its lines, else the first split time), S the split
/// lines' share (mixing). It is carried by lines of the group's typical weight w = N sum w^2 / sum w at
/// t_r: a Poisson number of such lines adds w P_g(t) / N to P's variance, beyond what the group's lines
/// still alive add to the lines' spread. R (hence P_err, the effective lines and G) includes the sum over
/// the groups, and allowance_unresolved_from marks where it first exceeds kAllowanceShare of the lines'
/// own variance.
void add_unsplit_allowance(SurvivalCurve& c) {
  const std::size_t points = c.t.size();
  if (points == 0) return;
  const double n = static_cast<double>(c.particles);
  std::vector<double> extra(points, 0.0);
  std::size_t first = points;  // the first grid index any allowance applies to
  for (SurvivalCurve::UnsplitGroup& k : c.unsplit) {
    if (k.lines.size() != points) continue;
    std::size_t r = points, a = std::min(c.first_split, points - 1);
    for (std::size_t j = points; j-- > 0;)
      if (k.lines[j] >= kUnsplitReliable) {
        r = j;
        break;
      }
    if (r == points || r + 1 == points || !(k.P[r] > 0)) continue;
    for (std::size_t j = r + 1; j-- > c.first_split;)
      if (k.lines[j] >= 2 * kUnsplitReliable) {
        a = j;
        break;
      }
    // The rate from every leaving after t_a (its escape or first split), each line's time in the group
    // after t_a its exposure (censored at the last grid time): gamma = leavings / exposure, the maximum
    // likelihood rate. The leavings past t_r count: a rate from the halving before t_r alone, 20 lines
    // to 10, is uncertain by 40% and set the allowance ahead by a factor e^(0.4 gamma (t - t_r)).
    double gamma = 0, exposure = 0;
    for (std::size_t j = a; j + 1 < points; ++j) exposure += static_cast<double>(k.lines[j]) * (c.t[j + 1] - c.t[j]);
    if (exposure > 0) gamma = static_cast<double>(k.lines[a] - k.lines[points - 1]) / exposure;
    const double w = n * k.var[r] / k.P[r];
    k.allowance = true;
    k.reliable_until = c.t[r];
    k.rate_from = c.t[std::min(a, r)];
    k.decay_rate = gamma;
    k.typical_weight = w;
    // P_g(t) / P_g(t_r): no smaller than the group's own rate gives, nor than the split lines' decay
    // S(t) / S(t_r), S = P less the unsplit lines' share (mixing: a line that leaves its bouncing-ball
    // stretch decays as the chaotic population does, one that stays in it lives longer; the lines' own
    // error model assumes the same). Not P's own decay: where the light bouncing-ball lines' tail holds P
    // up (82/83 past t ~ 3500), the heavy ones are not in it.
    const double s_r = split_share(c, r);
    for (std::size_t j = r + 1; j < points; ++j) {
      const double own = std::exp(-gamma * (c.t[j] - c.t[r]));
      const double mixing = s_r > 0 ? std::max(0.0, split_share(c, j)) / s_r : 0.0;
      extra[j] += std::max(0.0, w * k.P[r] * std::max(own, mixing) / n - k.var[j]);
    }
    first = std::min(first, r + 1);
  }
  if (first == points) return;
  for (std::size_t j = first; j < points; ++j) {
    if (c.P_w[j] > 0 && extra[j] > 0) {
      const double own = c.P_w[j] * c.P_w[j] * std::max(0.0, c.R[j] - 1) / n;
      if (extra[j] > kAllowanceShare * own && !c.allowance_unresolved_from) c.allowance_unresolved_from = c.t[j];
      c.R[j] += n * extra[j] / (c.P_w[j] * c.P_w[j]);
    }
  }
  running_lines_variance(c);
}

void running_lines_variance(SurvivalCurve& c) {
  const double n = static_cast<double>(c.particles);
  c.G.resize(c.R.size());
  double g = 0;
  for (std::size_t j = 0; j < c.R.size(); ++j) {
    if (c.R[j] > 0) g = std::max(g, (c.R[j] - 1) / n);
    c.G[j] = g;
  }
}

namespace {

/// The unsplit lines on the grid, class by class (SurvivalCurve::unsplit_classes), from the exact tallies: the
/// classes a line starts in, the start cells less the cells that left.
void unsplit_class_curves(const LinesEstimator& e, SurvivalCurve& c, double n) {  // n: the sum P is a share of
  const std::size_t points = c.t.size();
  std::vector<UnsplitCell> alive;
  std::vector<int> slot(kUnsplitClasses, -1);  // a class's place in c.unsplit_classes
  for (int k = 0; k < kUnsplitClasses; ++k) {
    const UnsplitCell& start = e.unsplit_start[static_cast<std::size_t>(k)];
    if (start.lines == 0) continue;
    slot[static_cast<std::size_t>(k)] = static_cast<int>(c.unsplit_classes.size());
    c.unsplit_classes.emplace_back().classes = {k};
    alive.push_back(start);
  }
  auto next_cell = e.unsplit_left.begin();
  for (std::size_t j = 0; j < points; ++j) {
    for (; next_cell != e.unsplit_left.end() && next_cell->first / kUnsplitClasses == j; ++next_cell) {
      const int q = slot[next_cell->first % kUnsplitClasses];
      // a line leaves only the class it started in: more leaving than started is a damaged tally
      if (q < 0) throw std::logic_error("unsplit lines left a weight class no line started in");
      UnsplitCell& a = alive[static_cast<std::size_t>(q)];
      a.lines -= next_cell->second.lines;
      a.w = a.w.minus(next_cell->second.w);
      a.w2 = a.w2.minus(next_cell->second.w2);
    }
    std::uint64_t lines = 0;
    FixedSum total;
    for (std::size_t q = 0; q < c.unsplit_classes.size(); ++q) {
      c.unsplit_classes[q].lines.push_back(alive[q].lines);
      c.unsplit_classes[q].P.push_back(alive[q].w.value() / n);
      c.unsplit_classes[q].var.push_back(alive[q].w2.value() / (n * n));
      lines += alive[q].lines;
      total.merge(alive[q].w);
    }
    c.unsplit_lines.push_back(lines);
    c.unsplit_P.push_back(total.value() / n);  // rounded once, from the exact sum
  }
}

/// Lines: the split run's P, R, G and lines alive from the exact line tallies, then the unsplit lines. P is the
/// lines' share of their starting weight, sum Y(t) / sum w0 (P(0) = 1), and R - 1 its relative variance times N by
/// the delta method: (R_Y - 1) + (R_0 - 1) - 2 (X - 1) with R_Y = N sum Y^2 / (sum Y)^2, R_0 its value at t = 0 and
/// X = N sum Y w0 / (sum Y sum w0) (docs/model.md "Importance sampling").
void build_curve(const Scene& scene, const LinesEstimator& e, SurvivalCurve& c) {
  c.weighted = c.lines = true;
  c.max_weight = scene.sampling.max_weight();
  const double n = static_cast<double>(scene.particles);
  FixedSum in, out, in2, out2, inx, outx;
  std::uint64_t ended = 0;
  FixedSum::Scaled s0{};
  double start = 0, w_start = 0, r0 = 0;
  for (std::size_t j = 0; j < e.line_in.size(); ++j) {
    in.merge(e.line_in[j]);
    out.merge(e.line_out[j]);
    in2.merge(e.line2_in[j]);
    out2.merge(e.line2_out[j]);
    inx.merge(e.linex_in[j]);
    outx.merge(e.linex_out[j]);
    ended += e.lines_ended[j];
    // exact: sum Y_i(t_j), sum Y_i(t_j)^2, sum Y_i(t_j) w0_i
    const FixedSum y = in.minus(out), y2 = in2.minus(out2), yx = inx.minus(outx);
    const FixedSum::Scaled s1 = y.scaled(), s2 = y2.scaled(), sx = yx.scaled();
    const double w = y.value() / n;  // W as an unsplit weighted run rounds it: P the same bits when nothing splits
    if (j == 0) {
      s0 = s1;
      start = y.value();
      w_start = w;
    }
    c.P_w.push_back(w_start > 0 ? w / w_start : 0.0);
    // from the scaled sums (sum Y^2 may lie far below the double range)
    const double ry = s1.m > 0 ? n * std::ldexp(s2.m / (s1.m * s1.m), static_cast<int>(s2.e - 2 * s1.e)) : 0.0;
    const double x =
        s1.m > 0 && s0.m > 0 ? n * std::ldexp(sx.m / (s1.m * s0.m), static_cast<int>(sx.e - s1.e - s0.e)) : 0.0;
    if (j == 0) r0 = ry;
    // a difference of O(R) terms, each good to a few ulps: below 16 ulps of them it is rounding, not spread (every
    // line still at its start gives exactly 0, as a uniform run's P(0) = 1 has no error)
    const double rv = ry + r0 - 2 * x;
    c.R.push_back(s1.m > 0 ? 1 + (rv > 16 * 0x1p-52 * (ry + r0) ? rv : 0.0) : 0.0);
    c.lines_alive.push_back(scene.particles - ended);
  }
  unsplit_class_curves(e, c, start > 0 ? start : n);  // the unsplit shares on P's scale: over sum w0
  finish_lines_curve(scene, c);
}

}  // namespace

void finish_lines_curve(const Scene& scene, SurvivalCurve& c) {
  const std::size_t points = c.t.size();
  c.R_lines = c.R;
  running_lines_variance(c);
  c.unsplit.clear();
  c.allowance_unresolved_from.reset();
  if (points == 0) return;
  c.first_split = std::min(points - 1, static_cast<std::size_t>(scene.splitting.every / scene.survival_dt) + 1);
  // each class whose decay can be measured after the first split time a group of its own, the others pooled
  SurvivalCurve::UnsplitGroup rest;
  rest.lines.assign(points, 0);
  rest.P.assign(points, 0.0);
  rest.var.assign(points, 0.0);
  for (const SurvivalCurve::UnsplitGroup& k : c.unsplit_classes) {
    const bool measurable = std::any_of(k.lines.begin() + static_cast<std::ptrdiff_t>(c.first_split), k.lines.end(),
                                        [](std::uint64_t x) { return x >= 2 * kUnsplitReliable; });
    if (measurable) {
      c.unsplit.push_back(k);
      continue;
    }
    rest.classes.push_back(k.classes.front());
    for (std::size_t j = 0; j < points; ++j) {  // class by class in a fixed order: deterministic
      rest.lines[j] += k.lines[j];
      rest.P[j] += k.P[j];
      rest.var[j] += k.var[j];
    }
  }
  if (!rest.classes.empty()) c.unsplit.push_back(std::move(rest));
  if (!scene.splits_every_member()) add_unsplit_allowance(c);
}

namespace {

/// Each estimator's part of the curve. Counting: the survivors' counts are the whole curve.
void build_curve(const Scene& /*scene*/, const CountingEstimator& /*e*/, SurvivalCurve& /*c*/) {}

/// Weighted: W and Q from the exact cumulative sums, rounded once per grid point; P_w = W / W[0].
void build_curve(const Scene& scene, const WeightedEstimator& e, SurvivalCurve& c) {
  c.weighted = true;
  c.max_weight = scene.sampling.max_weight();
  const double n = static_cast<double>(scene.particles);
  FixedSum w = e.total_w, w2 = e.total_w2;
  c.W.push_back(w.value() / n);
  c.Q.push_back(w2.value() / n);
  for (std::size_t k = 0; k < e.escaped_w.size(); ++k) {
    w = w.minus(e.escaped_w[k]);
    w2 = w2.minus(e.escaped_w2[k]);
    c.W.push_back(w.value() / n);
    c.Q.push_back(w2.value() / n);
  }
  self_normalise(c);
}

}  // namespace

SurvivalCurve survival_curve(const Scene& scene, const Tally& tally) {
  SurvivalCurve c;
  c.t = survival_times(scene);
  c.survivors = survivors_on_grid(scene, tally);
  c.particles = scene.particles;
  std::visit([&](const auto& e) { build_curve(scene, e, c); }, tally.estimator);
  return c;
}

void running_replicate_variance(SurvivalCurve& c) {
  c.G.clear();
  for (std::size_t i = 0; i < c.P_w.size(); ++i) {
    const double rel = c.P_w[i] > 0 ? (c.E[i] / c.P_w[i]) * (c.E[i] / c.P_w[i]) : 0.0;
    c.G.push_back(std::max(c.G.empty() ? 0.0 : c.G.back(), rel));
  }
}

void self_normalise(SurvivalCurve& c) {
  c.P_w.clear();
  for (double w : c.W) c.P_w.push_back(c.W[0] > 0 ? w / c.W[0] : 0.0);
}

double SurvivalCurve::P_err(std::size_t i) const {
  const double n = static_cast<double>(particles), p = P(i);
  if (!weighted) return std::sqrt(p * (1 - p) / n);
  if (replicated) return E[i];
  if (lines) return p * std::sqrt(std::max(0.0, R[i] - 1) / n);
  // P = S(t) / S(0) linearised: (1 / (N m)) sum (w I - P w), whose variance per particle is Q (1 - 2P) + P^2 B
  const double m = weight_sum(0), B = Q[0];
  return m > 0 ? std::sqrt(std::max(0.0, Q[i] * (1 - 2 * p) + p * p * B) / n) / m : 0.0;
}

double SurvivalCurve::effective(std::size_t i) const {
  if (!weighted) return static_cast<double>(survivors[i]);
  if (replicated) {  // the count whose binomial error would be as large: (P / E)^2
    const double p = P_w[i];
    return p > 0 && E[i] > 0 ? (p / E[i]) * (p / E[i]) : static_cast<double>(survivors[i]);
  }
  if (lines) return R[i] > 0 ? static_cast<double>(particles) / R[i] : 0.0;
  const double w = weight_sum(i);
  return Q[i] > 0 ? static_cast<double>(particles) * w * w / Q[i] : 0.0;
}

double SurvivalCurve::log_cov(std::size_t i, std::size_t j) const {
  const std::size_t a = std::min(i, j), b = std::max(i, j);
  const double n = static_cast<double>(particles);
  if (!weighted) return (1 - P(a)) / (n * P(a));
  if (lines || replicated) return G[a];
  // E[w^2 (I_a - P_a)(I_b - P_b)] with I_a I_b = I_b (alive at b is alive at a), over N m^2, relative
  const double m = weight_sum(0), B = Q[0], pa = P_w[a], pb = P_w[b];
  return (Q[b] - pb * Q[a] - pa * Q[b] + pa * pb * B) / (n * m * m * pa * pb);
}

}  // namespace rotleak
