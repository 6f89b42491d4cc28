// One tail verdict over atlas points (analysis/regimes.hpp classify_tail with the amplitude): split runs of the
// atlas's scene at three line counts, so labelled slow (the sanitizer stage leaves it to the Release suite).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "analysis/regimes.hpp"
#include "analysis/run_summary.hpp"
#include "io/scene_file.hpp"
#include "paths.hpp"
#include "sim/engine/engine.hpp"

using namespace rotleak;

// One tail verdict (classify_tail with the amplitude): over atlas points (data/study/study.toml, mupo
// sampling, splitting, the fast-forward: scripts/atlas.sh's runs) at 2*10^4, 5*10^4 and 2*10^5 lines, the
// class, the regime, C and alpha_C agree: a resolved C (more than 3 of its errors) is a tail seen, so the class
// is persistent or transient and the regime decided (undecided only where the leak's sweep comes after the
// last survivor); no tail means no C; an alpha bound is not exceeded by alpha_C beyond 3 of its errors. The
// issue that asked for it saw 82/83 at 10^6 lines "unresolved, undecided" beside C = 8.4e-5 +- 2.4e-6, and a
// scan point at 2/3 "unresolved" beside C = 0.284 +- 0.020 where 2*10^4 and 2*10^5 lines said "persistent".
TEST(TailVerdict, ClassRegimeAndAmplitudeAgreeOnAtlasPoints) {
  for (const char* omega : {"2/3", "82/83", "1/golden", "2/3+1e-4"}) {
    std::string classes;
    for (const std::uint64_t lines : {20000u, 50000u, 200000u}) {
      const Scene scene =
          load_scene(std::string(test::source_dir()) + "/data/study/study.toml",
                     {std::string("leak.omega=") + omega, "ensemble.sampling=mupo", "run.splitting=true",
                      "run.fast_forward=true", "ensemble.particles=" + std::to_string(lines)});
      RunOptions o;
      const RunSummary r = summarise(scene, run_ensemble(plan_run(scene, o), o));
      const std::string at = std::string(omega) + " at " + std::to_string(lines) + " lines: " + r.tail_class.tail +
                             ", " + r.tail_class.regime + "; " + r.tail_class.note;
      classes += r.tail_class.tail + " ";
      const bool c_resolved =
          r.amplitude.value && *r.amplitude.value > 3 * std::hypot(r.amplitude.std_error, r.amplitude.drift);
      if (c_resolved) {
        EXPECT_TRUE(r.tail_class.tail == "persistent" || r.tail_class.tail == "transient") << at;
        EXPECT_TRUE(r.tail_class.regime != "undecided" || r.tail_class.note.find("tau2") != std::string::npos) << at;
      }
      if (r.tail_class.tail == "none") {
        EXPECT_FALSE(r.amplitude.value.has_value()) << at;
      }
      if (r.alpha.upper_bound && r.alpha_c.value) {
        EXPECT_LE(*r.alpha_c.value, *r.alpha.upper_bound + 3 * r.alpha_c.std_error) << at;
      }
    }
    std::printf("%-9s %s\n", omega, classes.c_str());
  }
}
