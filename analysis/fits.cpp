#include "analysis/fits.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rotleak {

namespace {

struct LinearFit {
  double slope = 0, intercept = 0;
  double var_intercept = 0, var_slope = 0, cov = 0;
  bool ok = false;
};

// Greenwood variance of sum_i u_i ln P(t_i) for increasing grid indices idx:
// Var = sum_k (g_k - g_{k-1}) (sum_{i>=k} u_i)^2 with g = (1 - P) / (N P).
double greenwood_variance(const SurvivalCurve& c, const std::vector<std::size_t>& idx, const std::vector<double>& u) {
  const std::size_t n = idx.size();
  if (c.weighted && !c.lines) {  // no independent increments: the full double sum over the covariance
    double var = 0;
    for (std::size_t i = 0; i < n; ++i) {
      var += u[i] * u[i] * c.log_cov(idx[i], idx[i]);
      for (std::size_t j = i + 1; j < n; ++j) var += 2 * u[i] * u[j] * c.log_cov(idx[i], idx[j]);
    }
    return var;
  }
  std::vector<double> tail(n + 1, 0.0);
  for (std::size_t k = n; k-- > 0;) tail[k] = tail[k + 1] + u[k];
  double var = 0, g_prev = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double g = c.log_cov(idx[k], idx[k]);  // Var ln P: Greenwood's, or the lines' (non-decreasing)
    var += (g - g_prev) * tail[k] * tail[k];
    g_prev = g;
  }
  return var;
}

// Split runs, in the tail: Cov(ln P(t_a), ln P(t_b)), a <= b, from P's two shares. The unsplit lines
// (one member each, of fixed weight w0) are single particles: the ones alive at b were alive at a with the
// same weight, so Cov(U_a, U_b) = (Q_b - U_a U_b) / N with Q_b = sum of w0^2 over those alive at b, / N
// (the weighted runs' formula, exact for them). The split share S carries its variance at a (the lines'
// spread less the unsplit lines') forward by mixing, Cov(S_a, S_b) = Var(S_a) min(S_b / S_a, P_b / P_a). On the
// diagonal this is the lines' (R - 1) / N. The independent-increments model of the kappa fits (G) gives a tail slope no
// error at all where G stops growing -- the same few lines carry P there, and the spread of ln P no longer grows --
// which is where the tail lives.
double split_tail_cov(const SurvivalCurve& c, std::size_t a, std::size_t b) {
  if (a > b) std::swap(a, b);
  const double n = static_cast<double>(c.particles);
  const auto unsplit_q = [&](std::size_t j) {
    double q = 0;
    for (const SurvivalCurve::UnsplitGroup& g : c.unsplit)
      if (j < g.var.size()) q += g.var[j];
    return q * n;
  };
  const double pa = c.P_w[a], pb = c.P_w[b];
  if (!(pa > 0) || !(pb > 0)) return 0;
  const double ua = a < c.unsplit_P.size() ? c.unsplit_P[a] : 0.0, ub = b < c.unsplit_P.size() ? c.unsplit_P[b] : 0.0;
  const double qa = unsplit_q(a), qb = unsplit_q(b);
  const double var_u_a = (qa - ua * ua) / n;
  const double var_p_a = pa * pa * std::max(0.0, c.R[a] - 1) / n;
  const double var_s_a = std::max(0.0, var_p_a - var_u_a);
  const double sa = pa - ua, sb = pb - ub;
  // the part of S_b that descends from S_a's lines decays like P (mixing), and is no more than S_b: lines
  // that split after a bring their weight from U into S (S_b > S_a), and where the unsplit lines carry
  // nearly all of P, S = P - U is rounding noise (at liouville(2), S_a = 1e-20 with S_b = 3e-9 gave C an
  // error of 10 for a value of 0.05)
  const double cov_s = sa > 0 && sb > 0 ? var_s_a * std::min(sb / sa, pb / pa) : 0.0;
  const double cov_u = (qb - ua * ub) / n;
  return (cov_s + cov_u) / (pa * pb);
}

