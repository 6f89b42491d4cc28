// The tiers every typed test runs over, and tolerances derived from each tier's epsilon.
#pragma once

#include <gtest/gtest.h>

#include "numeric/mpfr_fixed.hpp"
#include "numeric/tiers.hpp"

namespace rotleak::test {

/// Every point tier; Mpfr runs at the thread's default working precision (256 bits).
using Tiers = ::testing::Types<float, double, long double, dd_real, float128, mpfr256, Mpfr>;

struct TierNames {
  template <class R>
  static std::string GetName(int) {
    return num_traits<R>::name();
  }
};

/// k units of the tier's epsilon, as a double for comparisons.
template <class R>
double eps_times(double k) {
  return k * num_traits<R>::to_double(num_traits<R>::epsilon());
}

template <class R>
double as_double(const R& x) {
  return num_traits<R>::to_double(x);
}

}  // namespace rotleak::test
