// Carlson's symmetric elliptic integrals R_F and R_D over any tier's number type, and the arc length of an ellipse
// from them (docs/model.md, "The ellipse"): the boundary coordinate s of an elliptic table and its exact perimeter.
//   R_F(x, y, z) = 1/2 int_0^inf dt / sqrt((t + x)(t + y)(t + z)),
//   R_D(x, y, z) = 3/2 int_0^inf dt / ((t + z) sqrt((t + x)(t + y)(t + z))),   x, y, z >= 0 (at most one 0).
// Both by Carlson's duplication (Numer. Math. 33 (1979) 1; Numer. Algorithms 10 (1995) 13): each step maps the
// arguments to (x + l) / 4, ... with l = sqrt(x) sqrt(y) + sqrt(y) sqrt(z) + sqrt(z) sqrt(x), R_F unchanged and R_D
// = R_D(new) / 4 + 3 / (sqrt(z) (z + l)), and brings them 4 times closer together. Then:
// - a point tier (double, dd, float128, MPFR) takes the fifth-order series about their mean, after a fixed number
//   of steps set by its bits alone (no test on the data: the same operations for every argument, so a table's s
//   has one set of bits on every engine). The arguments start within eps_0 <= 2 of their mean (relative), so after
//   n steps eps_n <= 2 4^-n, and the series' error, of order eps_n^6, is far below the tier's epsilon from
//   n = ceil((bits + 11) / 12) + 1 (tests/test_carlson.cpp measures the error against MPFR at 320 bits);
// - an interval tier (MPFI) encloses the rest rigorously without a series: R_F and R_D decrease in each argument,
//   and R_F(m, m, m) = m^(-1/2), R_D(m, m, m) = m^(-3/2), so with m, M the least and largest argument
//   R_F in [M^(-1/2), m^(-1/2)] and R_D in [M^(-3/2), m^(-3/2)]: the hull of the three arguments' powers. Each
//   step shrinks that hull's relative width 4 times: bits / 2 + 4 steps reach the tier's precision.
// Header-only, no container, no GMP or MPFR: a device compiler can take it whole.
#pragma once

#include <cmath>
#include <type_traits>

#include "numeric/device.hpp"

namespace rotleak {
/// The tier's traits (numeric/num_traits.hpp, numeric/tiers.hpp): bits() sets the step count; the caller includes
/// them, and an interval tier's hull (numeric/mpfi_ops.hpp), so that this header needs neither GMP nor MPFR.
template <class R>
struct num_traits;
}  // namespace rotleak

