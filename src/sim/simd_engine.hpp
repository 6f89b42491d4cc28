// The vectorised double engine: four particles per AVX2 register, branch-free piece selection, lanes
// refilled from the id stream as particles end. Its translation unit alone is compiled for AVX2/FMA
// and selected at run time; it sees only the plain structs below (no shared inline code gets AVX2
// instructions), and asks the caller for new particles and hands back the ended ones.
#pragma once

#include <cstdint>

#include "sim/fate.hpp"

namespace rotleak::simd {

inline constexpr int kMaxWindows = 3;

/// Everything the kernel needs, in doubles, from a Model<double>.
struct Scene {
  double r, half_d, t_max;
  double L, inv_L, r_over_L, pi;
  double junction[4];
  bool rotating;
  // stationary leak: windows per piece (0 top, 1 right arc, 2 bottom, 3 left arc)
  int n_windows[4];
  double lo[4][kMaxWindows], hi[4][kMaxWindows];          // straight pieces: x ranges
  double from_x[4][kMaxWindows], from_y[4][kMaxWindows];  // arcs: bounding directions
  double to_x[4][kMaxWindows], to_y[4][kMaxWindows];
  // moving leak: phase = frac(start + omega t), omega = hi + lo
  double omega_hi, omega_lo, start, half_width;
  /// > 0: a lane whose straight-edge hit starts at least this many bounces between the straight
  /// edges is handed back (LaneEnd::handed_back) for the scalar fast-forward; 0: never.
  double handoff_bounces;
};

struct Start {
  double qx, qy, vx, vy, t;
  double collisions = 0;  ///< already made (a particle coming back from the fast-forward)
};

struct End {
  LaneEnd fate;  ///< a Fate, or handed back mid-flight (the state below)
  double t, qx, qy, vx, vy;
  int piece;
  std::uint64_t collisions;
};

/// Fills *start and *id with the next particle; false when there is none.
using NextParticle = bool (*)(void* ctx, Start* start, std::uint64_t* id);
using Finish = void (*)(void* ctx, std::uint64_t id, const End& end);

/// True when this CPU has AVX2 and FMA.
bool available();

/// Runs particles until next() has none left; requires available().
void run(const Scene& scene, void* ctx, NextParticle next, Finish finish);

}  // namespace rotleak::simd
