// Seed calibration (analysis/calibration.hpp): the spread statistics on draws with known errors, the
// pooled curve against its formula, and `calibrate` end to end on a small scene (its files read back).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "analysis/calibration.hpp"
#include "analysis/output/run_output.hpp"
#include "analysis/run_summary.hpp"
#include "io/files.hpp"
#include "io/scene_file.hpp"
#include "numeric/input.hpp"
#include "run/calibrate.hpp"
#include "scratch.hpp"
#include "sim/tally/tally.hpp"

using namespace rotleak;

// Gaussian values with their true errors: sd / err near 1 and coverage near 68% / 95% (K = 4000: the
// sampling errors are 1.1%, 0.7% and 0.35%; the bands are 4 of them). Errors reported half as large:
// sd / err near 2 and the verdict says so.
// K draws of 3 + 0.1 N(0, 1).
std::vector<double> gaussian_values(std::size_t K, unsigned seed) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> normal(0, 1);
  std::vector<double> x(K);
  for (double& v : x) v = 3 + 0.1 * normal(gen);
  return x;
}

TEST(SeedSpread, HonestErrorsCalibrateAndSmallOnesAreCaught) {
  const std::size_t K = 4000;
  const std::vector<double> x = gaussian_values(K, 5), e(K, 0.1), half(K, 0.05);
  const SeedSpread s = seed_spread(x, e);
  EXPECT_NEAR(s.sd_over_err, 1, 0.045);
  EXPECT_NEAR(s.chi2_dof, 1, 0.09);
  EXPECT_NEAR(s.coverage1, 0.6827, 0.03);
  EXPECT_NEAR(s.coverage2, 0.9545, 0.014);
  EXPECT_NEAR(s.pooled, 3, 4 * 0.1 / std::sqrt(K));
  EXPECT_EQ(spread_verdict(s), "honest");
  const SeedSpread t = seed_spread(x, half);
  EXPECT_NEAR(t.sd_over_err, 2, 0.09);
  EXPECT_EQ(spread_verdict(t), "errors too small");
  EXPECT_THROW(seed_spread({1.0}, {0.1}), std::invalid_argument);
}

// Errors twice the spread: "errors too large", unless most seeds took the value where the allowance for
// unsplit lines not drawn is the larger part of the error (the seeds cannot test that part: the lines
// it stands for are rarer than K runs draw); the allowance cannot excuse errors that are too small.
TEST(SeedSpread, ErrorsTooLargeWhereTheAllowanceDominatesAreUntested) {
  const std::size_t K = 400;
  const std::vector<double> x = gaussian_values(K, 7), twice(K, 0.2), half(K, 0.05);
  const SeedSpread s = seed_spread(x, twice);
  EXPECT_LT(s.sd_over_err, kHonestBand[0]);
  EXPECT_EQ(spread_verdict(s), "errors too large");
  EXPECT_EQ(spread_verdict(s, 0.4), "errors too large");
  EXPECT_EQ(spread_verdict(s, 0.9), "untested: mostly the allowance for lines not drawn");
  EXPECT_EQ(spread_verdict(seed_spread(x, half), 1.0), "errors too small");
}

// K = 3 by hand: x = 1, 2, 4 with unit errors. Mean 7/3, squared deviations 42/9, sd = sqrt(42/9 / 2) (the
// n - 1 of an unbiased variance); the others' means 3, 5/2, 3/2 put the seeds 2, 1/2, 5/2 away: one within 1
// error, two within 2.
TEST(SeedSpread, ThreeSeedsByHand) {
  const SeedSpread s = seed_spread({1, 2, 4}, {1, 1, 1});
  EXPECT_EQ(s.n, 3u);
  EXPECT_DOUBLE_EQ(s.pooled, 7.0 / 3);
  EXPECT_DOUBLE_EQ(s.sd, std::sqrt(7.0 / 3));
  EXPECT_DOUBLE_EQ(s.pooled_err, std::sqrt(7.0 / 3) / std::sqrt(3.0));
  EXPECT_DOUBLE_EQ(s.sd_over_err, std::sqrt(7.0 / 3));
  EXPECT_DOUBLE_EQ(s.chi2_dof, 7.0 / 3);
  EXPECT_DOUBLE_EQ(s.coverage1, 1.0 / 3);
  EXPECT_DOUBLE_EQ(s.coverage2, 2.0 / 3);
  EXPECT_DOUBLE_EQ(s.max_over_median, 2);
}

