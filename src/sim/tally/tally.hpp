// What a run counts: integer counts and exact sums that merge in any order (threads, ranks, shards,
// resumes), and the conservation law every run and merge checks.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include "numeric/fixed_sum.hpp"
#include "sim/model/fate.hpp"
#include "sim/model/scene.hpp"
#include "sim/tally/blocks.hpp"

namespace rotleak {

/// One particle's end, kept only when escape records are asked for.
struct EscapeRecord {
  double t = 0;  ///< escape time (or t_max for survivors)
  double s = 0;  ///< boundary coordinate of the escape collision
  std::uint64_t collisions = 0;
  Fate fate = Fate::survived;
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

/// Integer counts and exact fixed-point sums; merge() is exact and order-independent.
struct Tally {
  std::vector<std::uint64_t> escapes_per_bin;    ///< escapes with t in [k dt, (k+1) dt)
  std::vector<std::uint64_t> collision_density;  ///< windows x bins, row-major
  std::uint64_t collisions = 0, escaped = 0, survived = 0, stuck = 0;
  // Weighted runs only (a sampling scheme other than uniform; empty otherwise): the sums of the
  // weights w and of w^2 of the particles escaping in each bin and of all particles, and the
  // weighted collision density.
  bool weighted = false;
  std::vector<FixedSum> escaped_w, escaped_w2;
  FixedSum total_w, total_w2;
  std::vector<FixedSum> collision_density_w;
  // Split runs only (run.splitting; empty otherwise; sim/engine/population.hpp). By grid index j = 0 .. bins
  // (time t_j = j dt): each stretch of a line's constant living weight Y adds Y (and Y^2, exactly) at
  // the index where it begins (line_in) and again at the index where it ends (line_out), so the
  // cumulative sums give sum_i Y_i(t_j) and sum_i Y_i(t_j)^2 as exact differences: never a
  // subtraction of rounded numbers.
  bool split = false;
  std::vector<FixedSum> line_in, line_out, line2_in, line2_out;
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
  /// The unsplit lines (split runs): lines whose one member has never split (a bouncing-ball stretch at
  /// every split time so far), each of weight w0; they carry the heaviest lines of a run. They are kept by
  /// weight class (unsplit_class: factors of 8), since a few heavy ones can carry the stratum's variance
  /// among many light ones: unsplit_start[c] holds every line of class c (all start unsplit), and
  /// unsplit_left[j * kUnsplitClasses + c] those that left it (their member escaped or first split) from
  /// grid index j on. Sparse: a line leaves at a split time or at its escape.
  std::array<UnsplitCell, kUnsplitClasses> unsplit_start{};
  std::map<std::uint64_t, UnsplitCell> unsplit_left;

  void resize(const Scene& scene);
  /// A particle's end: its fate at time t (escapes binned by dt), its collisions, and, for weighted
  /// runs, its weight w in the exact sums.
  void add_end(Fate fate, double t, std::uint64_t collisions_made, double w, double dt);
  void merge(const Tally& other);
};

/// Throws std::logic_error unless the tally of the blocks `done` of a run of n particles adds up:
/// escaped + survived + stuck particles equal the particles of those blocks (runs without splitting),
/// and a split run's weights are conserved exactly (Tally::w_start ...). Every run checks its result.
void check_conservation(const Tally& t, const IntervalSet& done, std::uint64_t n);

}  // namespace rotleak
