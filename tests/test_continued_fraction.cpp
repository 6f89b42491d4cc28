// Continued fractions and approximations: exact round trips, known expansions, brute force.
#include <gtest/gtest.h>

#include <gmpxx.h>

#include <algorithm>
#include <cmath>

#include "analysis/continued_fraction.hpp"

using namespace rotleak;

namespace {

std::vector<long> as_longs(const std::vector<mpz_class>& v) {
  std::vector<long> out;
  for (const auto& z : v) out.push_back(z.get_si());
  return out;
}

// |x - p/q| compared exactly (rational x) or at 600 bits (irrational x: no ties, gaps >> 2^-600 here).
struct Distance {
  const ExactReal& x;
  mpq_class operator()(const mpz_class& p, const mpz_class& q) const {
    if (x.is_rational()) return abs(x.as_rational() - mpq_class(p, q));
    mpfr_t v;
    mpfr_init2(v, 600);
    x.round(v);
    mpq_class xq;
    mpfr_get_q(xq.get_mpq_t(), v);
    mpfr_clear(v);
    return abs(xq - mpq_class(p, q));
  }
};

// Best approximations of the first kind by trying every q <= Q.
std::vector<std::pair<long, long>> brute_first_kind(const ExactReal& x, long Q) {
  Distance dist{x};
  std::vector<std::pair<long, long>> out;
  mpq_class best = -1;
  mpfr_t v;
  mpfr_init2(v, 200);
  x.round(v);
  for (long q = 1; q <= Q; ++q) {
    mpfr_t t;
    mpfr_init2(t, 200);
    mpfr_mul_si(t, v, q, MPFR_RNDN);
    const long p0 = mpfr_get_si(t, MPFR_RNDD);
    mpfr_clear(t);
    for (long p = p0 - 1; p <= p0 + 2; ++p) {
      const mpq_class d = dist(mpz_class(p), mpz_class(q));
      if (best < 0 || d < best) {
        if (!out.empty() && out.back().second == q)
          out.back() = {p, q};
        else
          out.push_back({p, q});
        best = d;
      }
    }
  }
  mpfr_clear(v);
  return out;
}

}  // namespace

TEST(ContinuedFraction, RandomBigRationalsRoundTripExactly) {
  const unsigned long seed = 20261122;
  gmp_randclass rng(gmp_randinit_default);
  rng.seed(seed);
  for (int i = 0; i < 200; ++i) {
    const unsigned long bits = 1 + (i * 37) % 3000;
    mpq_class q(rng.get_z_bits(bits) - rng.get_z_bits(bits / 2 + 1), rng.get_z_bits(bits) + 1);
    q.canonicalize();
    const auto terms = cf_of_rational(q);
    EXPECT_EQ(rational_of_cf(terms), q) << "seed " << seed << " case " << i;
    for (std::size_t k = 1; k < terms.size(); ++k) EXPECT_GE(terms[k], 1);
    if (terms.size() > 1) {
      EXPECT_GE(terms.back(), 2);  // canonical form
    }
  }
}

TEST(ContinuedFraction, KnownExpansions) {
  EXPECT_EQ(as_longs(certified_cf(ExactReal::parse("golden"), 30).terms), std::vector<long>(30, 1));
  std::vector<long> sqrt2(30, 2);
  sqrt2[0] = 1;
  EXPECT_EQ(as_longs(certified_cf(ExactReal::parse("sqrt(2)"), 30).terms), sqrt2);
  std::vector<long> e{2};
  for (long k = 1; e.size() < 30; ++k) {
    e.push_back(1);
    e.push_back(2 * k);
    e.push_back(1);
  }
  e.resize(30);
  EXPECT_EQ(as_longs(certified_cf(ExactReal::parse("e"), 30).terms), e);
  const std::vector<long> pi{3, 7, 15, 1, 292, 1, 1, 1, 2, 1, 3, 1, 14, 2, 1, 1, 2, 2, 2, 2};
  EXPECT_EQ(as_longs(certified_cf(ExactReal::parse("pi"), 20).terms), pi);
  EXPECT_EQ(as_longs(certified_cf(ExactReal::parse("1008/1009"), 100).terms), (std::vector<long>{0, 1, 1008}));
  EXPECT_TRUE(certified_cf(ExactReal::parse("1008/1009"), 100).complete);
}

