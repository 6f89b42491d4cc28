// The double tier's own atan2 (numeric/atan2.hpp), which every engine takes: its error against MPFR's correctly
// rounded atan2, and its special cases against C's.
//
// Error model: the formula is deterministic. fdlibm's atan is within 1 ulp of atan(q) (the reduction's hi + lo
// constants, a degree-23 polynomial, a few roundings); atan2 first rounds q = y / x (half an ulp of q, which moves
// atan(q) by at most half an ulp of it: q atan'(q) / atan(q) <= 1), and off the first quadrant subtracts from pi
// (half an ulp more): below 2 ulp in all. The test measures the error in ulps of the correctly rounded result (exact
// value to 256 bits) at the arguments where the reduction switches ranges (the 2000 doubles around |y/x| = 7/16,
// 11/16, 19/16, 39/16 and 1, for x = +-1 and +-3), at points of the unit circle (what an arc hit's angle asks), at
// 4 * 10^5 pairs spread over 60 binades and every quadrant, and fails if any reaches 2 ulp; it prints the worst.
#include <gtest/gtest.h>
#include <mpfr.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "numeric/atan2.hpp"

using namespace rotleak;

namespace {

/// |atan2_of(y, x) - atan2(y, x)| in ulps of the correctly rounded atan2(y, x).
class UlpMeter {
 public:
  UlpMeter() { mpfr_inits2(256, y_, x_, a_, d_, static_cast<mpfr_ptr>(nullptr)); }
  ~UlpMeter() { mpfr_clears(y_, x_, a_, d_, static_cast<mpfr_ptr>(nullptr)); }
  UlpMeter(const UlpMeter&) = delete;
  UlpMeter& operator=(const UlpMeter&) = delete;

  double operator()(double y, double x) {
    mpfr_set_d(y_, y, MPFR_RNDN), mpfr_set_d(x_, x, MPFR_RNDN);
    mpfr_atan2(a_, y_, x_, MPFR_RNDN);
    const double rounded = mpfr_get_d(a_, MPFR_RNDN);
    mpfr_sub_d(d_, a_, formula::atan2_of(y, x), MPFR_RNDN);
    const double ulp =
        rounded == 0 ? std::numeric_limits<double>::denorm_min() : std::ldexp(1.0, std::ilogb(rounded) - 52);
    return std::fabs(mpfr_get_d(d_, MPFR_RNDN)) / ulp;
  }

 private:
  mpfr_t y_, x_, a_, d_;
};

}  // namespace

TEST(Atan2, WithinTwoUlpOfTheCorrectlyRoundedValue) {
  UlpMeter meter;
  double worst = 0;
  const auto look = [&](double y, double x) {
    const double e = meter(y, x);
    if (e > worst) worst = e;
    ASSERT_LT(e, 2.0) << "atan2(" << y << ", " << x << ")";
  };
  // where the reduction switches ranges, at x = 1 (atan itself) and x = 3 (through y / x), both signs
  for (const double edge : {7.0 / 16, 11.0 / 16, 19.0 / 16, 39.0 / 16, 1.0})
    for (const double x : {1.0, 3.0, -1.0, -3.0}) {
      double t = edge * std::fabs(x);
      for (int i = 0; i < 1000; ++i) t = std::nextafter(t, 0.0);
      for (int i = 0; i < 2000; ++i, t = std::nextafter(t, 10.0)) look(t, x), look(-t, x);
    }
  // points of the unit circle, as an arc hit asks (y = sin, x = cos, each rounded)
  double circle = 0;
  for (int i = 0; i < 100000; ++i) {
    const double a = -M_PI + 2 * M_PI * (i + 0.5) / 100000;
    look(std::sin(a), std::cos(a));
    circle = std::max(circle, meter(std::sin(a), std::cos(a)));
  }
  // pairs over 60 binades and every quadrant
  std::mt19937_64 rng(20261130);
  std::uniform_real_distribution<double> m(0.5, 1.0);
  std::uniform_int_distribution<int> e(-30, 30), sign(0, 1);
  for (int i = 0; i < 400000; ++i) {
    const double y = std::ldexp(m(rng), e(rng)) * (sign(rng) ? -1 : 1);
    const double x = std::ldexp(m(rng), e(rng)) * (sign(rng) ? -1 : 1);
    look(y, x);
  }
  std::printf("atan2_of: worst error %.3f ulp; on the unit circle %.3f ulp\n", worst, circle);
}

TEST(Atan2, SpecialCasesAreCs) {
  // signed zeros, infinities and NaN as C (Annex F) gives them: the same bits as the C library's atan2
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  const double values[] = {0.0, -0.0, 1.0, -1.0, 2.5, -2.5, 1e-310, -1e-310, 1e300, -1e300, inf, -inf};
  for (const double y : values)
    for (const double x : values) {
      const double ours = formula::atan2_of(y, x), c = std::atan2(y, x);
      if (!std::isfinite(y) || !std::isfinite(x) || y == 0 || x == 0)
        EXPECT_EQ(std::bit_cast<std::uint64_t>(ours), std::bit_cast<std::uint64_t>(c)) << y << ", " << x;
      else  // within 2 ulp of C's (an underflow to 0 or a subnormal: the ulp of the subnormals)
        EXPECT_LE(std::fabs(ours - c), 2 * std::ldexp(1.0, (c == 0 ? -1022 : std::max(std::ilogb(c), -1022)) - 52))
            << y << ", " << x;
    }
  EXPECT_TRUE(std::isnan(formula::atan2_of(nan, 1.0)));
  EXPECT_TRUE(std::isnan(formula::atan2_of(1.0, nan)));
}
