// Uses an installed rotleak as any other project would: the quick-start scene from the installed
// data, an ensemble on the engine, P(t) and its kappa fit. Prints one line; exit 1 if the fit failed.
#include <cstdio>

#include "analysis/fits.hpp"
#include "io/scene_file.hpp"
#include "sim/engine/engine.hpp"
#include "sim/tally/survival.hpp"
#include "version.hpp"

int main() {
  const rotleak::Scene scene =
      rotleak::load_scene(ROTLEAK_DATA_DIR "/scenes/quickstart.toml", {"ensemble.particles=20000"});
  const rotleak::RunResult r = rotleak::run_ensemble(scene, rotleak::RunOptions{});
  const rotleak::SurvivalCurve c = rotleak::survival_curve(scene, r.tally);
  const rotleak::KappaFit k = rotleak::fit_kappa(c, 0, 300);
  std::printf("consumer of rotleak %s: %llu collisions, kappa = %.5g +- %.2g\n", rotleak::kVersion,
              static_cast<unsigned long long>(r.tally.collisions), k.value, k.std_error);
  return k.ok ? 0 : 1;
}