TEST(ContinuedFraction, CertifiedTermsDoNotChangeWithFourTimesThePrecision) {
  for (const char* s : {"ln(19)", "2*ln(19)", "pi", "sqrt(7)", "e/3", "liouville(3)"}) {
    const ExactReal x = ExactReal::parse(s);
    const CertifiedExpansion a = certified_cf(x, 25);
    const CertifiedExpansion b = certified_cf(x, 25, 4 * a.precision_bits);
    ASSERT_GE(b.precision_bits, 4 * a.precision_bits) << s;
    ASSERT_EQ(b.terms.size(), a.terms.size());
    for (std::size_t k = 0; k < a.terms.size(); ++k) EXPECT_EQ(a.terms[k], b.terms[k]) << s << " term " << k;
  }
}

// liouville(10): only 1, 8, 9, 10, 11 and 10^((m-1) m!) - 1 occur.
TEST(ContinuedFraction, LiouvilleExpansionStructure) {
  const CertifiedExpansion cf = certified_cf(ExactReal::parse("liouville(10)"), 40);
  std::vector<mpz_class> big;
  for (unsigned long m = 2, fact = 2; m <= 6; ++m, fact *= m) {
    mpz_class p;
    mpz_ui_pow_ui(p.get_mpz_t(), 10, (m - 1) * fact);
    big.push_back(p - 1);
  }
  int seen_big = 0;
  for (std::size_t k = 1; k < cf.terms.size(); ++k) {
    const mpz_class& a = cf.terms[k];
    const bool small = a == 1 || a == 8 || a == 9 || a == 10 || a == 11;
    const bool huge = std::find(big.begin(), big.end(), a) != big.end();
    EXPECT_TRUE(small || huge) << "term " << k << " = " << a.get_str();
    seen_big += huge;
  }
  EXPECT_GE(seen_big, 3);  // 99, 10^12 - 1, 10^72 - 1 within 40 terms
  // the exact partial sums share the certified prefix
  const auto partial = cf_of_rational(liouville_partial_sum(10, 6));
  for (std::size_t k = 0; k < 20; ++k) EXPECT_EQ(partial[k], cf.terms[k]) << k;
}

TEST(Approximation, FirstKindMatchesBruteForce) {
  for (const char* s :
       {"ln(19)", "pi", "sqrt(2)", "golden", "e", "2*ln(19)", "355/113", "7/5", "liouville(10)", "0.4"}) {
    const ExactReal x = ExactReal::parse(s);
    const BestApproximations best = best_approximations(x, mpz_class(300));
    std::vector<std::pair<long, long>> got;
    for (const auto& f : best.list) got.push_back({f.p.get_si(), f.q.get_si()});
    EXPECT_EQ(got, brute_first_kind(x, 300)) << s;
  }
}

// Second kind: records of min_p |q x - p|; these are the convergents (c_0 too unless a_1 = 1).
TEST(Approximation, SecondKindAreTheConvergents) {
  for (const char* s : {"ln(19)", "pi", "golden", "e", "sqrt(3)"}) {
    const ExactReal x = ExactReal::parse(s);
    mpfr_t v, t;
    mpfr_inits2(300, v, t, static_cast<mpfr_ptr>(nullptr));
    x.round(v);
    std::vector<long> records;
    double best = 2;
    for (long q = 1; q <= 2000; ++q) {
      mpfr_mul_si(t, v, q, MPFR_RNDN);
      mpfr_t fr;
      mpfr_init2(fr, 300);
      mpfr_frac(fr, t, MPFR_RNDN);
      double d = mpfr_get_d(fr, MPFR_RNDN);
      d = std::min(d, 1 - d);
      mpfr_clear(fr);
      if (d < best) {
        best = d;
        records.push_back(q);
      }
    }
    mpfr_clears(v, t, static_cast<mpfr_ptr>(nullptr));
    const CertifiedExpansion cf = certified_cf(x, 30);
    std::vector<long> second;
    for (const auto& f : best_second_kind(cf.terms, mpz_class(2000))) second.push_back(f.q.get_si());
    EXPECT_EQ(records, second) << s;
    // semiconvergents between c_{k-1} and c_k run from c_{k-2} towards c_k, j = 1..a_k - 1
    const auto conv = convergents(cf.terms);
    const auto semis = semiconvergents(cf.terms, 2, 1000);
    ASSERT_EQ(semis.size(), cf.terms[2].get_ui() - 1);
    for (std::size_t j = 0; j < semis.size(); ++j) EXPECT_EQ(semis[j].q, conv[0].q + (j + 1) * conv[1].q);
  }
}

