#include "analysis/calibration.hpp"

#include <algorithm>
#include <boost/math/distributions/binomial.hpp>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>
#include <cmath>
#include <stdexcept>

namespace rotleak {

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const std::size_t m = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m), v.end());
  const double hi = v[m];
  if (v.size() % 2) return hi;
  return 0.5 * (hi + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m)));
}

}  // namespace

SeedSpread seed_spread(const std::vector<double>& x, const std::vector<double>& e) {
  if (x.size() != e.size() || x.size() < 2) throw std::invalid_argument("seed_spread: needs >= 2 values and errors");
  SeedSpread s;
  s.n = x.size();
  const double n = static_cast<double>(s.n);
  double sum = 0;
  for (double v : x) sum += v;
  s.pooled = sum / n;
  double ss = 0;
  for (double v : x) ss += (v - s.pooled) * (v - s.pooled);
  s.sd = std::sqrt(ss / (n - 1));
  s.pooled_err = s.sd / std::sqrt(n);
  s.median_err = median(e);
  s.sd_over_err = s.median_err > 0 ? s.sd / s.median_err : 0.0;
  double chi2 = 0, in1 = 0, in2 = 0;
  for (std::size_t k = 0; k < s.n; ++k) {
    // the others' mean: the seed's own value is not its own reference
    const double others = (sum - x[k]) / (n - 1), d = std::abs(x[k] - others);
    if (e[k] > 0) chi2 += (x[k] - s.pooled) * (x[k] - s.pooled) / (e[k] * e[k]);
    in1 += d <= e[k] ? 1 : 0;
    in2 += d <= 2 * e[k] ? 1 : 0;
  }
  s.chi2_dof = chi2 / (n - 1);
  s.coverage1 = in1 / n;
  s.coverage2 = in2 / n;
  const double m = median(x);
  s.max_over_median = m != 0 ? *std::max_element(x.begin(), x.end()) / m : 0.0;
  return s;
}

HonestBand honest_band(std::size_t K, std::size_t tests) {
  if (K < 2) throw std::invalid_argument("honest_band: needs K >= 2 seeds");
  if (tests < 1) throw std::invalid_argument("honest_band: needs tests >= 1");
  namespace bm = boost::math;
  const double k = static_cast<double>(K), a = kCalibrationFalseAlarm / static_cast<double>(tests);
  HonestBand b;
  b.false_alarm_each = a;
  const bm::chi_squared chi2(k - 1);
  b.lo = std::min(kHonestBand[0], std::sqrt(bm::quantile(chi2, a / 2) / (k - 1)));
  b.hi = std::max(kHonestBand[1], std::sqrt(bm::quantile(bm::complement(chi2, a / 2)) / (k - 1)));
  b.coverage2_expected = 2 * bm::cdf(bm::normal(), 2 * std::sqrt((k - 1) / k)) - 1;
  const bm::binomial count(k, b.coverage2_expected);
  std::size_t c = 0;  // the smallest count whose lower tail P(X <= c) reaches a
  while (c < K && bm::cdf(count, static_cast<double>(c)) < a) ++c;
  b.coverage2_floor = std::min(kHonestCoverage2, static_cast<double>(c) / k);
  return b;
}

CurveVerdict curve_verdict(const std::vector<SeedSpread>& times) {
  CurveVerdict v;
  v.judged = times.size();
  if (times.empty()) return v;
  v.band = honest_band(times.front().n, times.size());
  for (const SeedSpread& s : times) {
    if (s.n != times.front().n) throw std::invalid_argument("curve_verdict: every time needs the same seeds");
    v.outside += s.sd_over_err < v.band.lo || s.sd_over_err > v.band.hi ? 1 : 0;
    v.uncovered += s.coverage2 < v.band.coverage2_floor ? 1 : 0;
  }
  return v;
}

std::string spread_verdict(const SeedSpread& s, double model_share) {
  if (!(s.median_err > 0)) return "no errors reported";
  const HonestBand b = honest_band(s.n);
  if (s.sd_over_err > b.hi || s.coverage2 < b.coverage2_floor) return "errors too small";
  if (s.sd_over_err < b.lo)
    return model_share > 0.5 ? "untested: mostly the allowance for lines not drawn" : "errors too large";
  return "honest";
}

namespace {

/// pool_curves' split structure: the classes, R before the allowance, then finish_lines_curve. False (p untouched)
/// where a curve lacks its structure.
bool pool_structure(const std::vector<SurvivalCurve>& curves, const Scene& scene, SurvivalCurve& p) {
  for (const SurvivalCurve& c : curves)
    if (c.R_lines.size() != p.t.size()) return false;
  const std::size_t points = p.t.size();
  const double K = static_cast<double>(curves.size());
  std::vector<int> classes;  // every class any run holds, in class order
  for (const SurvivalCurve& c : curves)
    for (const SurvivalCurve::UnsplitGroup& k : c.unsplit_classes) classes.push_back(k.classes.front());
  std::sort(classes.begin(), classes.end());
  classes.erase(std::unique(classes.begin(), classes.end()), classes.end());
  p.unsplit_classes.assign(classes.size(), {});
  for (std::size_t q = 0; q < classes.size(); ++q) {
    SurvivalCurve::UnsplitGroup& g = p.unsplit_classes[q];
    g.classes = {classes[q]};
    g.lines.assign(points, 0);
    g.P.assign(points, 0.0);
    g.var.assign(points, 0.0);
  }
  p.unsplit_lines.assign(points, 0);
  p.unsplit_P.assign(points, 0.0);
  for (std::size_t i = 0; i < points; ++i) {
    double sp = 0, sq = 0;
    for (const SurvivalCurve& c : curves) {  // seed order, class order: deterministic
      sp += c.P_w[i];
      sq += c.R_lines[i] * c.P_w[i] * c.P_w[i];
      p.unsplit_lines[i] += c.unsplit_lines[i];
      p.unsplit_P[i] += c.unsplit_P[i] / K;
      for (const SurvivalCurve::UnsplitGroup& k : c.unsplit_classes) {
        const std::size_t q = static_cast<std::size_t>(
            std::lower_bound(classes.begin(), classes.end(), k.classes.front()) - classes.begin());
        p.unsplit_classes[q].lines[i] += k.lines[i];
        p.unsplit_classes[q].P[i] += k.P[i] / K;
        p.unsplit_classes[q].var[i] += k.var[i] / (K * K);
      }
    }
    // one curve is its own pool: its R as it is, not R P^2 / P^2 rounded twice
    p.R[i] = curves.size() == 1 ? curves.front().R_lines[i] : sp > 0 ? K * sq / (sp * sp) : 0.0;
  }
  Scene pooled = scene;
  pooled.particles = p.particles;
  finish_lines_curve(pooled, p);
  return true;
}

}  // namespace