// The variance behind sd / err is unbiased at any K: over B batches of K = 3 honest Gaussian errors the mean
// of (sd / err)^2 is 1, with standard error sqrt(2 / (K - 1) / B) (chi-square with K - 1 degrees of freedom
// over K - 1). Dividing by K instead gives (K - 1) / K = 2/3, 47 standard errors away at B = 20000.
TEST(SeedSpread, VarianceIsUnbiasedOverSmallBatches) {
  const std::size_t K = 3, B = 20000;
  const std::vector<double> x = gaussian_values(K * B, 11), e(K, 0.1);
  double sum = 0;
  for (std::size_t b = 0; b < B; ++b) {
    const std::vector<double> batch(x.begin() + static_cast<std::ptrdiff_t>(K * b),
                                    x.begin() + static_cast<std::ptrdiff_t>(K * (b + 1)));
    const double r = seed_spread(batch, e).sd_over_err;
    sum += r * r;
  }
  const double mean = sum / static_cast<double>(B), se = std::sqrt(2.0 / (K - 1) / static_cast<double>(B));
  EXPECT_NEAR(mean, 1, 4 * se);
}

// The verdict's region for K seeds (honest_band): at K = 100 the promised band and floor bind (the chi-square
// interval, [0.78, 1.21], lies inside [0.7, 1.5]); at K = 16 the data cannot resolve them, and the region
// widens. The stated rate: honest Gaussian errors are called dishonest with probability at most
// 2 kCalibrationFalseAlarm (each test at kCalibrationFalseAlarm), measured over M = 20000 calibrations of
// K = 16 seeds (its binomial standard error at 2% is 0.1%; the test allows 4 of them). Errors reported half
// as large (sd / err near 2) are caught in most of them. The issue that asked for it: 16 seeds with sd / err
// 0.94 and 14 within 2 errors were called "errors too small"; they are honest.
TEST(SeedSpread, VerdictJudgesWithItsSeedCount) {
  const HonestBand b100 = honest_band(100), b16 = honest_band(16), b3 = honest_band(3);
  EXPECT_DOUBLE_EQ(b100.lo, kHonestBand[0]);
  EXPECT_DOUBLE_EQ(b100.hi, kHonestBand[1]);
  EXPECT_DOUBLE_EQ(b100.coverage2_floor, kHonestCoverage2);
  EXPECT_LT(b16.lo, kHonestBand[0]);
  EXPECT_LT(b16.coverage2_floor, kHonestCoverage2);
  // the floor by hand: the binomial lower tail P(X <= c) summed term by term; the floor's count c is the
  // first whose tail reaches kCalibrationFalseAlarm
  {
    const double p2 = b16.coverage2_expected;
    double tail = 0, below = 0;
    double c = 0;
    for (; c <= 16; ++c) {
      below = tail;
      tail +=
          std::tgamma(17.0) / (std::tgamma(c + 1) * std::tgamma(17 - c)) * std::pow(p2, c) * std::pow(1 - p2, 16 - c);
      if (tail >= kCalibrationFalseAlarm) break;
    }
    EXPECT_LT(below, kCalibrationFalseAlarm);
    EXPECT_DOUBLE_EQ(b16.coverage2_floor, c / 16.0);
  }
  EXPECT_GT(b3.hi, b16.hi);
  EXPECT_NEAR(b16.coverage2_expected, 0.947, 0.001);  // P(|Z| <= 2 sqrt(15/16))
  EXPECT_THROW(honest_band(1), std::invalid_argument);

  const std::size_t K = 16, M = 20000;
  const std::vector<double> x = gaussian_values(K * M, 13), e(K, 0.1), half(K, 0.05);
  std::size_t false_alarms = 0, caught = 0;
  for (std::size_t m = 0; m < M; ++m) {
    const std::vector<double> batch(x.begin() + static_cast<std::ptrdiff_t>(K * m),
                                    x.begin() + static_cast<std::ptrdiff_t>(K * (m + 1)));
    false_alarms += spread_verdict(seed_spread(batch, e)) != "honest" ? 1 : 0;
    caught += spread_verdict(seed_spread(batch, half)) == "errors too small" ? 1 : 0;
  }
  const double rate = static_cast<double>(false_alarms) / M, stated = 2 * kCalibrationFalseAlarm;
  EXPECT_LT(rate, stated + 4 * std::sqrt(stated * (1 - stated) / M)) << false_alarms << " of " << M;
  std::printf("K = 16: %zu of %zu honest calibrations called dishonest, %zu of %zu with errors half as large caught\n",
              false_alarms, M, caught, M);
  EXPECT_GT(static_cast<double>(caught) / M, 0.8) << caught << " of " << M;

  std::vector<double> sixteen = gaussian_values(K, 17);
  SeedSpread s = seed_spread(sixteen, e);
  s.sd_over_err = 0.943;
  s.coverage2 = 14.0 / 16;
  EXPECT_EQ(spread_verdict(s), "honest");
}

