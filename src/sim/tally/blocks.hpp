// Particle ids are run in blocks of kBlockSize; which blocks of a run are done is a set of half-open
// intervals of block indices, small however many particles run (blocks finish nearly in order).
// Checkpoints, shards and MPI ranks all speak of work in these terms.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace rotleak {

/// Particles per block: the unit of work sharing, of progress and of checkpoints.
inline constexpr std::uint64_t kBlockSize = 4096;

/// Blocks of n particles.
inline std::uint64_t block_count(std::uint64_t n) { return n / kBlockSize + (n % kBlockSize != 0); }

class IntervalSet;
/// Particles in a set of blocks of a run of n particles (the last block may be short).
std::uint64_t particles_in(const IntervalSet& blocks, std::uint64_t n);

/// A set of unsigned integers as sorted, disjoint, non-adjacent half-open intervals [lo, hi).
class IntervalSet {
 public:
  using Interval = std::pair<std::uint64_t, std::uint64_t>;

  IntervalSet() = default;
  /// [lo, hi) (empty when lo >= hi).
  static IntervalSet range(std::uint64_t lo, std::uint64_t hi) {
    IntervalSet s;
    s.insert(lo, hi);
    return s;
  }

  /// Adds [lo, hi); returns false (and adds nothing) if any of it was already in the set.
  bool insert(std::uint64_t lo, std::uint64_t hi) {
    if (lo >= hi) return true;
    auto it = std::lower_bound(iv_.begin(), iv_.end(), Interval{lo, 0});
    // an interval starting before lo may reach into [lo, hi)
    if (it != iv_.begin() && std::prev(it)->second > lo) return false;
    if (it != iv_.end() && it->first < hi) return false;
    it = iv_.insert(it, {lo, hi});
    if (it != iv_.begin() && std::prev(it)->second == it->first) {  // join the left neighbour
      std::prev(it)->second = it->second;
      it = iv_.erase(it) - 1;
    }
    if (std::next(it) != iv_.end() && std::next(it)->first == it->second) {  // and the right one
      it->second = std::next(it)->second;
      iv_.erase(std::next(it));
    }
    return true;
  }
  bool insert(const IntervalSet& o) {
    bool ok = true;
    for (const auto& [lo, hi] : o.iv_) ok = insert(lo, hi) && ok;
    return ok;
  }

  bool contains(std::uint64_t x) const {
    auto it = std::upper_bound(iv_.begin(), iv_.end(), Interval{x, UINT64_MAX});
    return it != iv_.begin() && std::prev(it)->second > x;
  }
  std::uint64_t size() const {
    std::uint64_t n = 0;
    for (const auto& [lo, hi] : iv_) n += hi - lo;
    return n;
  }
  bool empty() const { return iv_.empty(); }
  /// [lo, hi) minus this set.
  IntervalSet complement_in(std::uint64_t lo, std::uint64_t hi) const {
    IntervalSet out;
    std::uint64_t at = lo;
    for (const auto& [a, b] : iv_) {
      if (b <= at) continue;
      if (a >= hi) break;
      if (a > at) out.iv_.push_back({at, a});
      at = std::max(at, b);
    }
    if (at < hi) out.iv_.push_back({at, hi});
    return out;
  }
  /// The k-th smallest element (k < size()).
  std::uint64_t nth(std::uint64_t k) const {
    for (const auto& [lo, hi] : iv_) {
      if (k < hi - lo) return lo + k;
      k -= hi - lo;
    }
    return UINT64_MAX;
  }
  /// The elements of ranks [k0, k1) (the k0-th smallest up to, not including, the k1-th).
  IntervalSet slice(std::uint64_t k0, std::uint64_t k1) const {
    IntervalSet out;
    std::uint64_t rank = 0;  // rank of the current interval's first element
    for (const auto& [lo, hi] : iv_) {
      const std::uint64_t len = hi - lo;
      const std::uint64_t a = std::max(k0, rank), b = std::min(k1, rank + len);
      if (a < b) out.iv_.push_back({lo + (a - rank), lo + (b - rank)});
      rank += len;
      if (rank >= k1) break;
    }
    return out;
  }
  const std::vector<Interval>& intervals() const { return iv_; }
  bool operator==(const IntervalSet& o) const { return iv_ == o.iv_; }

  /// "a-b,c-d" (half-open), "" when empty.
  std::string text() const {
    std::string out;
    for (const auto& [lo, hi] : iv_) out += (out.empty() ? "" : ",") + std::to_string(lo) + "-" + std::to_string(hi);
    return out;
  }

 private:
  std::vector<Interval> iv_;
};

inline std::uint64_t particles_in(const IntervalSet& blocks, std::uint64_t n) {
  std::uint64_t count = 0;
  for (const auto& [lo, hi] : blocks.intervals()) count += std::min(n, hi * kBlockSize) - std::min(n, lo * kBlockSize);
  return count;
}

}  // namespace rotleak
