// The generic core over every tier: boundary, frames, reflection law, time reversal, periodic orbits.
// Tolerances are multiples of the tier's epsilon (times the chaos amplification where it applies).
#include <gtest/gtest.h>

#include <random>

#include "geometry/stadium.hpp"
#include "tiers.hpp"

using namespace rotleak;
using rotleak::test::as_double;
using rotleak::test::eps_times;

template <class R>
class Geometry : public ::testing::Test {
 protected:
  Stadium<R> st{ExactReal::parse("2"), ExactReal::parse("1")};

  // Distance of q from piece p's curve (0 on the boundary).
  R off_boundary(Piece p, const Vec2<R>& q) const {
    using std::abs;
    using std::sqrt;
    if (p == Piece::top) return abs(q.y - st.r());
    if (p == Piece::bottom) return abs(q.y + st.r());
    const R dx = q.x - st.arc_centre_x(p);
    return abs(sqrt(dx * dx + q.y * q.y) - st.r());
  }
  R speed(const Vec2<R>& v) const {
    using std::sqrt;
    return sqrt(dot(v, v));
  }

  /// Follows a periodic orbit from Birkhoff (s, p) through the expected pieces; returns the total
  /// time and leaves the final point and velocity in q, v.
  R follow(const BoundaryPoint<R>& start, const R& p, const std::vector<Piece>& pieces, Vec2<R>& q) const {
    Vec2<R> v = st.velocity(start, p);
    q = start.q;
    R t(0);
    for (Piece expected : pieces) {
      const Hit<R> h = st.next_hit(q, v);
      EXPECT_EQ(h.piece, expected);
      t += h.t;
      v = st.reflect(h.piece, h.q, v);
      q = h.q;
    }
    return t;
  }
};
TYPED_TEST_SUITE(Geometry, rotleak::test::Tiers, rotleak::test::TierNames);

TYPED_TEST(Geometry, PointsAndFramesLieOnTheBoundary) {
  using R = TypeParam;
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 2000; ++i) {
    const BoundaryPoint<R> b = this->st.at(R(u(gen)));
    EXPECT_LE(as_double(this->off_boundary(b.piece, b.q)), eps_times<R>(8));
    EXPECT_LE(std::abs(as_double(this->speed(b.tangent)) - 1), eps_times<R>(4));
    EXPECT_LE(std::abs(as_double(dot(b.tangent, b.normal))), eps_times<R>(4));
    // inward: a small step along the normal stays inside the stadium
    const Vec2<R> inside = b.q + R(1e-3) * b.normal;
    EXPECT_LT(as_double(inside.y), 1.0);
  }
}

TYPED_TEST(Geometry, BoundaryCoordinateRoundTripsIncludingJunctions) {
  using R = TypeParam;
  std::vector<R> ss{R(0), R(0.5), R(0.25), R(0.75)};
  for (int k = 0; k < 4; ++k) {
    ss.push_back(this->st.junction(k));
    ss.push_back(this->st.junction(k) + num_traits<R>::epsilon());
    ss.push_back(this->st.junction(k) - num_traits<R>::epsilon());
  }
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 1000; ++i) ss.push_back(R(u(gen)));
  for (const R& s : ss) {
    const BoundaryPoint<R> b = this->st.at(s);
    const R back = this->st.s_of(b.piece, b.q);
    using std::abs;
    R diff = abs(back - s);
    if (diff > R(0.5)) diff = 1 - diff;  // s = 0 and s -> 1 are the same point
    EXPECT_LE(as_double(diff), eps_times<R>(16)) << "s = " << as_double(s);
  }
  // the junctions are the values docs/model.md gives ("The billiard"): 0.09725..., 0.40275..., 0.59725..., 0.90275...
  // (printed to 5 digits)
  EXPECT_NEAR(as_double(this->st.junction(0)), 0.09725, 5e-6);
  EXPECT_NEAR(as_double(this->st.junction(1)), 0.40275, 5e-6);
  EXPECT_NEAR(as_double(this->st.junction(2)), 0.59725, 5e-6);
  EXPECT_NEAR(as_double(this->st.junction(3)), 0.90275, 5e-6);
  EXPECT_EQ(this->st.junction(0), round_exact<R>(ExactReal::parse("1/(4 + 2*pi)")));
}

TYPED_TEST(Geometry, CollisionsStayOnTheBoundaryAtUnitSpeed) {
  using R = TypeParam;
  std::mt19937_64 gen(3);
  std::uniform_real_distribution<double> u(0, 1);
  const int n = std::is_same_v<R, mpfr256> ? 200 : 2000;
  for (int trial = 0; trial < 5; ++trial) {
    const BoundaryPoint<R> b = this->st.at(R(u(gen)));
    Vec2<R> q = b.q, v = this->st.velocity(b, R(2 * u(gen) - 1));
    for (int k = 1; k <= n; ++k) {
      const Hit<R> h = this->st.next_hit(q, v);
      ASSERT_GE(as_double(h.t), 0.0);
      // next_hit assumes |v| = 1; a speed error e = |v.v - 1| puts the exit point off the circle
      // by about e t^2 / (2r). On top of that a few roundings of q + t v.
      const double speed_error = std::abs(as_double(R(dot(v, v) - 1)));
      const double t = as_double(h.t);
      ASSERT_LE(as_double(this->off_boundary(h.piece, h.q)), eps_times<R>(32) + speed_error * t * t)
          << "collision " << k;
      v = this->st.reflect(h.piece, h.q, v);
      q = h.q;
      ASSERT_LE(std::abs(as_double(this->speed(v)) - 1), eps_times<R>(4 + k)) << "collision " << k;
    }
  }
}

