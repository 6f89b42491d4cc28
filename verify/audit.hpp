// The audit of a scene: which of its trajectories, statistics and scalars can be believed, per tier.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "sim/engine/engine.hpp"
#include "sim/model/scene.hpp"
#include "verify/lyapunov.hpp"
#include "verify/shadow.hpp"

namespace rotleak {

/// Where the audit's heavy parts run: in this process (the defaults), or shared by the ranks of an
/// MPI job (the run layer's audit_shared replaces them). With a team every rank calls audit() and
/// each hook is a collective.
struct AuditWork {
  /// An ensemble: every caller gets what run_ensemble(scene, options) gives (tally and records).
  std::function<RunResult(const Scene&, const RunOptions&)> ensemble = [](const Scene& s, const RunOptions& o) {
    return run_ensemble(s, o);
  };
  /// Shadows of `ids` in their order, on the reporting rank (the others may get none); progress(done,
  /// of) counts this process's own shadows.
  std::function<std::vector<ShadowResult>(const Scene&, const std::vector<std::uint64_t>& ids, const ShadowOptions&,
                                          int threads, const std::function<void(std::size_t, std::size_t)>& progress)>
      shadows = shadow_many;
  bool reports = true;  ///< false: this rank only helps with the ensembles and shadows (an empty report)
  /// Collective: true where `ok` is true on every rank (a choice all must take alike, such as whether
  /// the vectorised ensemble runs: machines of a cluster may differ).
  std::function<bool(bool ok)> all = [](bool ok) { return ok; };
};

struct AuditOptions {
  std::size_t sample = 1000;  ///< particles shadowed, stratified by their double escape time
  std::vector<std::string> tiers{"float", "double", "long_double", "dd", "float128", "mpfr:256"};
  std::uint64_t stratify_particles = 200000;  ///< ids scanned (double) to build the strata
  std::size_t max_collisions = 1500;          ///< shadow horizon cap (long survivors)
  double tolerance = 1e-6;
  std::uint64_t stats_particles = 1000000;  ///< ensemble size of the statistics check (<= scene's)
  int threads = 0;
  bool progress = false;
  AuditWork work;
};

struct Quantiles {
  double q10 = 0, q25 = 0, median = 0, q75 = 0, q90 = 0;
  std::size_t n = 0;
};

struct TierAudit {
  std::string name;
  double escape_time_exact_fraction = 0;  ///< over sampled particles whose truth escapes in the horizon
  std::size_t escapes_compared = 0;
  Quantiles horizon_collisions, horizon_time;                     ///< over particles whose horizon was observed
  Quantiles horizon_collisions_mupo, horizon_collisions_chaotic;  ///< by class of the particle
  ClassGrowth growth;
  std::size_t beyond_horizon = 0;  ///< censored: escaped or capped before leaving tolerance
};

/// Two-sample comparison of one tier's ensemble with the reference (long double) ensemble.
struct WindowTest {
  double from = 0, to = 0;
  std::uint64_t escapes_tier = 0, escapes_ref = 0, at_risk_tier = 0, at_risk_ref = 0;
  double z = 0;  ///< two-proportion z statistic of the escape fraction in the window
};
struct StatisticsCheck {
  std::string tier;
  std::vector<WindowTest> windows;
  double max_abs_z = 0;
  double kappa = 0, kappa_error = 0, kappa_diff = 0, kappa_diff_error = 0;
  std::optional<double> alpha;
  double alpha_error = 0;
  std::optional<double> alpha_diff;
  double alpha_diff_error = 0;
  bool consistent = false;
  bool identical_to_scalar_double = false;  ///< (double_simd) same survivors at every grid time
};

struct ScalarCheck {
  std::string tier;
  double phase_error_at_tmax = 0;  ///< bound on |leak phase error| at t_max from t's own rounding
  double omega_single_drift = 0;   ///< |omega - fl(omega)| * t_max
  double omega_split_drift = 0;    ///< |omega - (hi + lo)| * t_max (what the engine uses)
  double time_ulp_at_tmax = 0;
  double split_matters_after = 0;   ///< time at which |omega - (hi + lo)| t reaches 1e-3 of the leak width
  double single_matters_after = 0;  ///< the same for omega rounded once
  bool omega_is_rounded = false;    ///< the tier holds a nearby rational, not omega
  bool phase_resolved = false;      ///< phase errors << leak width
  std::string note;
};

struct Verdict {
  std::string tier, statistic, verdict, reason;  ///< verdict: trusted | trusted as a statistic | untested | not trusted
};

struct AuditReport {
  std::size_t sample = 0;
  std::vector<std::uint64_t> ids;
  long max_truth_bits = 0;
  LyapunovEstimate lyapunov_tangent, lyapunov_divergence;
  std::vector<TierAudit> tiers;
  std::vector<StatisticsCheck> statistics;
  std::vector<ScalarCheck> scalars;
  std::vector<Verdict> verdicts;
  double seconds = 0;
  /// Wall seconds of its parts: the stratification scan, the shadows, the statistics ensembles, the
  /// rest (Lyapunov exponents, verdicts); on a team, as rank 0 saw them.
  double stratify_seconds = 0, shadow_seconds = 0, ensemble_seconds = 0, analysis_seconds = 0;
  /// Wall seconds of each statistics ensemble (float, double, long_double, double_simd), the same ids
  /// each: what run.tier = auto weighs the trusted tiers by.
  std::vector<std::pair<std::string, double>> ensemble_seconds_by_tier;
  int threads = 0;  ///< per process
  int ranks = 1;    ///< MPI processes that shared the audit
};

/// The audit follows single particles through every tier: a split scene (run.splitting = true) is
/// refused as input (InputError naming run.splitting); its verdict for the double tier is the unsplit one's.
void check_auditable(const Scene& scene);
AuditReport audit(const Scene& scene, const AuditOptions& options);

/// The checks on the scene's scalars alone (no simulation): phase resolution and omega's representation (a list of
/// leaks: the leak whose phase is resolved least well against its width, named in the note).
ScalarCheck scalar_check(const Scene& scene, const std::string& tier);
/// The one rule on a tier's scalars, which the audit's verdicts, run.tier = auto and simulate's warning all
/// apply: why the tier cannot be trusted on this scene whatever its ensembles show (a moving leak's phase
/// not resolved to 1e-3 of its width at t_max, or the time grid finer than 100 ulps of t_max), or nothing.
std::optional<std::string> scalar_rejection(const Scene& scene, const ScalarCheck& c);

/// The share of a tier's sampled escape times it must reproduce exactly (and at least one compared) for its
/// trajectories, and with them its statistics, to be trusted (docs/guide/trust.md, "One verdict").
inline constexpr double kTrustedEscapeShare = 0.99;
/// The ensemble comparison's threshold in standard errors: every window's |z| below it, kappa's and alpha's
/// differences within it (about 6 windows and 2 fits: a false alarm below 1e-3).
inline constexpr double kEnsembleSigmas = 4;
bool trajectories_trusted(const TierAudit& t);
/// The ensemble rule on a comparison's numbers (alpha_diff set where both ensembles have alpha);
/// `alpha_presence_agrees`: where it is not set, whether both lack alpha (one with and one without differ).
bool ensemble_consistent(const StatisticsCheck& c, bool alpha_presence_agrees);
/// The verdicts of a report whose tiers and statistics are filled (audit() calls it): per tier, in order (less
/// precise first), its scalars (scalar_check), then trajectories, P(t), kappa and alpha by one rule
/// (docs/guide/trust.md, "One verdict"): a statistic is not trusted where the tier's scalars fail
/// (scalar_rejection), whatever else agrees; trusted where its trajectories are (trajectories_trusted); else its
/// ensemble against its reference decides, "untested" where the reference's own scalars fail; a tier without an
/// ensemble leans on the most precise tier below it with one. The vectorised double engine shares the double
/// tier's verdict.
void judge(const Scene& scene, AuditReport& rep);

}  // namespace rotleak