// Var(sum_i u_i ln P(t_i)) over grid points in the tail: split runs that hold unsplit lines by the full
// double sum over split_tail_cov, every other curve by greenwood_variance.
double tail_log_variance(const SurvivalCurve& c, const std::vector<std::size_t>& idx, const std::vector<double>& u) {
  if (!(c.lines && !c.unsplit.empty())) return greenwood_variance(c, idx, u);
  double var = 0;
  for (std::size_t i = 0; i < idx.size(); ++i) {
    var += u[i] * u[i] * split_tail_cov(c, idx[i], idx[i]);
    for (std::size_t j = i + 1; j < idx.size(); ++j) var += 2 * u[i] * u[j] * split_tail_cov(c, idx[i], idx[j]);
  }
  return std::max(var, 0.0);
}

// Grid indices of [from, to] spaced by a factor 10^(1/50) in t (50 per decade) among those keep(i) accepts,
// with their ln t.
template <class Keep>
void log_spaced_points(const SurvivalCurve& c, std::size_t from, std::size_t to, Keep keep,
                       std::vector<std::size_t>& idx, std::vector<double>& x) {
  double next = c.t[from];
  for (std::size_t i = from; i <= to; ++i) {
    if (c.t[i] + 1e-12 < next || !keep(i)) continue;
    idx.push_back(i);
    x.push_back(std::log(c.t[i]));
    next = c.t[i] * std::pow(10.0, 1.0 / 50);
  }
}

// The grid points of [from, to] with survivors: their indices and times (kappa's fit window).
void window_points(const SurvivalCurve& c, double from, double to, std::vector<std::size_t>& idx,
                   std::vector<double>& x) {
  for (std::size_t i = 0; i < c.t.size(); ++i)
    if (c.t[i] >= from && c.t[i] <= to && c.survivors[i] > 0) {
      idx.push_back(i);
      x.push_back(c.t[i]);
    }
}

// Least-squares weights over the abscissae x: slope = sum w_i y_i, intercept = sum v_i y_i for any y;
// xm and sxx their mean and spread. False when the x do not spread.
bool ls_weights(const std::vector<double>& x, std::vector<double>& w, std::vector<double>& v, double& xm, double& sxx) {
  const std::size_t n = x.size();
  xm = 0;
  for (double xi : x) xm += xi;
  xm /= static_cast<double>(n);
  sxx = 0;
  for (double xi : x) sxx += (xi - xm) * (xi - xm);
  if (!(sxx > 0)) return false;
  w.resize(n);
  v.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    w[i] = (x[i] - xm) / sxx;
    v[i] = 1.0 / static_cast<double>(n) - xm * w[i];
  }
  return true;
}

// Least squares of y = ln P against x over the chosen grid points, errors from greenwood_variance.
LinearFit fit_line(const SurvivalCurve& c, const std::vector<std::size_t>& idx, const std::vector<double>& x) {
  LinearFit f;
  const std::size_t n = idx.size();
  if (n < 3) return f;
  std::vector<double> w, v;
  double xm = 0, sxx = 0;
  if (!ls_weights(x, w, v, xm, sxx)) return f;
  double ym = 0;
  std::vector<double> y(n);
  for (std::size_t i = 0; i < n; ++i) {
    y[i] = std::log(c.P(idx[i]));
    ym += y[i];
  }
  ym /= static_cast<double>(n);
  double sxy = 0;
  for (std::size_t i = 0; i < n; ++i) sxy += (x[i] - xm) * (y[i] - ym);
  f.slope = sxy / sxx;
  f.intercept = ym - f.slope * xm;
  std::vector<double> both(n);
  for (std::size_t i = 0; i < n; ++i) both[i] = v[i] + w[i];
  f.var_slope = greenwood_variance(c, idx, w);
  f.var_intercept = greenwood_variance(c, idx, v);
  f.cov = 0.5 * (greenwood_variance(c, idx, both) - f.var_slope - f.var_intercept);
  f.ok = true;
  return f;
}

double log_slope_at(const SurvivalCurve& c, std::size_t i) {
  // d ln P / dt from a symmetric difference over about 10% of t.
  const double t = c.t[i];
  std::size_t a = i, b = i;
  while (a > 0 && c.t[a] > 0.95 * t) --a;
  while (b + 1 < c.t.size() && c.t[b] < 1.05 * t && c.survivors[b + 1] > 0) ++b;
  if (b == a || c.survivors[a] == 0 || c.survivors[b] == 0) return 0;
  return (std::log(c.P(b)) - std::log(c.P(a))) / (c.t[b] - c.t[a]);
}

