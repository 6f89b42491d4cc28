// The leak: exact phase at large omega*t, and the stationary window path against the s-based test.
#include <gtest/gtest.h>

#include <random>

#include "leak/leak.hpp"
#include "names.hpp"
#include "tiers.hpp"

using namespace rotleak;

namespace {

// frac(s0 + omega t) exactly, for rational omega and s0 and a double t, as a double.
double exact_phase(const mpq_class& s0, const mpq_class& omega, double t) {
  mpq_class x = s0 + omega * mpq_class(t);
  mpz_class fl;
  mpz_fdiv_q(fl.get_mpz_t(), x.get_num_mpz_t(), x.get_den_mpz_t());
  x -= fl;
  return x.get_d();
}

}  // namespace

TEST(LeakPhase, ExactAtLargeOmegaTimesT) {
  const mpq_class omega(1008, 1009), s0(1, 10);
  LeakSchedule<double> sched(ExactReal::rational(s0), ExactReal::rational(omega));
  std::mt19937_64 gen(17);
  std::uniform_real_distribution<double> logt(0, 12);
  for (int i = 0; i < 2000; ++i) {
    const double t = std::pow(10.0, logt(gen));  // up to omega * t = 10^12
    const double got = sched.phase(t), want = exact_phase(s0, omega, t);
    double diff = std::abs(got - want);
    if (diff > 0.5) diff = 1 - diff;
    // hi*t split exactly; the rest carries a few roundings of size <= 1 ulp of 1
    EXPECT_LE(diff, 4 * 0x1p-52) << "t = " << t;
  }
}

TEST(LeakPhase, NaiveDoubleProductLosesWhatTheSplitKeeps) {
  // The reason for the split: fmod(omega * t, 1) in plain double loses ~log2(omega t) bits.
  const mpq_class omega(1008, 1009);
  const double t = 1e12 + 0.5;
  const double naive = std::fmod(omega.get_d() * t, 1.0);
  LeakSchedule<double> sched(ExactReal::parse("0"), ExactReal::rational(omega));
  const double want = exact_phase(0, omega, t);
  EXPECT_LT(std::abs(sched.phase(t) - want), 1e-14);
  EXPECT_GT(std::abs(naive - want), 1e-6);
}

TEST(LeakPhase, StationaryWhenOmegaIsZero) {
  LeakSchedule<double> sched(ExactReal::parse("1.25"), ExactReal::parse("0"));
  EXPECT_FALSE(sched.rotating());
  EXPECT_EQ(sched.phase(1e6), 0.25);  // start reduced mod 1 exactly
}

// Stationary leaks use per-piece windows (no atan2); they must agree with the s-based definition
// everywhere except within rounding of the leak's edges.
class LeakWindows : public ::testing::TestWithParam<std::pair<const char*, const char*>> {};

TEST_P(LeakWindows, AgreeWithTheBoundaryCoordinateTest) {
  const auto [start, width] = GetParam();
  Stadium<double> st(ExactReal::parse("2"), ExactReal::parse("1"));
  Leak<double> leak(st, ExactReal::parse(width), ExactReal::parse(start), ExactReal::parse("0"));
  Leak<double> moving(st, ExactReal::parse(width), ExactReal::parse(start), ExactReal::parse("1e-300"));
  std::mt19937_64 gen(23);
  std::uniform_real_distribution<double> u(0, 1);
  int inside = 0;
  for (int i = 0; i < 200000; ++i) {
    const double s = u(gen);
    const BoundaryPoint<double> b = st.at(s);
    const double s_back = st.s_of(b.piece, b.q);
    const double edge_distance = formula::distance_to_leak_end(s_back, leak.schedule().start(), leak.half_width());
    if (edge_distance < 1e-12) continue;  // within rounding of an edge: either answer is right
    const bool by_s = formula::in_leak(s_back, leak.schedule().phase(0.0), leak.half_width());
    EXPECT_EQ(leak.hit(b.piece, b.q, 0.0), by_s) << "s = " << s << " start " << start;
    EXPECT_EQ(moving.hit(b.piece, b.q, 0.0), by_s) << "s = " << s << " start " << start;
    inside += by_s;
  }
  // the fraction inside is the width (binomial, 200000 draws: 5 sigma)
  const double w = ExactReal::parse(width).to_double();
  EXPECT_NEAR(inside / 200000.0, w, 5 * std::sqrt(w * (1 - w) / 200000.0));
}

INSTANTIATE_TEST_SUITE_P(Positions, LeakWindows,
                         ::testing::Values(std::pair{"0", "0.01"}, std::pair{"0.1", "0.01"},
                                           std::pair{"0.1022", "0.01"}, std::pair{"0.1024", "0.01"},
                                           std::pair{"0.25", "0.01"}, std::pair{"0.5", "0.01"},
                                           std::pair{"0.75", "0.01"}, std::pair{"0.998", "0.01"},
                                           std::pair{"0.3", "0.9"}, std::pair{"0.9", "0.5"}, std::pair{"0.6", "0.3"},
                                           std::pair{"0.3", "1e-9"}, std::pair{"0.7", "0.5"}),
                         rotleak::test::IndexedName());

TEST(LeakStraddle, JunctionCasesOfTheStationaryTable) {
  // s_L = 0.1022 still overlaps the straight top edge; s_L = 0.1024 lies wholly on the arc (docs/model.md, "Published
  // values").
  Stadium<double> st(ExactReal::parse("2"), ExactReal::parse("1"));
  const double j0 = st.junction(0);
  EXPECT_LT(0.1022 - 0.005, j0);
  EXPECT_GT(0.1024 - 0.005, j0);
  Leak<double> a(st, ExactReal::parse("0.01"), ExactReal::parse("0.1022"), ExactReal::parse("0"));
  Leak<double> b(st, ExactReal::parse("0.01"), ExactReal::parse("0.1024"), ExactReal::parse("0"));
  const BoundaryPoint<double> just_before = st.at(j0 - 1e-6);  // on the top edge
  EXPECT_EQ(just_before.piece, Piece::top);
  EXPECT_TRUE(a.hit(just_before.piece, just_before.q, 0));
  EXPECT_FALSE(b.hit(just_before.piece, just_before.q, 0));
}
