// The MUPO covering f_L(s) (docs/model.md, "The MUPO covering f_L(s)"): while a bouncing-ball orbit with small p
// crosses the straight edge, the leak centre at its n-th reflection is frac(n x) with x = t_c omega, t_c = 2r(1 +
// delta), n = 0..N, N = floor((d / 2r) / sqrt(delta)). f_L(s) counts the leak intervals [frac(n x) - lambda/2, frac(n
// x) + lambda/2] covering s.
//
// Points live on an integer circle Z_M: for rational x and lambda, M is the common denominator and
// everything is exact; otherwise M = 2^120 and x, lambda/2 are rounded once from certified
// enclosures, each point then off by at most N * 2^-120 (`error_bound`).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "numeric/exact.hpp"

namespace rotleak {

using u128 = unsigned __int128;

struct CoveringInput {
  ExactReal omega, delta = ExactReal::parse("1e-7"), lambda = ExactReal::parse("0.01");
  ExactReal d = ExactReal::parse("2"), r = ExactReal::parse("1");
};

/// Largest N accepted (2 (N+1) interval ends are sorted in memory).
inline constexpr std::uint64_t kMaxCoveringPoints = 50'000'000;

struct GapCount {
  double length = 0;  ///< in units of s
  std::uint64_t count = 0;
  std::string exact;  ///< the exact length as a rational "a/b" (exact mode only)
};

struct Segment {
  double from = 0, to = 0;  ///< s range [from, to)
  std::uint64_t value = 0;  ///< f_L on it
};

struct Covering {
  std::uint64_t N = 0;            ///< points are n = 0..N
  bool exact = false;             ///< rational inputs: everything below exact
  double error_bound = 0;         ///< max displacement of any point / interval end, in s
  std::string x_text;             ///< x = t_c omega as used (exact rational, or a decimal)
  std::vector<Segment> segments;  ///< f_L as a piecewise-constant function on [0, 1)
  // metrics
  double zero_measure = 0, max_zero_gap = 0;
  std::uint64_t clusters = 0;  ///< maximal arcs where f_L > 0 (on the circle)
  std::uint64_t min = 0, max = 0;
  double mean = 0, cv = 0;            ///< mean = (N + 1) lambda; cv = L2 deviation / mean
  double discrepancy = 0;             ///< star discrepancy of the points frac(n x)
  std::vector<GapCount> gaps;         ///< three-distance structure: distinct gaps between neighbours
  bool three_distance_holds = false;  ///< <= 3 lengths, and with 3 the largest = sum of the others
  double seconds = 0;
};

/// Throws std::invalid_argument (message names the input) for delta outside (0,1), lambda outside
/// (0,1), d or r <= 0, or N above kMaxCoveringPoints.
Covering mupo_covering(const CoveringInput& in);

/// f_L sampled as bin averages on `bins` equal bins of [0, 1).
std::vector<double> covering_profile(const Covering& c, std::size_t bins);

}  // namespace rotleak
