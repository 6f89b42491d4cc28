// The shared sin and cos (numeric/sin_cos.hpp) that the double tier's initial states and the kernel's
// vectorised draws evaluate: its error against MPFR's correctly rounded sin and cos over the range it is
// used on, and the kernel's vectorised draws and initial states against the scalar core's, bit for bit.
//
// Error model: the formula is deterministic; fdlibm's analysis bounds its error below 1 ulp of the result
// (a double-double reduction good to ~1e-33, polynomials within 2^-58 relative, a few roundings). The test
// measures the error in ulps of the correctly rounded result (exact value to 256 bits) at every argument
// where the reduction is hardest (the 2000 doubles around each multiple of pi/4 in [-8, 8], where sin or cos
// is near zero or the quadrant changes), at tiny arguments, and at 2 * 10^5 uniform ones, and fails if any
// reaches 1 ulp.
#include <gtest/gtest.h>
#include <mpfr.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "geometry/stadium.hpp"
#include "kernel_widths.hpp"
#include "numeric/exact.hpp"
#include "numeric/sin_cos.hpp"
#include "sim/engine/kernel_adapter.hpp"
#include "sim/kernel/simd_engine.hpp"
#include "sim/model/initial.hpp"
#include "stadium_sizes.hpp"

using namespace rotleak;

namespace {

/// |ours - f(x)| in ulps of f(x) correctly rounded to double; f = sin (which = 0) or cos (1).
class UlpMeter {
 public:
  UlpMeter() { mpfr_inits2(256, x_, s_, c_, d_, static_cast<mpfr_ptr>(nullptr)); }
  ~UlpMeter() { mpfr_clears(x_, s_, c_, d_, static_cast<mpfr_ptr>(nullptr)); }
  UlpMeter(const UlpMeter&) = delete;
  UlpMeter& operator=(const UlpMeter&) = delete;

  /// The larger of the two errors (sin, cos) at x, in ulps.
  double error(double x) {
    const formula::SinCos<double> ours = formula::sin_cos(x);
    mpfr_set_d(x_, x, MPFR_RNDN);
    mpfr_sin_cos(s_, c_, x_, MPFR_RNDN);
    return std::max(ulps(ours.sin, s_), ulps(ours.cos, c_));
  }

