// The survival estimators: what a run adds beyond its particle counts to estimate P(t) and its error,
// one type per way of sampling (OpenMC's tallies as scores: each estimator its own type, not a flag).
// Each adds a particle's (or member's) end (its fate, its escape bin for escapes, its weight), merges exactly in any
// order (integers and FixedSum), is encoded by io/tally_file.cpp and builds its survival curve in
// sim/tally/survival.cpp.
//   CountingEstimator  uniform sampling: the escape histogram's integer counts are P (binomial error);
//   WeightedEstimator  importance sampling: exact sums of the weights w and w^2, P_w and its moment Q;
//   LinesEstimator     population splitting: each line's living weight in time, the lines independent.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include "numeric/fixed_sum.hpp"
#include "sim/model/fate.hpp"

namespace rotleak {

/// Uniform sampling: every particle weighs 1 and Tally's integer counts are the whole estimate.
struct CountingEstimator {
  static constexpr const char* kName = "counting";
  void resize(std::size_t /*bins*/) {}
  void add_end(Fate /*fate*/, std::size_t /*bin*/, double /*w*/) {}
  void merge(const CountingEstimator& /*other*/) {}
  bool operator==(const CountingEstimator&) const = default;
};

/// Importance sampling (a scheme other than uniform): the sums of the weights w and of w^2 of all
/// particles and of those escaping in each bin.
struct WeightedEstimator {
  static constexpr const char* kName = "weighted";
  std::vector<FixedSum> escaped_w, escaped_w2;  ///< by escape bin
  FixedSum total_w, total_w2;
  void resize(std::size_t bins);
  void add_end(Fate fate, std::size_t bin, double w);
  void merge(const WeightedEstimator& o);
  bool operator==(const WeightedEstimator&) const = default;
};

/// A set of unsplit lines: how many, and the exact sums of their weights and squared weights.
struct UnsplitCell {
  std::uint64_t lines = 0;
  FixedSum w, w2;
  void add(double w0) {
    ++lines;
    w.add(w0);
    w2.add_square(w0);
  }
  void merge(const UnsplitCell& o) {
    lines += o.lines;
    w.merge(o.w);
    w2.merge(o.w2);
  }
  bool operator==(const UnsplitCell&) const = default;
};

/// Weight classes of unsplit lines: class c holds w0 in [2^(-3c - 2), 2^(-3c + 1)) (c = 0 takes w0 >= 1/4,
/// the last class everything below), from the binary exponent alone: the same class on every machine.
inline constexpr int kUnsplitClasses = 16;
inline int unsplit_class(double w0) {
  int e = 0;
  std::frexp(w0, &e);  // w0 = m 2^e, m in [0.5, 1)
  const int c = (1 - e) / 3;
  return c < 0 ? 0 : c >= kUnsplitClasses ? kUnsplitClasses - 1 : c;
}

/// Population splitting (run.splitting; sim/engine/population.hpp): the N lines are the independent
/// units. By grid index j = 0 .. bins (time t_j = j dt): each stretch of a line's constant living weight
/// Y adds Y (and Y^2, exactly) at the index where it begins (line_in) and again at the index where it
/// ends (line_out), so the cumulative sums give sum_i Y_i(t_j) and sum_i Y_i(t_j)^2 as exact
/// differences: never a subtraction of rounded numbers. Tally's escapes_per_bin counts members.
struct LinesEstimator {
  static constexpr const char* kName = "lines";
  std::vector<FixedSum> line_in, line_out, line2_in, line2_out;
  /// The same for Y w0 (a line's living weight times its starting weight, each product rounded once): sum_i
  /// Y_i(t_j) w0_i, the covariance of the curve with its start that the ratio P = sum Y / sum w0 needs.
  std::vector<FixedSum> linex_in, linex_out;
  std::vector<std::uint64_t> lines_ended;                   ///< lines whose weight fell to 0, by grid index
  std::vector<std::uint64_t> born_per_bin, culled_per_bin;  ///< copies made, members the roulette removed, by bin
  std::uint64_t splits = 0, culls = 0;
  std::uint64_t levels = 0;          ///< split times passed by the longest-lived line (maximum over blocks)
  std::uint64_t max_population = 0;  ///< most members of one block at one split time
  std::uint64_t max_line = 0;        ///< most members of one line at one split time, before the roulette
  /// Weight conservation, exact (member weights are w0 2^-level): the lines' starting weight plus what
  /// roulette survivors gained equals the weight escaped, removed by the roulette, and alive at the
  /// end (survived to t_max, or stuck). A split keeps it exactly; check_conservation() enforces it.
  FixedSum w_start, w_gained, w_escaped, w_removed, w_alive_end;
  /// The unsplit lines: lines whose one member has never split (a bouncing-ball stretch at every split
  /// time so far), each of weight w0; they carry the heaviest lines of a run. They are kept by weight
  /// class (unsplit_class: factors of 8), since a few heavy ones can carry the stratum's variance among
  /// many light ones: unsplit_start[c] holds every line of class c (all start unsplit), and
  /// unsplit_left[j * kUnsplitClasses + c] those that left it (their member escaped or first split) from
  /// grid index j on. Sparse: a line leaves at a split time or at its escape.
  std::array<UnsplitCell, kUnsplitClasses> unsplit_start{};
  std::map<std::uint64_t, UnsplitCell> unsplit_left;

  void resize(std::size_t bins);
  /// A member's end, of weight w: escaped, or alive at the end (stuck, or survived to t_max).
  void add_end(Fate fate, std::size_t bin, double w);
  void merge(const LinesEstimator& o);

  // What run_lines books, step by step.
  /// A line starts: one unsplit member of weight w0.
  void start_line(double w0);
  /// The line of weight w0 leaves the unsplit stratum from grid index g on.
  void leave_unsplit(std::size_t g, double w0);
  /// A stretch of constant living weight y over grid indices [from, to) (to = points: to the end).
  void stretch(std::size_t from, std::size_t to, double y, double w0);
  /// A member split in two at a split time in `bin`.
  void split(std::size_t bin);
  /// The roulette kept (at twice its weight) or removed a member of `weight` at a split time in `bin`.
  void roulette(bool kept, double weight, std::size_t bin);
  /// Throws std::logic_error unless the weights are conserved exactly.
  void check_conservation() const;
  bool operator==(const LinesEstimator&) const = default;
};

}  // namespace rotleak
