// A run's plan: the scene checked once for a run, and what the run resolves from it once -- the engine
// and its lanes, the threads, the stadium in double -- handed down to the engine, the samplers and the
// population engine, which read it and check nothing again. plan_run (sim/engine/engine.hpp) is the one
// place that makes one; docs/design.md, "The data path", shows where it goes.
#pragma once

#include <cstdint>
#include <memory>

#include "geometry/stadium.hpp"
#include "numeric/tier.hpp"
#include "sim/model/scene.hpp"

namespace rotleak {

/// Which double engine runs: the generic scalar core, the vectorised one (AVX2, 4 lanes a register,
/// or AVX-512, 8), or the scalar core on a GPU (sim/gpu; only when asked for).
enum class Engine { automatic, scalar, simd, gpu };

struct RunOptions;

class RunPlan {
 public:
  /// The scene, its keys and the memory its tallies need checked (load_scene, check_resources); its
  /// tier is auto until with_tier() settles it.
  const Scene& scene() const { return scene_; }
  /// The stadium in double, rounded once from the scene's exact d and r: the one every part of a run uses.
  const Stadium<double>& stadium() const { return *stadium_; }
  /// The engine that runs: scalar, simd or gpu (automatic while the tier is auto).
  Engine engine() const { return engine_; }
  /// The kernel's lanes a register (simd: 4 or 8; scalar: 0).
  int simd_lanes() const { return lanes_; }
  /// Threads asked for (0: OpenMP's default).
  int threads() const { return threads_; }
  /// The same plan for `particles` of its particles (a shard's ids): fewer particles need no new checks.
  RunPlan with_particles(std::uint64_t particles) const;
  /// The plan once a tier of auto is chosen: the engine asked for resolved against it and checked (an
  /// InputError naming --engine). A plan whose tier is not auto is returned as it is.
  RunPlan with_tier(Tier tier) const;

 private:
  friend RunPlan plan_run(Scene scene, const RunOptions& options);
  RunPlan() = default;
  Scene scene_;
  std::shared_ptr<const Stadium<double>> stadium_;
  Engine asked_ = Engine::automatic;
  Engine engine_ = Engine::automatic;
  int lanes_ = 0;
  int lanes_asked_ = 0;
  int threads_ = 0;
};

}  // namespace rotleak
