// The vectorised engine against the scalar core: bit-identical where the arithmetic is the same,
// statistically equivalent everywhere (two-sample Kolmogorov-Smirnov on escape times).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "analysis/fits.hpp"
#include "io/run_output.hpp"
#include "io/scene_file.hpp"
#include "names.hpp"
#include "sim/engine.hpp"
#include "sim/simd_engine.hpp"

using namespace rotleak;

namespace {

Scene scene(const std::string& start, const std::string& omega, std::uint64_t n = 20000,
            const std::string& width = "0.02") {
  return parse_scene("[leak]\nwidth = \"" + width + "\"\nstart = \"" + start + "\"\nomega = \"" + omega +
                     "\"\n[ensemble]\nparticles = " + std::to_string(n) +
                     "\nseed = 5\n[run]\nt_max = 3000\n[observe]\nescapes = true\n[fit]\nkappa_window = [0, 200]\n");
}

RunResult run(const Scene& s, Engine e, int threads = 2) {
  RunOptions o;
  o.engine = e;
  o.threads = threads;
  return run_ensemble(s, o);
}

// Two-sample KS: the largest gap between the two empirical escape-time distributions, against the
// alpha = 1e-3 critical value c sqrt((n + m) / (n m)), c = sqrt(-ln(alpha / 2) / 2) = 1.95.
double ks_distance(std::vector<double> a, std::vector<double> b) {
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  std::size_t i = 0, j = 0;
  double d = 0;
  while (i < a.size() && j < b.size()) {
    const double x = std::min(a[i], b[j]);
    while (i < a.size() && a[i] <= x) ++i;
    while (j < b.size() && b[j] <= x) ++j;
    d = std::max(d, std::abs(static_cast<double>(i) / static_cast<double>(a.size()) -
                             static_cast<double>(j) / static_cast<double>(b.size())));
  }
  return d;
}

std::vector<double> escape_times(const RunResult& r) {
  std::vector<double> t;
  for (const auto& e : r.records) t.push_back(e.fate == Fate::escaped ? e.t : 1e300);
  return t;
}

}  // namespace

class SimdStationary : public ::testing::TestWithParam<const char*> {};

TEST_P(SimdStationary, BitIdenticalToTheScalarCore) {
  if (!simd::available()) GTEST_SKIP() << "no AVX2+FMA on this CPU";
  const Scene s = scene(GetParam(), "0");
  const RunResult a = run(s, Engine::scalar), b = run(s, Engine::simd);
  EXPECT_EQ(b.engine, Engine::simd);
  EXPECT_EQ(escapes_csv(0, a.records), escapes_csv(0, b.records));
  EXPECT_EQ(survival_csv(survival_curve(s, a.tally)), survival_csv(survival_curve(s, b.tally)));
  EXPECT_EQ(a.tally.collisions, b.tally.collisions);
}

INSTANTIATE_TEST_SUITE_P(LeakPositions, SimdStationary,
                         ::testing::Values("0", "0.1022", "0.1024", "0.25", "0.5", "0.95"),
                         rotleak::test::IndexedName());

TEST(Simd, OneAndTwoThreadsGiveIdenticalFiles) {
  if (!simd::available()) GTEST_SKIP() << "no AVX2+FMA on this CPU";
  const Scene s = scene("0", "0");
  const RunResult a = run(s, Engine::simd, 1), b = run(s, Engine::simd, 2);
  EXPECT_EQ(escapes_csv(0, a.records), escapes_csv(0, b.records));
}

// A moving leak also computes atan2 (xsimd's against libm's): per particle the runs may part in a
// last bit; the escape-time distributions must still agree (KS, alpha = 1e-3), and kappa within errors.
TEST(Simd, RotatingLeaksAgreeInDistribution) {
  if (!simd::available()) GTEST_SKIP() << "no AVX2+FMA on this CPU";
  for (const char* omega : {"2/3", "ln(19)", "1008/1009"}) {
    const Scene s = scene("0.3", omega, 40000);
    const RunResult a = run(s, Engine::scalar), b = run(s, Engine::simd);
    const auto ta = escape_times(a), tb = escape_times(b);
    const double n = static_cast<double>(ta.size());
    EXPECT_LT(ks_distance(ta, tb), 1.95 * std::sqrt(2 / n)) << omega;
    std::size_t same = 0;
    for (std::size_t i = 0; i < ta.size(); ++i) same += ta[i] == tb[i];
    EXPECT_GT(static_cast<double>(same) / n, 0.9) << omega << ": most particles identical";
    const SurvivalCurve ca = survival_curve(s, a.tally);
    const SurvivalCurve cb = survival_curve(s, b.tally);
    const KappaFit ka = fit_kappa(ca, 0, 200), kb = fit_kappa(cb, 0, 200);
    EXPECT_NEAR(ka.value, kb.value, 3 * std::hypot(ka.std_error, kb.std_error)) << omega;
  }
}

// First collisions: a leak of 0.999 takes nearly every particle at its first hit, so the escape
// records are the first collisions themselves; they agree exactly (no ulps to allow).
TEST(Simd, FirstCollisionsAgreeExactly) {
  if (!simd::available()) GTEST_SKIP() << "no AVX2+FMA on this CPU";
  const Scene s = scene("0.5", "0", 20000, "0.999");
  const RunResult a = run(s, Engine::scalar), b = run(s, Engine::simd);
  std::size_t first = 0;
  for (std::size_t i = 0; i < a.records.size(); ++i) {
    if (a.records[i].collisions != 1) continue;
    ++first;
    EXPECT_EQ(a.records[i].t, b.records[i].t) << i;
    EXPECT_EQ(a.records[i].s, b.records[i].s) << i;
  }
  EXPECT_GT(first, 19000u);
}

TEST(Simd, RefusesWhatItCannotRun) {
  Scene s = scene("0", "0");
  s.collision_density = CollisionDensitySpec{};
  EXPECT_EQ(resolve_engine(Engine::automatic, s), Engine::scalar);  // f_c needs the scalar observer
  EXPECT_THROW(resolve_engine(Engine::simd, s), std::runtime_error);
  s.collision_density.reset();
  s.tier = Tier::long_double;
  EXPECT_EQ(resolve_engine(Engine::automatic, s), Engine::scalar);
}
