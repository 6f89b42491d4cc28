// What a mean-value enclosure needs of an MPFI interval beyond the core's arithmetic: the hull of two,
// the midpoint, the magnitude, the intersection (verify/lohner.cpp, numeric/jet.hpp).
#pragma once

#include <cmath>
#include <stdexcept>

#include "numeric/mpfr_real.hpp"

namespace rotleak {

/// The smallest interval holding a and b.
inline Mpfi hull(const Mpfi& a, const Mpfi& b) {
  Mpfi r;
  mpfi_union(r.data(), a.data(), b.data());
  return r;
}

/// The midpoint (rounded to this thread's precision) as a thin interval.
inline Mpfi midpoint(const Mpfi& a) {
  mpfr_t m;
  mpfr_init2(m, MpfrPrecision::current());
  mpfi_mid(m, a.data());
  Mpfi r;
  mpfi_set_fr(r.data(), m);
  mpfr_clear(m);
  return r;
}

/// The largest |x| over the interval, rounded up, as a double.
inline double magnitude(const Mpfi& a) {
  mpfr_t m;
  mpfr_init2(m, mpfi_get_prec(a.data()));  // exact: the end point itself, then rounded up once
  mpfi_mag(m, a.data());
  const double d = mpfr_get_d(m, MPFR_RNDU);
  mpfr_clear(m);
  return d;
}

/// log2 of the interval's width, rounded up (a width below double's range still has one; -inf for a
/// point).
inline double log2_width(const Mpfi& a) {
  mpfr_t w;
  mpfr_init2(w, 53);
  mpfi_diam_abs(w, a.data());
  long exponent = 0;
  const double mantissa = mpfr_get_d_2exp(&exponent, w, MPFR_RNDU);
  mpfr_clear(w);
  return std::log2(mantissa) + static_cast<double>(exponent);
}

/// The interval [-radius, radius] (radius a double, exact).
inline Mpfi symmetric(double radius) { return hull(Mpfi(-radius), Mpfi(radius)); }

/// a and b intersected; both must enclose the same value, so an empty intersection is a defect.
inline Mpfi intersect(const Mpfi& a, const Mpfi& b) {
  Mpfi r;
  mpfi_intersect(r.data(), a.data(), b.data());
  if (mpfi_is_empty(r.data())) throw std::logic_error("intersect: two enclosures of one value are disjoint");
  return r;
}

}  // namespace rotleak
