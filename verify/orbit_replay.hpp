// Proven periodic orbits replayed through the precision tiers (docs/model.md, "Periodic orbits"): a tier
// starts on the orbit, rounded into its own precision, and follows it through the geometry core until it
// leaves it. An unstable orbit amplifies the tier's error by |Lambda| a period, so the collision where the
// divergence passes a tolerance is known in advance: k* = n ln(tol / u) / ln|Lambda| for unit roundoff
// u, within the window of the error model's constant.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "numeric/exact.hpp"
#include "numeric/tier.hpp"
#include "sim/engine/engine.hpp"
#include "verify/orbits.hpp"

namespace rotleak {

struct ReplayOptions {
  double tolerance = 1e-6;  ///< divergence max(L |ds|, |dp|) at which the tier has left the orbit
  /// The error model's constant A: the divergence at collision k is u A |Lambda|^(k/n). A holds the start
  /// rounded into the tier (s, p, then the point and velocity computed from them: a few u, in a metric that
  /// scales s by L ~ 10) and the first collisions' rounding, projected on the unstable direction: between
  /// a_min and a_max (measured 0.03 .. 5.4 over 24 replays: 4 orbits x 6 tiers, tests/test_orbits.cpp)
  double a_min = 1e-2, a_max = 1e1;
  /// Test seam: after each reflection v.x += kick v.x in the tier (a one-ulp change of double's reflection:
  /// 2^-53); 0 in every real replay.
  double reflection_kick = 0;
  std::size_t max_periods = 400;
};

struct OrbitReplay {
  std::string tier, code;
  std::size_t period = 0;
  double log_multiplier = 0;
  double unit_roundoff = 0;
  std::size_t departure = 0;    ///< first collision past the tolerance (0: not within max_periods)
  double predicted = 0;         ///< n ln(tol / u) / ln|Lambda|
  double low = 0, high = 0;     ///< the window: A from a_max to a_min, and one collision for the crossing
  std::size_t wrong_piece = 0;  ///< first collision before departure on a piece the code does not say (0: none)
  bool pass = false;
};

/// The orbit replayed in `tier` (float, double, long_double, dd, float128, mpfr:N); its truth re-proven at
/// 2 bits(tier) + 64 bits.
OrbitReplay replay_orbit(const ExactReal& d, const ExactReal& r, const ProvenOrbit& orbit, const std::string& tier,
                         const ReplayOptions& opt = {});

/// One engine's replay of a proven orbit: the particle started at bounce 0 (double), a stationary leak of
/// width 1e-6 centred there; it must escape at its first return, collision n, at the orbit's length.
struct OrbitEngineReplay {
  std::string engine, code;
  std::string expected, got;
  bool pass = false;
};
OrbitEngineReplay replay_orbit_engine(const ExactReal& d, const ExactReal& r, const ProvenOrbit& orbit, Engine engine,
                                      bool fast_forward);

/// The tiers an orbit replay runs by default.
std::vector<std::string> replay_tiers();

}  // namespace rotleak
