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
  return s;
}

}  // namespace rotleak
