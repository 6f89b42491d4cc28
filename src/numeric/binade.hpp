// The binade of an IEEE number and a power of two, as std::ilogb and std::ldexp(1, e) give them, read from and
// written into a double's bits where it is normal (a libm call each costs more than the fast-forward's whole
// step: next_run asks for three per stretch); every other case, and other types, through libm.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

#include "numeric/device.hpp"

namespace rotleak {

/// std::ilogb(x): the exponent e with |x| in [2^e, 2^(e+1)) (x finite, non-zero; libm's answers otherwise).
template <class R>
ROTLEAK_HD inline int binade_of(R x) {
  return std::ilogb(x);
}
template <>
ROTLEAK_HD inline int binade_of<double>(double x) {
  const int biased = static_cast<int>((std::bit_cast<std::uint64_t>(x) >> 52) & 0x7ff);
  if (biased == 0 || biased == 0x7ff) return std::ilogb(x);  // zero, subnormal, infinite, NaN
  return biased - 1023;
}

/// std::ldexp(R(1), e): 2^e.
template <class R>
ROTLEAK_HD inline R pow2(int e) {
  return std::ldexp(R(1), e);
}
template <>
ROTLEAK_HD inline double pow2<double>(int e) {
  if (e < -1022 || e > 1023) return std::ldexp(1.0, e);  // subnormal, or out of range
  return std::bit_cast<double>(static_cast<std::uint64_t>(e + 1023) << 52);
}

}  // namespace rotleak