// A curve judged at many correlated times as one verdict (curve_verdict): honest errors fail it at the stated
// rate. Each of R = 200 calibrations has K = 100 seeds whose values follow random walks over M = 400 times
// (x_k(i) = sum of i + 1 standard normals, reported error sqrt(i + 1): honest, and correlated between times as a
// survival curve is). Bonferroni over the M times bounds the rate of honest curves called dishonest by
// kCalibrationFalseAlarm per test kind, 2% in all; the test allows that plus 4 binomial standard errors over R.
// A band for one time applied at every time (the verdict before) calls far more of them dishonest, and errors
// reported half as large are still caught in every calibration (sd / err near 2 lies above either band).
TEST(SeedSpread, CurveVerdictHoldsItsRateOverManyTimes) {
  const std::size_t K = 100, M = 400, R = 200;
  std::mt19937_64 gen(29);
  std::normal_distribution<double> normal(0, 1);
  std::size_t family = 0, per_time = 0, caught = 0;
  const HonestBand one = honest_band(K);
  std::vector<double> walk(K), e(K), half(K), x(K);
  for (std::size_t r = 0; r < R; ++r) {
    std::fill(walk.begin(), walk.end(), 0.0);
    std::vector<SeedSpread> honest, small;
    bool fails_one = false;
    for (std::size_t i = 0; i < M; ++i) {
      for (std::size_t k = 0; k < K; ++k) walk[k] += normal(gen);
      std::fill(e.begin(), e.end(), std::sqrt(static_cast<double>(i + 1)));
      std::fill(half.begin(), half.end(), 0.5 * std::sqrt(static_cast<double>(i + 1)));
      honest.push_back(seed_spread(walk, e));
      small.push_back(seed_spread(walk, half));
      const SeedSpread& s = honest.back();
      fails_one = fails_one || s.sd_over_err < one.lo || s.sd_over_err > one.hi || s.coverage2 < one.coverage2_floor;
    }
    const CurveVerdict v = curve_verdict(honest);
    EXPECT_EQ(v.judged, M);
    family += v.honest() ? 0 : 1;
    per_time += fails_one ? 1 : 0;
    caught += curve_verdict(small).honest() ? 0 : 1;
  }
  const double stated = 2 * kCalibrationFalseAlarm, n = static_cast<double>(R);
  const double allowed = stated + 4 * std::sqrt(stated * (1 - stated) / n);
  std::printf(
      "K = %zu, %zu times: %zu of %zu honest curves called dishonest (one time's band at every time: %zu), "
      "%zu of %zu with errors half as large caught\n",
      K, M, family, R, per_time, caught, R);
  EXPECT_LE(static_cast<double>(family) / n, allowed) << family << " of " << R;
  EXPECT_GT(static_cast<double>(per_time) / n, allowed) << per_time << " of " << R;
  EXPECT_EQ(caught, R);
  const HonestBand many = honest_band(K, M);
  EXPECT_DOUBLE_EQ(many.false_alarm_each, kCalibrationFalseAlarm / static_cast<double>(M));
  EXPECT_LT(many.coverage2_floor, one.coverage2_floor);
  EXPECT_LE(many.lo, one.lo);
  EXPECT_TRUE(curve_verdict({}).judged == 0 && !curve_verdict({}).honest());
  EXPECT_THROW(honest_band(K, 0), std::invalid_argument);
}

// The sd / err band is chi-square's central interval with K - 1 degrees of freedom, checked against that
// distribution's closed form for even degrees: P(chi2_{2m} <= x) = 1 - e^{-x/2} sum_{j<m} (x/2)^j / j!. At K = 5
// and 9 (4 and 8 degrees) both ends lie outside kHonestBand, so each end's tail is the judgement's rate / 2; at
// K = 17 the upper end is kHonestBand's for one test, not for four. A band with K degrees (mutant
// tests/mutants/calibration-band-dof.patch) puts the low end's tail at 0.0124 for K = 9 where 0.005 belongs.
double chi2_even_cdf(double x, int dof) {
  double term = 1, sum = 1;
  for (int j = 1; j < dof / 2; ++j) sum += term *= (x / 2) / j;
  return 1 - std::exp(-x / 2) * sum;
}

