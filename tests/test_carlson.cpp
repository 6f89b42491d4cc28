// Carlson's integrals and the ellipse's arc length (numeric/carlson.hpp) in every point tier against a truth computed
// independently: the interval tier's monotone enclosure at 320 bits (no series), whose width is checked; and the
// ellipse's perimeter against Gauss's arithmetic-geometric mean (its own algorithm, in MPFR) and the exact node
// ellipse_quarter's enclosure.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "numeric/carlson.hpp"
#include "numeric/mpfi_ops.hpp"
#include "tiers.hpp"

using namespace rotleak;
using rotleak::test::as_double;

namespace {

template <class R>
class CarlsonTier : public ::testing::Test {};
using PointTiers = ::testing::Types<double, long double, dd_real, float128, mpfr256>;
TYPED_TEST_SUITE(CarlsonTier, PointTiers, rotleak::test::TierNames);

/// |value - truth| / |truth| in units of R's epsilon, truth an enclosure at 320 bits (its midpoint; its width must
/// be far below R's epsilon).
template <class R>
double relative_ulps(const R& value, const Mpfi& truth) {
  const MpfrPrecision bits(320);
  EXPECT_LT(truth.width() / std::abs(truth.hi()), 1e-80) << "the enclosure is too wide to judge by";
  mpfr_t v, m;
  mpfr_inits2(320, v, m, static_cast<mpfr_ptr>(nullptr));
  num_traits<R>::to_mpfr(v, value);
  mpfi_mid(m, truth.data());
  mpfr_sub(v, v, m, MPFR_RNDN);
  mpfr_div(v, v, m, MPFR_RNDN);
  const double rel = std::abs(mpfr_get_d(v, MPFR_RNDN));
  mpfr_clears(v, m, static_cast<mpfr_ptr>(nullptr));
  return rel / num_traits<R>::to_double(num_traits<R>::epsilon());
}

/// Arguments from one of the three 0 to wide spreads (one argument 0: the complete integrals).
std::vector<std::array<double, 3>> arguments() {
  std::vector<std::array<double, 3>> a = {{0, 1, 2}, {0, 0.25, 1}, {1, 1, 1}, {0.5, 1, 1}, {1e-6, 1, 3}, {2, 3, 4}};
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 40; ++i) a.push_back({u(gen), 0.01 + u(gen), 0.01 + 3 * u(gen)});
  return a;
}

}  // namespace

/// R_F and R_D in each point tier within a few ulps of the rigorous enclosure (error model: the series' truncation
/// is far below epsilon by the step count, so what is left is rounding, a few ulps per duplication step taken once
/// since each step contracts the spread; measured at most 1.7 ulps in double, 4.1 in MPFR at 256 bits, so 8 ulps).
TYPED_TEST(CarlsonTier, RfAndRdAreWithinAFewUlpsOfTheEnclosure) {
  using R = TypeParam;
  double worst = 0;
  for (const auto& [x, y, z] : arguments()) {
    const Mpfi tf = [&] {
      const MpfrPrecision bits(320);
      return carlson::rf(Mpfi(x), Mpfi(y), Mpfi(z));
    }();
    const Mpfi td = [&] {
      const MpfrPrecision bits(320);
      return carlson::rd(Mpfi(x), Mpfi(y), Mpfi(z));
    }();
    const double ef = relative_ulps(carlson::rf(R(x), R(y), R(z)), tf);
    const double ed = relative_ulps(carlson::rd(R(x), R(y), R(z)), td);
    EXPECT_LE(ef, 8) << "R_F(" << x << ", " << y << ", " << z << ")";
    EXPECT_LE(ed, 8) << "R_D(" << x << ", " << y << ", " << z << ")";
    worst = std::max({worst, ef, ed});
  }
  this->RecordProperty("worst_ulps", std::to_string(worst));
}

