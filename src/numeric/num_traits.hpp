// One traits struct per number type, after CAPD: name, bits, epsilon, the one correct rounding of an
// exact input into the type, pi, and the exact error of a product (for the leak phase). Generic code
// asks these instead of spelling constants. Boost.Multiprecision stays out of this header: its
// MPFR-backed type has its own (numeric/mpfr_fixed.hpp), for the code that uses it.
#pragma once

#include <mpfr.h>

#include <cmath>
#include <limits>
#include <string>

#include "numeric/device.hpp"
#include "numeric/exact.hpp"

namespace rotleak {

template <class R>
struct num_traits;

namespace detail {

/// Rounding of exact values through MPFR at the type's bits, for every type that has from_mpfr.
template <class R, class Traits>
struct rounded_from_mpfr {
  static R from_exact(const ExactReal& x) {
    mpfr_t tmp;
    mpfr_init2(tmp, Traits::bits());
    x.round(tmp, MPFR_RNDN);
    R r = Traits::from_mpfr(tmp);
    mpfr_clear(tmp);
    return r;
  }
  static R pi() { return from_exact(ExactReal::pi()); }
};

template <class R, mpfr_prec_t Bits, class Traits>
struct ieee_traits : rounded_from_mpfr<R, Traits> {
  static constexpr mpfr_prec_t bits() { return Bits; }
  ROTLEAK_HD static R epsilon() { return std::numeric_limits<R>::epsilon(); }
  ROTLEAK_HD static double to_double(R x) { return static_cast<double>(x); }
  /// e with a*b = prod + e exactly (prod = fl(a*b)).
  ROTLEAK_HD static R product_error(R a, R b, R prod) {
    using std::fma;
    return fma(a, b, -prod);
  }
};

}  // namespace detail

template <>
struct num_traits<float> : detail::ieee_traits<float, 24, num_traits<float>> {
  static std::string name() { return "float"; }
  static void to_mpfr(mpfr_ptr out, float x) { mpfr_set_flt(out, x, MPFR_RNDN); }
  static float from_mpfr(const mpfr_t x) { return mpfr_get_flt(x, MPFR_RNDN); }
};
template <>
struct num_traits<double> : detail::ieee_traits<double, 53, num_traits<double>> {
  static std::string name() { return "double"; }
  static void to_mpfr(mpfr_ptr out, double x) { mpfr_set_d(out, x, MPFR_RNDN); }
  static double from_mpfr(const mpfr_t x) { return mpfr_get_d(x, MPFR_RNDN); }
};
template <>
struct num_traits<long double>
    : detail::ieee_traits<long double, std::numeric_limits<long double>::digits, num_traits<long double>> {
  static std::string name() { return "long_double"; }
  static void to_mpfr(mpfr_ptr out, long double x) { mpfr_set_ld(out, x, MPFR_RNDN); }
  static long double from_mpfr(const mpfr_t x) { return mpfr_get_ld(x, MPFR_RNDN); }
};
/// The exact value rounded once, correctly, into R (for interval types: enclosed).
template <class R>
R round_exact(const ExactReal& x) {
  return num_traits<R>::from_exact(x);
}

/// An exact value as an unevaluated sum hi + lo of two R (hi = fl(x), lo = fl(x - hi)): carries
/// about twice R's precision, which the leak phase needs at large omega*t.
template <class R>
struct two_term {
  R hi{0}, lo{0};
};

template <class R>
two_term<R> two_term_of(const ExactReal& x) {
  two_term<R> out;
  mpfr_t hi;
  mpfr_init2(hi, num_traits<R>::bits());
  x.round(hi, MPFR_RNDN);
  mpq_class hq;
  mpfr_get_q(hq.get_mpq_t(), hi);
  mpfr_clear(hi);
  // hi is the rounded value itself (exact in R; a point for interval types), lo encloses the rest
  out.hi = round_exact<R>(ExactReal::rational(hq));
  out.lo = round_exact<R>(x - ExactReal::rational(hq));
  return out;
}

}  // namespace rotleak