TEST(HonestBand, TheSdBandIsTheChiSquareIntervalOfKMinusOneDegrees) {
  int upper_free = 0, upper_bound = 0;
  for (const std::size_t tests : {std::size_t{1}, std::size_t{4}})
    for (const std::size_t K : {std::size_t{5}, std::size_t{9}, std::size_t{17}}) {
      const HonestBand b = honest_band(K, tests);
      const double a = kCalibrationFalseAlarm / static_cast<double>(tests), dof = static_cast<double>(K - 1);
      EXPECT_DOUBLE_EQ(b.false_alarm_each, a);
      ASSERT_LT(b.lo, kHonestBand[0]) << "K = " << K;
      EXPECT_NEAR(chi2_even_cdf(dof * b.lo * b.lo, static_cast<int>(K - 1)), a / 2, 1e-9 * a) << "K = " << K;
      if (b.hi > kHonestBand[1]) {
        ++upper_free;
        EXPECT_NEAR(1 - chi2_even_cdf(dof * b.hi * b.hi, static_cast<int>(K - 1)), a / 2, 1e-9 * a) << "K = " << K;
      } else {
        ++upper_bound;
        EXPECT_EQ(b.hi, kHonestBand[1]);
        EXPECT_LT(1 - chi2_even_cdf(dof * b.hi * b.hi, static_cast<int>(K - 1)), a / 2);  // the band binds
      }
    }
  EXPECT_EQ(upper_bound, 1);  // K = 17 at one test: sqrt(34.27 / 16) = 1.46 lies inside kHonestBand
  EXPECT_EQ(upper_free, 5);
}

// Each edge of the verdict decides as documented on either side of it (analysis/calibration.hpp): sd / err just
// inside lo and hi is honest, just outside "errors too large" / "errors too small"; coverage at 2 errors at the
// floor is honest, a hair under it "errors too small"; errors too large are "untested" only where the allowance is
// more than half the error (0.5 itself is not); no reported error is "no errors reported".
TEST(HonestBand, EachEdgeDecidesOnEitherSide) {
  for (const std::size_t K : {std::size_t{5}, std::size_t{16}, std::size_t{100}}) {
    const HonestBand b = honest_band(K);
    SeedSpread s;
    s.n = K;
    s.median_err = 0.1;
    s.coverage2 = 1;
    const auto at = [&](double sd_over_err, double coverage2, double share = 0) {
      SeedSpread t = s;
      t.sd_over_err = sd_over_err, t.coverage2 = coverage2;
      return spread_verdict(t, share);
    };
    const double below = -std::numeric_limits<double>::infinity(), above = -below;
    EXPECT_EQ(at(b.lo, 1), "honest") << K;
    EXPECT_EQ(at(std::nextafter(b.lo, below), 1), "errors too large") << K;
    EXPECT_EQ(at(b.hi, 1), "honest") << K;
    EXPECT_EQ(at(std::nextafter(b.hi, above), 1), "errors too small") << K;
    EXPECT_EQ(at(1, b.coverage2_floor), "honest") << K;
    EXPECT_EQ(at(1, std::nextafter(b.coverage2_floor, below)), "errors too small") << K;
    EXPECT_EQ(at(std::nextafter(b.lo, below), 1, 0.5), "errors too large") << K;
    EXPECT_EQ(at(std::nextafter(b.lo, below), 1, std::nextafter(0.5, above)),
              "untested: mostly the allowance for lines not drawn")
        << K;
    // the allowance excuses no small error
    EXPECT_EQ(at(std::nextafter(b.hi, above), 1, 1.0), "errors too small") << K;
    s.median_err = 0;
    EXPECT_EQ(at(1, 1), "no errors reported") << K;
  }
  // a curve: one time a hair outside the band, or a hair under the floor, and it is not honest
  const HonestBand b = honest_band(16, 3);
  SeedSpread s;
  s.n = 16, s.median_err = 0.1, s.sd_over_err = 1, s.coverage2 = 1;
  std::vector<SeedSpread> times(3, s);
  EXPECT_TRUE(curve_verdict(times).honest());
  times[1].sd_over_err = b.hi;
  times[2].coverage2 = b.coverage2_floor;
  EXPECT_TRUE(curve_verdict(times).honest());
  times[1].sd_over_err = std::nextafter(b.hi, 2.0);
  EXPECT_EQ(curve_verdict(times).outside, 1u);
  EXPECT_FALSE(curve_verdict(times).honest());
  times[1].sd_over_err = 1;
  times[2].coverage2 = std::nextafter(b.coverage2_floor, 0.0);
  EXPECT_EQ(curve_verdict(times).uncovered, 1u);
  EXPECT_FALSE(curve_verdict(times).honest());
  // too small wins over too large where both hold (coverage under its floor); seeds of one count only
  SeedSpread both = s;
  both.sd_over_err = std::nextafter(b.lo, 0.0), both.coverage2 = std::nextafter(b.coverage2_floor, 0.0);
  EXPECT_EQ(spread_verdict(both, 1.0), "errors too small");
  SeedSpread other = s;
  other.n = 17;
  EXPECT_THROW(curve_verdict({s, other}), std::invalid_argument);
}

