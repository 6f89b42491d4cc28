// atan2(y, x) of two doubles: the double tier's own, so that every engine -- the scalar core, the vectorised
// kernel's exact fallback, the GPU engine -- takes the same bits from the same operations, whatever the C library
// or the device's math library would round differently (glibc's and CUDA's atan2 each differ from the correctly
// rounded value by up to an ulp, and not in the same places). The other tiers keep their own (MPFR's is correctly
// rounded): tier_atan2 below.
//
// The method is fdlibm's (FreeBSD msun e_atan2.c and s_atan.c; their notice: "Copyright (C) 1993 by Sun
// Microsystems, Inc. All rights reserved. Developed at SunSoft, a Sun Microsystems, Inc. business. Permission to use,
// copy, modify, and distribute this software is freely granted, provided that this notice is preserved."): y/x
// reduced to |y/x| in the first octant's neighbourhood, atan(t) reduced to one of five ranges around 0, 1/2, 1, 3/2
// and infinity with atan of the range's point as hi + lo, then an odd minimax polynomial of degree 23. Error
// against the correctly rounded atan2: below 2 ulp (atan's own error below 1 ulp, the rounded quotient y / x half an
// ulp more, the subtraction from pi off the first quadrant half an ulp more); tests/test_atan2.cpp measures it
// against MPFR on every quadrant, the ranges' edges and 5.8 * 10^5 arguments, and docs/model.md states the figure.
// Every operation is one IEEE rounding in program order (no contraction: the build's -ffp-contract=off and nvcc's
// -fmad=false).
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <type_traits>

#include "numeric/device.hpp"