/// Special values the enclosure must hold: R_F(0, 1, 1) = pi / 2, R_D(0, 1, 1) = 3 pi / 4 (DLMF 19.20.1, 19.20.18:
/// R_D(0, y, y) = 3 pi / (4 y^(3/2))), R_F(x, x, x) = x^(-1/2).
TEST(Carlson, TheEnclosureHoldsTheClosedForms) {
  const MpfrPrecision bits(320);
  mpfr_t pi;
  mpfr_init2(pi, 340);
  mpfr_const_pi(pi, MPFR_RNDN);
  const Mpfi rf = carlson::rf(Mpfi(0), Mpfi(1), Mpfi(1)), rd = carlson::rd(Mpfi(0), Mpfi(1), Mpfi(1));
  mpfr_t half_pi, three_quarter_pi;
  mpfr_inits2(340, half_pi, three_quarter_pi, static_cast<mpfr_ptr>(nullptr));
  mpfr_div_ui(half_pi, pi, 2, MPFR_RNDN);
  mpfr_mul_ui(three_quarter_pi, pi, 3, MPFR_RNDN);
  mpfr_div_ui(three_quarter_pi, three_quarter_pi, 4, MPFR_RNDN);
  EXPECT_TRUE(rf.contains(half_pi)) << rf.lo() << " " << rf.hi();
  EXPECT_TRUE(rd.contains(three_quarter_pi)) << rd.lo() << " " << rd.hi();
  EXPECT_LT(rf.width(), 1e-90);
  EXPECT_LT(rd.width(), 1e-90);
  const Mpfi four = carlson::rf(Mpfi(4), Mpfi(4), Mpfi(4));
  mpfr_t half;
  mpfr_init2(half, 53);
  mpfr_set_d(half, 0.5, MPFR_RNDN);
  EXPECT_TRUE(four.contains(half)) << four.lo() << " " << four.hi();
  mpfr_clear(half);
  mpfr_clears(pi, half_pi, three_quarter_pi, static_cast<mpfr_ptr>(nullptr));
}

/// The ellipse's perimeter 4 ellipse_quarter(a, b), in double and as the exact node, against Gauss's AGM series
/// (a different algorithm: L = 2 pi / M(a, b) (a^2 - sum_n 2^(n-1) c_n^2), c_0^2 = a^2 - b^2, c_(n+1) = (a_n - b_n)/2),
/// for round, flat and tall ellipses.
TEST(Carlson, TheEllipsesPerimeterIsGausssArithmeticGeometricMean) {
  for (const auto& [a, b] : std::vector<std::pair<int, int>>{{2, 1}, {1, 2}, {5, 4}, {100, 1}, {3, 3}}) {
    SCOPED_TRACE(std::to_string(a) + " " + std::to_string(b));
    mpfr_t an, bn, cn2, sum, t, pow2, L;
    mpfr_inits2(320, an, bn, cn2, sum, t, pow2, L, static_cast<mpfr_ptr>(nullptr));
    mpfr_set_ui(an, a, MPFR_RNDN), mpfr_set_ui(bn, b, MPFR_RNDN);
    mpfr_set_si(cn2, a * a - b * b, MPFR_RNDN);
    mpfr_set_d(pow2, 0.5, MPFR_RNDN);
    mpfr_mul(sum, cn2, pow2, MPFR_RNDN);  // n = 0: 2^-1 c_0^2
    for (int n = 1; n < 40; ++n) {
      mpfr_sub(t, an, bn, MPFR_RNDN);
      mpfr_div_ui(t, t, 2, MPFR_RNDN);
      mpfr_sqr(cn2, t, MPFR_RNDN);  // c_n = (a_(n-1) - b_(n-1)) / 2
      mpfr_mul(t, an, bn, MPFR_RNDN);
      mpfr_add(an, an, bn, MPFR_RNDN);
      mpfr_div_ui(an, an, 2, MPFR_RNDN);
      mpfr_sqrt(bn, t, MPFR_RNDN);
      mpfr_mul_ui(pow2, pow2, 2, MPFR_RNDN);
      mpfr_mul(t, cn2, pow2, MPFR_RNDN);
      mpfr_add(sum, sum, t, MPFR_RNDN);
    }
    mpfr_set_ui(L, static_cast<unsigned long>(a * a), MPFR_RNDN);
    mpfr_sub(L, L, sum, MPFR_RNDN);
    mpfr_const_pi(t, MPFR_RNDN);
    mpfr_mul(L, L, t, MPFR_RNDN);
    mpfr_mul_ui(L, L, 2, MPFR_RNDN);
    mpfr_div(L, L, an, MPFR_RNDN);
    const double agm = mpfr_get_d(L, MPFR_RNDN);
    // in double as s takes it: the arcs from the top and from the side vertex to psi = pi/4, each with
    // u <= 1/sqrt(2); a few ulps each (ellipse_quarter at u = 1 itself subtracts two terms that grow like
    // ln(a / b) for a flat ellipse: the tables take the exact node instead)
    const double h = std::sqrt(0.5), a2 = a * a, b2 = b * b;
    const double quarter = carlson::ellipse_arc(h, h, a2, b2) + carlson::ellipse_arc(h, h, b2, a2);
    EXPECT_NEAR(4 * quarter, agm, 4 * 0x1p-52 * agm);
    const ExactReal exact =
        ExactReal::ellipse_quarter(ExactReal::parse(std::to_string(a)), ExactReal::parse(std::to_string(b)));
    mpfi_t box;
    mpfi_init2(box, 300);
    exact.enclose(box, 300);
    mpfi_mul_ui(box, box, 4);
    EXPECT_GT(mpfi_is_inside_fr(L, box), 0) << "the exact node's enclosure misses the AGM's perimeter";
    mpfr_sub(t, &box->right, &box->left, MPFR_RNDU);
    EXPECT_LT(mpfr_get_d(t, MPFR_RNDU), 1e-70);
    mpfi_clear(box);
    EXPECT_EQ(exact.text(), a == b ? "(pi*" + std::to_string(a) + "/2)" : ExactReal::parse(exact.text()).text());
    mpfr_clears(an, bn, cn2, sum, t, pow2, L, static_cast<mpfr_ptr>(nullptr));
  }
}