// The times calibrate judges (resolved_in_seeds): every seed's P above 0 and the median seed's effective survivors at
// least min_effective -- at it resolved, a hair above it not; one seed with no survivor, not, whatever the others.
TEST(HonestBand, ATimeIsJudgedWhereTheMedianSeedHasItsSurvivors) {
  const auto curve = [](std::uint64_t alive) {
    SurvivalCurve c;
    c.particles = 1000;
    c.t = {0, 1};
    c.survivors = {1000, alive};
    return c;
  };
  const std::vector<SurvivalCurve> three = {curve(90), curve(100), curve(500)};
  EXPECT_TRUE(resolved_in_seeds(three, 1, 100.0));
  EXPECT_FALSE(resolved_in_seeds(three, 1, std::nextafter(100.0, 1e9)));
  EXPECT_FALSE(resolved_in_seeds({curve(100), curve(0), curve(500)}, 1, 1.0));
  EXPECT_TRUE(resolved_in_seeds({curve(100), curve(1), curve(500)}, 1, 1.0));
}

// Pooling split runs: P the mean, R = K sum R_k P_k^2 / (sum P_k)^2, N the sum: P's error of the pool is
// that of one run of all lines.
TEST(PoolCurves, SplitRunsPoolToOneRunOfAllLines) {
  SurvivalCurve a, b;
  for (SurvivalCurve* c : {&a, &b}) {
    c->weighted = c->lines = true;
    c->particles = 1000;
    c->t = {0, 1};
    c->survivors = {1000, 900};
    c->lines_alive = {1000, 900};
  }
  a.P_w = {1, 0.5};
  a.R = {1, 2};
  b.P_w = {1, 0.3};
  b.R = {1, 4};
  a.G = {0, 0.001};
  b.G = {0, 0.003};
  const SurvivalCurve p = pool_curves({a, b});
  EXPECT_EQ(p.particles, 2000u);
  EXPECT_DOUBLE_EQ(p.P(1), 0.4);
  // sum Y^2 = N (R_a P_a^2 + R_b P_b^2) = 1000 (0.5 + 0.36); sum Y = 1000 (0.8); R = 2000 sum Y^2 / (sum Y)^2
  EXPECT_DOUBLE_EQ(p.R[1], 2 * (0.5 + 0.36) / (0.8 * 0.8));
  EXPECT_EQ(p.lines_alive[1], 1800u);
  SurvivalCurve other = b;
  other.t = {0, 2};
  EXPECT_THROW(pool_curves({a, other}), std::invalid_argument);
}

// Runs of splitting over starts pool as one run of all their replicates: two runs of two replicates, P(1) from
// {0.4, 0.6} and {0.25, 0.35}, pool to the four's mean and standard error, computed here from the four values; a run
// of another replicate count is refused. (Pooling them read a split run's fields they lack: calibrate crashed.)
TEST(PoolCurves, RunsOfReplicatesPoolAsAllTheirReplicates) {
  const auto run = [](double lo, double hi) {
    SurvivalCurve c;
    c.weighted = c.replicated = true;
    c.replicates = 2, c.particles = 500;
    c.t = {0, 1};
    c.survivors = {1000, 400};
    c.P_w = {1, (lo + hi) / 2};
    c.E = {0, std::abs(hi - lo) / 2};  // two values: their sd / sqrt 2 is half their difference
    c.replicates_nonzero = {2, 2};
    return c;
  };
  const SurvivalCurve p = pool_curves({run(0.4, 0.6), run(0.25, 0.35)});
  const double v[] = {0.4, 0.6, 0.25, 0.35};
  double m = 0, ss = 0;
  for (const double x : v) m += x / 4;
  for (const double x : v) ss += (x - m) * (x - m);
  EXPECT_TRUE(p.replicated);
  EXPECT_EQ(p.replicates, 4);
  EXPECT_DOUBLE_EQ(p.P(1), m);
  EXPECT_NEAR(p.P_err(1), std::sqrt(ss / 3 / 4), 1e-15);
  EXPECT_EQ(p.P_err(0), 0.0);
  EXPECT_EQ(p.replicates_nonzero[1], 4);
  EXPECT_EQ(p.survivors[1], 800u);
  SurvivalCurve three = run(0.4, 0.6);
  three.replicates = 3;
  EXPECT_THROW(pool_curves({run(0.4, 0.6), three}), std::invalid_argument);
}

