#include "analysis/run_summary.hpp"

#include "numeric/input.hpp"

#include <utility>

namespace rotleak {

RunSummary summarise(const Scene& scene, RunResult result) {
  RunSummary s;
  s.scene = scene;
  s.curve = survival_curve(scene, result.tally);
  s.result = std::move(result);
  fit_curve(s);
  return s;
}

RunSummary summarise(const Scene& scene, IcSplitRun run, RunResult result) {
  RunSummary s;
  s.scene = scene;
  s.curve = ic_curve(run);
  s.result = std::move(result);
  s.result.tally.collisions = run.collisions();
  s.start_splitting = std::move(run);
  fit_curve(s);
  return s;
}

void fit_curve(RunSummary& s) {
  const Scene& scene = s.scene;
  s.kappa = fit_kappa(s.curve, scene.kappa_window.from, scene.kappa_window.to);
  add_window_systematic(s.kappa, s.curve, scene.t_max);
  s.alpha = find_alpha(s.curve, s.kappa, scene.alpha_factor, scene.alpha_sigma, scene.min_survivors);
  add_alpha_systematic(s.alpha, s.curve, s.kappa);
  add_uniform_reach(s.alpha, s.curve);
  s.tail = fit_tail(s.curve, s.alpha);
  s.amplitude = fit_amplitude(s.curve, s.kappa, scene.min_survivors);
  s.alpha_c = alpha_from_amplitude(s.kappa, s.amplitude, scene.alpha_factor);
  s.tail_class = classify_tail(scene, s.curve, s.alpha, &s.kappa, &s.amplitude);
  // a stratum's P is not the whole boundary's, which the tail model predicts
  const StartSplitSpec& g = scene.start_splitting;
  const bool part = g.on && (g.p_lo > 0 || g.p_hi < 1 || g.edges);
  if (scene.on_table() || part) {  // the leak times and the tail model are the stadium's theory (docs/tables.md)
    s.rate_jumps = decay_rate_jumps(s.curve, 100);
    return;
  }
  s.leak_times = leak_times(scene);
  try {
    // the tail model counts the bouncing-ball orbits of starts uniform on the whole boundary, not of entries
    if (scene.enter_through < 0) s.prediction = predict_tail(scene);
  } catch (const InputError&) {
    s.prediction.reset();  // a leak too wide for the model: no prediction, the run stands
  }
  s.rate_jumps = decay_rate_jumps(s.curve, 100);
}

}  // namespace rotleak
