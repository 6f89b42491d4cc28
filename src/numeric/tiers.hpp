// The precision tiers beyond the IEEE types: double-double (QD's dd_real), quad (__float128 through
// Boost.Multiprecision), MPFR and MPFI at the thread's working precision. Each gets its num_traits;
// the geometry core runs on all of them unchanged.
#pragma once

#include <qd/dd_real.h>
#include <qd/qd_real.h>

#include <boost/multiprecision/float128.hpp>
#include <cmath>
#include <string>

#include "numeric/mpfr_real.hpp"
#include "numeric/num_traits.hpp"
#include "numeric/tier.hpp"  // first: its TierKind::float128, declared after the type below, would shadow it

// MPFR 4 built with float128 support (Debian's is); g++ 12 has no _Float128 in C++, __float128 is the same type.
extern "C" __float128 mpfr_get_float128(mpfr_srcptr, mpfr_rnd_t);
extern "C" int mpfr_set_float128(mpfr_ptr, __float128, mpfr_rnd_t);

namespace rotleak {

using float128 = boost::multiprecision::float128;

template <>
struct num_traits<dd_real> : detail::rounded_from_mpfr<dd_real, num_traits<dd_real>> {
  static constexpr mpfr_prec_t bits() { return 106; }
  static std::string name() { return "dd"; }
  static dd_real epsilon() { return dd_real(std::numeric_limits<dd_real>::epsilon()); }
  static double to_double(const dd_real& x) { return x.x[0] + x.x[1]; }
  /// Rounded at out's precision (exact when out has the bits to span hi and lo).
  static void to_mpfr(mpfr_ptr out, const dd_real& x) {
    mpfr_set_d(out, x.x[0], MPFR_RNDN);
    mpfr_add_d(out, out, x.x[1], MPFR_RNDN);
  }
  static dd_real from_mpfr(const mpfr_t x) {
    // hi + lo with hi = RN53(x) and lo = RN53(x - hi): exact for a 106-bit x
    mpfr_t rest;
    mpfr_init2(rest, mpfr_get_prec(x) + 64);
    const double hi = mpfr_get_d(x, MPFR_RNDN);
    mpfr_sub_d(rest, x, hi, MPFR_RNDN);
    const double lo = mpfr_get_d(rest, MPFR_RNDN);
    mpfr_clear(rest);
    return dd_real(hi, lo);
  }
  static dd_real product_error(const dd_real& a, const dd_real& b, const dd_real& prod) {
    return to_dd_real(qd_real(a) * qd_real(b) - qd_real(prod));  // 212-bit product: the error to dd precision
  }
};

template <>
struct num_traits<float128> : detail::rounded_from_mpfr<float128, num_traits<float128>> {
  static constexpr mpfr_prec_t bits() { return 113; }
  static std::string name() { return "float128"; }
  static float128 epsilon() { return std::numeric_limits<float128>::epsilon(); }
  static double to_double(const float128& x) { return x.convert_to<double>(); }
  static void to_mpfr(mpfr_ptr out, const float128& x) { mpfr_set_float128(out, x.backend().value(), MPFR_RNDN); }
  static float128 from_mpfr(const mpfr_t x) { return float128(mpfr_get_float128(x, MPFR_RNDN)); }
  static float128 product_error(const float128& a, const float128& b, const float128& prod) {
    return fma(a, b, float128(-prod));
  }
};

template <>
struct num_traits<Mpfr> : detail::rounded_from_mpfr<Mpfr, num_traits<Mpfr>> {
  static mpfr_prec_t bits() { return MpfrPrecision::current(); }
  static std::string name() { return "mpfr" + std::to_string(bits()); }
  static Mpfr epsilon() {
    Mpfr e(1);
    mpfr_mul_2si(e.data(), e.data(), 1 - bits(), MPFR_RNDN);
    return e;
  }
  static double to_double(const Mpfr& x) { return mpfr_get_d(x.data(), MPFR_RNDN); }
  static void to_mpfr(mpfr_ptr out, const Mpfr& x) { mpfr_set(out, x.data(), MPFR_RNDN); }
  static Mpfr from_mpfr(const mpfr_t x) {
    Mpfr r;
    mpfr_set(r.data(), x, MPFR_RNDN);
    return r;
  }
  static Mpfr product_error(const Mpfr& a, const Mpfr& b, const Mpfr& prod) { return fma(a, b, -prod); }
};

template <>
struct num_traits<Mpfi> {
  static mpfr_prec_t bits() { return MpfrPrecision::current(); }
  static std::string name() { return "mpfi" + std::to_string(bits()); }
  static Mpfi epsilon() {
    Mpfi e(1);
    mpfi_mul_2si(e.data(), e.data(), 1 - bits());
    return e;
  }
  /// Midpoint (intervals are reported by width separately).
  static double to_double(const Mpfi& x) {
    mpfr_t m;
    mpfr_init2(m, 53);
    mpfi_mid(m, x.data());
    const double d = mpfr_get_d(m, MPFR_RNDN);
    mpfr_clear(m);
    return d;
  }
  static void to_mpfr(mpfr_ptr out, const Mpfi& x) { mpfi_mid(out, x.data()); }
  /// An enclosure of the exact value.
  static Mpfi from_exact(const ExactReal& x) {
    // enclose() sets its output's precision, which an inline significand cannot take: go through a plain mpfi_t
    mpfi_t box;
    mpfi_init2(box, bits());
    x.enclose(box, bits());
    Mpfi r;
    mpfi_set(r.data(), box);
    mpfi_clear(box);
    return r;
  }
  static Mpfi pi() { return from_exact(ExactReal::pi()); }
  static Mpfi product_error(const Mpfi& a, const Mpfi& b, const Mpfi& prod) { return a * b - prod; }
};

}  // namespace rotleak