TYPED_TEST(Geometry, ReflectionLaw) {
  using R = TypeParam;
  std::mt19937_64 gen(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 500; ++i) {
    const BoundaryPoint<R> b = this->st.at(R(u(gen)));
    const Vec2<R> v_in = this->st.velocity(b, R(2 * u(gen) - 1));
    const Hit<R> h = this->st.next_hit(b.q, v_in);
    const Vec2<R> v_out = this->st.reflect(h.piece, h.q, v_in);
    const Vec2<R> n = this->st.inward_normal(h.piece, h.q), t = this->st.tangent(h.piece, h.q);
    // tangential component kept, normal component reversed, outgoing points inward
    EXPECT_LE(std::abs(as_double(dot(v_out, t) - dot(v_in, t))), eps_times<R>(16));
    EXPECT_LE(std::abs(as_double(dot(v_out, n) + dot(v_in, n))), eps_times<R>(16));
    EXPECT_GE(as_double(dot(v_out, n)), -eps_times<R>(16));
    // Birkhoff p of the outgoing velocity is its tangential component
    EXPECT_LE(std::abs(as_double(this->st.birkhoff_p(h.piece, h.q, v_out) - dot(v_out, t))), eps_times<R>(4));
  }
}

// Run k collisions forward, flip the velocity, run k back: the start comes back up to rounding
// amplified by the chaos. Amplification per collision is bounded by ~ (1 + 2 * flight / r) <= 10
// here, so the tolerance is eps * 10^k (k = 4) -- tier-scaled, and tight for MPFR.
TYPED_TEST(Geometry, TimeReversalReturnsToTheStart) {
  using R = TypeParam;
  std::mt19937_64 gen(13);
  std::uniform_real_distribution<double> u(0, 1);
  const int k = 4;
  for (int trial = 0; trial < 50; ++trial) {
    const BoundaryPoint<R> b = this->st.at(R(u(gen)));
    const Vec2<R> v0 = this->st.velocity(b, R(1.8 * u(gen) - 0.9));  // away from grazing
    Vec2<R> q = b.q, v = v0;
    R t(0);
    for (int i = 0; i < k; ++i) {  // k flights, k - 1 reflections: v is the incoming velocity at q_k
      const Hit<R> h = this->st.next_hit(q, v);
      t += h.t;
      q = h.q;
      if (i + 1 < k) v = this->st.reflect(h.piece, h.q, v);
    }
    v = Vec2<R>{R(-v.x), R(-v.y)};
    for (int i = 0; i < k; ++i) {
      const Hit<R> h = this->st.next_hit(q, v);
      t -= h.t;
      q = h.q;
      if (i + 1 < k) v = this->st.reflect(h.piece, h.q, v);
    }
    using std::abs;
    const double tol = eps_times<R>(1e4);
    EXPECT_LE(as_double(abs(q.x - b.q.x) + abs(q.y - b.q.y)), tol) << "trial " << trial;
    EXPECT_LE(as_double(abs(v.x + v0.x) + abs(v.y + v0.y)), tol) << "trial " << trial;
    EXPECT_LE(as_double(abs(t)), tol) << "trial " << trial;
  }
}

TYPED_TEST(Geometry, BouncingBallOrbitHasPeriodFour) {
  using R = TypeParam;
  const BoundaryPoint<R> b = this->st.at(R(0));  // midpoint of the top edge, p = 0: straight down
  Vec2<R> q;
  const R t = this->follow(b, R(0), {Piece::bottom, Piece::top}, q);
  EXPECT_LE(std::abs(as_double(t) - 4.0), eps_times<R>(8));
  EXPECT_LE(std::abs(as_double(q.x - b.q.x)), eps_times<R>(8));
  EXPECT_LE(std::abs(as_double(q.y - b.q.y)), eps_times<R>(8));
}

TYPED_TEST(Geometry, LongAxisOrbitHasPeriodTwiceTheLength) {
  using R = TypeParam;
  // leftmost point: quarter of the left arc past its start; p = 0 sends the particle along +x
  const R s = this->st.junction(2) + (this->st.junction(3) - this->st.junction(2)) / 2;
  const BoundaryPoint<R> b = this->st.at(s);
  Vec2<R> q;
  const R t = this->follow(b, R(0), {Piece::right_arc, Piece::left_arc}, q);
  EXPECT_LE(std::abs(as_double(t) - 8.0), eps_times<R>(16));  // 2 (d + 2r)
  // The orbit is unstable: each bounce multiplies a transverse error by at most 1 + 2 * 4 / r = 9
  // (flight 4, focusing arc of radius 1), so the start's few-eps error returns at most 81 times larger.
  EXPECT_LE(std::abs(as_double(q.x - b.q.x)) + std::abs(as_double(q.y - b.q.y)), eps_times<R>(4 * 81));
}

TYPED_TEST(Geometry, PerimeterAndAreaAreRoundedOnce) {
  using R = TypeParam;
  EXPECT_EQ(this->st.perimeter(), round_exact<R>(ExactReal::parse("4 + 2*pi")));
  EXPECT_EQ(this->st.area(), round_exact<R>(ExactReal::parse("4 + pi")));
}
