// The mean-value (Lohner) enclosure of a trajectory (verify/lohner.hpp): jets give the formulas' true
// derivatives, the set holds the high-precision truth at every collision, it widens at about the Lyapunov
// rate where plain intervals widen at about 4 bits a collision, and a certificate it gives is re-proven
// inside itself at twice the bits.
#include <gmpxx.h>
#include <gtest/gtest.h>
#include <mpfi.h>

#include <cmath>
#include <numeric>
#include <random>

#include "geometry/formulas.hpp"
#include "io/scene_file.hpp"
#include "numeric/jet.hpp"
#include "numeric/tiers.hpp"
#include "sim/model/sampling.hpp"
#include "verify/certify.hpp"
#include "verify/lohner.hpp"
#include "verify/trace.hpp"

using namespace rotleak;

namespace {

Scene stationary() { return parse_scene("[leak]\nwidth = \"0.01\"\nstart = \"0\"\n"); }

std::array<double, 5> collide_d(const std::array<double, 4>& s) {
  const auto e = formula::next_exit(1.0, 1.0, s[0], s[1], s[2], s[3]);
  const auto v = formula::reflect(e.straight, e.cx, e.x, e.y, s[2], s[3]);
  return {e.x, e.y, v.x, v.y, e.t};
}

}  // namespace

// Forward-mode jets through next_exit and reflect against central differences (error model: the
// difference quotient's truncation O(h^2 f''') plus rounding O(eps / h); h = 1e-6 gives ~1e-9 of the
// derivative's scale), on straight and arc flights alike.
TEST(Lohner, JetsGiveTheFormulasDerivatives) {
  using J = Jet<double, 4>;
  const std::array<std::array<double, 4>, 4> starts{{
      {0.3, 1.0, std::cos(-1.1), std::sin(-1.1)},   // top edge to the bottom edge
      {0.3, 1.0, std::cos(-0.3), std::sin(-0.3)},   // top edge to the right arc
      {1.6, 0.8, std::cos(2.9), std::sin(2.9)},     // right arc to the left arc
      {-1.4, -0.9, std::cos(0.05), std::sin(0.05)}  // left arc, nearly flat, to the right arc
  }};
  for (const auto& s : starts) {
    std::array<J, 4> x;
    for (int i = 0; i < 4; ++i) x[i] = J::variable(s[i], i);
    const auto e = formula::next_exit(J(1), J(1), x[0], x[1], x[2], x[3]);
    const auto v = formula::reflect(e.straight, e.cx, e.x, e.y, x[2], x[3]);
    const std::array<const J*, 5> out{&e.x, &e.y, &v.x, &v.y, &e.t};
    const double h = 1e-6;
    for (int j = 0; j < 4; ++j) {
      auto up = s, down = s;
      up[j] += h;
      down[j] -= h;
      const auto fu = collide_d(up), fd = collide_d(down);
      for (int i = 0; i < 5; ++i) {
        const double fdiff = (fu[i] - fd[i]) / (2 * h);
        EXPECT_NEAR(out[i]->d[j], fdiff, 1e-6 * (1 + std::abs(fdiff))) << "output " << i << ", input " << j;
      }
    }
  }
}

// At every collision the set's box holds the truth (the core in MPFR at 3000 bits, whose own error after
// 250 collisions is below 2^(-3000 + 4 * 250), far inside a box at least 2^-400 wide), and its time too.
TEST(Lohner, TheSetHoldsTheTruthAtEveryCollision) {
  const Scene scene = stationary();
  const auto sampler = make_sampler(scene);
  for (std::uint64_t id = 0; id < 4; ++id) {
    const InitialDraw draw = sampler->draw(id);
    std::vector<std::array<Mpfr, 3>> truth;
    {
      MpfrPrecision bits(3000);
      Model<Mpfr> m = model_of<Mpfr>(scene);
      m.t_max = Mpfr(1e300);
      trace(m, draw, 250, [&](const TraceStep<Mpfr>& s) {
        truth.push_back({s.q.x, s.q.y, s.t});
        return true;
      });
    }
    ASSERT_EQ(truth.size(), 250u);
    MpfrPrecision bits(400);
    Model<Mpfi> m = model_of<Mpfi>(scene);
    LohnerEnclosure set(m, draw);
    std::size_t k = 0;
    try {
      for (; k < truth.size(); ++k) {
        const EnclosedCollision e = set.step();
        ASSERT_TRUE(e.q.x.contains(truth[k][0].data())) << "particle " << id << ", collision " << k + 1;
        ASSERT_TRUE(e.q.y.contains(truth[k][1].data())) << "particle " << id << ", collision " << k + 1;
        ASSERT_TRUE(e.t.contains(truth[k][2].data())) << "particle " << id << ", collision " << k + 1;
      }
    } catch (const UncertainDecision&) {
    }
    EXPECT_GE(k, 200u) << "particle " << id;  // 400 bits at ~1.4 bits a collision: ~250
  }
}

