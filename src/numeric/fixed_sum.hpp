// An exact, order-independent sum of non-negative terms: a binary fixed-point integer whose 64-bit
// limbs cover just the range the terms have reached, at any scale. A term m 2^e (a double, or its
// exact square, or any unsigned integer of up to 128 bits at any power of two) is added without
// rounding, so any grouping and order of the same terms (threads, ranks, restarts) gives the same
// bits, for weights as large as 2^60 and as small as the smallest subnormal (4.9e-324), and for their
// squares far below the range of a double. Weighted tallies use it for sums of weights and of squared
// weights; split runs reach P ~ 1e-300, whose line weights square to 1e-600.
//
// Terms arrive at a few nearby scales (f_c adds particles' weights, a few binades apart, to each bin):
// a term is added to a 128-bit staging word, an integer times 2^scale, when it lies at or above that
// scale and fits (the word starts kStageBelow binades below its first term, so smaller terms fit too);
// only a term below the scale, one too large for the word, or a sum about to wrap carries the word
// into the limbs. Every reader sees the staged word as added (it works on a settled copy), so
// the value, the words and the comparisons are those of the term-by-term sum.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace rotleak {

class FixedSum {
 public:
  /// A value as m 2^e with m in [0.5, 1) (m = 0 for zero): what value() would round, without its range.
  struct Scaled {
    double m = 0;
    long e = 0;
    /// this / o as a double (o non-zero); exact to about one ulp
    double over(const Scaled& o) const { return std::ldexp(m / o.m, static_cast<int>(e - o.e)); }
  };

  /// Adds x >= 0 (finite), exactly.
  void add(double x) {
    if (!(x >= 0) || !(x < 0x1p1000)) throw std::domain_error("FixedSum::add: term outside [0, 2^1000)");
    long pos = 0;
    if (const std::uint64_t m = integer_of(x, pos)) stage(m, pos);
  }

  /// Adds x n times, exactly: x n in one step (n < 2^64).
  void add_times(double x, std::uint64_t n) {
    if (!(x >= 0) || !(x < 0x1p1000)) throw std::domain_error("FixedSum::add_times: term outside [0, 2^1000)");
    long pos = 0;
    if (const std::uint64_t m = integer_of(x, pos)) stage(static_cast<unsigned __int128>(m) * n, pos);
  }

  /// Adds x^2 exactly (x >= 0 finite), even where x^2 leaves the range of a double.
  void add_square(double x) {
    if (!(x >= 0) || !(x < 0x1p500)) throw std::domain_error("FixedSum::add_square: term outside [0, 2^500)");
    long pos = 0;
    if (const std::uint64_t m = integer_of(x, pos)) stage(static_cast<unsigned __int128>(m) * m, 2 * pos);
  }

  /// Adds v 2^pos exactly.
  void add_bits(unsigned __int128 v, long pos) {
    if (v == 0) return;
    const long limb = floor_div(pos, 64);
    const int bit = static_cast<int>(pos - 64 * limb);
    // v << bit spans up to three limbs
    const std::uint64_t lo = static_cast<std::uint64_t>(v), hi = static_cast<std::uint64_t>(v >> 64);
    std::uint64_t part[3];
    if (bit == 0) {
      part[0] = lo, part[1] = hi, part[2] = 0;
    } else {
      part[0] = lo << bit;
      part[1] = (hi << bit) | (lo >> (64 - bit));
      part[2] = hi >> (64 - bit);
    }
    cover(limb, limb + 3);
    add_at(limb - base_, part, 3);
  }

  void merge(const FixedSum& o) {
    if (o.staged_) add_bits(o.staged_, o.staged_pos_);
    if (o.limb_.empty()) return;
    cover(o.base_, o.base_ + static_cast<long>(o.limb_.size()));
    add_at(o.base_ - base_, o.limb_.data(), o.limb_.size());
  }

