// The MPFR and MPFI number types: significands up to 512 bits inside the number, wider ones on the
// heap; both must behave as plain MPFR does, whatever mix of precisions meets in one expression.
#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "numeric/mpfr_real.hpp"

namespace rotleak {
namespace {

// One below, at, and above the inline limit (512 bits), and a precision far above it.
class MpfrStorage : public ::testing::TestWithParam<long> {};

TEST_P(MpfrStorage, ZerosAreZeroAndNotNan) {
  MpfrPrecision p(GetParam());
  const Mpfr a, b(0), c(0L), d(0.0), e(-0.0);
  for (const Mpfr* x : {&a, &b, &c, &d, &e}) {
    EXPECT_TRUE(mpfr_zero_p(x->data())) << GetParam() << " bits";
    EXPECT_EQ(mpfr_get_prec(x->data()), GetParam());
  }
  EXPECT_TRUE(mpfr_signbit(e.data()));  // -0.0 keeps its sign
  EXPECT_FALSE(mpfr_signbit(d.data()));
  const Mpfi i;
  EXPECT_TRUE(mpfi_is_zero(i.data()));
}

TEST_P(MpfrStorage, ArithmeticMatchesPlainMpfr) {
  const long bits = GetParam();
  MpfrPrecision p(bits);
  const Mpfr x = Mpfr(1) / Mpfr(3), y = -x, z = x * 2 + 1, w = 1 - x;
  mpfr_t ref, third;
  mpfr_inits2(bits, ref, third, static_cast<mpfr_ptr>(nullptr));
  mpfr_set_si(third, 1, MPFR_RNDN);
  mpfr_div_si(third, third, 3, MPFR_RNDN);
  EXPECT_TRUE(mpfr_equal_p(x.data(), third));
  mpfr_neg(ref, third, MPFR_RNDN);
  EXPECT_TRUE(mpfr_equal_p(y.data(), ref));
  mpfr_mul_si(ref, third, 2, MPFR_RNDN);
  mpfr_add_si(ref, ref, 1, MPFR_RNDN);
  EXPECT_TRUE(mpfr_equal_p(z.data(), ref));
  mpfr_si_sub(ref, 1, third, MPFR_RNDN);
  EXPECT_TRUE(mpfr_equal_p(w.data(), ref));
  EXPECT_TRUE(y < 0 && x > 0 && x != 0 && !(x == 0) && x <= 1 && x >= 0);
  mpfr_clears(ref, third, static_cast<mpfr_ptr>(nullptr));
}

TEST_P(MpfrStorage, CopiesAndMovesAcrossPrecisionsKeepTheValue) {
  Mpfr wide, narrow;
  {
    MpfrPrecision p(GetParam());
    wide = Mpfr(2) / Mpfr(7);
  }
  {
    MpfrPrecision p(100);
    narrow = Mpfr(5);
  }
  std::vector<Mpfr> v;
  v.push_back(wide);  // copy
  v.push_back(std::move(narrow));
  v.reserve(64);  // moves both
  Mpfr again = v[0];
  EXPECT_TRUE(mpfr_equal_p(again.data(), wide.data()));
  EXPECT_EQ(mpfr_get_prec(again.data()), GetParam());
  EXPECT_EQ(mpfr_get_prec(v[1].data()), 100);
  EXPECT_EQ(mpfr_get_si(v[1].data(), MPFR_RNDN), 5);
  again = v[1];  // assignment changes the precision with the value
  EXPECT_EQ(mpfr_get_prec(again.data()), 100);
  Mpfr moved = std::move(v[0]);
  EXPECT_TRUE(mpfr_equal_p(moved.data(), wide.data()));
}

INSTANTIATE_TEST_SUITE_P(Bits, MpfrStorage, ::testing::Values(256L, 512L, 513L, 4096L),
                         [](const ::testing::TestParamInfo<long>& bits) {
                           return std::to_string(bits.param) + "_bits";
                         });

}  // namespace
}  // namespace rotleak
