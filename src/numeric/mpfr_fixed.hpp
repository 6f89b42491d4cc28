// MPFR through Boost.Multiprecision at a fixed number of decimal digits: the precision is part of
// the type, so no global (thread-shared) default precision is ever read or written. Heavy to
// compile: included only where the type is used (tests, benchmarks); the tiers run Mpfr instead.
#pragma once

#include <boost/multiprecision/mpfr.hpp>

#include "numeric/num_traits.hpp"

namespace rotleak {

template <unsigned Digits10>
using mpfr_fixed =
    boost::multiprecision::number<boost::multiprecision::mpfr_float_backend<Digits10>, boost::multiprecision::et_off>;
/// The reference tier of the foundation: 77 decimal digits = 257 bits.
using mpfr256 = mpfr_fixed<77>;

template <unsigned D>
struct num_traits<mpfr_fixed<D>> : detail::rounded_from_mpfr<mpfr_fixed<D>, num_traits<mpfr_fixed<D>>> {
  using R = mpfr_fixed<D>;
  // Boost's digits10 -> bits rule (detail::digits10_2_2, not constexpr); a test checks they agree.
  static constexpr mpfr_prec_t bits() { return (D * 1000L) / 301 + (((D * 1000L) % 301) ? 2 : 1); }
  static std::string name() { return "mpfr" + std::to_string(bits()); }
  static R epsilon() { return std::numeric_limits<R>::epsilon(); }
  static double to_double(const R& x) { return mpfr_get_d(x.backend().data(), MPFR_RNDN); }
  static void to_mpfr(mpfr_ptr out, const R& x) { mpfr_set(out, x.backend().data(), MPFR_RNDN); }
  static R from_mpfr(const mpfr_t x) {
    R r;
    mpfr_set(r.backend().data(), x, MPFR_RNDN);
    return r;
  }
  static R product_error(const R& a, const R& b, const R& prod) { return fma(a, b, R(-prod)); }
};

}  // namespace rotleak
