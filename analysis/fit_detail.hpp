// What the fits of analysis/fits.cpp and the tail amplitude of analysis/amplitude.cpp share: the
// covariances of ln P (Greenwood's, the weighted and split runs'), weighted least squares of a line, and
// the local slope of ln P. Internal to analysis/: the interface is analysis/fits.hpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "analysis/fits.hpp"

namespace rotleak::fit_detail {

struct LinearFit {
  double slope = 0, intercept = 0;
  double var_intercept = 0, var_slope = 0, cov = 0;
  bool ok = false;
};

// Greenwood variance of sum_i u_i ln P(t_i) for increasing grid indices idx:
// Var = sum_k (g_k - g_{k-1}) (sum_{i>=k} u_i)^2 with g = (1 - P) / (N P).
inline double greenwood_variance(const SurvivalCurve& c, const std::vector<std::size_t>& idx,
                                 const std::vector<double>& u) {
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
inline double split_tail_cov(const SurvivalCurve& c, std::size_t a, std::size_t b) {
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
inline double tail_log_variance(const SurvivalCurve& c, const std::vector<std::size_t>& idx,
                                const std::vector<double>& u) {
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
inline void window_points(const SurvivalCurve& c, double from, double to, std::vector<std::size_t>& idx,
                          std::vector<double>& x) {
  for (std::size_t i = 0; i < c.t.size(); ++i)
    if (c.t[i] >= from && c.t[i] <= to && c.survivors[i] > 0) {
      idx.push_back(i);
      x.push_back(c.t[i]);
    }
}

// Least-squares weights over the abscissae x: slope = sum w_i y_i, intercept = sum v_i y_i for any y;
// xm and sxx their mean and spread. False when the x do not spread.
inline bool ls_weights(const std::vector<double>& x, std::vector<double>& w, std::vector<double>& v, double& xm,
                       double& sxx) {
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
inline LinearFit fit_line(const SurvivalCurve& c, const std::vector<std::size_t>& idx, const std::vector<double>& x) {
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

inline double log_slope_at(const SurvivalCurve& c, std::size_t i) {
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
inline double alpha_p_err(const SurvivalCurve& c, std::size_t i, double fit) {
  if (!c.weighted || c.lines) return c.P_err(i);
  return std::max(c.P_err(i), std::sqrt(c.max_weight * fit / static_cast<double>(c.particles)));
}

/// Cov(ln P(t_i), the fitted ln P at time t): the fit is a linear combination sum_j (v_j + t w_j) ln P(t_j)
/// of the window's grid points (least squares weights), each correlated with ln P(t_i) through the
/// curve's covariance (for a cumulative curve the shared early increments make it positive).
inline double cov_with_fit(const SurvivalCurve& c, const KappaFit& k, std::size_t i, double t) {
  std::vector<std::size_t> idx;
  std::vector<double> x, w, v;
  window_points(c, k.from, k.to, idx, x);
  double xm = 0, sxx = 0;
  if (idx.size() < 3 || !ls_weights(x, w, v, xm, sxx)) return 0;
  double cov = 0;
  for (std::size_t j = 0; j < idx.size(); ++j) cov += (v[j] + t * w[j]) * c.log_cov(i, idx[j]);
  return cov;
}

}  // namespace rotleak::fit_detail
