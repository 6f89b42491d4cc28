// An exact, order-independent sum of non-negative doubles: a 192-bit fixed-point integer with 128
// fractional bits (resolution 2^-128 ~ 2.9e-39, sums below 2^64). Each term is truncated once to
// that grid -- a deterministic function of the term alone -- and the integer additions are exact,
// so any grouping and order of the same terms (threads, ranks, restarts) gives the same bits.
// Weighted tallies use it for sums of weights and of squared weights.
#pragma once

#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace rotleak {

class FixedSum {
 public:
  static constexpr int kFractionBits = 128;

  /// Adds x >= 0 (finite, below 2^63), truncated to a multiple of 2^-128.
  void add(double x) {
    if (!(x >= 0) || !(x < 0x1p63)) throw std::domain_error("FixedSum::add: term outside [0, 2^63)");
    if (x == 0) return;
    int e = 0;
    const double m = std::frexp(x, &e);                               // x = m 2^e, m in [0.5, 1)
    const auto mant = static_cast<std::uint64_t>(std::ldexp(m, 53));  // x = mant 2^(e - 53), exact
    const int shift = e - 53 + kFractionBits;                         // bit position of mant's lowest bit
    if (shift <= -64) return;                                         // below the grid
    std::uint64_t part[3] = {0, 0, 0};
    if (shift < 0) {
      part[0] = mant >> -shift;
    } else {
      const int limb = shift / 64, bit = shift % 64;
      part[limb] = mant << bit;
      if (bit != 0 && limb + 1 < 3) part[limb + 1] = mant >> (64 - bit);
    }
    add_limbs(part);
  }

  void merge(const FixedSum& o) { add_limbs(o.limb_); }

  /// this - o, for o <= this (a cumulative sum minus a part of it).
  FixedSum minus(const FixedSum& o) const {
    FixedSum r = *this;
    unsigned borrow = 0;
    for (int i = 0; i < 3; ++i) {
      const std::uint64_t a = r.limb_[i], b = o.limb_[i];
      const std::uint64_t d = a - b - borrow;
      borrow = (a < b || (a == b && borrow)) ? 1u : 0u;
      r.limb_[i] = d;
    }
    if (borrow) throw std::logic_error("FixedSum::minus: negative result");
    return r;
  }

  /// The sum rounded to a double (error below one ulp of the result, plus the 2^-128 grid).
  double value() const {
    return std::ldexp(static_cast<double>(limb_[2]), 128 - kFractionBits) +
           std::ldexp(static_cast<double>(limb_[1]), 64 - kFractionBits) +
           std::ldexp(static_cast<double>(limb_[0]), -kFractionBits);
  }

  bool operator==(const FixedSum& o) const {
    return limb_[0] == o.limb_[0] && limb_[1] == o.limb_[1] && limb_[2] == o.limb_[2];
  }
  const std::uint64_t* limbs() const { return limb_; }
  /// The sum whose limbs() are l (least significant first): how saved tallies are read back.
  static FixedSum from_limbs(const std::uint64_t* l) {
    FixedSum f;
    for (int i = 0; i < 3; ++i) f.limb_[i] = l[i];
    return f;
  }

 private:
  void add_limbs(const std::uint64_t* p) {
    unsigned carry = 0;
    for (int i = 0; i < 3; ++i) {
      const std::uint64_t s = limb_[i] + p[i];
      const unsigned c1 = s < limb_[i] ? 1u : 0u;
      const std::uint64_t s2 = s + carry;
      const unsigned c2 = s2 < s ? 1u : 0u;
      limb_[i] = s2;
      carry = c1 | c2;
    }
    if (carry) throw std::overflow_error("FixedSum: sum beyond 2^64");
  }

  std::uint64_t limb_[3] = {0, 0, 0};
};

}  // namespace rotleak
