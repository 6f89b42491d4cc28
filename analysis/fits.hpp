// Fits to a survival curve: kappa (exponential rate), alpha (algebraic-tail weight, docs/model.md "Observables"), z
// (tail exponent). Error model: the survivor counts S(t) of N independent particles; ln P(t) then has Greenwood's
// covariance Cov(ln P(a), ln P(b)) = (1 - P(a)) / (N P(a)) for a <= b, which every standard error below is propagated
// through (least squares on a cumulative curve is correlated, so the residual scatter would understate the error).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sim/survival.hpp"

namespace rotleak {

struct KappaFit {
  bool ok = false;
  double value = 0, std_error = 0;  ///< kappa and its standard error
  double log_amplitude = 0;         ///< ln A in P ~ A exp(-kappa t)
  double from = 0, to = 0;          ///< window actually used
  std::size_t points = 0;
  std::string method =
      "least squares of ln P(t) on the grid points in the window; standard error from the binomial (Greenwood) "
      "covariance of ln P";
  /// Standard error of the fitted ln P at time t (extrapolation uncertainty).
  double log_se_at(double t) const;
  double var_a = 0, var_b = 0, cov_ab = 0;  ///< covariance of (ln A, -kappa)
  /// Window systematic: half the spread of kappa over the family of windows (window_family), beside
  /// the statistical std_error (ln P is nowhere exactly straight, so kappa depends on the window).
  std::optional<double> window_systematic;
  struct FamilyMember {
    double from, to, value;
  };
  std::vector<FamilyMember> window_family;
};

/// kappa's window systematic for the window [from, to]: kappa fitted on the six windows with start
/// from or from + (to - from)/6 and end 2to/3, to or 4to/3 (clamped to t_max); the systematic is half
/// of (largest - smallest) over those that fit. Sets k.window_systematic and k.window_family.
void add_window_systematic(KappaFit& k, const SurvivalCurve& c, double t_max);

struct AlphaResult {
  /// P at the first crossing of 10x the exponential fit that lies more than 3 standard errors (P's
  /// and the extrapolated line's) above it, while at least min_survivors effective survivors remain
  std::optional<double> value;
  double std_error = 0;                   ///< binomial and fit-extrapolation errors combined
  double crossing_time = 0;               ///< t of that crossing (when resolved)
  std::optional<double> upper_bound;      ///< when no crossing before statistics run out
  double resolved_until = 0;              ///< last t with at least min_survivors survivors
  double bound_until = 0;                 ///< no crossing: last t where P's upper limit lies below factor x the fit
  bool crossing_not_significant = false;  ///< P crossed factor x the fit at resolved_until, within 3 errors of it
  double factor = 10;
  double sigma = 3;  ///< standard errors P must lie above the fit for the crossing to count
  std::uint64_t min_survivors = 100;
  std::string note;
};

struct TailFit {
  std::optional<double> z;  ///< P ~ t^-z
  double std_error = 0;
  double from = 0, to = 0;
  std::size_t points = 0;
  std::string method =
      "least squares of ln P against ln t on log-spaced grid points from the alpha crossing to the end of the "
      "stable stretch: local exponents over successive factor-1.5 segments of t agree (they differ by less than 30% "
      "or by less than 3 standard errors) and at least 100 effective survivors remain";
  std::string note;  ///< why z is not defined, when it is not
};

KappaFit fit_kappa(const SurvivalCurve& c, double from, double to);
AlphaResult find_alpha(const SurvivalCurve& c, const KappaFit& k, double factor = 10, double sigma = 3,
                       std::uint64_t min_survivors = 100);
TailFit fit_tail(const SurvivalCurve& c, const AlphaResult& a);

}  // namespace rotleak
