// The published stationary table (docs/model.md, "Published values") at reduced size. Tolerance per row: the literature
// allowance (2% in kappa, 15% in alpha: their fit method is not stated) plus 3 standard errors of
// our own estimate at this particle count (binomial / Greenwood error model, see analysis/fits.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <string>

#include "analysis/fits.hpp"
#include "analysis/regimes.hpp"
#include "io/scene_file.hpp"
#include "paths.hpp"
#include "sim/engine/engine.hpp"
#include "sim/tally/survival.hpp"

using namespace rotleak;

struct Row {
  const char* s_L;
  double kappa, alpha;
  std::uint64_t particles;
};

class StationaryTable : public ::testing::TestWithParam<Row> {};

// Each row through one engine; both engines run every row (each has its own reflection and leak
// test, so a physics error in either shows here, not only in a bit-identity check).
// With fast_forward, the bouncing-ball phases are jumped in closed form rather than stepped (sim/fast_forward.hpp):
// the same allowances hold, so a wrong jump (time, position or a missed leak) shows against the literature,
// not only against a stepped run that shares the same error.
void check_row(const Row& row, Engine engine, bool fast_forward = false) {
  const Scene scene =
      load_scene(std::string(rotleak::test::source_dir()) + "/data/scenes/stationary_sL_" + row.s_L + ".toml",
                 {"ensemble.particles=" + std::to_string(row.particles),
                  std::string("run.fast_forward=") + (fast_forward ? "true" : "false")});
  RunOptions opt;
  opt.engine = engine;
  const RunResult res = run_ensemble(scene, opt);
  const SurvivalCurve c = survival_curve(scene, res.tally);
  const KappaFit k = fit_kappa(c, scene.kappa_window.from, scene.kappa_window.to);
  const AlphaResult a = find_alpha(c, k);
  ASSERT_TRUE(k.ok);
  EXPECT_NEAR(k.value, row.kappa, 0.02 * row.kappa + 3 * k.std_error) << "s_L = " << row.s_L;
  ASSERT_TRUE(a.value.has_value()) << "s_L = " << row.s_L << ": alpha unresolved, bound " << a.upper_bound.value_or(-1);
  EXPECT_NEAR(*a.value, row.alpha, 0.15 * row.alpha + 3 * a.std_error) << "s_L = " << row.s_L;
  // Tighter: our own systematic against the table, measured at 10^7 particles per row (docs/guide/tails.md, "The
  // published table, reproduced"), is -0.12..-0.37% in kappa and -1.3..+7.5% in alpha; allowances of
  // 0.5% and 10% plus 3 standard errors hold those, and fail a leak 2% too wide (kappa moves ~2%).
  EXPECT_NEAR(k.value, row.kappa, 0.005 * row.kappa + 3 * k.std_error) << "s_L = " << row.s_L << " (0.5% band)";
  EXPECT_NEAR(*a.value, row.alpha, 0.10 * row.alpha + 3 * a.std_error) << "s_L = " << row.s_L << " (10% band)";
  EXPECT_EQ(res.tally.stuck, 0u);
  std::printf("s_L = %s (%s engine%s): kappa %.5g +- %.2g (lit %.4g), alpha %.3g +- %.2g (lit %.3g), N = %llu\n",
              row.s_L, to_string(res.engine).c_str(), fast_forward ? ", fast-forward" : "", k.value, k.std_error,
              row.kappa, *a.value, a.std_error, row.alpha, static_cast<unsigned long long>(row.particles));
}

TEST_P(StationaryTable, ReproducesKappaAndAlpha) { check_row(GetParam(), Engine::automatic); }
TEST_P(StationaryTable, ReproducesKappaAndAlphaOnTheScalarEngine) { check_row(GetParam(), Engine::scalar); }
TEST_P(StationaryTable, ReproducesKappaAndAlphaWithFastForward) { check_row(GetParam(), Engine::automatic, true); }
TEST_P(StationaryTable, ReproducesKappaAndAlphaWithFastForwardOnTheScalarEngine) {
  check_row(GetParam(), Engine::scalar, true);
}

// Particle counts: enough that 3 standard errors of alpha stay below the 15% allowance
// (alpha N survivors at the crossing: N = 2e6 gives 280 for s_L = 0).
INSTANTIATE_TEST_SUITE_P(Spec5, StationaryTable,
                         ::testing::Values(Row{"0", 4.402e-3, 1.4e-4, 2000000}, Row{"0.1", 4.748e-3, 3.6e-4, 1000000},
                                           Row{"0.1022", 4.752e-3, 5.7e-4, 1000000},
                                           Row{"0.1024", 4.750e-3, 9.5e-4, 1000000},
                                           Row{"0.11", 4.683e-3, 2.9e-3, 500000},
                                           Row{"0.25", 4.382e-3, 3.4e-3, 500000}),
                         [](const ::testing::TestParamInfo<Row>& row) {
                           std::string name = std::string("sL_") + row.param.s_L;
                           std::replace(name.begin(), name.end(), '.', '_');
                           return name;
                         });

// The rotating example scene, as shipped (data/scenes/rotating.toml: omega = 1, 10^6 particles), against
// the study's published alpha for omega = 1 (data/literature/rotating.csv), with the allowance of the
// stationary rows (15%, the fit method is not stated) plus 3 standard errors of our estimate; its tail
// persists (the high regime).
TEST(RotatingExample, TheSceneFileGivesThePublishedAlpha) {
  std::ifstream lit(std::string(rotleak::test::source_dir()) + "/data/literature/rotating.csv");
  double published = 0;
  for (std::string line; std::getline(lit, line);)
    if (line.rfind("alpha,1,", 0) == 0) published = std::stod(line.substr(8, line.find(',', 8) - 8));
  ASSERT_GT(published, 0) << "no alpha for omega = 1 in data/literature/rotating.csv";
  const Scene scene = load_scene(std::string(rotleak::test::source_dir()) + "/data/scenes/rotating.toml");
  ASSERT_EQ(scene.omega.sign(), 1);
  const RunResult res = run_ensemble(scene, RunOptions{});
  const SurvivalCurve c = survival_curve(scene, res.tally);
  const KappaFit k = fit_kappa(c, scene.kappa_window.from, scene.kappa_window.to);
  const AlphaResult a = find_alpha(c, k);
  ASSERT_TRUE(a.value.has_value()) << a.note;
  EXPECT_NEAR(*a.value, published, 0.15 * published + 3 * a.std_error);
  const TailClass t = classify_tail(scene, c, a, &k);
  EXPECT_EQ(t.tail, "persistent") << t.note;
  EXPECT_EQ(t.regime, "high");
  std::printf("rotating.toml: alpha %.3g +- %.2g (published %.3g), N = %llu\n", *a.value, a.std_error, published,
              static_cast<unsigned long long>(scene.particles));
}
