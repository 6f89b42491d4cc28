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
