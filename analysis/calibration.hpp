// Calibration of error bars against independent seeds: K runs of one scene that differ only in
// ensemble.seed are K independent draws of every statistic, so the spread of a statistic across them
// is its true standard error, whatever the run's own error model assumes. A statistic's reported
// errors are honest where the spread matches them (sd / median error near 1) and where each run's
// value lies within 2 of its errors of the others' mean about 95% of the time (docs/model.md,
// "Calibration"). Nothing here runs anything: run/calibrate.hpp runs the seeds and writes the files.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "sim/tally/survival.hpp"

namespace rotleak {

/// One statistic's values and reported errors over the seeds (seeds without a value left out).
struct SeedSpread {
  std::size_t n = 0;           ///< seeds with a value
  double pooled = 0;           ///< mean of the values
  double pooled_err = 0;       ///< sd / sqrt(n): the pooled mean's error from the spread itself
  double sd = 0;               ///< sample standard deviation of the values (n - 1)
  double median_err = 0;       ///< median of the reported errors
  double sd_over_err = 0;      ///< sd / median_err (1 for honest errors); 0 when median_err is 0
  double chi2_dof = 0;         ///< sum ((x_k - mean) / e_k)^2 / (n - 1) over seeds with e_k > 0
  double coverage1 = 0;        ///< fraction of seeds with |x_k - mean of the others| <= e_k
  double coverage2 = 0;        ///< ... <= 2 e_k
  double max_over_median = 0;  ///< largest value over the median value (a rare heavy seed shows here)
};

/// What honest errors look like over enough seeds: sd / median error within the band, and at least the
/// floor's share of the seeds within 2 errors of the others' mean (95% for Gaussian errors; with K = 100
/// seeds its sampling error is about 2%, and sd / err's about 7%). These are the precision a user is
/// promised; with few seeds the data cannot resolve it, and honest_band widens them to what K seeds can.
inline constexpr double kHonestBand[2] = {0.7, 1.5};
inline constexpr double kHonestCoverage2 = 0.9;
/// The probability with which each of the two tests (sd / err, coverage at 2 errors) calls honest
/// Gaussian errors dishonest when the fixed band and floor are not the binding ones (small K).
inline constexpr double kCalibrationFalseAlarm = 0.01;

/// The acceptance region for K seeds (docs/model.md, "Calibration against seeds"). sd / err: with honest
/// Gaussian errors of one size, (K - 1) (sd / err)^2 follows chi-square with K - 1 degrees of freedom; its
/// central 1 - kCalibrationFalseAlarm interval, joined with kHonestBand. Coverage at 2 errors: a seed's
/// distance to the others' mean has variance err^2 K / (K - 1), so it lies within 2 errors with
/// p2 = P(|Z| <= 2 sqrt((K - 1) / K)), and the count of such seeds is Binomial(K, p2) (the seeds' distances
/// share the mean, a correlation of order 1 / K that the test neglects; tests/test_calibration.cpp
/// measures the false-alarm rate it leaves); the floor is the smallest count whose lower tail holds at least
/// kCalibrationFalseAlarm, over K, and never above kHonestCoverage2.
/// `tests`: how many such judgements one verdict makes (a curve's grid times): each then runs at
/// kCalibrationFalseAlarm / tests (Bonferroni), so that honest errors fail any of them with probability at most
/// kCalibrationFalseAlarm per test kind, however the times are correlated.
struct HonestBand {
  double lo = 0, hi = 0;          ///< sd / err band
  double coverage2_floor = 0;     ///< the least share of seeds within 2 errors
  double coverage2_expected = 0;  ///< p2
  double false_alarm_each = 0;    ///< kCalibrationFalseAlarm / tests: each judgement's own rate
};
HonestBand honest_band(std::size_t K, std::size_t tests = 1);

/// A curve judged at many times as one verdict (docs/model.md, "Calibration against seeds"): honest_band(K,
/// judged times), so that a long curve with honest errors passes at the stated rate, where a band for one
/// time would fail it somewhere by chance (its times are many, and correlated in ways the band cannot know).
struct CurveVerdict {
  HonestBand band;
  std::size_t judged = 0;     ///< times judged
  std::size_t outside = 0;    ///< times with sd / err outside band.lo .. band.hi
  std::size_t uncovered = 0;  ///< times with coverage at 2 errors under band.coverage2_floor
  bool honest() const { return judged > 0 && outside == 0 && uncovered == 0; }
};
/// The spreads of the times judged, all over the same K seeds (K >= 2). None judged: judged = 0, honest false.
CurveVerdict curve_verdict(const std::vector<SeedSpread>& times);

/// "honest", "errors too small" (sd / err above the band or coverage under the floor, honest_band(s.n)),
/// "errors too large" (sd / err below the band), or "no errors reported" (median error 0). model_share: the
/// share of the seeds whose value was taken where a split run's allowance for unsplit lines not drawn holds
/// more than a third of P's variance (past summary.json's unresolved_from). Where that is most of them and
/// sd / err lies below the band, the verdict says the seeds cannot test the error: its main term stands for
/// lines rarer than the seeds drew (docs/model.md, "Calibration against seeds"), which only a spread over
/// enough runs to draw them could show.
std::string spread_verdict(const SeedSpread& s, double model_share = 0);

/// The spread of x (values) against e (their reported errors), both one entry per seed. Needs n >= 2.
SeedSpread seed_spread(const std::vector<double>& x, const std::vector<double>& e);

/// The pooled curve of K runs of one scene with different seeds (same grid): the run of all their
/// particles together. P is the mean of the seeds' P; its second moment is pooled the same way (lines:
/// R = K sum R_k P_k^2 / (sum P_k)^2; weighted: Q the mean of Q_k; counts summed), so the pooled curve's
/// fits are those of one run of K N particles. Throws std::invalid_argument when the grids differ.
/// Split runs that keep their structure (unsplit_classes and R_lines, as every run and every curve read with
/// its lines.csv does) pool it too, given `scene` (its split schedule and grid): each class's lines summed,
/// its P the mean, its var the mean over K; R before the allowance pooled as R is; then the groups and the
/// allowance of one run of K N lines (finish_lines_curve). One curve pools to itself, bit for bit.
SurvivalCurve pool_curves(const std::vector<SurvivalCurve>& curves, const Scene* scene = nullptr);

/// Whether P at grid index i is resolved in every seed: P > 0 and at least min_effective effective
/// survivors (lines, for split runs) in the median seed.
bool resolved_in_seeds(const std::vector<SurvivalCurve>& curves, std::size_t i, double min_effective);

}  // namespace rotleak
