// sin and cos of one argument together, written once over a number type T that is a double or a pack of
// double lanes (the vectorised kernel): the double tier's initial states (Stadium<double>::at, a flow
// start's direction) and the kernel's vectorised draws both evaluate this formula, in the same order
// with one rounding per operation, so the two engines start every particle from the same bits without
// libm (whose sin and cos cannot be vectorised). The other tiers keep their own sin and cos (MPFR's are
// correctly rounded): each tier computes the initial point at its own precision (docs/model.md, "Initial
// conditions").
//
// The method is fdlibm's (FreeBSD msun, k_sin.c and k_cos.c, Sun's public-domain code): x is reduced by
// the nearest multiple k pi/2 with pi/2 split in three parts (33 + 33 + 53 bits), the first two products
// exact, the remainder carried as y0 + y1 (a double-double, |error| < 1e-33 for |x| < 8); then the kernels'
// minimax polynomials on [-pi/4, pi/4] (|polynomial error| < 2^-58 relative), and the quadrant k mod 4
// picks the signs. Error against the correctly rounded sin and cos: < 1 ulp over the whole range it is
// used on, |x| <= 8 (arc angles in [0, pi], flow angles in [0, 2 pi)); tests/test_sin_cos.cpp measures it
// against MPFR on every quadrant boundary and 4 * 10^6 arguments, and docs/model.md states the figure.
// Header-only, templates only, no dependency but the selection hook (the kernel instantiates it on its
// own pack type; see geometry/formulas.hpp).
#pragma once

#include <cmath>
#include <type_traits>

#include "numeric/device.hpp"
#include "numeric/select.hpp"

namespace rotleak::formula {

template <class T>
struct SinCos {
  T sin, cos;
};

namespace sin_cos_detail {
inline constexpr double kTwoOverPi = 6.36619772367581382433e-01;
inline constexpr double kPio2_1 = 1.57079632673412561417e+00;   ///< first 33 bits of pi/2
inline constexpr double kPio2_2 = 6.07710050630396597660e-11;   ///< next 33 bits
inline constexpr double kPio2_2t = 2.02226624879595063154e-21;  ///< pi/2 - (kPio2_1 + kPio2_2), rounded

/// fdlibm's __kernel_sin(y0, y1) for |y0 + y1| <= pi/4 (k_sin.c, the form with a tail).
template <class T>
ROTLEAK_HD inline T kernel_sin(const T& x, const T& y) {
  const T S1(-1.66666666666666324348e-01), S2(8.33333333332248946124e-03), S3(-1.98412698298579493134e-04),
      S4(2.75573137070700676789e-06), S5(-2.50507602534068634195e-08), S6(1.58969099521155010221e-10);
  const T z = x * x;
  const T w = z * z;
  const T r = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
  const T v = z * x;
  return x - ((z * (T(0.5) * y - v * r) - y) - v * S1);
}

/// fdlibm's __kernel_cos(y0, y1) for |y0 + y1| <= pi/4 (FreeBSD k_cos.c).
template <class T>
ROTLEAK_HD inline T kernel_cos(const T& x, const T& y) {
  const T C1(4.16666666666666019037e-02), C2(-1.38888888888741095749e-03), C3(2.48015872894767294178e-05),
      C4(-2.75573143513906633035e-07), C5(2.08757232129817482790e-09), C6(-1.13596475577881948265e-11);
  const T z = x * x;
  const T w2 = z * z;
  const T r = z * (C1 + z * (C2 + z * C3)) + w2 * w2 * (C4 + z * (C5 + z * C6));
  const T hz = T(0.5) * z;
  const T w = T(1.0) - hz;
  return w + (((T(1.0) - w) - hz) + (z * r - x * y));
}
}  // namespace sin_cos_detail

/// sin x and cos x for |x| <= 8, within 1 ulp of the correctly rounded values (see above).
template <class T>
ROTLEAK_HD inline SinCos<T> sin_cos(const T& x) {
  using std::floor;
  using std::nearbyint;
  using namespace sin_cos_detail;
  const T k = nearbyint(x * T(kTwoOverPi));
  const T t = x - k * T(kPio2_1);  // exact: k kPio2_1 has 36 bits, and t is x's difference from a near value
  const T w = k * T(kPio2_2);      // exact
  // t - w as r + e exactly (Knuth's two-sum), then the third part of pi/2
  const T r = t - w;
  const T bb = r - t;
  const T e = (t - (r - bb)) + (-w - bb);
  const T lo = e - k * T(kPio2_2t);
  const T y0 = r + lo;
  const T y1 = (r - y0) + lo;
  const T s = kernel_sin(y0, y1), c = kernel_cos(y0, y1);
  // the quadrant n = k mod 4 (k a small integer, exactly represented): n 0: (s, c), 1: (c, -s), 2: (-s, -c),
  // 3: (-c, s)
  const T n = k - T(4.0) * floor(k * T(0.25));
  const mask_of<T> odd = (n == T(1.0)) | (n == T(3.0)), sin_negative = n >= T(2.0),
                   cos_negative = (n == T(1.0)) | (n == T(2.0));
  const T a = select(odd, c, s), b = select(odd, s, c);
  return {select(sin_negative, T(-a), a), select(cos_negative, T(-b), b)};
}

/// sin and cos of an angle in [0, 2 pi] in a tier: the shared formula above in the double tier (which the
/// vectorised kernel evaluates too), in every other tier the tier's own (MPFR's correctly rounded ones).
template <class R>
ROTLEAK_HD inline SinCos<R> tier_sin_cos(const R& angle) {
  if constexpr (std::is_same_v<R, double>) {
    return sin_cos(angle);
  } else {
    using std::cos;
    using std::sin;
    return {sin(angle), cos(angle)};
  }
}

}  // namespace rotleak::formula
