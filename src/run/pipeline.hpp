// The run pipeline: scene -> tier (auto resolved by the audit) -> engine -> summary -> run directory.
// `rotleak simulate` is argument parsing plus simulate(); scans, MPI ranks, checkpoints and tests
// call run_scene() and the io writers the same way.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "analysis/run_summary.hpp"
#include "io/json.hpp"
#include "sim/engine.hpp"

namespace rotleak {

/// Status lines for a person (the command line sends them to stderr); may be empty.
using Note = std::function<void(const std::string&)>;

/// Runs a scene and summarises it, no files: a tier of auto is chosen first (verify/auto_tier),
/// then the engine is checked against the tier actually run.
RunSummary run_scene(Scene scene, RunOptions options, const std::string& engine = "auto", const Note& note = {});

struct SimulateRequest {
  std::string scene_path;
  std::vector<std::string> overrides;  ///< "section.key=value", on top of the file
  std::filesystem::path out;
  bool force = false;           ///< replace an existing run directory
  std::string engine = "auto";  ///< auto, scalar, simd
  RunOptions run;               ///< threads, progress
  Note note;
};

struct SimulateOutcome {
  RunSummary summary;
  json document;  ///< summary.json as written
  std::filesystem::path dir;
};

/// Loads and validates the scene, stages the run directory (before any work), runs, writes, commits.
SimulateOutcome simulate(const SimulateRequest& request);

}  // namespace rotleak