/// P's standard error at the alpha crossing. Weighted runs: the sample's own error can miss what it
/// has not sampled -- the exponential part, carried only by the mixture's uniform component (weight
/// up to max_weight), whose survivors near the crossing are a handful or none -- so it is at least
/// that part's Poisson error, sqrt(max_weight * fit / N), with the fitted exponential as its size.
/// Split runs sample the exponential part as well (the lines' spread is its error): no floor.
double alpha_p_err(const SurvivalCurve& c, std::size_t i, double fit) {
  if (!c.weighted || c.lines) return c.P_err(i);
  return std::max(c.P_err(i), std::sqrt(c.max_weight * fit / static_cast<double>(c.particles)));
}

/// Cov(ln P(t_i), the fitted ln P at time t): the fit is a linear combination sum_j (v_j + t w_j) ln P(t_j)
/// of the window's grid points (least squares weights), each correlated with ln P(t_i) through the
/// curve's covariance (for a cumulative curve the shared early increments make it positive).
double cov_with_fit(const SurvivalCurve& c, const KappaFit& k, std::size_t i, double t) {
  std::vector<std::size_t> idx;
  std::vector<double> x, w, v;
  window_points(c, k.from, k.to, idx, x);
  double xm = 0, sxx = 0;
  if (idx.size() < 3 || !ls_weights(x, w, v, xm, sxx)) return 0;
  double cov = 0;
  for (std::size_t j = 0; j < idx.size(); ++j) cov += (v[j] + t * w[j]) * c.log_cov(i, idx[j]);
  return cov;
}

}  // namespace

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
      // The crossing between the grid points: ln P and the excess linear in t between the last point
      // below the factor and this one (a grid point is not the crossing; on a coarse grid P at the
      // first point above can lie well past it).
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
      // Errors through the crossing: at t* ln P = ln factor + ln A - kappa t*. Moving ln P by d moves t*
      // by -d / (kappa + s) (s = d ln P / dt) and ln alpha by d kappa / (kappa + s): P's relative error
      // times the crossing-shift factor. Moving the extrapolated line by e moves ln alpha by s e /
      // (kappa + s). d and e are correlated (ln P at t* shares the early increments the fit is made
      // of): Var ln alpha = (kappa^2 Var d + s^2 Var e + 2 kappa s Cov(d, e)) / (kappa + s)^2.
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
      return a;
    }
    prev = i;
    prev_excess = excess;
  }
  if (gap) last = prev;
  a.resolved_until = c.t[last];
  // No crossing while P is resolved. The true P never grows (an estimate may: a split run's roulette
  // raises it at split times), so a crossing at t* > t gives alpha = P(t*) <= P(t) <= P's upper limit:
  // every grid time where the data exclude P >= factor x fit (P's upper limit below it) bounds alpha by
  // that upper limit. Go on past the resolved range (the upper limits only widen there) until a time
  // is not excluded. The upper limit is P + 3 standard errors (the line's included), and at least
  // P + 6 max_weight / N: zero survivors among N draws exclude a probability above 6 / N at 99.75%
  // (Poisson), and a survivor nobody drew could carry weight up to max_weight.
  // Split runs: the bound stays within the resolved range, where the lines' own spread is P's error
  // (past it, a line nobody followed could carry any weight the splits left it).
  const double zero_events = c.lines ? 0.0 : 6 * c.max_weight / static_cast<double>(c.particles);
  // The last resolved time bounds alpha too (no crossing before it): by P's upper limit there, not P
  // itself (a bound of P alone lay below the pooled alpha in 40 of 110 runs at 82/83).
  const double fit_last = std::exp(k.log_amplitude - k.value * c.t[last]);
  double best = c.P(last) + sigma * alpha_p_err(c, last, fit_last);
  for (std::size_t i = 0; i < c.t.size(); ++i) {
    if (c.lines && i > last) break;
    if (c.t[i] < k.from) continue;
    const double fit = std::exp(k.log_amplitude - k.value * c.t[i]);
    const double se = std::hypot(alpha_p_err(c, i, fit), factor * fit * k.log_se_at(c.t[i]));
    const double ub = c.P(i) + std::max(sigma * se, zero_events);
    if (!(ub < factor * fit)) break;
    best = std::min(best, ub);
    a.bound_until = c.t[i];
  }
  a.upper_bound = best;
  a.note =
      gap ? "P crosses factor x the fit after resolved_until, where P is not resolved (too few effective survivors): "
            "alpha is bounded from above by P's upper limit until then, not measured"
          : "no significant crossing: until bound_until, P's upper limit (P + 3 errors, at least 6 max_weight / N) "
            "stays below factor x the fit, and the smallest of them bounds alpha from above";
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
  if (!c.weighted || c.lines) return;
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
  // The stable stretch: local exponents over successive factor-1.5 segments [t_k, 1.5 t_k] must agree
  // (within 30% or within 3 standard errors); the first disagreement ends it (a kink, a cut-off).
  {
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
        if (diff > 0.3 * std::max(std::abs(z), std::abs(z_prev)) && diff > 3 * std::sqrt(var + se_prev * se_prev))
          break;
      }
      first = false;
      z_prev = z;
      se_prev = std::sqrt(var);
      stable_end = b;
      seg = b;
    }
    if (stable_end > start) end = stable_end;
    if (c.t[end] < 2 * c.t[start]) {
      f.note = "the local exponent is stable over less than a factor 2 in time after the crossing";
      f.from = c.t[start];
      f.to = c.t[end];
      return f;
    }
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