  /// this - o, for o <= this (a cumulative sum minus a part of it).
  FixedSum minus(const FixedSum& other) const {
    FixedSum r = *this, settled_o;
    r.settle();
    const FixedSum& o = other.settled(settled_o);
    if (o.limb_.empty()) return r;
    r.cover(o.base_, o.base_ + static_cast<long>(o.limb_.size()));
    const std::size_t off = static_cast<std::size_t>(o.base_ - r.base_);
    unsigned borrow = 0;
    for (std::size_t i = off; i < r.limb_.size(); ++i) {
      const std::size_t k = i - off;
      if (k >= o.limb_.size() && !borrow) break;
      const std::uint64_t a = r.limb_[i], b = k < o.limb_.size() ? o.limb_[k] : 0;
      const std::uint64_t d = a - b - borrow;
      borrow = (a < b || (a == b && borrow)) ? 1u : 0u;
      r.limb_[i] = d;
    }
    if (borrow) throw std::logic_error("FixedSum::minus: negative result");
    r.trim();
    return r;
  }

  /// The sum rounded to a double: its top three limbs, highest first (error below one ulp of the
  /// result); 0 below the double range, inf above it.
  double value() const {
    FixedSum tmp;
    const FixedSum& f = settled(tmp);
    const long top = f.top_limb();
    if (top == kNone) return 0;
    double v = 0;
    for (long k = top; k > top - 3 && k >= f.base_; --k)
      v += std::ldexp(static_cast<double>(f.limb(k)), int_exp(64 * k));
    return v;
  }

  /// The sum as m 2^e, at any scale (value() is its rounding into a double).
  Scaled scaled() const {
    FixedSum tmp;
    const FixedSum& f = settled(tmp);
    const long top = f.top_limb();
    if (top == kNone) return {};
    double v = 0;  // the top three limbs, scaled by 2^(-64 top)
    for (long k = top; k > top - 3 && k >= f.base_; --k)
      v += std::ldexp(static_cast<double>(f.limb(k)), static_cast<int>(64 * (k - top)));
    int e = 0;
    const double m = std::frexp(v, &e);
    return {m, e + 64 * top};
  }

  /// Equal values (whatever their staging and untrimmed limbs); the work is the limbs held, never the
  /// span between two sums' scales (a read file's sum may lie anywhere: found by fuzz_tally).
  bool operator==(const FixedSum& other) const {
    const FixedSum a = trimmed(), o = other.trimmed();
    return a.base_ == o.base_ && a.limb_ == o.limb_;
  }

  /// Limb indices any sum the suite forms lies within: terms from 2^-2148 (the smallest subnormal,
  /// squared; limb -34) to 2^1000 times fewer than 2^128 of them (limb 17). A reader refuses a sum
  /// outside them (a merge would otherwise cover the span between, one word a limb).
  static constexpr long kLowestLimb = -64, kLimbEnd = 64;

  /// The value as (lowest limb index, limbs from there up), zero limbs trimmed at both ends: equal
  /// values give equal words (how tally files store a sum).
  long base() const { return trimmed().base_; }
  std::vector<std::uint64_t> limbs() const { return trimmed().limb_; }
  static FixedSum from_limbs(long base, std::vector<std::uint64_t> limbs) {
    FixedSum f;
    f.base_ = base;
    f.limb_ = std::move(limbs);
    f.trim();
    return f;
  }

 private:
  static constexpr long kNone = -(1L << 40);

  /// Binades below a term that starts the staging word, kept so that smaller terms stage too.
  static constexpr int kStageBelow = 24;
  /// v 2^pos into the staging word when it lies at or above the word's scale and fits (v 2^(pos -
  /// scale) below 2^127, the sum not wrapping), else the word into the limbs first and v starts it again
  void stage(unsigned __int128 v, long pos) {
    const long s = pos - staged_pos_;
    if (s >= 0 && s < 128 && (v >> (127 - s)) == 0) {
      const unsigned __int128 t = v << s, sum = staged_ + t;
      if (sum >= t) {  // no wrap-around
        staged_ = sum;
        return;
      }
    }
    settle();
    const int down = std::min(kStageBelow, leading_zeros(v) - 1);
    staged_ = v << down, staged_pos_ = pos - down;
  }
  static int leading_zeros(unsigned __int128 v) {
    const auto hi = static_cast<std::uint64_t>(v >> 64);
    return hi ? std::countl_zero(hi) : 64 + std::countl_zero(static_cast<std::uint64_t>(v));
  }
  /// The staging word into the limbs.
  void settle() {
    if (staged_) add_bits(staged_, staged_pos_);
    staged_ = 0;
  }
  /// This sum with its staging word in the limbs: itself, or `tmp` made so.
  const FixedSum& settled(FixedSum& tmp) const {
    if (!staged_) return *this;
    tmp = *this;
    tmp.settle();
    return tmp;
  }