// calibrate on a tiny uniform scene: calibration.csv has a row per grid time, calibration.json the
// statistics, both written under the directory, the points are ordinary runs; a second call skips them.
TEST(Calibrate, WritesItsFilesAndResumes) {
  const test::ScratchDir dir("rotleak_calibrate_test_");
  std::filesystem::create_directories(dir.path);
  const std::string scene = (dir.path / "scene.toml").string();
  write_file_atomic(scene, "[ensemble]\nparticles = 3000\n[run]\nt_max = 500\n[observe]\nsurvival_dt = 5\n");
  CalibrateRequest req;
  req.scene_path = scene;
  req.seeds = 4;
  req.out = dir.path / "cal";
  req.run.threads = 1;
  const CalibrateOutcome out = calibrate(req);
  EXPECT_EQ(out.ran, 4u);
  const std::string csv = read_file(req.out / "calibration.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "t,resolved,seeds,P,P_err,P_err_model,sd_over_err,chi2_dof,coverage1,coverage2,max_over_median");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 101);
  EXPECT_EQ(out.document.at("seeds").size(), 4u);
  EXPECT_TRUE(out.document.at("statistics").contains("kappa"));
  EXPECT_TRUE(out.document.at("statistics").contains("kappa_total"));
  EXPECT_GT(out.document.at("P").at("resolved_times").get<int>(), 50);
  const CalibrateOutcome again = calibrate(req);
  EXPECT_EQ(again.ran, 0u);
  EXPECT_EQ(again.skipped, 4u);
  EXPECT_EQ(read_file(req.out / "calibration.csv"), csv);
  req.seeds = 1;
  EXPECT_THROW(calibrate(req), InputError);
  req.seeds = 4;
  req.overrides = {"ensemble.seed=3"};
  EXPECT_THROW(calibrate(req), InputError);
}

// The allowance for unsplit lines not drawn, by hand: a group of 50 unsplit lines of weight 0.02 (N = 1000
// lines) until t = 10, then 15 until t = 20, then 5: t_r = 20 (the last time with 10), t_a = 10 (the last
// with 20, after the first split at t = 2); gamma by maximum likelihood, every leaving after t_a over the
// lines' time in the group from t_a, 45 / (50 + 10 x 15 + 19 x 5); past t_r P's variance gains
// w P_g(t_r) max(exp(-gamma (t - t_r)), P(t) / P(t_r)) / N less what the 5 lines alive still give. P decays
// at 0.1 until t = 30 (slower than gamma: mixing sets the allowance) and at 0.5 after (the group's own
// rate does). A second group of 500 light lines (weight 1e-6) stays populated and adds nothing.
namespace {

// A split run of N = 1000 lines on t = 0..40 (R = 2) with one unsplit group of weight w = 0.02 whose 50 lines fall to
// 15 after t = 10 and to 5 after t = 20, P(t) given: the UnsplitAllowance tests' curve.
template <class Pt>
SurvivalCurve one_heavy_group(Pt P, double w) {
  SurvivalCurve c;
  c.weighted = c.lines = true;
  c.particles = 1000;
  c.first_split = 2;
  const double n = 1000;
  SurvivalCurve::UnsplitGroup heavy;
  heavy.classes = {unsplit_class(w)};
  for (int k = 0; k <= 40; ++k) {
    const std::uint64_t alive = k <= 10 ? 50 : k <= 20 ? 15 : 5;
    c.t.push_back(k);
    c.survivors.push_back(1000);
    c.lines_alive.push_back(1000);
    c.P_w.push_back(P(k));
    c.R.push_back(2);
    c.G.push_back(1 / n);
    heavy.lines.push_back(alive);
    heavy.P.push_back(static_cast<double>(alive) * w / n);
    heavy.var.push_back(static_cast<double>(alive) * w * w / (n * n));
  }
  c.unsplit = {heavy};
  return c;
}

}  // namespace

TEST(UnsplitAllowance, ExtendsAGroupsDecayPastItsLastReliableTime) {
  const double n = 1000, w = 0.02, light = 1e-6;
  const auto P = [](double t) { return 1e-2 * std::exp(t <= 30 ? -0.1 * t : -3 - 0.5 * (t - 30)); };
  SurvivalCurve c = one_heavy_group(P, w);
  SurvivalCurve::UnsplitGroup many;  // and 500 light lines that never decay: no allowance of their own
  many.classes = {unsplit_class(light)};
  for (int k = 0; k <= 40; ++k) {
    many.lines.push_back(500);
    many.P.push_back(500 * light / n);
    many.var.push_back(500 * light * light / (n * n));
  }
  c.unsplit.push_back(many);
  const SurvivalCurve before = c;
  add_unsplit_allowance(c);
  const SurvivalCurve::UnsplitGroup& h = c.unsplit[0];
  ASSERT_TRUE(h.allowance);
  EXPECT_FALSE(c.unsplit[1].allowance);
  EXPECT_EQ(h.reliable_until, 20);
  EXPECT_EQ(h.rate_from, 10);
  const double gamma = 45.0 / (50 + 10 * 15 + 19 * 5);
  EXPECT_NEAR(h.decay_rate, gamma, 1e-12);
  EXPECT_NEAR(h.typical_weight, w, 1e-12);
  bool own = false, mixing = false;  // both branches are met
  for (int k = 0; k <= 40; ++k) {
    const double added = c.P_w[k] * c.P_w[k] * (c.R[k] - before.R[k]) / n;
    const double decay = std::max(std::exp(-gamma * (k - 20)), P(k) / P(20));
    if (k > 20) (decay == P(k) / P(20) ? mixing : own) = true;
    const double expect = k <= 20 ? 0.0 : std::max(0.0, w * (15 * w / n) * decay / n - 5 * w * w / (n * n));
    EXPECT_NEAR(added, expect, 1e-12 * (expect + 1e-30)) << "t = " << k;
  }
  EXPECT_TRUE(own && mixing);
  ASSERT_TRUE(c.allowance_unresolved_from.has_value());
  EXPECT_GT(*c.allowance_unresolved_from, 20);
  for (std::size_t k = 1; k < c.G.size(); ++k) EXPECT_GE(c.G[k], c.G[k - 1]);
}

// Where P becomes a bound, on either side of each edge: allowance_unresolved_from is the first time the allowance
// exceeds kAllowanceShare = 1/2 of the lines' own variance P^2 (R - 1) / N. The fixture above with R chosen per time
// so that the allowance is just under half the own variance up to t = 25 and just over it there: it starts at 25;
// with 25 just under as well, at 26. p_bounded holds from that time on, for split runs only.
TEST(UnsplitAllowance, PIsABoundFromTheFirstTimeTheAllowanceTakesHalfItsVariance) {
  const double n = 1000;
  const SurvivalCurve c = one_heavy_group([](double t) { return 1e-2 * std::exp(-0.1 * t); }, 0.02);
  SurvivalCurve probe = c;
  add_unsplit_allowance(probe);
  std::vector<double> extra(c.t.size());  // the allowance, which R does not change
  for (std::size_t k = 0; k < c.t.size(); ++k) extra[k] = c.P_w[k] * c.P_w[k] * (probe.R[k] - c.R[k]) / n;
  ASSERT_EQ(extra[20], 0.0);
  ASSERT_GT(extra[25], 0.0);
  ASSERT_GT(extra[26], 0.0);
  for (std::size_t edge : {std::size_t{25}, std::size_t{26}}) {
    SurvivalCurve d = c;
    for (std::size_t k = 0; k < d.t.size(); ++k)
      if (extra[k] > 0)
        d.R[k] = 1 + n * extra[k] / (kAllowanceShare * d.P_w[k] * d.P_w[k]) * (k < edge ? 1 + 1e-6 : 1 - 1e-6);
    add_unsplit_allowance(d);
    ASSERT_TRUE(d.allowance_unresolved_from.has_value()) << edge;
    EXPECT_EQ(*d.allowance_unresolved_from, static_cast<double>(edge));
    EXPECT_FALSE(p_bounded(d, edge - 1));
    EXPECT_TRUE(p_bounded(d, edge));
    EXPECT_TRUE(p_bounded(d, d.t.size() - 1));
    d.lines = false;  // a run without splitting never bounds P so
    EXPECT_FALSE(p_bounded(d, d.t.size() - 1));
  }
  SurvivalCurve none = c;  // the allowance under half everywhere: P is measured at every time
  for (std::size_t k = 0; k < none.t.size(); ++k)
    if (extra[k] > 0) none.R[k] = 1 + n * extra[k] / (kAllowanceShare * none.P_w[k] * none.P_w[k]) * (1 + 1e-6);
  add_unsplit_allowance(none);
  EXPECT_FALSE(none.allowance_unresolved_from.has_value());
  EXPECT_FALSE(p_bounded(none, none.t.size() - 1));
}

// Weight classes come from the binary exponent alone: factors of 8, the heaviest from 1/4 up.
TEST(UnsplitAllowance, WeightClassesAreFactorsOfEight) {
  EXPECT_EQ(unsplit_class(2.0), 0);
  EXPECT_EQ(unsplit_class(0.25), 0);
  EXPECT_EQ(unsplit_class(0.2499), 1);
  EXPECT_EQ(unsplit_class(1.0 / 32), 1);
  EXPECT_EQ(unsplit_class(0.0312), 2);
  EXPECT_EQ(unsplit_class(1e-300), kUnsplitClasses - 1);
}

// lines.csv keeps a split run's structure (the unsplit lines class by class, R before the allowance): read back
// with survival.csv it gives the run's own P_err, G, unresolved_from and tail errors bit for bit, where
// survival.csv alone (P_err only, no groups) gives other tail errors; one curve pools to itself bit for bit, and
// the pool of two sums each class's lines.
TEST(LinesCsv, ARefitGivesTheRunsOwnErrorsBitForBit) {
  const Scene scene = parse_scene("", {"leak.omega=82/83", "ensemble.sampling=mupo", "run.splitting=true",
                                       "run.t_max=6000", "ensemble.particles=20000"});
  RunOptions o;
  const RunSummary run = summarise(scene, run_ensemble(plan_run(scene, o), o));
  ASSERT_TRUE(run.curve.allowance_unresolved_from.has_value());
  SurvivalCurve back = read_survival_csv(survival_csv(run.curve), scene);
  const SurvivalCurve csv_only = back;
  read_lines_csv(lines_csv(run.curve), scene, back);
  std::size_t differ_without = 0;
  for (std::size_t i = 0; i < run.curve.t.size(); ++i) {
    ASSERT_EQ(back.P_err(i), run.curve.P_err(i)) << "t = " << run.curve.t[i];
    ASSERT_EQ(back.G[i], run.curve.G[i]) << "t = " << run.curve.t[i];
    differ_without += csv_only.P_err(i) != run.curve.P_err(i) || csv_only.G[i] != run.curve.G[i];
  }
  EXPECT_EQ(back.allowance_unresolved_from, run.curve.allowance_unresolved_from);
  EXPECT_FALSE(csv_only.allowance_unresolved_from.has_value());
  RunSummary a, b, c;
  a.scene = b.scene = c.scene = scene;
  a.curve = run.curve;
  b.curve = back;
  c.curve = csv_only;
  fit_curve(a);
  fit_curve(b);
  fit_curve(c);
  EXPECT_EQ(a.amplitude.std_error, b.amplitude.std_error);
  EXPECT_EQ(a.tail.std_error, b.tail.std_error);
  EXPECT_EQ(a.alpha.upper_bound, b.alpha.upper_bound);
  EXPECT_EQ(a.tail_class.tail, b.tail_class.tail);

  std::printf("survival.csv alone: P_err or G differ at %zu of %zu grid times\n", differ_without, run.curve.t.size());
  EXPECT_GT(differ_without, 0u);

  const SurvivalCurve one = pool_curves({run.curve}, &scene);
  for (std::size_t i = 0; i < run.curve.t.size(); ++i) ASSERT_EQ(one.P_err(i), run.curve.P_err(i)) << i;
  EXPECT_EQ(one.allowance_unresolved_from, run.curve.allowance_unresolved_from);
  const SurvivalCurve two = pool_curves({run.curve, back}, &scene);
  EXPECT_EQ(two.particles, 2 * run.curve.particles);
  ASSERT_EQ(two.unsplit_classes.size(), run.curve.unsplit_classes.size());
  for (std::size_t q = 0; q < two.unsplit_classes.size(); ++q)
    EXPECT_EQ(two.unsplit_classes[q].lines.front(), 2 * run.curve.unsplit_classes[q].lines.front());

  // damage is a one-line error naming lines.csv
  const std::string good = lines_csv(run.curve);
  for (const std::string& bad :
       {good.substr(0, good.size() / 2), std::string("t,P\n"), good.substr(0, good.find('\n') + 1) + "0,2,1,1,1,1\n"}) {
    SurvivalCurve x = read_survival_csv(survival_csv(run.curve), scene);
    try {
      read_lines_csv(bad, scene, x);
      ADD_FAILURE() << "read damaged lines.csv";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("lines.csv", 0), 0u) << e.what();
    }
  }
}
