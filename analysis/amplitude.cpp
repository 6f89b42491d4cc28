// The tail amplitude C in P ~ C / t (fit_amplitude) and what follows from it: alpha read off the
// two-part law P = A exp(-kappa t) + C / t (alpha_from_amplitude, two_part_crossing). Declared in
// analysis/fits.hpp; docs/model.md, "Observables".
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <utility>

#include "analysis/fit_detail.hpp"
#include "analysis/fits.hpp"

namespace rotleak {

using namespace fit_detail;

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

namespace {

/// The tail's range: from the first resolved time past the kappa window where P stands 100 x above the
/// extrapolated fit (start; size() if none) to the last resolved time (end).
std::pair<std::size_t, std::size_t> tail_range(const SurvivalCurve& c, const KappaFit& k,
                                               const std::function<bool(std::size_t)>& resolved) {
  std::size_t start = c.t.size(), end = 0;
  for (std::size_t i = 0; i < c.t.size(); ++i) {
    if (!resolved(i)) continue;
    end = i;
    if (start == c.t.size() && c.t[i] > k.to &&
        std::log(c.P(i)) - (k.log_amplitude - k.value * c.t[i]) > std::log(100.0))
      start = i;
  }
  return {start, end};
}

/// The longest flat stretch of t P from the start: the first n points (n >= 3, the last at least a factor
/// 2 past the start) over which d ln(t P) / d ln t is within kFlatSlope of 0 or within 3 errors; 0 if none.
/// a.slope, a.slope_error: the whole range's slope (for the note) or, when flat, the stretch's.
std::size_t flat_points(const SurvivalCurve& c, const std::vector<std::size_t>& idx, const std::vector<double>& x,
                        TailAmplitude& a) {
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
  const double t_start = c.t[idx.front()];
  for (std::size_t n = idx.size(); n >= 3 && c.t[idx[n - 1]] >= 2 * t_start; --n) {
    double b = 0, se = 0;
    if (!slope_over(n, b, se)) break;
    if (n == idx.size()) a.slope = b, a.slope_error = se;  // the whole resolved range, for the note
    if (std::abs(b) <= kFlatSlope || std::abs(b) <= 3 * se) {
      a.slope = b;
      a.slope_error = se;
      return n;
    }
  }
  return 0;
}

/// C: the mean of t P over the stretch idx, its error from ln P's covariance, and its drift (half the
/// difference of the means over the stretch's early and late halves in ln t).
void mean_of_tP(const SurvivalCurve& c, const std::vector<std::size_t>& idx, TailAmplitude& a) {
  const std::size_t n = idx.size();
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
}

}  // namespace

TailAmplitude fit_amplitude(const SurvivalCurve& c, const KappaFit& k, std::uint64_t min_survivors) {
  TailAmplitude a;
  if (!k.ok) {
    a.note = "no kappa fit: the exponential head cannot be told from the tail";
    return a;
  }
  const std::function<bool(std::size_t)> resolved = [&](std::size_t i) {
    return c.P(i) > 0 && c.effective(i) >= static_cast<double>(min_survivors);
  };
  const auto [start, end] = tail_range(c, k, resolved);
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
  const std::size_t n = flat_points(c, idx, x, a);
  if (n == 0) {
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
  mean_of_tP(c, idx, a);
  a.note = a.to < c.t[end] ? "mean of t P(t) over the flat stretch; past it t P(t) is no longer flat (the tail ends "
                             "or bends)"
                           : "mean of t P(t) over the resolved range past the exponential head";
  return a;
}

}  // namespace rotleak
