#include "analysis/run_summary.hpp"

#include <utility>

namespace rotleak {

RunSummary summarise(const Scene& scene, RunResult result) {
  RunSummary s;
  s.scene = scene;
  s.curve = survival_curve(scene, result.tally);
  s.result = std::move(result);
  s.kappa = fit_kappa(s.curve, scene.kappa_window.from, scene.kappa_window.to);
  s.alpha = find_alpha(s.curve, s.kappa);
  s.tail = fit_tail(s.curve, s.alpha);
  s.tail_class = classify_tail(scene, s.curve, s.alpha);
  s.leak_times = leak_times(scene);
  s.rate_jumps = decay_rate_jumps(s.curve, 100);
  return s;
}

}  // namespace rotleak
