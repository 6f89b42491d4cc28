// The MUPO covering: the sweep against direct counting, the three-distance theorem, the cases of docs/model.md "The
// MUPO covering f_L(s)".
#include <gtest/gtest.h>

#include <random>

#include "analysis/covering.hpp"

using namespace rotleak;

namespace {

CoveringInput input(const std::string& omega, const std::string& delta = "1e-7", const std::string& lambda = "0.01") {
  CoveringInput in;
  in.omega = ExactReal::parse(omega);
  in.delta = ExactReal::parse(delta);
  in.lambda = ExactReal::parse(lambda);
  return in;
}

// f_L at s counted directly from the definition, exactly (rational x and lambda).
std::uint64_t direct_count(const mpq_class& x, const mpq_class& half, std::uint64_t N, const mpq_class& s) {
  std::uint64_t count = 0;
  for (std::uint64_t n = 0; n <= N; ++n) {
    mpq_class c = x * n;
    mpz_class fl;
    mpz_fdiv_q(fl.get_mpz_t(), c.get_num_mpz_t(), c.get_den_mpz_t());
    c -= fl;
    mpq_class off = s - c;  // circular offset in [-1/2, 1/2)
    mpz_class k;
    mpq_class shifted = off + mpq_class(1, 2);
    mpz_fdiv_q(k.get_mpz_t(), shifted.get_num_mpz_t(), shifted.get_den_mpz_t());
    off -= k;
    count += (off >= -half && off < half);  // half-open [c - h, c + h)
  }
  return count;
}

}  // namespace

TEST(Covering, SpecCasesOneSpotThreeClustersNoGap) {
  const Covering one = mupo_covering(input("1"));
  EXPECT_EQ(one.N, 3162u);
  EXPECT_TRUE(one.exact);
  EXPECT_EQ(one.clusters, 1u);
  EXPECT_GT(one.zero_measure, 0.98);
  const Covering two_thirds = mupo_covering(input("2/3"));
  EXPECT_EQ(two_thirds.clusters, 3u);
  EXPECT_GT(two_thirds.zero_measure, 0.9);
  const Covering near_one = mupo_covering(input("100/101"));
  EXPECT_EQ(near_one.zero_measure, 0.0);
  EXPECT_EQ(near_one.max_zero_gap, 0.0);
  EXPECT_GT(near_one.min, 0u);
  // less uniform -> larger coefficient of variation
  EXPECT_GT(one.cv, two_thirds.cv);
  EXPECT_GT(two_thirds.cv, near_one.cv);
  // only 2 r omega matters: omega = 2/3 with r = 1 is omega = 4/3 with r = 1/2 (and d halved keeps N)
  CoveringInput half_r = input("4/3");
  half_r.r = ExactReal::parse("1/2");
  half_r.d = ExactReal::parse("1");
  const Covering same = mupo_covering(half_r);
  EXPECT_EQ(same.zero_measure, two_thirds.zero_measure);
  EXPECT_EQ(same.x_text, two_thirds.x_text);
}

TEST(Covering, SweepAgreesWithDirectCounting) {
  const std::uint64_t seed = 99;
  std::mt19937_64 gen(seed);
  for (const char* omega : {"2/3", "22/23", "70/71", "1008/1009", "3/7"}) {
    const Covering c = mupo_covering(input(omega, "1e-4", "0.05"));
    ASSERT_TRUE(c.exact);
    // x and N from the definition (docs/model.md, "The MUPO covering f_L(s)") directly, not from the code's own x_text:
    // t_c = 2r(1 + delta), x = t_c omega (direct_count reduces n x itself), N = (d / 2r) / sqrt(delta) = (2/2) /
    // (1/100)
    const mpq_class x = mpq_class(2) * (mpq_class(1) + mpq_class(1, 10000)) * mpq_class(omega), half(1, 40);
    ASSERT_EQ(c.N, 100u);
    std::uniform_int_distribution<std::size_t> pick(0, c.segments.size() - 1);
    for (int i = 0; i < 40; ++i) {
      const Segment& seg = c.segments[pick(gen)];
      const mpq_class mid = (mpq_class(seg.from) + mpq_class(seg.to)) / 2;  // inside the segment
      EXPECT_EQ(seg.value, direct_count(x, half, c.N, mid)) << omega << " at s = " << mid.get_d() << ", seed " << seed;
    }
    // integral of f_L = (N + 1) lambda exactly
    EXPECT_NEAR(c.mean, static_cast<double>(c.N + 1) * 0.05, 1e-12 * c.mean);
  }
}

