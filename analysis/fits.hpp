// Fits to a survival curve: kappa (exponential rate), alpha (algebraic-tail weight, docs/model.md "Observables"), z
// (tail exponent). Error model: the survivor counts S(t) of N independent particles; ln P(t) then has Greenwood's
// covariance Cov(ln P(a), ln P(b)) = (1 - P(a)) / (N P(a)) for a <= b, which every standard error below is propagated
// through (least squares on a cumulative curve is correlated, so the residual scatter would understate the error).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sim/tally/survival.hpp"

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
  /// Statistical error: P's error at the crossing times the crossing-shift factor kappa / (kappa + s)
  /// (s = d ln P / dt there: a P that reads high crosses earlier, where P is larger) and the fit's
  /// extrapolation error times |s| / (kappa + s), combined (docs/model.md "Observables").
  double std_error = 0;
  /// Window systematic: half the spread of alpha over kappa's window family (alpha found again with
  /// each member's fit), beside std_error; empty when fewer than two members resolve alpha.
  std::optional<double> systematic;
  double shift_factor = 1;                ///< kappa / (kappa + s) at the crossing
  double crossing_time = 0;               ///< t of that crossing, interpolated between grid points
  std::optional<double> upper_bound;      ///< when no crossing before statistics run out
  double resolved_until = 0;              ///< last t with at least min_survivors survivors
  double bound_until = 0;                 ///< no crossing: last t where P's upper limit lies below factor x the fit
  bool crossing_not_significant = false;  ///< P crossed factor x the fit at resolved_until, within 3 errors of it
  double factor = 10;
  double sigma = 3;  ///< standard errors P must lie above the fit for the crossing to count
  std::uint64_t min_survivors = 100;
  /// Weighted runs without splitting: the smallest alpha their uniform share can carry, factor x
  /// min_survivors x max_weight / N (the exponential part at the crossing, alpha / factor, is sampled
  /// by that share alone, eps N particles of weight max_weight); a value or bound below it is unreliable
  /// (typical runs read low: the few heavy uniform draws it needs are missing), and the note says so.
  std::optional<double> uniform_reach;
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

/// The tail amplitude C of P ~ C / t (docs/model.md "Observables"): the mean of t P(t) over log-spaced grid
/// points (50 per decade) of the longest stretch [from, to] over which t P(t) is flat, from the first
/// resolved time past kappa's window at which P exceeds the extrapolated exponential fit 100 times (its
/// head then holds under 1% of P) to the last resolved one (at least min_survivors effective survivors).
/// Flat: the least-squares slope b of ln(t P) against ln t is within kFlatSlope of 0 or within 3 of its
/// standard errors, over at least a factor 2 in t. Null, with the reason in the note, where no such
/// stretch exists (no tail, not resolved, or not ~1/t: then slope holds b over the whole resolved range).
struct TailAmplitude {
  std::optional<double> value;
  double std_error = 0;  ///< from P's covariance over the points (a cumulative curve's points are correlated)
  /// Drift: half the difference of t P's means over the stretch's early and late halves (in ln t): what
  /// the choice of stretch can move C by where t P is not exactly flat. Beside std_error, like alpha's
  /// window systematic.
  double drift = 0;
  double from = 0, to = 0;  ///< 0 when P never exceeds 100 x the fit where resolved
  std::size_t points = 0;
  double slope = 0, slope_error = 0;  ///< b = d ln(t P) / d ln t over [from, to] and its standard error
  /// t P(t) at `from`, where the exponential head falls under 1% of P, and its error: the tail's height
  /// where it begins, also where it is not flat (a transient tail near a rational omega declines from there).
  double height = 0, height_error = 0;
  std::string note;
};
/// |d ln(t P) / d ln t| below which a tail counts as 1/t whatever the errors (z within 10% of 1).
inline constexpr double kFlatSlope = 0.1;

/// alpha read off the two-part law P = A exp(-kappa t) + C / t (the kappa fit's A and kappa, the tail's C): the
/// crossing C / t = (factor - 1) A exp(-kappa t) beyond 1 / kappa, where P = factor x the fit, and alpha =
/// factor A exp(-kappa t) there. Smoother than the first grid point above the line (find_alpha): it uses the
/// whole tail's mean instead of one point. Its error propagates C's (stat. and drift) and the fit's
/// covariance of (ln A, kappa).
struct AlphaFromAmplitude {
  std::optional<double> value;
  double std_error = 0;
  double crossing_time = 0;
  std::string note;
};
AlphaFromAmplitude alpha_from_amplitude(const KappaFit& k, const TailAmplitude& amp, double factor = 10);
/// The crossing of C / t with (factor - 1) e^{ln A - kappa t} beyond 1 / kappa (there ln C - ln t - ln((factor - 1)
/// A) + kappa t rises), by bisection; nullopt when C / t already lies above at 1 / kappa. alpha_from_amplitude and
/// the tail model's crossing with the chaotic part (factor 2, A = 1) both solve it.
std::optional<double> two_part_crossing(double C, double log_A, double kappa, double factor);

KappaFit fit_kappa(const SurvivalCurve& c, double from, double to);
AlphaResult find_alpha(const SurvivalCurve& c, const KappaFit& k, double factor = 10, double sigma = 3,
                       std::uint64_t min_survivors = 100);
TailFit fit_tail(const SurvivalCurve& c, const AlphaResult& a);
TailAmplitude fit_amplitude(const SurvivalCurve& c, const KappaFit& k, std::uint64_t min_survivors = 100);
/// alpha's window systematic (AlphaResult::systematic): alpha found again with kappa fitted on each
/// window of k.window_family (add_window_systematic first); half of (largest - smallest) over the
/// members that resolve alpha, the main value included.
void add_alpha_systematic(AlphaResult& a, const SurvivalCurve& c, const KappaFit& k);
/// Sets a.uniform_reach for a weighted run without splitting and, when alpha (or its bound) lies below
/// it, says in the note that it is unreliable there.
void add_uniform_reach(AlphaResult& a, const SurvivalCurve& c);

}  // namespace rotleak