TEST(Approximation, SmallestDenominatorWithinEps) {
  for (const char* s : {"ln(19)", "pi", "golden", "liouville(10)"}) {
    const ExactReal x = ExactReal::parse(s);
    for (const char* eps : {"1e-2", "1e-4", "1e-6"}) {
      const auto got = smallest_denominator_within(x, ExactReal::parse(eps));
      ASSERT_TRUE(got.has_value());
      // brute force: the first q with a p inside
      Distance dist{x};
      const mpq_class e = ExactReal::parse(eps).as_rational();
      mpfr_t v;
      mpfr_init2(v, 200);
      x.round(v);
      long q_found = 0;
      for (long q = 1; q <= 100000 && !q_found; ++q) {
        mpfr_t t;
        mpfr_init2(t, 200);
        mpfr_mul_si(t, v, q, MPFR_RNDN);
        const long p0 = mpfr_get_si(t, MPFR_RNDD);
        mpfr_clear(t);
        for (long p = p0; p <= p0 + 1; ++p)
          if (dist(mpz_class(p), mpz_class(q)) < e) q_found = q;
      }
      mpfr_clear(v);
      EXPECT_EQ(got->q.get_si(), q_found) << s << " eps " << eps;
      EXPECT_LT(dist(got->p, got->q), e);
    }
  }
}

TEST(Approximation, SignedErrorEnclosureContainsTheError) {
  const ExactReal x = ExactReal::parse("ln(19)");
  const DecimalEnclosure e = signed_error(x, Fraction{53, 18}, 8);
  mpfr_t lo, hi, v;
  mpfr_inits2(300, lo, hi, v, static_cast<mpfr_ptr>(nullptr));
  mpfr_set_str(lo, e.lo.c_str(), 10, MPFR_RNDN);
  mpfr_set_str(hi, e.hi.c_str(), 10, MPFR_RNDN);
  (x - ExactReal::parse("53/18")).round(v);
  EXPECT_LE(mpfr_cmp(lo, v), 0);
  EXPECT_GE(mpfr_cmp(hi, v), 0);
  EXPECT_LT(mpfr_get_d(hi, MPFR_RNDN), 0);  // ln(19) < 53/18
  mpfr_clears(lo, hi, v, static_cast<mpfr_ptr>(nullptr));
}

// Certification refuses to go on where an enclosure does not decide a quotient: around 22/7 = [3; 7], which sits
// on the boundary of the cylinders [3; 7, ...] and [3; 6, 1, ...], only a0 = 3 is certified, also when an end is
// 22/7 itself (its expansion ends at a1: an end of the cylinder, not inside it); just below it both ends share
// [3; 7] and differ after.
TEST(ContinuedFraction, AnEnclosureCertifiesOnlyWhatBothEndsShare) {
  const mpq_class x(22, 7), tiny(1, mpz_class("1000000000000000000000000000000"));
  EXPECT_EQ(as_longs(cf_common_prefix(x - tiny, x + tiny, 10)), std::vector<long>{3});
  EXPECT_EQ(as_longs(cf_common_prefix(x - tiny, x, 10)), std::vector<long>{3});
  EXPECT_EQ(as_longs(cf_common_prefix(x, x + tiny, 10)), std::vector<long>{3});
  EXPECT_EQ(as_longs(cf_common_prefix(x - tiny, x - tiny / 2, 10)), (std::vector<long>{3, 7}));
  EXPECT_EQ(as_longs(cf_common_prefix(x, x, 10)), std::vector<long>{3}) << "22/7 ends the cylinder of [3; 7]";
}

// One ulp decides: the two doubles around sqrt 7 = [2; 1, 1, 1, 4, 1, 1, 1, 4, ...] certify only the quotients
// their ends share (a prefix of sqrt 7's certified ones, far fewer than 40), and the double just above sqrt 7,
// an exact rational one ulp off, has an expansion that leaves sqrt 7's within the 40 certified quotients: the
// claim "these are the quotients" fails for the neighbour.
TEST(ContinuedFraction, OneUlpAwayTheCertifiedQuotientsAreNotTheValues) {
  const CertifiedExpansion cf = certified_cf(ExactReal::parse("sqrt(7)"), 40);
  ASSERT_GE(cf.terms.size(), 40u);
  const double s = std::sqrt(7.0);
  const double below = std::nextafter(s, 0.0), above = std::nextafter(s, 4.0);
  const std::vector<mpz_class> both = cf_common_prefix(mpq_class(below), mpq_class(above), 40);
  EXPECT_GT(both.size(), 10u);
  EXPECT_LT(both.size(), 30u);
  for (std::size_t k = 0; k < both.size(); ++k) EXPECT_EQ(both[k], cf.terms[k]) << k;
  const std::vector<mpz_class> off = cf_of_rational(mpq_class(above), 40);
  std::size_t same = 0;
  while (same < std::min(off.size(), cf.terms.size()) && off[same] == cf.terms[same]) ++same;
  EXPECT_LT(same, 40u) << "the neighbour's expansion must leave sqrt 7's within the certified quotients";
  EXPECT_GE(same, both.size());
}
