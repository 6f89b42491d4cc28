// Sampling schemes for the initial conditions. "uniform" draws the invariant measure (every particle
// weight 1). "mupo" draws a defensive mixture q = eps u + (1 - eps) g of the uniform density u and a
// density g concentrated near the bouncing-ball family -- the orbits that make the survival tail --
// and gives each particle the weight w = u / q of its own initial point, so that
// P(t) = E_q[w 1{T > t}] is estimated without bias at every t, and w <= 1 / eps everywhere.
// A scheme is a Sampler: another density (another leak motion, another billiard, an adaptive one) is
// another class, not another branch in the engine.
#pragma once

#include <Random123/philox.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "geometry/stadium.hpp"
#include "sim/model/initial.hpp"
#include "sim/model/scene.hpp"

namespace rotleak {

/// Draws particle id's initial data and weighs a draw. Both are functions of (seed, id) and the
/// scene alone, so every engine, tier and thread rebuilds the same particle with the same weight.
class Sampler {
 public:
  virtual ~Sampler() = default;
  virtual InitialDraw draw(std::uint64_t id) const = 0;
  /// u / q at this draw (1 for the uniform scheme).
  virtual double weight(const InitialDraw& d) const = 0;
  /// False for the uniform scheme: the engine then keeps no weighted tallies.
  virtual bool weighted() const = 0;
  /// The uniform Birkhoff scheme's initial conditions (whose draws the vectorised kernel can make itself,
  /// simd::uniform_starts), else null.
  virtual const InitialConditions* uniform_birkhoff() const { return nullptr; }
};

/// A riding band (docs/model.md, "Riding orbits"): a bouncing-ball orbit whose drift along the straight edges
/// keeps pace with the leak's pattern. Between two top hits (4 r apart) the leak advances 2X = 4 r omega; near
/// a rational a/b of 2X mod 1 (offset eta = 2X - a/b) its b spots drift by eta a hit, and an orbit drifting
/// 4 r |p| / L a hit rides with them: |p| = L |eta| / (4 r), in a gap as long as it stays on the edge. It keeps
/// within a gap over its crossing (d / (4 r p) hits) while |p - that| / p < L (1/b - lambda) / d: the band.
struct RidingBand {
  long long a = 0, b = 1;  ///< the rational of 2X mod 1
  double eta = 0;          ///< 2X mod 1 - a/b
  double p = 0;            ///< the riding |p|
  double lo = 0, hi = 0;   ///< the band of |p| drawn
};
/// The riding bands of the scene: one per best approximation a/b of 2X mod 1 (no fraction with a smaller
/// denominator comes as close) with b lambda < 1 (its spots leave gaps), eta != 0 (an exact rational's
/// orbits ride at rest: the log-uniform part holds them), and the riding |p| in [p_min, p_max] and below
/// d kappa0 (its crossing, d / p, outlasts the chaotic decay time 1 / kappa0, kappa0 = lambda L / (pi area),
/// so that it can carry P where the chaotic part does not). None for a
/// stationary leak. 2X mod 1 from omega's exact value (an MPFI enclosure wide enough for its integer part).
std::vector<RidingBand> riding_bands(const Scene& scene);

/// The scheme of scene.sampling, on the scene's stadium in double `st` (a run's plan holds it).
std::unique_ptr<Sampler> make_sampler(const Scene& scene, const Stadium<double>& st);
/// The same on a stadium built from the scene: for a caller outside a run (one trajectory, a test).
std::unique_ptr<Sampler> make_sampler(const Scene& scene);

/// Philox words of particle id for a purpose other than the uniform draw (counter word 2 = purpose).
inline r123::Philox4x64::ctr_type sampling_words(std::uint64_t seed, std::uint64_t id, std::uint64_t purpose) {
  r123::Philox4x64 gen;
  const r123::Philox4x64::key_type key = {{seed, InitialConditions::kStreamInitial}};
  const r123::Philox4x64::ctr_type ctr = {{id, 0, purpose, 0}};
  return gen(ctr, key);
}

}  // namespace rotleak