// The widening, in bits a collision over 400 collisions, on 6 particles: the Lyapunov exponent is 0.94 a
// collision, 1.35 bits (docs/model.md); the mean-value set stays within 1.6, plain intervals lose more than
// 3 (a deterministic computation: fixed particles, fixed bits).
TEST(Lohner, WidensAtTheLyapunovRateNotTheIntervalRate) {
  const Scene scene = stationary();
  const auto sampler = make_sampler(scene);
  const std::size_t n = 400;
  double lohner = 0, interval = 0;
  for (std::uint64_t id = 0; id < 6; ++id) {
    const InitialDraw draw = sampler->draw(id);
    const std::vector<double> wl = enclosure_log2_widths(scene, draw, 800, n, Enclosure::lohner);
    const std::vector<double> wi = enclosure_log2_widths(scene, draw, 1900, n, Enclosure::interval);
    ASSERT_EQ(wl.size(), n + 1);
    ASSERT_EQ(wi.size(), n + 1);
    lohner += (wl[n] - wl[0]) / n / 6;
    interval += (wi[n] - wi[0]) / n / 6;
  }
  EXPECT_LT(lohner, 1.6);
  EXPECT_GT(lohner, 1.0);  // below the Lyapunov rate would be a set that misses the truth
  EXPECT_GT(interval, 3.0);
}

// A certified escape is proven again at twice the bits, at the same collision, with its time inside the first
// enclosure; both methods prove the same escape.
TEST(Lohner, ACertifiedEscapeIsReprovenInsideItselfAtTwiceTheBits) {
  const Scene scene = stationary();
  const auto sampler = make_sampler(scene);
  int proven = 0;
  for (std::uint64_t id = 0; id < 12; ++id) {
    const InitialDraw draw = sampler->draw(id);
    const auto attempts = certify(scene, draw, 64, 8192, 5000);
    if (!attempts.back().escape_certified) continue;
    ++proven;
    const Certificate& first = attempts.back();
    const Certificate again = certify_at(scene, draw, 2 * first.bits, 5000);
    ASSERT_TRUE(again.escape_certified) << "particle " << id;
    EXPECT_EQ(again.escape_collision, first.escape_collision);
    EXPECT_GE(again.escape_time_lo, first.escape_time_lo);
    EXPECT_LE(again.escape_time_hi, first.escape_time_hi);
    const auto plain = certify(scene, draw, 64, 1 << 15, 5000, Enclosure::interval);
    ASSERT_TRUE(plain.back().escape_certified) << "particle " << id;
    EXPECT_EQ(plain.back().escape_collision, first.escape_collision);
    EXPECT_LE(plain.back().escape_time_lo, first.escape_time_hi);
    EXPECT_GE(plain.back().escape_time_hi, first.escape_time_lo);
  }
  EXPECT_GE(proven, 10);
}

namespace {

using DMat4 = std::array<std::array<double, 4>, 4>;

// The exact inverse of a matrix of doubles, by Gauss-Jordan over the rationals (GMP): no rounding anywhere.
std::array<std::array<mpq_class, 4>, 4> exact_inverse(const DMat4& q) {
  std::array<std::array<mpq_class, 8>, 4> m;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 8; ++j) m[i][j] = j < 4 ? mpq_class(q[i][j]) : mpq_class(j - 4 == i ? 1 : 0);
  for (int c = 0; c < 4; ++c) {
    int piv = c;
    while (m[piv][c] == 0) ++piv;  // the matrices here are invertible
    std::swap(m[piv], m[c]);
    const mpq_class d = m[c][c];
    for (int j = 0; j < 8; ++j) m[c][j] /= d;
    for (int i = 0; i < 4; ++i)
      if (i != c && m[i][c] != 0) {
        const mpq_class f = m[i][c];
        for (int j = 0; j < 8; ++j) m[i][j] -= f * m[c][j];
      }
  }
  std::array<std::array<mpq_class, 4>, 4> inv;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) inv[i][j] = m[i][j + 4];
  return inv;
}