namespace rotleak::carlson {

/// Whether R is an interval type (its comparisons may be undecided; it has hi()).
template <class R>
inline constexpr bool is_interval = requires(const R& r) {
  r.hi();
};

/// Duplication steps for a tier of `bits` bits: a point tier's (before its series), an interval tier's (before its
/// monotone enclosure).
ROTLEAK_HD constexpr int point_steps(long bits) { return static_cast<int>((bits + 11) / 12) + 1; }
ROTLEAK_HD constexpr int interval_steps(long bits) { return static_cast<int>(bits / 2) + 4; }

template <class R>
ROTLEAK_HD inline int steps() {
  if constexpr (std::is_same_v<R, double>)
    return point_steps(53);  // without the traits: the engines' double needs no MPFR
  else if constexpr (is_interval<R>)
    return interval_steps(static_cast<long>(num_traits<R>::bits()));
  else
    return point_steps(static_cast<long>(num_traits<R>::bits()));
}

/// One duplication step: (x, y, z) -> ((x + l) / 4, ...); returns sqrt(z) (z + l) of the old arguments (R_D's term).
template <class R>
ROTLEAK_HD inline R duplicate(R& x, R& y, R& z) {
  using std::sqrt;
  const R sx = sqrt(x), sy = sqrt(y), sz = sqrt(z);
  const R l = sx * (sy + sz) + sy * sz;
  const R term = sz * (z + l);
  const R quarter = R(1) / R(4);
  x = (x + l) * quarter, y = (y + l) * quarter, z = (z + l) * quarter;
  return term;
}

/// R_F(x, y, z).
template <class R>
ROTLEAK_HD inline R rf(R x, R y, R z) {
  using std::sqrt;
  const int n = steps<R>();
  for (int i = 0; i < n; ++i) duplicate(x, y, z);
  if constexpr (is_interval<R>) {
    return hull(hull(R(1) / sqrt(x), R(1) / sqrt(y)), R(1) / sqrt(z));
  } else {
    const R a = (x + y + z) / R(3);
    const R dx = (a - x) / a, dy = (a - y) / a, dz = (a - z) / a;
    const R e2 = dx * dy - dz * dz, e3 = dx * dy * dz;
    return (R(1) + (e2 / R(24) - R(1) / R(10) - R(3) * e3 / R(44)) * e2 + e3 / R(14)) / sqrt(a);
  }
}

/// R_D(x, y, z).
template <class R>
ROTLEAK_HD inline R rd(R x, R y, R z) {
  using std::sqrt;
  const int n = steps<R>();
  R sum(0), fac(1);
  const R quarter = R(1) / R(4);
  for (int i = 0; i < n; ++i) {
    sum = sum + fac / duplicate(x, y, z);
    fac = fac * quarter;
  }
  if constexpr (is_interval<R>) {
    const R rest = hull(hull(R(1) / (x * sqrt(x)), R(1) / (y * sqrt(y))), R(1) / (z * sqrt(z)));
    return R(3) * sum + fac * rest;
  } else {
    const R a = (x + y + R(3) * z) / R(5);
    const R dx = (a - x) / a, dy = (a - y) / a, dz = (a - z) / a;
    const R ea = dx * dy, eb = dz * dz, ec = ea - eb, ed = ea - R(6) * eb, ee = ed + ec + ec;
    const R c1 = R(3) / R(14), c2 = R(1) / R(6), c3 = R(9) / R(22), c4 = R(3) / R(26);
    const R c5 = c3 / R(4), c6 = R(3) * c4 / R(2);
    const R series = R(1) + ed * (c5 * ed - c1 - c6 * dz * ee) + dz * (c2 * ee + dz * (dz * c4 * ea - c3 * ec));
    return R(3) * sum + fac * series / (a * sqrt(a));
  }
}

/// The arc length int_0^phi sqrt(P^2 cos^2 t + Q^2 sin^2 t) dt from t = 0 to the angle phi with sin(phi) = u,
/// cos(phi) = w >= 0 (u^2 + w^2 = 1), from p2 = P^2 and q2 = Q^2: P E(phi | 1 - Q^2 / P^2) in Carlson's form (DLMF
/// 19.25.9) made homogeneous,
///   P^2 u R_F(x, y, P^2) - (P^2 - Q^2) P^2 u^3 R_D(x, y, P^2) / 3,
/// x = P^2 w^2, y = x + Q^2 u^2 (= P^2 - (P^2 - Q^2) u^2).
/// On the ellipse (a sin psi, b cos psi) the arc from the top (0, b) is this with P = a, Q = b, u = sin psi; from the
/// vertex (a, 0), with P = b, Q = a, u = its angle's sine. Well conditioned for u <= 1/sqrt(2) (the caller measures
/// from the nearer vertex); u = 1 gives the quarter perimeter.
template <class R>
ROTLEAK_HD inline R ellipse_arc(const R& u, const R& w, const R& p2, const R& q2) {
  const R x = p2 * (w * w), y = x + q2 * (u * u);
  return p2 * u * rf(x, y, p2) - (p2 - q2) * p2 * (u * u * u) * rd(x, y, p2) / R(3);
}

/// The quarter perimeter of the ellipse with semi-axes a, b from a2 = a^2, b2 = b^2: ellipse_arc at u = 1.
template <class R>
ROTLEAK_HD inline R ellipse_quarter(const R& a2, const R& b2) {
  return ellipse_arc(R(1), R(0), a2, b2);
}

}  // namespace rotleak::carlson
