#include "analysis/fits.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "analysis/fit_detail.hpp"

namespace rotleak {

using namespace fit_detail;

double KappaFit::log_se_at(double t) const { return std::sqrt(std::max(0.0, var_a + t * t * var_b + 2 * t * cov_ab)); }

KappaFit fit_kappa(const SurvivalCurve& c, double from, double to) {
  KappaFit k;
  k.from = from;
  k.to = to;
  std::vector<std::size_t> idx;
  std::vector<double> x;
  window_points(c, from, to, idx, x);
  const LinearFit f = fit_line(c, idx, x);
  k.points = idx.size();
  // no escape among the fitted points: the decay was not measured (one particle gave "-0 +- 0")
  if (!f.ok || c.survivors[idx.front()] == c.survivors[idx.back()]) return k;
  k.ok = true;
  if (c.lines)
    k.method =
        "least squares of ln P(t) on the grid points in the window; standard error from the spread of the independent "
        "lines of the split run (ln P with independent increments, delta method)";
  else if (c.weighted)
    k.method =
        "least squares of ln P(t) on the grid points in the window; standard error from the covariance of the "
        "weighted ln P (exact second-moment tallies, delta method)";
  k.value = -f.slope;
  k.std_error = std::sqrt(f.var_slope);
  k.log_amplitude = f.intercept;
  k.var_a = f.var_intercept;
  k.var_b = f.var_slope;
  k.cov_ab = f.cov;
  return k;
}

void add_window_systematic(KappaFit& k, const SurvivalCurve& c, double t_max) {
  if (!k.ok) return;
  const double a = k.from, b = k.to;
  double lo = k.value, hi = k.value;
  for (double start : {a, a + (b - a) / 6})
    for (double end : {a + (b - a) * 2 / 3, b, std::min(t_max, a + (b - a) * 4 / 3)}) {
      if (!(end > start)) continue;
      const KappaFit f = fit_kappa(c, start, end);
      if (!f.ok) continue;
      k.window_family.push_back({start, end, f.value});
      lo = std::min(lo, f.value);
      hi = std::max(hi, f.value);
    }
  k.window_systematic = (hi - lo) / 2;
}

namespace {

/// alpha at a significant crossing found at grid index i (prev: the last judged point before it, when
/// adjacent): the crossing interpolated between the two (ln P and the excess linear in t; a grid point is
/// not the crossing, and on a coarse grid P at the first point above can lie well past it), and its error
/// through the crossing. At t* ln P = ln factor + ln A - kappa t*: moving ln P by d moves t* by -d / (kappa
/// + s) (s = d ln P / dt) and ln alpha by d kappa / (kappa + s), P's relative error times the
/// crossing-shift factor; moving the extrapolated line by e moves ln alpha by s e / (kappa + s). d and e
/// are correlated (ln P at t* shares the early increments the fit is made of): Var ln alpha = (kappa^2 Var
/// d + s^2 Var e + 2 kappa s Cov(d, e)) / (kappa + s)^2.
void set_crossing(const SurvivalCurve& c, const KappaFit& k, std::size_t i, std::size_t prev, double prev_excess,
                  double excess, double lf, AlphaResult& a) {
  const double P = c.P(i), fit = std::exp(k.log_amplitude - k.value * c.t[i]);
  double t_star = c.t[i], ln_alpha = std::log(P);
  if (prev + 1 == i && prev_excess <= lf && excess > prev_excess) {
    const double f = (lf - prev_excess) / (excess - prev_excess);
    t_star = c.t[prev] + f * (c.t[i] - c.t[prev]);
    const double lp0 = std::log(c.P(prev));
    ln_alpha = lp0 + f * (std::log(P) - lp0);
  }
  a.value = std::exp(ln_alpha);
  a.crossing_time = t_star;
  a.resolved_until = c.t[i];
  const double s = log_slope_at(c, i);
  const double rel = k.value + s;
  a.shift_factor = rel > 0 ? k.value / rel : 1.0;
  const double p_err = alpha_p_err(c, i, fit);
  const double var_d = std::pow(p_err / P, 2), se_e = k.log_se_at(t_star);
  double var = var_d * a.shift_factor * a.shift_factor;
  if (rel > 0) {
    // the covariance only where P's error is the curve's own (a Poisson floor is not correlated)
    const double cov = p_err == c.P_err(i) ? cov_with_fit(c, k, i, t_star) : 0.0;
    var = (k.value * k.value * var_d + s * s * se_e * se_e + 2 * k.value * s * cov) / (rel * rel);
    var = std::max(var, 0.0);
  }
  a.std_error = *a.value * std::sqrt(var);
  a.note =
      "P where it first exceeds the extrapolated exponential fit by the factor (interpolated between grid "
      "points)";
}

/// No crossing while P is resolved (last: the last resolved grid index). The true P never grows (an
/// estimate may: a split run's roulette raises it at split times), so a crossing at t* > t gives alpha =
/// P(t*) <= P(t) <= P's upper limit: every grid time where the data exclude P >= factor x fit (P's upper
/// limit below it) bounds alpha by that upper limit. Go on past the resolved range (the upper limits only
/// widen there) until a time is not excluded. The upper limit is P + 3 standard errors (the line's
/// included), and at least P + 6 max_weight / N: zero survivors among N draws exclude a probability above
/// 6 / N at 99.75% (Poisson), and a survivor nobody drew could carry weight up to max_weight. Split runs:
/// the bound stays within the resolved range, where the lines' own spread is P's error (past it, a line
/// nobody followed could carry any weight the splits left it).
void set_bound(const SurvivalCurve& c, const KappaFit& k, std::size_t last, bool gap, AlphaResult& a) {
  a.resolved_until = c.t[last];
  const double zero_events = c.lines ? 0.0 : 6 * c.max_weight / static_cast<double>(c.particles);
  // The last resolved time bounds alpha too (no crossing before it): by P's upper limit there, not P
  // itself (a bound of P alone lay below the pooled alpha in 40 of 110 runs at 82/83).
  const double fit_last = std::exp(k.log_amplitude - k.value * c.t[last]);
  double best = c.P(last) + a.sigma * alpha_p_err(c, last, fit_last);
  for (std::size_t i = 0; i < c.t.size(); ++i) {
    if (c.lines && i > last) break;
    if (c.t[i] < k.from) continue;
    const double fit = std::exp(k.log_amplitude - k.value * c.t[i]);
    const double se = std::hypot(alpha_p_err(c, i, fit), a.factor * fit * k.log_se_at(c.t[i]));
    const double ub = c.P(i) + std::max(a.sigma * se, zero_events);
    if (!(ub < a.factor * fit)) break;
    best = std::min(best, ub);
    a.bound_until = c.t[i];
  }
  a.upper_bound = best;
  a.note =
      gap ? "P crosses factor x the fit after resolved_until, where P is not resolved (too few effective survivors): "
            "alpha is bounded from above by P's upper limit until then, not measured"
          : "no significant crossing: until bound_until, P's upper limit (P + 3 errors, at least 6 max_weight / N) "
            "stays below factor x the fit, and the smallest of them bounds alpha from above";
}

}  // namespace

AlphaResult find_alpha(const SurvivalCurve& c, const KappaFit& k, double factor, double sigma,
                       std::uint64_t min_survivors) {
  AlphaResult a;
  a.factor = factor;
  a.sigma = sigma;
  a.min_survivors = min_survivors;
  if (!k.ok) {
    a.note = "no kappa fit";
    return a;
  }
  const double lf = std::log(factor);
  std::size_t last = 0;
  bool gap = false;  // the crossing fell among unresolved points
  // the last point judged before i (resolved, in or after the window) and its excess over the fit
  std::size_t prev = c.t.size();
  double prev_excess = 0;
  for (std::size_t i = 0; i < c.t.size(); ++i) {
    // unresolved points are skipped, not the end: a weighted run's effective survivors can dip
    // (the exponential part dying out) and recover (the tail its scheme samples well); raw counts
    // only fall, so for uniform runs this is the old stop
    if (c.effective(i) < static_cast<double>(min_survivors)) continue;
    last = i;
    if (c.t[i] < k.from) continue;
    const double line = k.log_amplitude - k.value * c.t[i];
    const double excess = std::log(c.P(i)) - line;
    if (excess > lf) {
      // Grid points before this one were skipped as unresolved: the crossing lies somewhere among them,
      // where P is not known, and P here is only a lower limit of alpha (P(t*) >= P(t) for t* <= t).
      // (At omega = 82/83 with 10^6 lines the crossing at t ~ 4340 falls where the unsplit lines'
      // allowance leaves P unresolved, and P at the first resolved point, up to t = 9300, read as alpha
      // scattered 2.6 times its errors.) Bounded from above below, from the last point before the gap.
      if (prev < c.t.size() && prev + 1 != i) {
        gap = true;
        break;
      }
      // The crossing counts only if P there lies more than 3 standard errors (its own and the
      // extrapolated line's) above the line: a lucky particle of tiny weight is not a tail.
      const double P = c.P(i), fit = std::exp(line);
      const double se = std::hypot(alpha_p_err(c, i, fit), fit * k.log_se_at(c.t[i]));
      if (!(P - fit > sigma * se)) {
        a.resolved_until = c.t[i];
        a.crossing_not_significant = true;
        a.upper_bound = P + sigma * alpha_p_err(c, i, fit);
        a.note =
            "P crosses factor x the fit here, but is not 3 standard errors above the fit: not significant; P + 3 "
            "errors bounds alpha from above";
        return a;
      }
      set_crossing(c, k, i, prev, prev_excess, excess, lf, a);
      return a;
    }
    prev = i;
    prev_excess = excess;
  }
  set_bound(c, k, gap ? prev : last, gap, a);
  return a;
}

void add_alpha_systematic(AlphaResult& a, const SurvivalCurve& c, const KappaFit& k) {
  if (!a.value) return;
  double lo = *a.value, hi = *a.value;
  std::size_t members = 0;
  for (const KappaFit::FamilyMember& m : k.window_family) {
    const KappaFit f = fit_kappa(c, m.from, m.to);
    const AlphaResult b = find_alpha(c, f, a.factor, a.sigma, a.min_survivors);
    if (!b.value) continue;
    ++members;
    lo = std::min(lo, *b.value);
    hi = std::max(hi, *b.value);
  }
  if (members >= 2) a.systematic = (hi - lo) / 2;
}

void add_uniform_reach(AlphaResult& a, const SurvivalCurve& c) {
  if (!c.weighted || c.lines || c.replicated) return;  // only the mupo mixture has a uniform share
  const double reach =
      a.factor * static_cast<double>(a.min_survivors) * c.max_weight / static_cast<double>(c.particles);
  a.uniform_reach = reach;
  const std::optional<double> v = a.value ? a.value : a.upper_bound;
  if (v && *v < reach) {
    char text[300];
    std::snprintf(text, sizeof text,
                  "; UNRELIABLE: below the uniform share's reach %.3g (factor x min_survivors x max_weight / N): the "
                  "exponential part is carried by a few heavy uniform draws, and typical runs read low; run.splitting "
                  "samples it",
                  reach);
    a.note += text;
  }
}

namespace {

/// The end of the tail's stable stretch from grid index start, at most end: local exponents over
/// successive factor-1.5 segments [t_k, 1.5 t_k] must agree (within 30% or within 3 standard errors); the
/// first disagreement ends it (a kink, a cut-off). end itself when no segment is judged.
std::size_t stable_stretch_end(const SurvivalCurve& c, std::size_t start, std::size_t end) {
  std::size_t seg = start, stable_end = start;
  double z_prev = 0, se_prev = 0;
  bool first = true;
  while (true) {
    std::size_t b = seg;
    while (b < end && c.t[b] < 1.5 * c.t[seg]) ++b;
    if (b == seg || c.t[b] < 1.5 * c.t[seg] * 0.999) break;  // the last partial segment is not judged
    const double dl = std::log(c.t[b]) - std::log(c.t[seg]);
    const double z = (std::log(c.P(seg)) - std::log(c.P(b))) / dl;
    const double var = std::max(0.0, c.log_cov(seg, seg) + c.log_cov(b, b) - 2 * c.log_cov(seg, b)) / (dl * dl);
    if (!first) {
      const double diff = std::abs(z - z_prev);
      if (diff > 0.3 * std::max(std::abs(z), std::abs(z_prev)) && diff > 3 * std::sqrt(var + se_prev * se_prev)) break;
    }
    first = false;
    z_prev = z;
    se_prev = std::sqrt(var);
    stable_end = b;
    seg = b;
  }
  return stable_end > start ? stable_end : end;
}

}  // namespace

TailFit fit_tail(const SurvivalCurve& c, const AlphaResult& a) {
  TailFit f;
  if (!a.value) return f;
  // resolved end of the tail
  std::size_t end = 0, start = c.t.size();
  for (std::size_t i = 0; i < c.t.size(); ++i) {
    if (c.t[i] >= a.crossing_time && start == c.t.size()) start = i;
    if (c.effective(i) >= static_cast<double>(a.min_survivors)) end = i;
  }
  if (start >= end || c.t[end] < 2 * c.t[start]) {
    f.note = "the tail is resolved over less than a factor 2 in time";
    return f;
  }
  end = stable_stretch_end(c, start, end);
  if (c.t[end] < 2 * c.t[start]) {
    f.note = "the local exponent is stable over less than a factor 2 in time after the crossing";
    f.from = c.t[start];
    f.to = c.t[end];
    return f;
  }
  std::vector<std::size_t> idx;
  std::vector<double> x;
  log_spaced_points(
      c, start, end, [](std::size_t) { return true; }, idx, x);
  LinearFit lf = fit_line(c, idx, x);
  if (!lf.ok) return f;
  if (c.lines && !c.unsplit.empty()) {  // the full double sum over the tail's covariance (split_tail_cov)
    std::vector<double> w, v;
    double xm = 0, sxx = 0;
    ls_weights(x, w, v, xm, sxx);
    lf.var_slope = tail_log_variance(c, idx, w);
  }
  f.z = -lf.slope;
  f.std_error = std::sqrt(lf.var_slope);
  f.from = c.t[start];
  f.to = c.t[end];
  f.points = idx.size();
  return f;
}

}  // namespace rotleak