bool holds(const std::array<std::array<Mpfi, 4>, 4>& box, const std::array<std::array<mpq_class, 4>, 4>& x) {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (!mpfi_is_inside_q(x[i][j].get_mpq_t(), box[i][j].data())) return false;
  return true;
}

// A rotation in doubles: the product of three Givens rotations by the given angles (orthogonal up to rounding).
DMat4 rotation(double a, double b, double c) {
  DMat4 q{};
  for (int i = 0; i < 4; ++i) q[i][i] = 1;
  const auto givens = [&](int i, int j, double t) {
    for (int r = 0; r < 4; ++r) {
      const double x = q[r][i], y = q[r][j];
      q[r][i] = std::cos(t) * x - std::sin(t) * y;
      q[r][j] = std::sin(t) * x + std::cos(t) * y;
    }
  };
  givens(0, 1, a), givens(1, 2, b), givens(2, 3, c);
  return q;
}

}  // namespace

// The inverse enclosure holds the exact inverse (rational Gauss-Jordan) of matrices that are orthogonal only up
// to a perturbation from 1e-12 to 1e-3 of their entries, where q^T alone (the enclosure without its error term)
// misses it by about the perturbation: 40 random rotations, each entry moved by a random relative amount.
TEST(LohnerInverse, HoldsTheExactInverseOfNearlyOrthogonalMatrices) {
  MpfrPrecision bits(128);
  std::mt19937_64 gen(5);
  std::uniform_real_distribution<double> angle(-3, 3), unit(-1, 1);
  int missed_by_transpose = 0;
  for (int n = 0; n < 40; ++n) {
    DMat4 q = rotation(angle(gen), angle(gen), angle(gen));
    const double size = std::pow(10.0, -12 + 9 * (n % 10) / 9.0);
    for (auto& row : q)
      for (double& v : row) v *= 1 + size * unit(gen);
    const auto inv = lohner_detail::inverse_enclosure(q);
    const auto exact = exact_inverse(q);
    EXPECT_TRUE(holds(inv, exact)) << "matrix " << n << ", perturbation " << size;
    std::array<std::array<Mpfi, 4>, 4> transpose;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) transpose[i][j] = Mpfi(q[j][i]);
    missed_by_transpose += !holds(transpose, exact);
  }
  EXPECT_EQ(missed_by_transpose, 40) << "q^T alone must miss a non-orthogonal q's inverse, or the test shows nothing";
}

// It refuses a matrix too far from orthogonal for its bound (||I - q^T q|| >= 1/2), and its claim is exact where
// q is: the identity's enclosure is the identity's points, which do not hold the inverse of the identity with one
// entry one ulp above 1 (1 / (1 + 2^-52)), while that matrix's own enclosure does.
TEST(LohnerInverse, RefusesAFarFromOrthogonalMatrixAndSeesOneUlp) {
  MpfrPrecision bits(128);
  DMat4 far{};
  for (int i = 0; i < 4; ++i) far[i][i] = 1.5;
  EXPECT_THROW(lohner_detail::inverse_enclosure(far), UncertainDecision);
  DMat4 id{};
  for (int i = 0; i < 4; ++i) id[i][i] = 1;
  DMat4 ulp = id;
  ulp[0][0] = std::nextafter(1.0, 2.0);
  const auto of_id = lohner_detail::inverse_enclosure(id);
  EXPECT_TRUE(holds(of_id, exact_inverse(id)));
  EXPECT_FALSE(holds(of_id, exact_inverse(ulp)))
      << "the identity's enclosure must not hold a one-ulp neighbour's inverse";
  EXPECT_TRUE(holds(lohner_detail::inverse_enclosure(ulp), exact_inverse(ulp)));
}