  static long floor_div(long a, long b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }
  /// x >= 0 finite as m 2^pos, m an integer below 2^53, read off its bits (0 for x = 0).
  static std::uint64_t integer_of(double x, long& pos) {
    const auto bits = std::bit_cast<std::uint64_t>(x);
    const auto biased = static_cast<long>(bits >> 52);  // the sign bit is 0
    const std::uint64_t frac = bits & ((std::uint64_t{1} << 52) - 1);
    if (biased == 0) {  // zero or subnormal: frac 2^-1074
      pos = -1074;
      return frac;
    }
    pos = biased - 1075;
    return frac | (std::uint64_t{1} << 52);
  }
  static int int_exp(long e) { return e < -100000 ? -100000 : e > 100000 ? 100000 : static_cast<int>(e); }
  long end() const { return base_ + static_cast<long>(limb_.size()); }
  std::uint64_t limb(long k) const { return k >= base_ && k < end() ? limb_[static_cast<std::size_t>(k - base_)] : 0; }
  long top_limb() const {
    for (std::size_t i = limb_.size(); i-- > 0;)
      if (limb_[i]) return base_ + static_cast<long>(i);
    return kNone;
  }

  /// Grows the limbs to hold indices [lo, hi) (and one above for a carry).
  void cover(long lo, long hi) {
    if (limb_.empty()) {
      base_ = lo;
      limb_.assign(static_cast<std::size_t>(hi + 1 - lo), 0);
      return;
    }
    if (lo < base_) {
      limb_.insert(limb_.begin(), static_cast<std::size_t>(base_ - lo), 0);
      base_ = lo;
    }
    if (hi + 1 > end()) limb_.resize(static_cast<std::size_t>(hi + 1 - base_), 0);
  }

  /// Adds p[0 .. n) at limb offset `off`, carrying upwards (growing at the top when needed).
  void add_at(long off, const std::uint64_t* p, std::size_t n) {
    auto i = static_cast<std::size_t>(off);
    unsigned carry = 0;
    for (std::size_t k = 0; k < n || carry; ++k, ++i) {
      if (i == limb_.size()) limb_.push_back(0);
      const std::uint64_t add = k < n ? p[k] : 0;
      const std::uint64_t s = limb_[i] + add;
      const unsigned c1 = s < add ? 1u : 0u;
      const std::uint64_t s2 = s + carry;
      const unsigned c2 = s2 < s ? 1u : 0u;
      limb_[i] = s2;
      carry = c1 | c2;
    }
  }

  void trim() {
    std::size_t lo = 0, hi = limb_.size();
    while (hi > 0 && limb_[hi - 1] == 0) --hi;
    while (lo < hi && limb_[lo] == 0) ++lo;
    if (lo == hi) {
      limb_.clear();
      base_ = 0;
      return;
    }
    limb_.erase(limb_.begin() + static_cast<std::ptrdiff_t>(hi), limb_.end());
    limb_.erase(limb_.begin(), limb_.begin() + static_cast<std::ptrdiff_t>(lo));
    base_ += static_cast<long>(lo);
  }
  FixedSum trimmed() const {
    FixedSum f = *this;
    f.settle();
    f.trim();
    return f;
  }

  std::vector<std::uint64_t> limb_;  ///< limb_[k] weighs 2^(64 (base_ + k))
  long base_ = 0;
  unsigned __int128 staged_ = 0;  ///< terms at scale 2^staged_pos_ not yet in the limbs
  long staged_pos_ = 0;
};

}  // namespace rotleak