namespace rotleak::formula {

namespace atan2_detail {

/// The high 32 bits of x (sign, exponent, top of the mantissa), as fdlibm reads them.
ROTLEAK_HD inline std::int32_t high_word(double x) {
  return static_cast<std::int32_t>(std::bit_cast<std::uint64_t>(x) >> 32);
}
ROTLEAK_HD inline std::uint32_t low_word(double x) {
  return static_cast<std::uint32_t>(std::bit_cast<std::uint64_t>(x));
}

/// atan x (s_atan.c), x finite.
ROTLEAK_HD inline double atan(double x) {
  // atan(1/2), atan(1), atan(3/2), atan(inf) = pi/2, each as hi + lo; taken by the branch as constants, not from a
  // table by index (an indexed table is copied into a GPU thread's local memory at every call)
  constexpr double hi0 = 4.63647609000806093515e-01, hi1 = 7.85398163397448278999e-01, hi2 = 9.82793723247329054082e-01,
                   hi3 = 1.57079632679489655800e+00;
  constexpr double lo0 = 2.26987774529616870924e-17, lo1 = 3.06161699786838301793e-17, lo2 = 1.39033110312309984516e-17,
                   lo3 = 6.12323399573676603587e-17;
  constexpr double aT[] = {3.33333333333329318027e-01,  -1.99999999998764832476e-01, 1.42857142725034663711e-01,
                           -1.11111104054623557880e-01, 9.09088713343650656196e-02,  -7.69187620504482999495e-02,
                           6.66107313738753120669e-02,  -5.83357013379057348645e-02, 4.97687799461593236017e-02,
                           -3.65315727442169155270e-02, 1.62858201153657823623e-02};
  const std::int32_t hx = high_word(x), ix = hx & 0x7fffffff;
  if (ix >= 0x44100000) return hx > 0 ? hi3 + lo3 : -hi3 - lo3;  // |x| >= 2^66
  bool reduced = true;
  double hi = 0, lo = 0;
  if (ix < 0x3fdc0000) {            // |x| < 7/16
    if (ix < 0x3e400000) return x;  // |x| < 2^-27: atan x rounds to x
    reduced = false;
  } else {
    x = x < 0 ? -x : x;
    if (ix < 0x3ff30000) {    // |x| < 19/16
      if (ix < 0x3fe60000) {  // 7/16 <= |x| < 11/16
        hi = hi0, lo = lo0;
        x = (2.0 * x - 1.0) / (2.0 + x);
      } else {  // 11/16 <= |x| < 19/16
        hi = hi1, lo = lo1;
        x = (x - 1.0) / (x + 1.0);
      }
    } else if (ix < 0x40038000) {  // 19/16 <= |x| < 39/16
      hi = hi2, lo = lo2;
      x = (x - 1.5) / (1.0 + 1.5 * x);
    } else {  // 39/16 <= |x| < 2^66
      hi = hi3, lo = lo3;
      x = -1.0 / x;
    }
  }
  const double z = x * x, w = z * z;
  // the sum of aT[i] z^(i+1), i = 0 .. 10, as its odd and even halves
  const double s1 = z * (aT[0] + w * (aT[2] + w * (aT[4] + w * (aT[6] + w * (aT[8] + w * aT[10])))));
  const double s2 = w * (aT[1] + w * (aT[3] + w * (aT[5] + w * (aT[7] + w * aT[9]))));
  if (!reduced) return x - x * (s1 + s2);
  const double r = hi - ((x * (s1 + s2) - lo) - x);
  return hx < 0 ? -r : r;
}

}  // namespace atan2_detail

/// atan2(y, x) in double (e_atan2.c): within 2 ulp of the correctly rounded value (above), with C's special cases
/// (signed zeros, infinities; NaN in, NaN out).
ROTLEAK_HD inline double atan2_of(double y, double x) {
  using atan2_detail::high_word;
  using atan2_detail::low_word;
  constexpr double pi_o_4 = 7.8539816339744827900E-01, pi_o_2 = 1.5707963267948965580E+00,
                   pi = 3.1415926535897931160E+00, pi_lo = 1.2246467991473531772E-16;
  const std::int32_t hx = high_word(x), hy = high_word(y);
  const std::uint32_t lx = low_word(x), ly = low_word(y);
  const std::int32_t ix = hx & 0x7fffffff, iy = hy & 0x7fffffff;
  if (x != x || y != y) return x + y;                             // NaN
  if (hx == 0x3ff00000 && lx == 0) return atan2_detail::atan(y);  // x = 1
  int m = ((hy >> 31) & 1) | ((hx >> 30) & 2);                    // 2 sign(x) + sign(y)
  if ((iy | static_cast<std::int32_t>(ly)) == 0) {                // y = 0
    if (m <= 1) return y;
    return m == 2 ? pi : -pi;
  }
  if ((ix | static_cast<std::int32_t>(lx)) == 0) return hy < 0 ? -pi_o_2 : pi_o_2;  // x = 0
  if (ix == 0x7ff00000) {                                                           // x infinite
    // by m: +-pi/4 or +-3pi/4, else +-0 or +-pi (selected, not indexed: no table in a GPU thread's local memory)
    const double a = iy == 0x7ff00000 ? (m >= 2 ? 3.0 * pi_o_4 : pi_o_4) : (m >= 2 ? pi : 0.0);
    return (m & 1) ? -a : a;
  }
  if (iy == 0x7ff00000) return hy < 0 ? -pi_o_2 : pi_o_2;  // y infinite
  const std::int32_t k = (iy - ix) >> 20;
  double z;
  if (k > 60) {  // |y/x| > 2^60
    z = pi_o_2 + 0.5 * pi_lo;
    m &= 1;
  } else if (hx < 0 && k < -60) {  // 0 > |y|/x > -2^-60
    z = 0.0;
  } else {
    const double q = y / x;
    z = atan2_detail::atan(q < 0 ? -q : q);
  }
  switch (m) {
    case 0:
      return z;
    case 1:
      return -z;
    case 2:
      return pi - (z - pi_lo);
    default:
      return (z - pi_lo) - pi;
  }
}

/// atan2_of compiled once, out of line, for the machine's base instruction set (numeric/atan2.cpp): what the
/// vectorised kernels' exact fallbacks call, lane by lane, since a kernel object built for AVX2 or AVX-512 must hold
/// no inline copy of the scalar core's code (the linker could keep that copy for the core too).
double atan2_scalar(double y, double x);

/// atan2 in a tier: atan2_of above in the double tier (every engine's), the tier's own in every other.
template <class R>
ROTLEAK_HD inline R tier_atan2(const R& y, const R& x) {
  if constexpr (std::is_same_v<R, double>) {
    return atan2_of(y, x);
  } else {
    using std::atan2;
    return R(atan2(y, x));
  }
}

}  // namespace rotleak::formula