 private:
  double ulps(double ours, mpfr_t exact) {
    if (mpfr_zero_p(exact)) return ours == 0 ? 0 : 1e300;
    // ulp of the double nearest the exact value: 2^(e - 53) with exact = m 2^e, m in [1/2, 1); subnormal ulp floor
    const long e = std::max<long>(mpfr_get_exp(exact), -1021);
    mpfr_set_d(d_, ours, MPFR_RNDN);
    mpfr_sub(d_, d_, exact, MPFR_RNDN);
    mpfr_abs(d_, d_, MPFR_RNDN);
    mpfr_mul_2si(d_, d_, 53 - e, MPFR_RNDN);
    return mpfr_get_d(d_, MPFR_RNDN);
  }
  mpfr_t x_, s_, c_, d_;
};

TEST(SinCos, WithinOneUlpOfTheCorrectlyRoundedValuesOverItsRange) {
  UlpMeter meter;
  double worst = 0, worst_x = 0;
  std::size_t checked = 0;
  const auto check = [&](double x) {
    const double e = meter.error(x);
    ++checked;
    if (e > worst) worst = e, worst_x = x;
  };
  // around every multiple of pi/4 in [-8, 8]: the 1000 doubles on each side
  for (int k = -10; k <= 10; ++k) {
    const double centre = k * 0.78539816339744830962;
    double up = centre, down = centre;
    for (int i = 0; i < 1000; ++i) {
      check(up), check(down);
      up = std::nextafter(up, 1e300), down = std::nextafter(down, -1e300);
    }
  }
  // tiny arguments, down to the subnormals, and both signs
  for (double x = 1; x > 0; x /= 2) check(x), check(-x);
  check(0.0), check(-0.0);
  check(8.0), check(-8.0), check(M_PI), check(2 * M_PI), check(M_PI / 2);
  // uniform over the range
  std::mt19937_64 gen(20261127);
  std::uniform_real_distribution<double> uni(-8, 8);
  for (int i = 0; i < 200000; ++i) check(uni(gen));
  std::printf("sin_cos: %zu arguments in [-8, 8], largest error %.3f ulp (at x = %.17g)\n", checked, worst, worst_x);
  EXPECT_LT(worst, 1.0) << "at x = " << worst_x;
}

TEST(SinCos, TheKernelsInitialStatesAreTheCoresBitForBit) {
  for (const test::Size& size : test::kSizes) {
    const Scene scene = test::scene_of(size, {});
    const Model<double> model = Model<double>::from(scene);
    const Stadium<double>& st = model.stadium;
    simd::KernelScene ks = simd_scene(model);
    // s: uniform, and a few ulps around each junction; p across (-1, 1)
    std::vector<double> s, p, u;
    std::mt19937_64 gen(7);
    std::uniform_real_distribution<double> uni(0, 1);
    for (int i = 0; i < 20000; ++i) s.push_back(uni(gen)), p.push_back(2 * uni(gen) - 1), u.push_back(uni(gen));
    for (int j = 0; j < 4; ++j) {
      double a = st.junction(j), b = a;
      for (int i = 0; i < 8; ++i) {
        s.push_back(a), s.push_back(b);
        p.push_back(0.5), p.push_back(-0.999999);
        u.push_back(i / 8.0), u.push_back(1 - std::ldexp(1, -53));
        a = std::nextafter(a, 2.0), b = std::nextafter(b, -1.0);
      }
    }
    for (int lanes : test::kernel_widths()) {
      ks.lanes = lanes;
      std::vector<simd::Start> out(s.size());
      std::vector<double> vx(u.size()), vy(u.size());
      simd::birkhoff_states(ks, s.data(), p.data(), out.data(), s.size());
      simd::flow_directions(ks, u.data(), vx.data(), vy.data(), u.size());
      std::size_t differ = 0;
      for (std::size_t i = 0; i < s.size(); ++i) {
        const BoundaryPoint<double> b = st.at(s[i]);
        const Vec2<double> v = st.velocity(b, p[i]);
        differ += out[i].qx != b.q.x || out[i].qy != b.q.y || out[i].vx != v.x || out[i].vy != v.y;
        const formula::SinCos<double> sc = Stadium<double>::sin_cos(formula::flow_angle(st.pi(), u[i]));
        differ += vx[i] != sc.cos || vy[i] != sc.sin;
      }
      EXPECT_EQ(differ, 0u) << size.name << ", " << lanes << " lanes";
    }
  }
}

// The kernel's own uniform draws (simd::uniform_starts: Philox4x64-10 per lane, the unit and symmetric
// conversions, the states): the scalar core's InitialConditions::draw and initial_state, bit for bit, on ids
// from 0, near 10^12 and near 2^64, for three seeds and two creation windows, at every kernel width.
TEST(SinCos, TheKernelsUniformDrawsAreTheCoresBitForBit) {
  for (const test::Size& size : test::kSizes) {
    for (const char* seed : {"1", "12345", "9223372036854775807"})
      for (const char* window : {"4", "0.37"}) {
        const Scene scene = test::scene_of(
            size, {std::string("ensemble.seed=") + seed, std::string("ensemble.creation_window=") + window});
        const Model<double> model = Model<double>::from(scene);
        const InitialConditions ic = initial_conditions(scene);
        simd::KernelScene ks = simd_scene(model);
        for (int lanes : test::kernel_widths()) {
          ks.lanes = lanes;
          for (const std::uint64_t first : {std::uint64_t{0}, std::uint64_t{999999999973}, ~std::uint64_t{0} - 300}) {
            const std::size_t n = 257;  // not a multiple of any pack
            std::vector<simd::Start> out(n);
            simd::uniform_starts(ks, ic.seed(), ic.creation_window(), first, n, out.data());
            std::size_t differ = 0;
            for (std::size_t i = 0; i < n; ++i) {
              const ParticleState<double> ps = initial_state(model.stadium, ic.draw(first + i));
              differ += out[i].qx != ps.q.x || out[i].qy != ps.q.y || out[i].vx != ps.v.x || out[i].vy != ps.v.y ||
                        out[i].t != ps.t || out[i].weight != 1 || out[i].collisions != 0;
            }
            EXPECT_EQ(differ, 0u) << size.name << " seed " << seed << " window " << window << " from id " << first
                                  << ", " << lanes << " lanes";
          }
        }
      }
  }
}

}  // namespace