namespace {

/// Runs of splitting over starts pooled as one run of all their replicates: P the mean of theirs (each run has as
/// many), its error from every replicate's spread (each run's within, (R - 1) R e^2, and between, R (m - M)^2).
SurvivalCurve pool_replicates(const std::vector<SurvivalCurve>& curves, SurvivalCurve p) {
  const SurvivalCurve& first = curves.front();
  for (const SurvivalCurve& c : curves)
    if (!c.replicated || c.replicates != first.replicates)
      throw std::invalid_argument("pool_curves: the runs differ in their replicates");
  const double R = first.replicates, K = static_cast<double>(curves.size());
  p.replicated = true;
  p.replicates = first.replicates * static_cast<int>(curves.size());
  p.particles = first.particles;  // a replicate's starts, as in each run
  for (std::size_t i = 0; i < p.t.size(); ++i) {
    double m = 0;
    int nonzero = 0;
    for (const SurvivalCurve& c : curves) {
      m += c.P_w[i];
      nonzero += c.replicates_nonzero.empty() ? 0 : c.replicates_nonzero[i];  // a curve read back has none
    }
    m /= K;
    double ss = 0;
    for (const SurvivalCurve& c : curves) ss += (R - 1) * R * c.E[i] * c.E[i] + R * (c.P_w[i] - m) * (c.P_w[i] - m);
    const double n = R * K, e = n > 1 ? std::sqrt(ss / (n - 1) / n) : 0.0;
    p.P_w.push_back(m);
    p.E.push_back(e);
    if (!first.replicates_nonzero.empty()) p.replicates_nonzero.push_back(nonzero);
  }
  running_replicate_variance(p);
  return p;
}

}  // namespace

SurvivalCurve pool_curves(const std::vector<SurvivalCurve>& curves, const Scene* scene) {
  if (curves.empty()) throw std::invalid_argument("pool_curves: no curves");
  const SurvivalCurve& first = curves.front();
  for (const SurvivalCurve& c : curves)
    if (c.t != first.t || c.weighted != first.weighted || c.lines != first.lines || c.particles != first.particles)
      throw std::invalid_argument("pool_curves: the runs differ in grid, sampling or particles");
  const std::size_t points = first.t.size();
  const double K = static_cast<double>(curves.size());
  SurvivalCurve p;
  p.t = first.t;
  p.weighted = first.weighted;
  p.lines = first.lines;
  p.max_weight = first.max_weight;
  p.particles = first.particles * curves.size();
  p.survivors.assign(points, 0);
  for (const SurvivalCurve& c : curves)
    for (std::size_t i = 0; i < points; ++i) p.survivors[i] += c.survivors[i];
  if (!p.weighted) return p;
  if (first.replicated) return pool_replicates(curves, p);
  for (std::size_t i = 0; i < points; ++i) {
    double sp = 0, sq = 0;  // seed order: the pooled curve does not depend on how the seeds were run
    for (const SurvivalCurve& c : curves) {
      sp += p.lines ? c.P_w[i] : c.weight_sum(i);  // importance sampling: the weight sums, normalised after
      sq += p.lines ? c.R[i] * c.P_w[i] * c.P_w[i] : c.Q[i];
    }
    (p.lines ? p.P_w : p.W).push_back(sp / K);
    if (p.lines) {
      p.R.push_back(sp > 0 ? K * sq / (sp * sp) : 0.0);
      std::uint64_t alive = 0;
      for (const SurvivalCurve& c : curves) alive += c.lines_alive[i];
      p.lines_alive.push_back(alive);
    } else {
      p.Q.push_back(sq / K);
    }
  }
  if (!p.lines) self_normalise(p);  // the pooled sample's share of its weight, as one run of K N particles
  // the structure where every curve keeps it (finish_lines_curve builds G with it), else G from the pooled R alone
  if (p.lines && !(scene && pool_structure(curves, *scene, p))) running_lines_variance(p);
  return p;
}

bool resolved_in_seeds(const std::vector<SurvivalCurve>& curves, std::size_t i, double min_effective) {
  std::vector<double> eff;
  for (const SurvivalCurve& c : curves) {
    if (!(c.P(i) > 0)) return false;
    eff.push_back(c.effective(i));
  }
  return median(eff) >= min_effective;
}

}  // namespace rotleak
