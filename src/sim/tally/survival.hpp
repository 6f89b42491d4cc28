// The survival curve of a run: survivors on the time grid t_k = k dt, built in one place from the
// engine's escape histogram (exact integer counts), for the fits, the files and the checks.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "sim/model/scene.hpp"
#include "sim/tally/tally.hpp"

namespace rotleak {

struct SurvivalCurve {
  std::vector<double> t;                 ///< grid times, increasing
  std::vector<std::uint64_t> survivors;  ///< survivors at each time (raw count, weighted runs too)
  std::uint64_t particles = 0;
  /// Weighted runs (importance sampling, not split): W[i] = (1/N) sum of the survivors' weights and Q[i] = (1/N)
  /// sum of their squared weights, each rounded once from the exact tallies; P_w[i] = W[i] / W[0], the survivors'
  /// share of the sample's weight (self-normalised: P(0) = 1 exactly; docs/model.md "Importance sampling"). A
  /// curve built by hand without W takes P_w as W.
  bool weighted = false;
  std::vector<double> P_w, Q, W;
  double max_weight = 1;  ///< the largest weight a particle can have (1 / eps for the mupo mixture)
  /// Split runs (weighted too): the N lines are the independent units. P_w[i] = (1/N) sum_i Y_i(t), Y_i
  /// a line's living weight; R[i] = N sum Y^2 / (sum Y)^2 (1 for equal lines; its second moment
  /// relative to P^2, which stays in range where Q itself would underflow); lines_alive[i]; Q unused.
  bool lines = false;
  std::vector<double> R;
  std::vector<std::uint64_t> lines_alive;

  /// The survivors' weight sum over N at t_i (W, or P_w for a curve built without it).
  double weight_sum(std::size_t i) const { return W.empty() ? P_w[i] : W[i]; }
  double P(std::size_t i) const {
    return weighted ? P_w[i] : static_cast<double>(survivors[i]) / static_cast<double>(particles);
  }
  /// Standard error of P(t_i): binomial, or for weighted runs the ratio's (delta method, m = W[0], B = Q[0]):
  /// Var = (Q (1 - 2P) + P^2 B) / (N m^2), 0 at t = 0 and binomial for unit weights.
  double P_err(std::size_t i) const;
  /// Effective number of survivors: the count, or (sum w)^2 / sum w^2 = N W^2 / Q for weighted runs.
  double effective(std::size_t i) const;
  /// Cov(ln P(t_i), ln P(t_j)): Greenwood's (1 - P_a) / (N P_a) for a = min(i, j); weighted runs
  /// (Q_b - P_b Q_a - P_a Q_b + P_a P_b B) / (N m^2 P_a P_b) with b = max(i, j) (Greenwood's for unit weights);
  /// split runs Var(ln P(t_a)) = (R_a - 1) / N, made non-decreasing in a (see G).
  double log_cov(std::size_t i, std::size_t j) const;
  /// Split runs: G[a] = max over k <= a of (R_k - 1) / N. The model: given the past at t_a, a line's
  /// weight decays on average like P itself (E[Y(b) | t_a] = Y(a) P_b / P_a, mixing), so ln P has
  /// independent increments with the variance the lines show; the running maximum keeps that
  /// variance from falling where the spread of a few lines happens to dip.
  std::vector<double> G;
  /// Split runs: the unsplit lines (LinesEstimator::unsplit_start and unsplit_left) on the grid: in all (their
  /// count and their weight sum over N, their share of P) and in groups for the allowance for lines not
  /// drawn (add_unsplit_allowance): each weight class whose decay can be measured after the first split
  /// time (at least 2 kUnsplitReliable lines there), and the other classes pooled. A group holds its
  /// count, its share of P and its squared weights' sum over N^2 (its share of P's variance).
  std::vector<std::uint64_t> unsplit_lines;
  std::vector<double> unsplit_P;  ///< rounded once from the exact sum of the classes' weights
  struct UnsplitGroup {
    std::vector<int> classes;  ///< unsplit_class values pooled here
    std::vector<std::uint64_t> lines;
    std::vector<double> P, var;
    bool allowance = false;
    double reliable_until = 0;  ///< t_r: the last time with kUnsplitReliable of the group's lines alive
    double rate_from = 0;       ///< t_a: gamma counts every leaving from t_a on (maximum likelihood)
    double decay_rate = 0;      ///< gamma
    double typical_weight = 0;  ///< N sum w^2 / sum w of the group's lines at t_r
  };
  std::vector<UnsplitGroup> unsplit;
  /// Split runs: the unsplit lines class by class (one class each, in class order), what unsplit is grouped
  /// from; and R before the allowance. With P_w, lines_alive, unsplit_lines and unsplit_P they are the whole
  /// split curve: finish_lines_curve rebuilds G, the groups and the allowance from them (lines.csv keeps them,
  /// so a refit gives a run's own errors bit for bit).
  std::vector<UnsplitGroup> unsplit_classes;
  std::vector<double> R_lines;
  std::size_t first_split = 0;  ///< grid index of the first split time (before it every line is unsplit)
  /// Splitting over initial conditions (sim/engine/ic_splitting.hpp; weighted too): P_w[i] the replicates' mean of
  /// P(T > t_i | stratum), E[i] its standard error from their spread, survivors[i] the states alive at t_i over all
  /// replicates (a raw count), particles the starts of one replicate; Var(ln P) by G as for split runs (the running
  /// maximum of (E / P)^2).
  bool replicated = false;
  std::vector<double> E;
  std::vector<int> replicates_nonzero;  ///< replicates whose P(t_i) is not 0
  int replicates = 0;

