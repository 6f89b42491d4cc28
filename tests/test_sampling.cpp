// Importance sampling of the initial conditions (sim/model/sampling.hpp): the weights integrate to 1, are
// functions of (seed, id), the exact weighted sums do not depend on thread count or order, and the
// "mupo" scheme estimates the same survival curve as "uniform" (unbiasedness), scene by scene.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "analysis/fits.hpp"
#include "io/scene_file.hpp"
#include "numeric/fixed_sum.hpp"
#include "paths.hpp"
#include "sim/engine/engine.hpp"
#include "sim/model/sampling.hpp"
#include "sim/tally/survival.hpp"

namespace rotleak {
namespace {

Scene scene_of(const std::string& file, std::vector<std::string> sets) {
  return load_scene(std::string(rotleak::test::source_dir()) + "/data/scenes/" + file, sets);
}

std::pair<long, std::vector<std::uint64_t>> a_limbs_of(const FixedSum& f) { return {f.base(), f.limbs()}; }

TEST(FixedSum, IsExactAndOrderIndependent) {
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> exponent(-60, 10);
  std::vector<double> x(20000);
  for (double& v : x) v = std::exp2(exponent(gen));
  FixedSum forward, backward, split_a, split_b;
  for (double v : x) forward.add(v);
  for (auto it = x.rbegin(); it != x.rend(); ++it) backward.add(*it);
  for (std::size_t i = 0; i < x.size(); ++i) (i % 3 ? split_a : split_b).add(x[i]);
  split_a.merge(split_b);
  EXPECT_TRUE(forward == backward);
  EXPECT_TRUE(forward == split_a);
  long double ref = 0;
  std::sort(x.begin(), x.end());
  for (double v : x) ref += v;
  EXPECT_NEAR(forward.value(), static_cast<double>(ref), 1e-15 * static_cast<double>(ref));
  FixedSum part;
  for (std::size_t i = 0; i < 100; ++i) part.add(x[i]);
  const FixedSum rest = forward.minus(part);
  FixedSum again = rest;
  again.merge(part);
  EXPECT_TRUE(again == forward);
  EXPECT_THROW(part.minus(forward), std::logic_error);
  EXPECT_THROW(part.add(-1), std::domain_error);
}

// Terms at the scale of the one before go to a 128-bit staging word (fixed_sum.hpp): the sum must read,
// compare, merge, subtract and store exactly as if every term went straight into the limbs, also when
// the word wraps around. Reference: each term in a FixedSum of its own, merged (merge adds limbs).
TEST(FixedSum, StagedTermsReadAsAddedAlsoWhenTheWordWraps) {
  const double w = std::nextafter(2.0, 4.0);  // 2^53 - 1 ... times 2^-51: a full 53-bit integer
  const std::uint64_t n = std::uint64_t{1} << 63;
  FixedSum staged, ref;
  const auto one = [](double x, std::uint64_t k) {
    FixedSum f;
    f.add_times(x, k);
    return f;
  };
  // 2^13 terms of about 2^116 at one scale: more than 2^128 in all, so the staging word wraps
  for (int i = 0; i < 8192; ++i) {
    staged.add_times(w, n);
    ref.merge(one(w, n));
    if (i == 4095) {  // a reader in the middle, on a copy and on the staged sum itself
      const FixedSum copy = staged;
      EXPECT_TRUE(copy == ref);
      EXPECT_EQ(staged.value(), ref.value());
      EXPECT_EQ(staged.limbs(), ref.limbs());
      EXPECT_EQ(staged.base(), ref.base());
    }
  }
  // other scales in between, then back: each change of scale carries the word into the limbs
  for (double x : {0.5, 0.75, 1e-300, 3.0, 0.5, std::ldexp(1.0, -1074), 0.625}) {
    staged.add(x), staged.add_times(x, 3), staged.add_square(x);
    ref.merge(one(x, 1)), ref.merge(one(x, 3));
    FixedSum sq;
    sq.add_square(x);
    ref.merge(sq);
  }
  EXPECT_TRUE(staged == ref);
  EXPECT_TRUE(ref == staged);
  EXPECT_EQ(staged.limbs(), ref.limbs());
  EXPECT_EQ(staged.scaled().m, ref.scaled().m);
  EXPECT_EQ(staged.scaled().e, ref.scaled().e);
  // a staged sum merged into another, and subtracted from itself, leaves what the limbs say
  FixedSum both = ref;
  both.merge(staged);
  FixedSum twice = ref;
  twice.merge(ref);
  EXPECT_TRUE(both == twice);
  EXPECT_TRUE(both.minus(staged) == ref);
  EXPECT_TRUE(staged.minus(ref) == FixedSum());
  FixedSum stored = FixedSum::from_limbs(staged.base(), staged.limbs());
  EXPECT_TRUE(stored == ref);
  FixedSum zero;
  zero.add(0.0);
  EXPECT_TRUE(zero == FixedSum());
  zero.add_times(0.25, 2);
  EXPECT_FALSE(zero == FixedSum());  // staged only, not yet in the limbs
  EXPECT_EQ(zero.value(), 0.5);
}

// Terms at nearby scales share the staging word (fixed_sum.hpp: it starts kStageBelow = 24 binades
// below its first term): weights spread over 40 binades as importance sampling gives them, added once
// or n times in random order; and, on a fresh word each, a 53-bit integer 73 .. 128 binades above the
// word's scale (below 2^126, 2^127, 2^128, 2^129, ...: from 76 on it would not fit the word), once and
// twice (the sum may wrap instead), then terms 24 and 25 binades below the first one (at the scale,
// and below it). Reference: each term in a FixedSum of its own, merged.
TEST(FixedSum, TermsOfNearbyScalesShareTheWordExactly) {
  const auto one = [](double x, std::uint64_t k) {
    FixedSum f;
    f.add_times(x, k);
    return f;
  };
  std::mt19937_64 gen(23);
  std::uniform_real_distribution<double> exponent(-40, 1);
  std::uniform_int_distribution<std::uint64_t> times(1, std::uint64_t{1} << 40);
  FixedSum staged, ref;
  for (int i = 0; i < 20000; ++i) {
    const double w = std::exp2(exponent(gen));
    const std::uint64_t n = i % 3 ? 1 : times(gen);
    staged.add_times(w, n);
    ref.merge(one(w, n));
    if (i % 4999 == 0) {
      EXPECT_EQ(staged.limbs(), ref.limbs()) << "after " << i + 1 << " terms";
    }
  }
  EXPECT_TRUE(staged == ref);
  const double m = std::nextafter(2.0, 0.0);  // (2^53 - 1) 2^-52: its integer has 53 bits
  for (int above : {73, 74, 75, 76, 100, 127, 128})
    for (int reps = 1; reps <= 2; ++reps) {
      FixedSum edge, edge_ref;
      edge.add(m), edge_ref.merge(one(m, 1));      // the word's scale: 2^(-52 - 24)
      const double x = std::ldexp(m, above - 24);  // its integer sits `above` binades above that scale
      for (int r = 0; r < reps; ++r) edge.add(x), edge_ref.merge(one(x, 1));
      for (int below : {24, 25}) {
        const double y = std::ldexp(m, -below);
        edge.add(y), edge_ref.merge(one(y, 1));
      }
      EXPECT_TRUE(edge == edge_ref) << above << " binades above, " << reps << " times";
      EXPECT_EQ(edge.limbs(), edge_ref.limbs()) << above << " binades above, " << reps << " times";
    }
}

// Split runs weigh particles down to 1e-300 and square those weights: the sum must keep every bit of
// terms far below 2^-128 (the old fixed grid dropped a 1e-40 entirely), in any order, and its square
// terms below the range of a double. Exact: a sum of powers of two is checked bit for bit.
TEST(FixedSum, KeepsTinyTermsExactlyInAnyOrder) {
  std::vector<double> x;
  for (int k = 100; k <= 127; ++k) x.push_back(std::ldexp(1.0, -k));  // 2^-100 .. 2^-127: all bits distinct
  x.push_back(1e-300);
  x.push_back(1e-40);
  x.push_back(std::ldexp(1.0, -1074));  // the smallest subnormal
  x.push_back(0.75);
  std::mt19937_64 gen(11);
  FixedSum first;
  for (double v : x) first.add(v);
  for (int trial = 0; trial < 50; ++trial) {
    std::shuffle(x.begin(), x.end(), gen);
    FixedSum a, b;
    for (std::size_t i = 0; i < x.size(); ++i) (i % 2 ? a : b).add(x[i]);
    a.merge(b);
    ASSERT_TRUE(a == first) << "trial " << trial;
  }
  // removing the big terms leaves exactly the small ones: 2^-100 .. 2^-127 sum to 2^-99 - 2^-127
  FixedSum big;
  for (double v : {1e-300, 1e-40, std::ldexp(1.0, -1074), 0.75}) big.add(v);
  const FixedSum small = first.minus(big);
  EXPECT_EQ(small.value(), std::ldexp(1.0, -99) - std::ldexp(1.0, -127));
  FixedSum tiny;
  tiny.add(1e-300);
  EXPECT_EQ(tiny.value(), 1e-300);
  FixedSum sub;
  sub.add(std::ldexp(1.0, -1074));
  sub.add(std::ldexp(1.0, -1074));
  EXPECT_EQ(sub.value(), std::ldexp(1.0, -1073));
  // squares: (1e-300)^2 = 1e-600 is kept, as m 2^e; twice it over once it is exactly 2
  FixedSum sq, sq2;
  sq.add_square(1e-300);
  sq2.add_square(1e-300);
  sq2.add_square(1e-300);
  EXPECT_EQ(sq.value(), 0.0);  // below the double range
  EXPECT_EQ(sq2.scaled().over(sq.scaled()), 2.0);
  EXPECT_NEAR(std::log10(sq.scaled().m) + static_cast<double>(sq.scaled().e) * std::log10(2.0), -600.0, 1e-12);
  // (1 + 2^-52)^2 = 1 + 2^-51 + 2^-104: add_square keeps the last bit that x * x rounds away
  FixedSum exact_sq, one;
  exact_sq.add_square(1 + 0x1p-52);
  one.add(1 + 0x1p-51);
  const FixedSum rest = exact_sq.minus(one);
  EXPECT_EQ(rest.value(), 0x1p-104);
  // bytes: equal values give equal (base, limbs) whatever the history
  EXPECT_EQ(a_limbs_of(first), a_limbs_of(FixedSum::from_limbs(first.base(), first.limbs())));
}

// Equality compares the values held, not the span between two sums' scales: a sum read from a damaged file
// at limb 2^50 against zero took 2^50 steps (found by fuzz_tally as a hang). The extremes the suite forms
// (the smallest subnormal squared, 2^1000 times many terms) lie inside [kLowestLimb, kLimbEnd).
TEST(FixedSum, EqualityIsOfValuesAndTheRangeHoldsEveryTerm) {
  const FixedSum far = FixedSum::from_limbs(1L << 50, {1});
  EXPECT_FALSE(far == FixedSum{});
  EXPECT_FALSE(FixedSum{} == far);
  EXPECT_TRUE(FixedSum::from_limbs(0, {0, 1, 0}) == FixedSum::from_limbs(1, {1}));
  EXPECT_FALSE(FixedSum::from_limbs(0, {0, 1}) == FixedSum::from_limbs(0, {1}));
  FixedSum staged, settled;
  staged.add(0.5);
  settled.merge(staged);
  EXPECT_TRUE(staged == settled);
  FixedSum low, high;
  low.add_square(std::ldexp(1.0, -1074));
  for (int k = 0; k < 64; ++k) high.add_times(std::nextafter(0x1p1000, 0.0), ~0ull);
  for (const FixedSum* f : {&low, &high}) {
    EXPECT_GE(f->base(), FixedSum::kLowestLimb);
    EXPECT_LE(f->base() + static_cast<long>(f->limbs().size()), FixedSum::kLimbEnd);
  }
}

// E_q[w] = 1. Error model: the sample mean of N independent weights, standard error sd(w) / sqrt(N);
// 5 standard errors (one test per scheme).
TEST(Sampling, WeightsIntegrateToOne) {
  for (const char* init : {"birkhoff", "flow"}) {
    const Scene scene =
        scene_of("stationary_sL_0.toml", {"ensemble.sampling=mupo", std::string("ensemble.init=") + init});
    const auto sampler = make_sampler(scene);
    const std::uint64_t n = 1000000;
    double sum = 0, sum2 = 0, biased = 0;
    for (std::uint64_t id = 0; id < n; ++id) {
      const double w = sampler->weight(sampler->draw(id));
      ASSERT_GT(w, 0.0);
      ASSERT_LE(w, 1 / scene.sampling.eps * (1 + 1e-12));
      sum += w;
      sum2 += w * w;
      biased += w < 0.1;
    }
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    EXPECT_NEAR(mean, 1.0, 5 * sd / std::sqrt(static_cast<double>(n))) << init;
    // a share 1 - eps of the particles come from the concentrated component, with small weights
    EXPECT_GT(biased / n, 0.8 * (1 - scene.sampling.eps)) << init;
  }
}

// Sharper: E_q[w 1_R] = u(R) for any region R, and in particular for the small regions where the
// concentrated component puts its particles (a wrong normalisation of g shows there at once, while
// the whole-space mean hardly moves). Same error model, 5 standard errors per region.
TEST(Sampling, WeightsGiveTheUniformMeasureOfRegions) {
  for (const char* init : {"birkhoff", "flow"}) {
    const Scene scene =
        scene_of("stationary_sL_0.toml", {"ensemble.sampling=mupo", std::string("ensemble.init=") + init});
    const auto sampler = make_sampler(scene);
    const bool flow = std::string(init) == "flow";
    const double d = 2, r = 1, L = 2 * d + 2 * M_PI * r, A = 2 * r * d + M_PI * r * r;
    struct Region {
      double lo, hi;  // |p| (birkhoff) or |angle - vertical| (flow)
      double measure;
    };
    // u-measure: birkhoff straight fraction 2d/L times |p| range (p uniform on (-1, 1), both signs);
    // flow: rectangle fraction 2rd/A times the angle fraction 2 x 2 (hi - lo) / (2 pi)
    auto measure = [&](double lo, double hi) {
      return flow ? (2 * r * d / A) * (4 * (hi - lo) / (2 * M_PI)) : (2 * d / L) * (hi - lo);
    };
    const std::vector<Region> regions = {
        {1e-6, 1e-3, measure(1e-6, 1e-3)}, {1e-11, 1e-9, measure(1e-11, 1e-9)}, {1e-3, 0.05, measure(1e-3, 0.05)}};
    const std::uint64_t n = 1000000;
    std::vector<double> sum(regions.size()), sum2(regions.size());
    for (std::uint64_t id = 0; id < n; ++id) {
      const InitialDraw dr = sampler->draw(id);
      const double w = sampler->weight(dr);
      double a;
      bool inside;
      if (flow) {
        const double centre = dr.u < 0.5 ? 0.25 : 0.75;
        a = std::abs(2 * M_PI * (dr.u - centre));
        inside = std::abs(dr.x) <= d / 2 && std::abs(dr.y) < r;
      } else {
        a = std::abs(dr.p);
        const double j0 = (d / 2) / L, j1 = (d / 2 + M_PI * r) / L, j2 = (1.5 * d + M_PI * r) / L;
        inside = dr.s < j0 || dr.s >= 1 - j0 || (dr.s >= j1 && dr.s < j2);
      }
      for (std::size_t k = 0; k < regions.size(); ++k)
        if (inside && a >= regions[k].lo && a < regions[k].hi) {
          sum[k] += w;
          sum2[k] += w * w;
        }
    }
    for (std::size_t k = 0; k < regions.size(); ++k) {
      const double mean = sum[k] / n, se = std::sqrt((sum2[k] / n - mean * mean) / n);
      EXPECT_NEAR(mean, regions[k].measure, 5 * se)
          << init << " region [" << regions[k].lo << ", " << regions[k].hi << ")";
      EXPECT_LT(se, 0.02 * regions[k].measure) << "the test must resolve the region";
    }
  }
}

// The riding bands (docs/model.md, "Riding orbits") by hand: at omega = 100/101, r = 1, 2X mod 1 = 97/101 and
// its best approximation 24/25 leaves eta = 97/101 - 24/25 = 1/2525: |p| = L / (4 * 2525) = 1.018e-3, where
// unsplit runs of 10^8 lines drawn on |p| in [5e-4, 2e-3] found their survivors past t = 3000 (1433 of them, 1273
// in [9.5e-4, 1.1e-3]); at 82/83, 79/83 and 20/21 leave eta = -1/1743 and |p| = L / (4 * 1743) = 1.47e-3 (the
// survivors' peak: 80 of 185 in [1.41e-3, 1.62e-3]). A stationary leak and an exact rational 2X (omega = 1/2)
// have none; the band's half width is L (1/b - lambda) / d, relative.
TEST(Sampling, RidingBandsByHand) {
  const double L = 4 + 2 * M_PI;
  const auto band_of = [](const std::vector<RidingBand>& bands, long long a, long long b) -> const RidingBand* {
    for (const RidingBand& x : bands)
      if (x.a == a && x.b == b) return &x;
    return nullptr;
  };
  const auto s101 = riding_bands(scene_of("stationary_sL_0.toml", {"ensemble.sampling=mupo", "leak.omega=100/101"}));
  const RidingBand* b25 = band_of(s101, 24, 25);
  ASSERT_NE(b25, nullptr);
  EXPECT_NEAR(b25->eta, 1.0 / 2525, 1e-15);
  EXPECT_NEAR(b25->p, L / (4 * 2525), 1e-15);
  EXPECT_NEAR(b25->hi / b25->p - 1, L * (1.0 / 25 - 0.01) / 2, 1e-12);
  const auto s83 = riding_bands(scene_of("stationary_sL_0.toml", {"ensemble.sampling=mupo", "leak.omega=82/83"}));
  const RidingBand* b21 = band_of(s83, 20, 21);
  ASSERT_NE(b21, nullptr);
  EXPECT_NEAR(b21->eta, 79.0 / 83 - 20.0 / 21, 1e-15);
  EXPECT_NEAR(b21->p, L / (4 * 1743), 1e-15);
  EXPECT_TRUE(riding_bands(scene_of("stationary_sL_0.toml", {"ensemble.sampling=mupo"})).empty());
  EXPECT_TRUE(riding_bands(scene_of("stationary_sL_0.toml", {"ensemble.sampling=mupo", "leak.omega=1/2"})).empty());
  // 2X mod 1 = 1/100 + 1e-7 with lambda = 1/100: the best approximation 1/100 has b lambda = 1 exactly -- its
  // spots cover the edge, no gap to ride in (the band's width L (1/b - lambda) / d would be 0) -- so no band
  const auto edge =
      riding_bands(scene_of("stationary_sL_0.toml", {"ensemble.sampling=mupo", "leak.omega=0.002500025"}));
  EXPECT_EQ(band_of(edge, 1, 100), nullptr);
  for (const RidingBand& b : edge) EXPECT_LT(static_cast<double>(b.b) * 0.01, 1.0) << b.a << "/" << b.b;
  for (const RidingBand& b : s101) {  // every band: a best approximation with gaps, inside the mupo range
    EXPECT_LT(static_cast<double>(b.b) * 0.01, 1.0);
    EXPECT_GE(b.p, 1e-12);
    EXPECT_LE(b.p, 0.05);
  }
}

// With riding bands the weights stay u / q exactly: E_q[w 1_R] = u(R) on a riding band and beside it, and
// E_q[w] = 1 (error model as above: 5 standard errors). ride = 0 draws the scheme without bands bit for bit.
TEST(Sampling, RidingBandsKeepTheWeightsExact) {
  const Scene scene =
      scene_of("stationary_sL_0.toml", {"ensemble.sampling=mupo", "leak.omega=100/101", "ensemble.sampling_ride=0.5"});
  const auto sampler = make_sampler(scene);
  const double d = 2, L = 2 * d + 2 * M_PI;
  const RidingBand band = riding_bands(scene).at(1);  // 24/25
  ASSERT_EQ(band.b, 25);
  struct Region {
    double lo, hi;
  };
  const std::vector<Region> regions = {{band.lo, band.hi}, {band.p, band.hi}, {1e-2, 0.05}, {1e-6, 1e-4}};
  const std::uint64_t n = 1000000;
  std::vector<double> sum(regions.size()), sum2(regions.size());
  double all = 0, all2 = 0;
  const double j0 = (d / 2) / L, j1 = (d / 2 + M_PI) / L, j2 = (1.5 * d + M_PI) / L;
  for (std::uint64_t id = 0; id < n; ++id) {
    const InitialDraw dr = sampler->draw(id);
    const double w = sampler->weight(dr);
    all += w;
    all2 += w * w;
    const bool inside = dr.s < j0 || dr.s >= 1 - j0 || (dr.s >= j1 && dr.s < j2);
    for (std::size_t k = 0; k < regions.size(); ++k)
      if (inside && std::abs(dr.p) >= regions[k].lo && std::abs(dr.p) < regions[k].hi) {
        sum[k] += w;
        sum2[k] += w * w;
      }
  }
  const double mean = all / n;
  EXPECT_NEAR(mean, 1.0, 5 * std::sqrt((all2 / n - mean * mean) / n));
  for (std::size_t k = 0; k < regions.size(); ++k) {
    const double m = sum[k] / n, se = std::sqrt((sum2[k] / n - m * m) / n);
    const double measure = (2 * d / L) * (regions[k].hi - regions[k].lo);
    EXPECT_NEAR(m, measure, 5 * se) << "region [" << regions[k].lo << ", " << regions[k].hi << ")";
    EXPECT_LT(se, 0.02 * measure) << "the test must resolve the region";
  }
  const auto plain = make_sampler(scene_of("stationary_sL_0.toml", {"ensemble.sampling=mupo", "leak.omega=100/101"}));
  const auto zero = make_sampler(
      scene_of("stationary_sL_0.toml", {"ensemble.sampling=mupo", "leak.omega=100/101", "ensemble.sampling_ride=0"}));
  for (std::uint64_t id = 0; id < 1000; ++id) {
    const InitialDraw a = plain->draw(id), b = zero->draw(id);
    EXPECT_EQ(a.s, b.s);
    EXPECT_EQ(a.p, b.p);
    EXPECT_EQ(plain->weight(a), zero->weight(b));
  }
}

TEST(Sampling, WeightIsAFunctionOfSeedAndId) {
  const Scene scene = scene_of("stationary_sL_0.toml", {"ensemble.sampling=mupo"});
  const auto a = make_sampler(scene), b = make_sampler(scene);
  for (std::uint64_t id : {0ull, 1ull, 77ull, 123456789ull}) {
    const InitialDraw da = a->draw(id), db = b->draw(id);
    EXPECT_EQ(da.s, db.s);
    EXPECT_EQ(da.p, db.p);
    EXPECT_EQ(a->weight(da), b->weight(db));
  }
  // the uniform component of the mixture draws exactly the uniform scheme's particle
  const Scene uniform = scene_of("stationary_sL_0.toml", {});
  const auto u = make_sampler(uniform);
  int same = 0;
  for (std::uint64_t id = 0; id < 1000; ++id) same += a->draw(id).s == u->draw(id).s;
  // Binomial(1000, eps): within 5 of its standard deviations of 1000 eps (a concentrated draw that hits the
  // uniform one's s has probability ~0)
  const double e = scene.sampling.eps, sd = std::sqrt(1000 * e * (1 - e));
  EXPECT_NEAR(same, 1000 * e, 5 * sd);
}

TEST(Sampling, WeightedTalliesDoNotDependOnThreadsOrEngine) {
  const Scene scene = scene_of("stationary_sL_0.toml", {"ensemble.sampling=mupo", "ensemble.particles=40000",
                                                        "run.t_max=2000", "run.fast_forward=true"});
  RunOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const RunResult a = run_ensemble(scene, one), b = run_ensemble(scene, two);
  ASSERT_NE(a.tally.get_if<WeightedEstimator>(), nullptr);
  EXPECT_TRUE(a.tally.estimator == b.tally.estimator);  // every weight sum, bit for bit
  EXPECT_EQ(a.tally.escapes_per_bin, b.tally.escapes_per_bin);
  RunOptions scalar;
  scalar.engine = Engine::scalar;
  const RunResult c = run_ensemble(scene, scalar);
  EXPECT_TRUE(a.tally.as<WeightedEstimator>().total_w == c.tally.as<WeightedEstimator>().total_w);
  EXPECT_EQ(a.tally.escapes_per_bin, c.tally.escapes_per_bin);  // stationary: the engines agree bit for bit
}

struct Case {
  const char* file;
  const char* omega;
  std::uint64_t particles;
};

// Unbiasedness: "mupo" and "uniform" estimate the same P(t). Compared at 12 log-spaced times from
// 20 to t_max where both have at least 100 effective survivors, |P_u - P_m| <= 4 sigma with sigma
// the two standard errors combined (independent runs: different seeds). Multiple testing: at most
// 12 x 8 = 96 comparisons, each false-alarming with probability 6.3e-5 at 4 sigma for a normal
// estimate, 0.6% for the whole test. kappa within 4 combined standard errors too.
class Unbiased : public ::testing::TestWithParam<Case> {};

TEST_P(Unbiased, MupoAndUniformAgreeOnPAndKappa) {
  const Case c = GetParam();
  const std::vector<std::string> common = {"ensemble.particles=" + std::to_string(c.particles), "run.t_max=3000",
                                           "run.fast_forward=true", std::string("leak.omega=") + c.omega};
  std::vector<std::string> u = common, m = common;
  u[0] = "ensemble.particles=" + std::to_string(5 * c.particles);  // uniform resolves the tail less well
  u.push_back("ensemble.seed=11");
  m.push_back("ensemble.seed=12");
  m.push_back("ensemble.sampling=mupo");
  const Scene su = scene_of(c.file, u), sm = scene_of(c.file, m);
  const SurvivalCurve cu = survival_curve(su, run_ensemble(su, RunOptions{}).tally);
  const SurvivalCurve cm = survival_curve(sm, run_ensemble(sm, RunOptions{}).tally);
  ASSERT_TRUE(cm.weighted);
  int compared = 0;
  for (int j = 0; j < 12; ++j) {
    const double t = 20 * std::pow(3000.0 / 20, j / 11.0);
    const std::size_t i = std::min(cu.t.size() - 1, static_cast<std::size_t>(std::lround(t / su.survival_dt)));
    if (cu.effective(i) < 100 || cm.effective(i) < 100) continue;
    ++compared;
    const double sigma = std::hypot(cu.P_err(i), cm.P_err(i));
    EXPECT_NEAR(cm.P(i), cu.P(i), 4 * sigma) << c.file << " omega " << c.omega << " t " << cu.t[i];
  }
  EXPECT_GE(compared, 6) << "too few times resolved by both";
  const KappaFit ku = fit_kappa(cu, su.kappa_window.from, su.kappa_window.to);
  const KappaFit km = fit_kappa(cm, sm.kappa_window.from, sm.kappa_window.to);
  ASSERT_TRUE(ku.ok && km.ok);
  EXPECT_NEAR(km.value, ku.value, 4 * std::hypot(ku.std_error, km.std_error)) << c.file << " omega " << c.omega;
  const AlphaResult au = find_alpha(cu, ku), am = find_alpha(cm, km);
  if (au.value && am.value) {
    EXPECT_NEAR(*am.value, *au.value, 4 * std::hypot(au.std_error, am.std_error)) << c.file << " omega " << c.omega;
  }
  std::printf("%s omega %s: %d times compared; kappa %.5g / %.5g; alpha %.3g +- %.2g (t %g) / %.3g +- %.2g (t %g)\n",
              c.file, c.omega, compared, ku.value, km.value, au.value.value_or(-1), au.std_error, au.crossing_time,
              am.value.value_or(-1), am.std_error, am.crossing_time);
}

INSTANTIATE_TEST_SUITE_P(
    TableAndRotating, Unbiased,
    ::testing::Values(Case{"stationary_sL_0.toml", "0", 200000}, Case{"stationary_sL_0.1.toml", "0", 200000},
                      Case{"stationary_sL_0.1022.toml", "0", 200000}, Case{"stationary_sL_0.1024.toml", "0", 200000},
                      Case{"stationary_sL_0.11.toml", "0", 200000}, Case{"stationary_sL_0.25.toml", "0", 200000},
                      Case{"stationary_sL_0.toml", "1", 200000}, Case{"stationary_sL_0.toml", "2/3", 200000}),
    [](const ::testing::TestParamInfo<Case>& param) {
      std::string name = std::string(param.param.file).substr(11) + "_omega_" + param.param.omega;
      for (char& ch : name)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return name;
    });

}  // namespace
}  // namespace rotleak