/// The arc from the top and from the side vertex meet: I(u; a, b) + I(u'; b, a) = quarter, where the point at angle
/// psi from the top has u = sin psi and, from the vertex, u' = cos psi (each measured from its own end).
TYPED_TEST(CarlsonTier, TheArcsFromBothEndsOfAQuarterAddUpToIt) {
  using R = TypeParam;
  using std::cos;
  using std::sin;
  const R a2(4), b2(1);
  const R quarter = carlson::ellipse_quarter(a2, b2);
  for (const double psi : {0.1, 0.5, 0.785, 1.2, 1.5}) {
    const R sn = sin(R(psi)), cs = cos(R(psi));
    const R sum = carlson::ellipse_arc(sn, cs, a2, b2) + carlson::ellipse_arc(cs, sn, b2, a2);
    EXPECT_NEAR(as_double(sum), as_double(quarter), rotleak::test::eps_times<R>(32) * as_double(quarter)) << psi;
  }
}

/// The exact node parses from its text, folds the circle, and refuses what is not two semi-axes > 0.
TEST(Carlson, TheExactQuarterParsesFoldsAndRefuses) {
  EXPECT_EQ(ExactReal::parse("ellipse_quarter(3, 3)").text(), "(pi*3/2)");
  const ExactReal q = ExactReal::parse("ellipse_quarter(2, 1/2)");
  EXPECT_EQ(ExactReal::parse(q.text()).text(), q.text());
  const double h = std::sqrt(0.5);  // the quarter as two halves in double, each measured from its end
  EXPECT_NEAR(q.to_double(), carlson::ellipse_arc(h, h, 4.0, 0.25) + carlson::ellipse_arc(h, h, 0.25, 4.0), 1e-15);
  for (const char* bad : {"ellipse_quarter(1)", "ellipse_quarter(0, 1)", "ellipse_quarter(1, -2)", "ellipse_quarter"})
    EXPECT_THROW(ExactReal::parse(bad), ExactParseError) << bad;
}