  /// The first grid time at which the allowances exceed kAllowanceShare times the lines' own variance
  /// (none: never): from there on a third of P's variance or more is the model's, and P is not claimed
  /// resolved.
  std::optional<double> allowance_unresolved_from;
};

/// Split runs: whether P at grid index i is only bounded, not measured: at or past allowance_unresolved_from,
/// where the allowance for lines not drawn holds a third of P's variance or more. Such a P is printed and
/// reported as a bound, P + 3 errors (docs/model.md, "Unsplit lines not drawn").
inline bool p_bounded(const SurvivalCurve& c, std::size_t i) {
  return c.lines && c.allowance_unresolved_from && c.t[i] >= *c.allowance_unresolved_from;
}

/// Unsplit lines alive below which their own spread no longer measures their share of P's error.
inline constexpr std::uint64_t kUnsplitReliable = 10;
/// P is resolved while the allowances stay below this share of the lines' own variance: the error is
/// then at least two thirds measured, at most sqrt(1.5) = 1.22 times the lines' spread where the model
/// stands for lines rarer than a seed calibration can draw (at a share of 1, a calibration's sd / err
/// sat at 1 / sqrt 2 = 0.71, the edge of its band, wherever those lines did not turn up).
inline constexpr double kAllowanceShare = 0.5;

/// Adds to a split curve's R the allowance for unsplit lines the run has not drawn (docs/model.md).
void add_unsplit_allowance(SurvivalCurve& c);
/// Split runs: G from R, the running maximum over the grid of (R - 1) / N (SurvivalCurve::G; where P = 0, R = 0
/// leaves it as it was): a run's G, a pooled curve's, one read back with its lines.csv. (A split curve read from
/// survival.csv alone builds its G from P_err row by row, read_survival_csv.)
void running_lines_variance(SurvivalCurve& c);
/// Runs of splitting over starts: G from P_w and E, the running maximum over the grid of (E / P)^2 (P = 0 leaves it as
/// it was): a run's curve, a pooled one's, one read back from survival.csv.
void running_replicate_variance(SurvivalCurve& c);
/// A split curve from its parts (SurvivalCurve::unsplit_classes: c.t, P_w, R holding R before the allowance,
/// lines_alive, unsplit_lines, unsplit_P, unsplit_classes set): R_lines, G, the groups (each class whose decay
/// can be measured after the first split time on its own, the others pooled in class order) and the
/// allowance. The run's curve and a curve read back from lines.csv go through it alike.
void finish_lines_curve(const Scene& scene, SurvivalCurve& c);

/// Grid times t_k = k dt for k = 0..bins, the last one clamped to t_max.
std::vector<double> survival_times(const Scene& scene);
/// Survivors at t_k (k = 0..bins, the last at t_max) from the escape histogram.
std::vector<std::uint64_t> survivors_on_grid(const Scene& scene, const Tally& tally);
/// Both together.
SurvivalCurve survival_curve(const Scene& scene, const Tally& tally);

/// A weighted (not split) curve's P_w from its W: P_w[i] = W[i] / W[0] (a run's, a pooled one's, one read back).
void self_normalise(SurvivalCurve& c);

}  // namespace rotleak