// Three-distance theorem: the gaps between neighbouring frac(n x), n = 0..N, take at most three
// lengths, and with three the largest is the sum of the other two. r = 1/2 and delta = 10^-6 make
// x = (1 + 10^-6) omega and N = 1000 d, so random omega and d give random x and N.
TEST(Covering, ThreeDistanceTheoremOverRandomCases) {
  const std::uint64_t seed = 4242;
  std::mt19937_64 gen(seed);
  std::uniform_int_distribution<int> small(2, 5000), num(1, 100000);
  const char* irrational[] = {"sqrt(2)", "ln(19)", "pi", "golden", "e", "sqrt(5) - 2", "liouville(10)"};
  for (int i = 0; i < 60; ++i) {
    CoveringInput in;
    in.r = ExactReal::parse("1/2");
    in.delta = ExactReal::parse("1e-6");
    in.lambda = ExactReal::parse("0.001");
    const int N = small(gen);
    in.d = ExactReal::rational(mpq_class(N, 1000));
    in.omega = (i % 2) ? ExactReal::parse(irrational[i % 7]) * ExactReal::rational(mpq_class(small(gen), 7))
                       : ExactReal::rational(mpq_class(num(gen), num(gen)));
    const Covering c = mupo_covering(in);
    EXPECT_EQ(c.N, static_cast<std::uint64_t>(N));
    EXPECT_TRUE(c.three_distance_holds) << "omega " << in.omega.text() << " N " << N << " seed " << seed;
    std::size_t nonzero = 0;
    std::uint64_t total = 0;
    for (const auto& g : c.gaps) {
      nonzero += g.length > 0;
      total += g.count;
    }
    EXPECT_LE(nonzero, 3u);
    EXPECT_EQ(total, c.N + 1);
  }
}

TEST(Covering, IrrationalOmegaIsCertifiedWithABound) {
  const Covering c = mupo_covering(input("ln(19)", "1e-8"));
  EXPECT_FALSE(c.exact);
  EXPECT_GT(c.error_bound, 0);
  EXPECT_LT(c.error_bound, 1e-30);
  EXPECT_TRUE(c.three_distance_holds);
  EXPECT_EQ(c.N, 10000u);
}

TEST(Covering, RejectsBadInput) {
  EXPECT_THROW(mupo_covering(input("2/3", "0")), std::invalid_argument);
  EXPECT_THROW(mupo_covering(input("2/3", "1")), std::invalid_argument);
  EXPECT_THROW(mupo_covering(input("2/3", "-1e-7")), std::invalid_argument);
  EXPECT_THROW(mupo_covering(input("2/3", "1e-7", "0")), std::invalid_argument);
  EXPECT_THROW(mupo_covering(input("2/3", "1e-7", "1")), std::invalid_argument);
  EXPECT_THROW(mupo_covering(input("2/3", "1e-20")), std::invalid_argument);  // N = 10^10: above the limit
}

TEST(Covering, ProfileIntegratesToTheMean) {
  const Covering c = mupo_covering(input("22/23"));
  const std::vector<double> prof = covering_profile(c, 1000);
  double sum = 0;
  for (double v : prof) sum += v / 1000;
  EXPECT_NEAR(sum, c.mean, 1e-9 * c.mean);
}
