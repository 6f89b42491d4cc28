// The shared physics formulas (geometry/formulas.hpp, leak/leak_formulas.hpp) and their selection hook
// (numeric/select.hpp) on one number: the branch not taken is never evaluated, an interval refuses a
// branch it cannot decide and agrees with double where it can, and f_c's bin is the one the scalar
// observer always took. (On packs they are checked through the kernel: tests/test_simd.cpp compares
// whole output files with the scalar core's.)
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "geometry/formulas.hpp"
#include "leak/leak_formulas.hpp"
#include "numeric/binade.hpp"
#include "numeric/mpfr_real.hpp"

namespace rotleak {
namespace {

TEST(SelectionHook, OneNumberEvaluatesOnlyTheBranchTaken) {
  int a = 0, b = 0;
  EXPECT_EQ(choose(
                true, [&] { return ++a; }, [&] { return ++b; }),
            1);
  EXPECT_EQ(choose(
                false, [&] { return ++a; }, [&] { return ++b + 10; }),
            11);
  EXPECT_EQ(a, 1);
  EXPECT_EQ(b, 1);
  EXPECT_FALSE(both(false, [&] { return ++a > 0; }));
  EXPECT_EQ(a, 1);  // not called
  EXPECT_TRUE(both(true, [&] { return ++a > 0; }));
  EXPECT_EQ(a, 2);
  EXPECT_EQ(select(true, 1.5, 2.5), 1.5);
  EXPECT_EQ(select(false, 1.5, 2.5), 2.5);
}

// A flight from the centre along (1, 1) crosses y = 1 exactly at the junction x = d/2 = 1: an interval
// around that direction cannot tell the top edge from the right arc, and next_exit must refuse (throw),
// not guess. A flight that clearly meets the top edge, or clearly the arc, is decided, and its interval
// holds the double's answer.
TEST(Formulas, IntervalsRefuseAnUndecidedEdgeAndAgreeWhereDecided) {
  MpfrPrecision p(128);
  const Mpfi r(1), hd(1), zero(0);
  const Mpfi c = Mpfi(1) / sqrt(Mpfi(2));  // (1, 1) / sqrt(2), an interval around it
  EXPECT_THROW(formula::next_exit(r, hd, zero, zero, c, c), UncertainDecision);

  for (const double angle : {0.3, 1.2, 2.0, -2.5, -0.4}) {
    const double vx = std::cos(angle), vy = std::sin(angle);
    const formula::Exit<double> d = formula::next_exit(1.0, 1.0, 0.1, -0.2, vx, vy);
    const formula::Exit<Mpfi> m = formula::next_exit(r, hd, Mpfi(0.1), Mpfi(-0.2), Mpfi(vx), Mpfi(vy));
    EXPECT_EQ(m.straight, d.straight) << angle;
    EXPECT_EQ(m.up, d.up) << angle;
    if (!d.straight) {
      EXPECT_EQ(m.right, d.right) << angle;
    }
    for (const auto& [iv, dv] : {std::pair{&m.t, d.t}, std::pair{&m.x, d.x}, std::pair{&m.y, d.y}}) {
      // the double is within a few ulps of the enclosed exact value
      const Mpfi diff = *iv - Mpfi(dv);
      EXPECT_LT(std::abs(mpfi_get_d(diff.data())), 1e-14) << angle;
    }
  }
}

// f_c's bin: floor(s bins) clamped, the same as the truncation the observer took, at bin edges too.
TEST(Formulas, DensityBinIsTheTruncationClamped) {
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (const int bins : {1, 2, 7, 100, 1000}) {
    std::vector<double> s = {0.0, std::nextafter(1.0, 0.0)};
    for (int k = 1; k < bins; ++k) {
      const double e = static_cast<double>(k) / bins;
      s.insert(s.end(), {std::nextafter(e, 0.0), e, std::nextafter(e, 1.0)});
    }
    for (int i = 0; i < 10000; ++i) s.push_back(u(gen));
    for (const double x : s) {
      int want = static_cast<int>(x * bins);
      want = want >= bins ? bins - 1 : want < 0 ? 0 : want;
      EXPECT_EQ(formula::density_bin(x, static_cast<double>(bins)), want) << x << " in " << bins << " bins";
    }
  }
}

TEST(Formulas, DistanceToTheLeaksEnds) {
  // a leak of half width 0.05 centred at 0.98 wraps past s = 0
  EXPECT_NEAR(formula::distance_to_leak_end(0.98, 0.98, 0.05), 0.05, 1e-15);
  EXPECT_NEAR(formula::distance_to_leak_end(0.02, 0.98, 0.05), 0.01, 1e-15);
  EXPECT_NEAR(formula::distance_to_leak_end(0.5, 0.98, 0.05), 0.43, 1e-15);
  EXPECT_TRUE(formula::in_leak(0.02, 0.98, 0.05));
  EXPECT_FALSE(formula::in_leak(0.04, 0.98, 0.05));
}

}  // namespace
}  // namespace rotleak

// The fast-forward's binade and power of two from a double's bits must be libm's ilogb and ldexp(1, e)
// everywhere: normal numbers of both signs over the whole exponent range, around every power of two,
// the subnormals, zero and the exponents that leave the normal range.
TEST(Binade, BitsGiveWhatLibmGives) {
  std::vector<double> xs = {0.0,
                            -0.0,
                            std::numeric_limits<double>::denorm_min(),
                            std::numeric_limits<double>::min(),
                            std::numeric_limits<double>::max(),
                            1.0,
                            -1.0,
                            0.5,
                            3.0};
  for (int e = -1074; e <= 1023; ++e) {
    const double p = std::ldexp(1.0, e);
    for (double x : {p, std::nextafter(p, 0.0), std::nextafter(p, 1e308), 1.5 * p})
      if (std::isfinite(x)) xs.push_back(x), xs.push_back(-x);
  }
  std::mt19937_64 g(5);
  for (int i = 0; i < 100000; ++i) {
    const double x = std::bit_cast<double>(g() & 0x7fefffffffffffffULL);  // any finite double
    xs.push_back(x), xs.push_back(-x);
  }
  std::size_t differ = 0;
  for (double x : xs) {
    if (x == 0) continue;  // ilogb(0) is FP_ILOGB0 either way (libm's answer)
    differ += rotleak::binade_of(x) != std::ilogb(x);
    differ += rotleak::binade_of(static_cast<float>(x)) != std::ilogb(static_cast<float>(x)) &&
              static_cast<float>(x) != 0 && std::isfinite(static_cast<float>(x));
  }
  EXPECT_EQ(differ, 0u) << "of " << xs.size();
  for (int e = -1100; e <= 1100; ++e) {
    const double want = std::ldexp(1.0, e), got = rotleak::pow2<double>(e);
    EXPECT_EQ(std::bit_cast<std::uint64_t>(got), std::bit_cast<std::uint64_t>(want)) << e;
  }
}
