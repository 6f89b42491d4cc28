// A run stopped after its first checkpoint, its tallies carried through the tally file's bytes as a resume reads
// them, and resumed on one thread (on the engine asked for): what the checkpoint tests compare with the whole run.
#pragma once

#include <atomic>

#include "io/scene_file.hpp"
#include "io/tally_file.hpp"
#include "sim/engine/engine.hpp"

namespace rotleak::test {

struct StopAndResume {
  RunResult part;     ///< the run stopped after its first checkpoint (2 threads)
  TallyFile read;     ///< that checkpoint, through encode_tally_file and decode_tally_file
  RunResult resumed;  ///< the rest of the blocks from it, on 1 thread
};

inline StopAndResume stop_and_resume(const Scene& scene, Engine engine = Engine::automatic,
                                     std::uint64_t gpu_launch_blocks = 0) {
  StopAndResume out;
  std::atomic<bool> stop{false};
  RunOptions first;
  first.threads = 2;
  first.engine = engine;
  first.gpu_launch_blocks = gpu_launch_blocks;
  first.checkpoint_seconds = 1e-9;
  first.stop = &stop;
  TallyFile saved{simulation_inputs(scene, "auto"), scene.particles, 0, scene.particles, {}, {}, {}};
  first.checkpoint = [&](const Tally& t, const IntervalSet& done, const std::vector<EscapeRecord>& rec) {
    saved.tally = t;
    saved.done = done;
    saved.records = rec;
    stop = true;
  };
  out.part = run_ensemble(scene, first);
  out.read = decode_tally_file(encode_tally_file(saved), "checkpoint");
  const IntervalSet todo = out.read.done.complement_in(0, block_count(scene.particles));
  RunOptions rest;
  rest.threads = 1;
  rest.engine = engine;
  rest.gpu_launch_blocks = gpu_launch_blocks;
  rest.blocks = &todo;
  rest.start_done = &out.read.done;
  rest.start = &out.read.tally;
  rest.start_records = &out.read.records;
  out.resumed = run_ensemble(scene, rest);
  return out;
}

}  // namespace rotleak::test
