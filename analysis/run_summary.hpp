// What one run says: the scene as run, the engine's tallies, the survival curve and its fits. Every
// command, scan point, rank and test that runs a scene summarises it here, and analysis/output/run_output.hpp
// writes it.
#pragma once

#include <optional>
#include <string>

#include "analysis/fits.hpp"
#include "analysis/regimes.hpp"
#include "analysis/tail_model.hpp"
#include "sim/engine/engine.hpp"
#include "sim/engine/ic_splitting.hpp"
#include "sim/model/scene.hpp"
#include "sim/tally/survival.hpp"

namespace rotleak {

struct RunSummary {
  Scene scene;  ///< as run (a tier of auto resolved)
  RunResult result;
  SurvivalCurve curve;
  KappaFit kappa;
  AlphaResult alpha;
  TailFit tail;
  TailAmplitude amplitude;                   ///< C in P ~ C / t
  AlphaFromAmplitude alpha_c;                ///< alpha from A exp(-kappa t) + C / t
  TailClass tail_class;                      ///< none / transient / persistent and the regime, from the measured P(t)
  LeakTimes leak_times;                      ///< the geometry's predicted time scales
  std::optional<TailPrediction> prediction;  ///< the covering model's tail (none: the scene lies outside it)
  std::vector<RateJump> rate_jumps;          ///< measured jumps of the decay rate (window 100)
  std::optional<std::string> tier_choice;    ///< why, when the scene asked for run.tier = auto
  /// Why the audit's rule (verify/audit.hpp, scalar_rejection) does not trust this tier's statistics on this
  /// scene (the leak phase or the time grid beyond it); none where it does. Set by the run layer.
  std::optional<std::string> precision_warning;
  /// Splitting over initial conditions (scene.start_splitting): its levels, factors and replicates.
  std::optional<IcSplitRun> start_splitting;

  double collisions_per_second() const {
    return result.wall_seconds > 0 ? static_cast<double>(result.tally.collisions) / result.wall_seconds : 0.0;
  }
};

/// The curve and the three fits (kappa on the scene's window, alpha, the tail exponent).
RunSummary summarise(const Scene& scene, RunResult result);
/// A run of splitting over initial conditions: its curve (ic_curve) and fits; result holds its collisions, wall time
/// and threads.
RunSummary summarise(const Scene& scene, IcSplitRun run, RunResult result);
/// The fits, the tail class, the predictions and the rate jumps of s.curve under s.scene's fit keys
/// (summarise calls it; `rotleak fit` calls it on a curve read back from survival.csv).
void fit_curve(RunSummary& s);

}  // namespace rotleak