std::optional<double> two_part_crossing(double C, double log_A, double kappa, double factor) {
  const auto g = [&](double t) { return std::log(C) - std::log(t) - std::log(factor - 1) - log_A + kappa * t; };
  double lo = 1 / kappa, hi = 2 / kappa;
  if (!(g(lo) < 0)) return std::nullopt;
  while (g(hi) < 0) hi *= 2;
  for (int i = 0; i < 200 && hi - lo > 1e-12 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (g(mid) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

AlphaFromAmplitude alpha_from_amplitude(const KappaFit& k, const TailAmplitude& amp, double factor) {
  AlphaFromAmplitude out;
  if (!k.ok || !amp.value || !(factor > 1) || !(k.value > 0)) {
    out.note = !amp.value ? "no tail amplitude C" : "no kappa fit";
    return out;
  }
  const auto alpha_at = [&](double C, double log_A, double kappa) -> std::optional<std::pair<double, double>> {
    const auto t = two_part_crossing(C, log_A, kappa, factor);
    if (!t) return std::nullopt;
    return std::make_pair(factor / (factor - 1) * C / *t, *t);
  };
  const auto base = alpha_at(*amp.value, k.log_amplitude, k.value);
  if (!base) {
    out.note = "C / t exceeds (factor - 1) x the fit already at t = 1 / kappa: no crossing of the two-part law";
    return out;
  }
  out.value = base->first;
  out.crossing_time = base->second;
  // first-order propagation: C's error (stat. and drift), and (ln A, -kappa) with the fit's covariance
  const double sC = std::hypot(amp.std_error, amp.drift);
  const auto partial = [&](double dC, double da, double dk) {
    const auto up = alpha_at(*amp.value + dC, k.log_amplitude + da, k.value + dk);
    const auto dn = alpha_at(*amp.value - dC, k.log_amplitude - da, k.value - dk);
    return up && dn ? (up->first - dn->first) / 2 : 0.0;
  };
  const double hC = 1e-4 * *amp.value, ha = 1e-4, hk = 1e-4 * k.value;
  const double jC = partial(hC, 0, 0) / hC, ja = partial(0, ha, 0) / ha, jb = -partial(0, 0, hk) / hk;  // b = -kappa
  const double var = jC * jC * sC * sC + ja * ja * k.var_a + jb * jb * k.var_b + 2 * ja * jb * k.cov_ab;
  out.std_error = std::sqrt(std::max(0.0, var));
  out.note = "P = A exp(-kappa t) + C / t crosses factor x the fit at t = " + std::to_string(out.crossing_time);
  return out;
}

TailAmplitude fit_amplitude(const SurvivalCurve& c, const KappaFit& k, std::uint64_t min_survivors) {
  TailAmplitude a;
  if (!k.ok) {
    a.note = "no kappa fit: the exponential head cannot be told from the tail";
    return a;
  }
  const auto resolved = [&](std::size_t i) {
    return c.P(i) > 0 && c.effective(i) >= static_cast<double>(min_survivors);
  };
  std::size_t start = c.t.size(), end = 0;
  for (std::size_t i = 0; i < c.t.size(); ++i) {
    if (!resolved(i)) continue;
    end = i;
    if (start == c.t.size() && c.t[i] > k.to &&
        std::log(c.P(i)) - (k.log_amplitude - k.value * c.t[i]) > std::log(100.0))
      start = i;
  }
  if (start == c.t.size()) {
    a.note = "P never exceeds 100 x the extrapolated exponential fit where it is resolved: no tail to measure";
    return a;
  }
  a.from = c.t[start];
  a.to = c.t[end];
  a.height = c.t[start] * c.P(start);
  a.height_error = c.t[start] * c.P_err(start);
  if (c.t[end] < 2 * c.t[start]) {
    a.note = "resolved over less than a factor 2 in t past where the exponential head falls under 1% of P";
    return a;
  }
  std::vector<std::size_t> idx;
  std::vector<double> x;
  log_spaced_points(c, start, end, resolved, idx, x);
  if (idx.back() != end) {  // the range's last resolved time belongs to it
    idx.push_back(end);
    x.push_back(std::log(c.t[end]));
  }
  // ln(t P) = ln t + ln P: its slope against ln t is 1 + the slope of ln P, with ln P's covariance
  const auto slope_over = [&](std::size_t n, double& b, double& se) {
    const std::vector<std::size_t> i(idx.begin(), idx.begin() + static_cast<std::ptrdiff_t>(n));
    const std::vector<double> xi(x.begin(), x.begin() + static_cast<std::ptrdiff_t>(n));
    std::vector<double> w, v;
    double xm = 0, sxx = 0;
    if (n < 3 || !ls_weights(xi, w, v, xm, sxx)) return false;
    b = 1;
    for (std::size_t j = 0; j < n; ++j) b += w[j] * std::log(c.P(i[j]));
    se = std::sqrt(tail_log_variance(c, i, w));
    return true;
  };
  // the longest flat stretch from the start: the last point at least a factor 2 past it that passes
  std::size_t n = idx.size();
  double b = 0, se = 0;
  bool flat = false;
  for (; n >= 3 && c.t[idx[n - 1]] >= 2 * c.t[start]; --n) {
    if (!slope_over(n, b, se)) break;
    if (n == idx.size()) a.slope = b, a.slope_error = se;  // the whole resolved range, for the note
    if (std::abs(b) <= kFlatSlope || std::abs(b) <= 3 * se) {
      flat = true;
      break;
    }
  }
  if (!flat) {
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "t P(t) is not flat over any stretch of a factor 2 in t from t = %g: d ln(t P) / d ln t = %.3g +- "
                  "%.2g over the resolved range, i.e. P ~ t^-%.3g, not C / t",
                  c.t[start], a.slope, a.slope_error, 1 - a.slope);
    a.note = buf;
    return a;
  }
  idx.resize(n);
  a.to = c.t[idx.back()];
  a.points = n;
  a.slope = b;
  a.slope_error = se;
  std::vector<double> u(n);
  double sum = 0, early = 0, late = 0;
  std::size_t n_early = 0;
  const double mid = 0.5 * (std::log(a.from) + std::log(a.to));
  for (std::size_t j = 0; j < n; ++j) {
    const double tp = c.t[idx[j]] * c.P(idx[j]);
    sum += tp;
    u[j] = tp / static_cast<double>(n);  // d C / d ln P(t_j)
    if (std::log(c.t[idx[j]]) <= mid) {
      early += tp;
      ++n_early;
    } else {
      late += tp;
    }
  }
  a.value = sum / static_cast<double>(n);
  a.std_error = std::sqrt(tail_log_variance(c, idx, u));
  if (n_early > 0 && n_early < n)
    a.drift = 0.5 * std::abs(late / static_cast<double>(n - n_early) - early / static_cast<double>(n_early));
  a.note = a.to < c.t[end] ? "mean of t P(t) over the flat stretch; past it t P(t) is no longer flat (the tail ends "
                             "or bends)"
                           : "mean of t P(t) over the resolved range past the exponential head";
  return a;
}

}  // namespace rotleak
