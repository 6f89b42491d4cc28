// The ensemble engine: OpenMP over particle ids, per-thread tallies merged as exact integers, so the
// result does not depend on the thread count. A run is planned once (plan_run: every check of the scene
// and the options against this machine) and the engine runs the plan.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sim/engine/plan.hpp"
#include "sim/model/initial.hpp"
#include "sim/model/scene.hpp"
#include "sim/tally/blocks.hpp"
#include "sim/tally/tally.hpp"

namespace rotleak {

class SplitRule;

/// How a run goes. plan_run reads threads, engine, simd_lanes and draws once into the plan; the engine
/// reads the plan's resolved values, and the rest (ids, blocks, checkpoints, progress, stop) from here.
struct RunOptions {
  int threads = 0;                    ///< 0: OpenMP's default
  Engine engine = Engine::automatic;  ///< automatic: simd for the double tier when the CPU has AVX2+FMA
  /// The vectorised kernel's lanes a register: 0 default_simd_lanes() (ROTLEAK_SIMD_LANES, else the
  /// widest this CPU runs), 4 (AVX2) or 8 (AVX-512).
  /// Every width gives the same bits; tests and benchmarks pick one.
  int simd_lanes = 0;
  /// The GPU engine's blocks a launch at most (0: its default, 2048 blocks; a split run's, 64): tests take fewer to
  /// run several launches on few particles. The result does not depend on it.
  std::uint64_t gpu_launch_blocks = 0;
  std::uint64_t first_id = 0;  ///< particles are ids [first_id, first_id + scene.particles)
  /// When set, particle i starts from (*draws)[i] instead of the scene's draw of its id (its size
  /// must be scene.particles): how verify replays chosen trajectories through the engine.
  const std::vector<InitialDraw>* draws = nullptr;
  /// Split runs: the rule that picks which members split (null: the scene's, make_split_rule).
  const SplitRule* split_rule = nullptr;
  /// Called from one thread at a time, at most after every block of particles: particles done of
  /// total, collisions so far; once more with final = true at the end. Empty: no reports.
  std::function<void(std::uint64_t done, std::uint64_t total, std::uint64_t collisions, bool final)> progress;

  // Checkpoints and resume. The run's ids form blocks of kBlockSize (block b: ids first_id + b
  // kBlockSize ...). Threads take the blocks to run in increasing order; the result never depends on
  // which thread ran which, nor on how the work was cut into epochs.
  /// Blocks to run; null: all of them. A resumed run passes the blocks its checkpoint lacks, an MPI
  /// rank its share of them.
  const IntervalSet* blocks = nullptr;
  /// The tallies (and escape records) of the blocks start_done, merged into the result.
  const IntervalSet* start_done = nullptr;
  const Tally* start = nullptr;
  const std::vector<EscapeRecord>* start_records = nullptr;
  /// Every checkpoint_seconds (0: never) the threads finish their blocks and checkpoint() gets the
  /// merged tallies of all blocks done so far (those of `start` included) and their set.
  double checkpoint_seconds = 0;
  std::function<void(const Tally&, const IntervalSet& done, const std::vector<EscapeRecord>& records)> checkpoint;
  /// Set (by a signal handler, say): the threads finish the blocks they hold and take no more; the
  /// result then has complete = false and checkpoint() is called.
  const std::atomic<bool>* stop = nullptr;
};

struct RunResult {
  Tally tally;
  std::vector<EscapeRecord> records;  ///< by id - first_id, when scene.escape_records
  double wall_seconds = 0;
  int threads = 1;
  int ranks = 1;                   ///< MPI processes that shared the run
  Engine engine = Engine::scalar;  ///< the one that ran
  int simd_lanes = 0;              ///< its lanes a register (simd: 4 or 8; scalar: 0)
  std::uint64_t first_id = 0;      ///< the ids run: [first_id, first_id + scene.particles)
  std::uint64_t of = 0;            ///< a shard (--ids A:B): the whole run's particle count; 0 otherwise
  IntervalSet done;                ///< blocks whose particles are in the tally
  bool complete = true;            ///< false when stopped before every block ran
};

/// The kernel width a run takes when RunOptions::simd_lanes leaves it open: the environment's
/// ROTLEAK_SIMD_LANES (4 or 8: forces the AVX2 or the AVX-512 kernel, so that both are tested and timed on
/// one machine), else the widest this CPU runs. A value other than 4 or 8, or a kernel this CPU cannot
/// run, is an InputError naming ROTLEAK_SIMD_LANES.
int default_simd_lanes();

/// The engine `requested` resolves to for this scene on this CPU.
Engine resolve_engine(Engine requested, const Scene& scene);
std::string to_string(Engine e);

/// Engine by name (auto, scalar, simd, gpu); an InputError naming `key` otherwise.
Engine parse_engine(const std::string& key, const std::string& name);
/// An InputError naming `key` unless engine `e` runs this scene on this CPU.
void check_engine(const std::string& key, Engine e, const Scene& scene);

/// Threads allowed per core (`--threads` above kThreadsPerCore x the cores is refused).
inline constexpr int kThreadsPerCore = 8;

/// Refuses, before anything is allocated, what this machine cannot hold: threads beyond
/// kThreadsPerCore x the cores, and tallies (survival bins and collision-density bins per thread,
/// escape records per particle) beyond 80% of the memory the process may use (physical memory, or
/// the address-space limit when lower). The InputError names the key that asks for most of it.
void check_resources(const Scene& scene, int threads);

/// The one place a run is checked: the memory its tallies need (check_resources), its tier (an
/// ensemble tier, or auto), a split run's needs (the double tier from the scene's own draws, no escape
/// records), the draws given, and -- once the tier is known -- the engine and its lanes (an InputError
/// naming --engine). Builds the stadium in double once.
RunPlan plan_run(Scene scene, const RunOptions& options);

/// Runs the plan's ensemble (its tier chosen: not auto). Checks nothing the plan holds.
RunResult run_ensemble(const RunPlan& plan, const RunOptions& options);
/// run_ensemble(plan_run(scene, options), options): for callers that build a scene and run it once.
RunResult run_ensemble(const Scene& scene, const RunOptions& options);

}  // namespace rotleak
