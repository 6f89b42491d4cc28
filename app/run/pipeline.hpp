// The run pipeline: scene -> tier (auto resolved by the audit) -> engine -> summary -> run directory.
// `rotleak simulate` is argument parsing plus simulate(); scans, MPI ranks, checkpoints and tests
// call run_scene() and the io writers the same way.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "analysis/output/run_output.hpp"
#include "analysis/run_summary.hpp"
#include "io/json.hpp"
#include "io/tally_file.hpp"
#include "run/team.hpp"
#include "sim/engine/engine.hpp"

namespace rotleak {

/// Status lines for a person (the command line sends them to stderr); may be empty.
using Note = std::function<void(const std::string&)>;

/// Whether a run continues from its checkpoint: never (one there is an error, unless --force), yes
/// (`--resume`: it must be there and match), or when one is there and matches (scan points).
enum class Resume { no, yes, if_any };

/// A run that outlives its process: checkpoints of the merged tallies at `path` (every
/// scene.checkpoint_seconds and when stopped), resumed from there; and a shard, ids [lo, hi).
struct Durability {
  std::filesystem::path path;  ///< the checkpoint file; empty: none
  Resume resume = Resume::no;
  std::optional<std::pair<std::uint64_t, std::uint64_t>> ids;  ///< run only ids [lo, hi) of the scene's particles
  /// The processes sharing the run (null: current_team()). Rank r of K runs the r-th of K equal runs of
  /// blocks and keeps its own checkpoint (path + "-rank<r>-of-<K>"); rank 0 gets the merged tallies.
  const Team* team = nullptr;
};

/// A run stopped (RunOptions::stop) before its end; its checkpoint holds the blocks done.
class RunInterrupted : public std::runtime_error {
 public:
  RunInterrupted(std::filesystem::path checkpoint, std::uint64_t done, std::uint64_t total);
  std::filesystem::path checkpoint;
  std::uint64_t done = 0, total = 0;  ///< particles
};

/// The checkpoint file of a run directory: DIR.checkpoint beside it (DIR.checkpoint-rank<r>-of-<K> for
/// rank r of an MPI run of K ranks).
std::filesystem::path checkpoint_path(const std::filesystem::path& out, int rank = 0, int ranks = 1);

/// The inputs text (io simulation_inputs) a run's tally files carry: the whole run's scene (tier
/// resolved) and the engine that ran.
std::string run_inputs(const Scene& whole, Engine ran);
/// The engine a saved run's summary.json says ran it.
Engine saved_engine(const json& summary);
/// The GPU engine under MPI: each rank on its own device, the ranks of a node taking its devices in turn (node rank
/// modulo the devices this process sees). Nothing for another engine, or where no device is visible.
void take_device(const RunPlan& plan, const Team& team);
/// Whether a run directory keeps its exact tallies in tally.bin: a shard's, for rotleak merge, and a split
/// run's, from which rotleak fit rebuilds its survival curve exactly (survival.csv does not carry the
/// unsplit lines' groups that its fits' errors use).
bool keeps_tally(const Scene& scene, bool shard);
/// Throws an InputError naming DIR unless the tally file f was made from `scene` (its particle count taken
/// as the whole run's, f.of) run by `engine`: a tally.bin that its directory's scene.toml does not describe.
void check_tally_inputs(const TallyFile& f, Scene scene, Engine engine, const std::string& dir);
/// Every file of a run directory (io run_texts), with tally.bin first where the run keeps its tallies: a
/// run of ids from its first_id out of `of` (a shard's `of` is the whole run's count). What simulate and
/// merge write and the Python module hands over.
RunTexts run_files(const RunSummary& s, std::uint64_t of, bool shard);

/// The blocks [lo, hi) rank `rank` of `ranks` runs of a run of `blocks`: the rank-th of equal runs.
std::pair<std::uint64_t, std::uint64_t> rank_share(std::uint64_t blocks, int rank, int ranks);

/// Collective: run_ensemble shared by the ranks of `team`, each its share of the blocks (options.blocks
/// must be null), the exact tallies merged; every rank gets the whole result (tally, records, done).
RunResult run_shared(const RunPlan& plan, RunOptions options, const Team& team);

/// Runs a planned scene and summarises it, no files: a tier of auto is chosen first (verify/auto_tier)
/// and the plan settled on it (RunPlan::with_tier: the engine checked against the tier actually run, an
/// InputError naming --engine). With `durable`, checkpoints are kept and resumed as it says; throws
/// RunInterrupted when RunOptions::stop ended the run early.
RunSummary run_scene(RunPlan plan, RunOptions options, const Note& note = {}, const Durability* durable = nullptr);

/// The plan of the scene of path and overrides for a run with `run`'s threads and engine (plan_run):
/// its keys (load_scene), the memory it needs, its tier and the engine against it (a tier of auto is
/// checked once chosen), validated once. Every InputError names the key or option.
/// With `text` (a Python rotleak.Scene's TOML) the scene is that text and `path` only names where it came from.
RunPlan checked_plan(const std::string& path, const std::vector<std::string>& overrides, const RunOptions& run,
                     const std::optional<std::string>& text = std::nullopt);

struct SimulateRequest {
  std::string scene_path;
  std::optional<std::string> scene_text;  ///< the scene itself (a Python Scene's TOML); scene_path then names it
  std::vector<std::string> overrides;     ///< "section.key=value", on top of the file
  /// The plan already made from scene_path and overrides by checked_plan (a scan's point, validated
  /// once when the scan enumerated its points); empty: simulate loads and checks it.
  std::optional<RunPlan> plan;
  std::filesystem::path out;
  bool force = false;          ///< replace an existing run directory
  RunOptions run;              ///< engine (checked against the tier run), threads, progress, stop
  Resume resume = Resume::no;  ///< continue from DIR.checkpoint
  std::optional<std::pair<std::uint64_t, std::uint64_t>> ids;  ///< a shard: ids [lo, hi); DIR/tally.bin for merge
  const Team* team = nullptr;                                  ///< null: current_team(); only its rank 0 writes
  Note note;
};

struct SimulateOutcome {
  RunSummary summary;  ///< on rank 0 (other ranks of an MPI run get their scene only)
  json document;       ///< summary.json as written (null on other ranks)
  std::filesystem::path dir;
};

/// Loads and validates the scene, stages the run directory (before any work), runs (checkpointing to
/// DIR.checkpoint, removed once the directory is committed), writes, commits.
SimulateOutcome simulate(const SimulateRequest& request);

struct MergeRequest {
  std::vector<std::filesystem::path> shards;  ///< run directories made with ids (each holds tally.bin)
  std::filesystem::path out;
  bool force = false;
  Note note;
};

/// Combines shards into the run their whole id range would have produced: checks that they share
/// inputs and tile the range exactly once, merges their exact tallies, writes the run directory.
SimulateOutcome merge_shards(const MergeRequest& request);

}  // namespace rotleak
