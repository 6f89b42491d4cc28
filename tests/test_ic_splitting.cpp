// Splitting over initial conditions (sim/engine/ic_splitting.hpp): unbiased down to 1e-22 on a clock whose law is
// known in closed form, caught when its kernel is not invariant, the same bits for any thread count, and the
// stadium's P where plain Monte Carlo measures it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "io/scene_file.hpp"
#include "sim/engine/engine.hpp"
#include "sim/engine/ic_splitting.hpp"
#include "sim/tally/survival.hpp"
#include "tests/paths.hpp"

namespace rotleak {
namespace {

/// T(s, p) = -(c / 2) ln max(2 |s - 1/2|, |p - 3/10| / (7/10)): with s uniform in [0, 1) and p in (-1, 1),
/// T > t asks 2 |s - 1/2| < e^(-2t/c) and |p - 3/10| < (7/10) e^(-2t/c), so P(T > t) = (7/10) e^(-4t/c) exactly
/// (before t_max); the set that outlives t is a box shrinking to the point (1/2, 3/10), which a sampler has to find
/// at every scale.
constexpr double kC = 400;
IcEnd box_clock(const IcPoint& x, double t_max) {
  const double m = std::max(2 * std::abs(x.s - 0.5), std::abs(x.p - 0.3) / 0.7);
  IcEnd e;
  const double T = m == 0 ? t_max : -(kC / 2) * std::log(m);
  if (T < t_max) e.t = T;
  e.collisions = 1;
  return e;
}
double box_P(double t) { return 0.7 * std::exp(-4 * t / kC); }

/// The box clock's run to t_max = 5000 (30 replicates of 1000 starts, seed 11) on the grid of every 500, with a
/// given kernel.
IcSplitRun box_run(const IcPropose& propose, double t_max = 5000, std::uint64_t starts = 1000, int replicates = 30,
                   std::uint64_t seed = 11) {
  const auto clock = [t_max](const IcPoint& x) { return box_clock(x, t_max); };
  IcSplitSpec spec;
  spec.starts = starts, spec.replicates = replicates;
  IcStratum whole;
  whole.s = {{0.0, 1.0}};
  whole.p = {{-1.0, 1.0}};
  std::vector<double> t;
  for (double x = 0; x <= t_max; x += 500) t.push_back(x);
  return ic_split(clock, whole, spec, t, t_max, seed, {}, propose);
}

Scene scene_of(const std::string& file) {
  return load_scene(std::string(rotleak::test::source_dir()) + "/data/scenes/" + file);
}

/// An asymmetric kernel: the symmetric proposal pulled a further half-scale toward (1/2, 3/10), where the long
/// lives are, with no Hastings ratio to undo the pull, so its chains leave the law given T > level and crowd the
/// centre.
IcPoint pulled(const IcStratum& st, const IcScales& sc, const IcPoint& x, const double* u) {
  IcPoint y = symmetric_proposal(st, sc, x, u);
  if (!st.contains(y)) return y;
  const int j = sc.halving(u[0]);
  y.s -= std::ldexp(sc.s / 2, -j) * (x.s > 0.5 ? 1 : -1);
  y.p -= std::ldexp(sc.p / 2, -j) * (x.p > 0.3 ? 1 : -1);
  return y;
}

// Error model: the replicates are independent, so (mean - P) / error is Student's t with R - 1 degrees of freedom;
// at 5 errors, a false failure in about 1 in 40000 per time for R = 30, 11 times checked.
TEST(IcSplitting, ReadsAClosedFormLawDownTo1e22WithinItsErrors) {
  const IcSplitRun run = box_run(symmetric_proposal);
  const std::vector<double>& t = run.t;
  ASSERT_GE(run.levels.size(), 30u);  // ln(0.7 e^-50) / ln(1/4): 36 levels to t_max
  for (std::size_t i = 0; i < t.size(); ++i) {
    SCOPED_TRACE("t = " + std::to_string(t[i]));
    const double P = box_P(t[i]), m = run.mean(i), e = run.error(i);
    ASSERT_GT(e, 0);
    EXPECT_LT(std::abs(m - P), 5 * e) << "mean " << m << " exact " << P << " error " << e;
    EXPECT_LT(e / P, 0.25);  // resolved: a quarter of P at most, 1.4e-22 at t_max
  }
  EXPECT_LT(box_P(t.back()), 2e-22);
  // the genealogy: stage 0's every start its own ancestor, a chain's states its seed's, so the count never grows
  for (const IcReplicate& r : run.replicates) {
    ASSERT_EQ(r.ancestors.size(), r.population.size());
    EXPECT_EQ(r.ancestors[0], 1000u);
    for (std::size_t j = 1; j < r.ancestors.size(); ++j) {
      EXPECT_LE(r.ancestors[j], r.ancestors[j - 1]);
      EXPECT_GE(r.ancestors[j], 1u);
      EXPECT_LE(r.stage_accepted[j], r.stage_proposals[j]);
    }
    EXPECT_LT(r.ancestors.back(), r.ancestors[1]);  // 36 levels of a shrinking box: fewer lines behind the last
  }
  const auto [fewest, from] = run.fewest_ancestors();
  EXPECT_GE(fewest, 1u);
  EXPECT_LE(fewest, run.replicates[0].ancestors.back());
  EXPECT_GE(from, run.levels.front());
}

// The converse: the same run with the pulled kernel reads the deep tail high by many of its errors.
TEST(IcSplitting, AKernelThatIsNotInvariantIsCaught) {
  const IcSplitRun run = box_run(pulled);
  const std::vector<double>& t = run.t;
  int off = 0;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (std::abs(run.mean(i) - box_P(t[i])) > 5 * run.error(i)) ++off;
  EXPECT_GE(off, 5) << "the pulled kernel's P agrees with the law at all but " << off << " of " << t.size();
  EXPECT_GT(run.mean(t.size() - 1), 10 * box_P(t.back()));
}

/// The box clock of the whole start hi + lo: its offsets from the centre in double-double (each hi - centre exact,
/// the centre being a double), so that it tells apart starts closer than a double's ulp, as a dd clock does.
IcEnd box_clock_dd(const IcPoint& x, double t_max) {
  const double ds = std::abs((x.s - 0.5) + x.s_lo), dp = std::abs((x.p - 0.3) + x.p_lo);
  const double m = std::max(2 * ds, dp / 0.7);
  IcEnd e;
  const double T = m == 0 ? t_max : -(kC / 2) * std::log(m);
  if (T < t_max) e.t = T;
  e.collisions = 1;
  return e;
}

// Below a double's ulp: to t_max = 8000 the box shrinks to 4e-18, below the ulp of s = 1/2 (1.1e-16), where a double
// clock cannot tell its starts apart. With the deep clock handed over where the moves fall below 2^20 double ulps,
// the sampler reads P = 0.7 e^-80 = 1.3e-35 within 5 errors at every 500 (the error model of the test above); the
// double clock alone says where its moves stop being resolved, before t_max.
TEST(IcSplitting, BelowADoublesUlpTheDeepClockReadsTheLaw) {
  constexpr double kTmax = 8000;
  IcSplitSpec spec;
  spec.starts = 1000, spec.replicates = 30, spec.deep_tier = TierKind::dd;
  IcStratum whole;
  whole.s = {{0.0, 1.0}};
  whole.p = {{-1.0, 1.0}};
  std::vector<double> t;
  for (double x = 0; x <= kTmax; x += 500) t.push_back(x);
  const EscapeClock clock = [](const IcPoint& x) { return box_clock(x, kTmax); };
  const EscapeClock deep = [](const IcPoint& x) { return box_clock_dd(x, kTmax); };
  const IcSplitRun run = ic_split(clock, whole, spec, t, kTmax, 11, {}, symmetric_proposal, deep);
  ASSERT_LT(run.handover, run.levels.size());
  EXPECT_GT(run.levels[run.handover], 3000);  // steps of 2^20 ulps of 1: the box at 2.3e-10, t ~ 4400
  EXPECT_TRUE(std::isinf(run.unresolved_from()));
  std::uint64_t handed = 0;
  for (const IcReplicate& r : run.replicates) handed += r.handed_over;
  EXPECT_GT(handed, 0u);
  for (std::size_t i = 0; i < t.size(); ++i) {
    SCOPED_TRACE("t = " + std::to_string(t[i]));
    const double P = box_P(t[i]), m = run.mean(i), e = run.error(i);
    ASSERT_GT(e, 0);
    EXPECT_LT(std::abs(m - P), 5 * e) << "mean " << m << " exact " << P << " error " << e;
    EXPECT_LT(e / P, 0.25);
  }
  EXPECT_LT(box_P(kTmax), 2e-35);
  // the converse: double alone, the same seed
  const IcSplitRun plain = ic_split(clock, whole, spec, t, kTmax, 11);
  EXPECT_EQ(plain.handover, plain.levels.size());
  EXPECT_LT(plain.unresolved_from(), kTmax);
}

// The error is calibrated against independent seeds: 20 runs of 10 replicates of 300 starts (t_max 3000, P down to
// 6.5e-14), their means' spread about the exact P over the root mean square of their errors. Error model: with
// honest errors the ratio is sqrt(chi^2_20 / 20) give or take the errors' own scatter; 99.9% of chi^2_20 / 20 lies in
// [0.29, 2.3], so the ratio in [0.5, 1.6] (the scatter of the errors widens it a little) at each of three times.
TEST(IcSplitting, ItsErrorIsTheSpreadOfIndependentSeeds) {
  constexpr int kSeeds = 20;
  std::vector<double> ss(7, 0), ee(7, 0);
  for (int k = 0; k < kSeeds; ++k) {
    const IcSplitRun run = box_run(symmetric_proposal, 3000, 300, 10, 100 + static_cast<std::uint64_t>(k));
    for (std::size_t i = 0; i < run.t.size(); ++i) {
      const double d = run.mean(i) - box_P(run.t[i]);
      ss[i] += d * d, ee[i] += run.error(i) * run.error(i);
    }
  }
  for (const std::size_t i : {2u, 4u, 6u}) {  // t = 1000, 2000, 3000
    const double ratio = std::sqrt(ss[i] / ee[i]);
    std::printf("t = %g: spread of %d seeds' means / their error = %.3f\n", 500.0 * static_cast<double>(i), kSeeds,
                ratio);
    EXPECT_GT(ratio, 0.5) << "t index " << i;
    EXPECT_LT(ratio, 1.6) << "t index " << i;
  }
}

// The stadium with its stationary leak, t_max 1000: splitting over the whole boundary against plain Monte Carlo on
// 2*10^5 particles, within 4 combined errors at every 100 time units, and the same counts on 1 and 2 threads.
TEST(IcSplitting, TheStadiumsPIsPlainMonteCarlosAndTheBitsDoNotDependOnThreads) {
  Scene sc = scene_of("stationary_sL_0.toml");
  sc.t_max = 1000, sc.particles = 200000, sc.survival_dt = 100;
  RunOptions opt;
  const RunResult plain = run_ensemble(sc, opt);
  const SurvivalCurve c = survival_curve(sc, plain.tally);
  IcSplitSpec spec;
  spec.starts = 2000, spec.replicates = 12;
  const EscapeClock clock = scene_clock(sc);
  const IcStratum st = ic_stratum(sc, 0, 1, false);
  EXPECT_DOUBLE_EQ(st.share(), 1.0);
  spec.threads = 1;
  const IcSplitRun one = ic_split(clock, st, spec, c.t, sc.t_max, 5);
  spec.threads = 2;
  const IcSplitRun two = ic_split(clock, st, spec, c.t, sc.t_max, 5);
  ASSERT_EQ(one.levels, two.levels);
  for (std::size_t r = 0; r < one.replicates.size(); ++r) {
    EXPECT_EQ(one.replicates[r].alive, two.replicates[r].alive);
    EXPECT_EQ(one.replicates[r].collisions, two.replicates[r].collisions);
    EXPECT_EQ(one.replicates[r].ancestors, two.replicates[r].ancestors);
  }
  ASSERT_GE(one.levels.size(), 1u);
  for (std::size_t i = 1; i < c.t.size(); ++i) {
    SCOPED_TRACE("t = " + std::to_string(c.t[i]));
    const double e = std::hypot(c.P_err(i), one.error(i));
    EXPECT_LT(std::abs(one.mean(i) - c.P(i)), 4 * e) << one.mean(i) << " vs " << c.P(i);
  }
}

}  // namespace
}  // namespace rotleak
