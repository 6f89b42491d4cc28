#include "run/pipeline.hpp"

#include <omp.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <utility>

#include "analysis/output/run_output.hpp"
#include "io/files.hpp"
#include "io/scene_file.hpp"
#include "io/tally_file.hpp"
#include "sim/gpu/gpu_engine.hpp"
#include "verify/audit.hpp"
#include "verify/auto_tier.hpp"

namespace rotleak {

namespace fs = std::filesystem;

namespace {

std::string particles_text(std::uint64_t done, std::uint64_t total) {
  return std::to_string(done) + " of " + std::to_string(total) + " particles";
}

}  // namespace

RunInterrupted::RunInterrupted(fs::path path, std::uint64_t d, std::uint64_t t)
    : std::runtime_error("interrupted after " + particles_text(d, t) +
                         (path.empty() ? std::string("; no checkpoint kept") : "; checkpoint " + path.string())),
      checkpoint(std::move(path)),
      done(d),
      total(t) {}

namespace {
/// A rank's own checkpoint beside the run's: PATH-rank<r>-of-<K> (PATH itself for a single process).
fs::path rank_checkpoint(fs::path path, int rank, int ranks) {
  if (ranks > 1) path += "-rank" + std::to_string(rank) + "-of-" + std::to_string(ranks);
  return path;
}
}  // namespace

fs::path checkpoint_path(const fs::path& out, int rank, int ranks) {
  const fs::path p = RunDirectory::normalise(out);
  return rank_checkpoint(p.parent_path() / (p.filename().string() + ".checkpoint"), rank, ranks);
}

std::string run_inputs(const Scene& whole, Engine ran) { return simulation_inputs(whole, to_string(ran)); }

Engine saved_engine(const json& summary) {
  const std::string name = summary.at("execution").at("engine").get<std::string>();
  return name == "simd" ? Engine::simd : name == "gpu" ? Engine::gpu : Engine::scalar;
}

void take_device(const RunPlan& plan, const Team& team) {
  if (plan.engine() != Engine::gpu) return;
  if (const int n = gpu::device_count(); n > 0) gpu::select_device(team.node_rank() % n);
}

bool keeps_tally(const Scene& scene, bool shard) { return shard || scene.splitting.on; }

void check_tally_inputs(const TallyFile& f, Scene scene, Engine engine, const std::string& dir) {
  scene.particles = f.of;
  const std::string why = inputs_difference(f.inputs, run_inputs(scene, engine));
  if (!why.empty()) throw InputError("DIR", dir, "its scene.toml does not match its tally.bin (" + why + ")");
}

RunTexts run_files(const RunSummary& s, std::uint64_t of, bool shard) {
  if (!keeps_tally(s.scene, shard)) return run_texts(s);
  Scene whole = s.scene;
  whole.particles = of;
  const RunResult& r = s.result;
  RunTexts t = run_texts(s, {"tally.bin"});
  t.files.insert(t.files.begin(),
                 {"tally.bin", encode_tally_file(TallyFile{run_inputs(whole, r.engine), s.scene.particles, r.first_id,
                                                           of, r.done, r.tally, r.records})});
  return t;
}

namespace {

/// Collective: every rank's tally file `part` (same inputs and ids, blocks that tile the run) sent to
/// rank 0 and merged there into `result`. True on rank 0, which then holds the whole run.
bool merge_at_rank0(const Team& team, RunResult& result, const std::string& part, const Scene& scene) {
  const std::vector<std::string> parts = team.gather(part);
  if (team.rank() != 0) return false;
  const std::uint64_t n = scene.particles;
  Tally merged;
  merged.resize(scene);
  IntervalSet done;
  for (std::size_t r = 0; r < parts.size(); ++r) {
    const TallyFile f = decode_tally_file(parts[r], "rank " + std::to_string(r));
    if (!done.insert(f.done)) throw std::logic_error("rank " + std::to_string(r) + " ran blocks another rank ran");
    merged.merge(f.tally);
    if (!result.records.empty())
      for (const auto& [lo, hi] : f.done.intervals())
        std::copy(f.records.begin() + static_cast<std::ptrdiff_t>(lo * kBlockSize),
                  f.records.begin() + static_cast<std::ptrdiff_t>(std::min(n, hi * kBlockSize)),
                  result.records.begin() + static_cast<std::ptrdiff_t>(lo * kBlockSize));
  }
  if (!(done == IntervalSet::range(0, block_count(n))))
    throw std::logic_error("the ranks' blocks do not cover the run: " + done.text());
  check_conservation(merged, done, n);
  result.tally = std::move(merged);
  result.done = std::move(done);
  return true;
}

}  // namespace

std::pair<std::uint64_t, std::uint64_t> rank_share(std::uint64_t blocks, int rank, int ranks) {
  const auto r = static_cast<std::uint64_t>(rank), k = static_cast<std::uint64_t>(ranks);
  return {blocks * r / k, blocks * (r + 1) / k};
}

RunResult run_shared(const RunPlan& plan, RunOptions options, const Team& team) {
  if (options.blocks) throw std::logic_error("run_shared: the ranks' blocks are its own to choose");
  if (team.size() == 1) return run_ensemble(plan, options);
  take_device(plan, team);
  const Scene& scene = plan.scene();
  const std::uint64_t n = scene.particles;
  const auto [lo, hi] = rank_share(block_count(n), team.rank(), team.size());
  const IntervalSet mine = IntervalSet::range(lo, hi);
  options.blocks = &mine;
  RunResult result = run_ensemble(plan, options);
  const std::string inputs = run_inputs(scene, result.engine);
  const auto file = [&] {
    return encode_tally_file(TallyFile{inputs, n, options.first_id, n, result.done, result.tally, result.records});
  };
  std::string merged;
  if (merge_at_rank0(team, result, file(), scene)) merged = file();
  team.broadcast(merged);
  if (team.rank() != 0) {
    TallyFile f = decode_tally_file(merged, "rank 0's merged tallies");
    result.tally = std::move(f.tally);
    result.records = std::move(f.records);
    result.done = std::move(f.done);
  }
  result.ranks = team.size();
  return result;
}

namespace {

/// The checkpoint this rank resumes from: none (an empty TallyFile) when there is none or, unless --resume
/// insists, when it was made with other inputs, ids or another rank share; --resume without a usable one
/// is an InputError. The run's share of blocks is [share_lo, share_hi) of `blocks`.
TallyFile read_checkpoint(const fs::path& path, const Durability& durable, const std::string& inputs,
                          std::uint64_t first, std::uint64_t n, std::uint64_t share_lo, std::uint64_t share_hi,
                          std::uint64_t blocks, int ranks, const Note& note) {
  TallyFile saved;
  const bool have = !path.empty() && fs::exists(path);
  if (durable.resume == Resume::yes && !have)
    throw InputError("--resume", path.string(),
                     ranks > 1 ? "no checkpoint of this rank: was the run made with another number of ranks?"
                               : "no checkpoint there: nothing to resume");
  if (durable.resume == Resume::no || !have) return saved;
  saved = read_tally_file(path);
  std::string why = inputs_difference(saved.inputs, inputs);
  if (why.empty() && (saved.particles != n || saved.first_id != first))
    why = "ids [" + std::to_string(saved.first_id) + ", " + std::to_string(saved.first_id + saved.particles) +
          ") vs [" + std::to_string(first) + ", " + std::to_string(first + n) + ")";
  if (why.empty() && !saved.done.empty() &&
      (saved.done.intervals().front().first < share_lo || saved.done.intervals().back().second > share_hi))
    why = "blocks of another rank's share (made with another number of ranks)";
  if (!why.empty() && durable.resume == Resume::yes)
    throw InputError("--resume", path.string(), "the checkpoint was made with other inputs (" + why + ")");
  if (!why.empty()) {
    if (note) note("[rotleak] " + path.string() + " was made with other inputs (" + why + "): starting over");
    return TallyFile{};
  }
  if (note)
    note("[rotleak] resuming from " + path.string() + ": " + std::to_string(particles_in(saved.done, n)) + " of " +
         std::to_string(share_hi == blocks && share_lo == 0 ? n
                                                            : particles_in(IntervalSet::range(share_lo, share_hi), n)) +
         " particles done");
  return saved;
}

}  // namespace

namespace {

/// A tier of auto chosen by auditing float, double and long double on the scene (verify/auto_tier): the
/// plan is settled on the tier, the caller gets its reason. Nothing for a scene with a tier of its own.
std::optional<std::string> choose_auto_tier(RunPlan& plan, const Note& note) {
  if (!plan.scene().tier.automatic()) return std::nullopt;
  if (note) note("[rotleak] run.tier = auto: auditing float, double, long double on this scene...");
  TierChoice c = choose_tier(plan.scene(), plan.threads());
  plan = plan.with_tier(c.tier);
  return std::move(c.reason);
}

/// A run that keeps checkpoints, resumes, runs a shard's ids or shares its blocks among MPI ranks: its
/// share, the checkpoint it resumes from, the checkpoints it writes, and the ranks' parts merged at the end.
class DurableRun {
 public:
  DurableRun(const RunPlan& plan, RunOptions options, const Note& note, const Durability& durable)
      : plan_(durable.ids ? plan.with_particles(durable.ids->second - durable.ids->first) : plan),
        scene_(plan_.scene()),
        options_(std::move(options)),
        note_(note),
        durable_(durable),
        team_(durable.team ? *durable.team : current_team()),
        whole_(plan.scene().particles),
        inputs_(run_inputs(plan.scene(), plan.engine())) {
    if (durable.ids) options_.first_id = durable.ids->first;
    share_ = rank_share(block_count(scene_.particles), team_.rank(), team_.size());
    if (!durable.path.empty()) path_ = rank_checkpoint(durable.path, team_.rank(), team_.size());
  }

  RunSummary run() {
    resume();
    if (!path_.empty()) {
      options_.checkpoint_seconds = scene_.checkpoint_seconds;
      options_.checkpoint = [this](const Tally& t, const IntervalSet& done, const std::vector<EscapeRecord>& rec) {
        write_tally_file(path_, timed(tally_file(done, t, rec)));
      };
    }
    take_device(plan_, team_);
    RunResult result = run_ensemble(plan_, options_);
    result.wall_seconds += saved_.wall_seconds;
    const std::uint64_t n = scene_.particles;
    if (!team_.all(result.complete)) {  // stopped (on some rank): every rank keeps what it has done
      if (result.complete && !path_.empty())
        write_tally_file(path_, timed(tally_file(result.done, result.tally, result.records)));
      throw RunInterrupted(path_, particles_in(result.done, n),
                           particles_in(IntervalSet::range(share_.first, share_.second), n));
    }
    if (team_.size() > 1) {
      if (!merge_at_rank0(team_, result, encode_tally_file(tally_file(result.done, result.tally, result.records)),
                          scene_)) {  // rank 0 summarises and writes
        RunSummary s;
        s.scene = scene_;
        return s;
      }
      result.ranks = team_.size();
    }
    if (durable_.ids) result.of = whole_;
    return summarise(scene_, std::move(result));
  }

 private:
  /// The checkpoint read (every rank agreeing on any failure), and the run set to go on from it: the
  /// blocks of this rank's share not done yet.
  void resume() {
    std::exception_ptr failure;
    try {
      saved_ = read_checkpoint(path_, durable_, inputs_, options_.first_id, scene_.particles, share_.first,
                               share_.second, block_count(scene_.particles), team_.size(), note_);
    } catch (...) {
      failure = std::current_exception();
    }
    agree(team_, failure);
    todo_ = saved_.done.complement_in(share_.first, share_.second);
    options_.blocks = &todo_;
    options_.start_done = &saved_.done;
    if (!saved_.done.empty()) {
      options_.start = &saved_.tally;
      options_.start_records = &saved_.records;
    }
  }
  /// This run's tallies as a tally file (checkpoints, the ranks' parts).
  TallyFile tally_file(const IntervalSet& done, const Tally& t, const std::vector<EscapeRecord>& rec) const {
    return TallyFile{inputs_, scene_.particles, options_.first_id, whole_, done, t, rec};
  }
  /// A checkpoint keeps the time spent so far, so that a resumed run reports the whole run's time beside
  /// the whole run's collisions (the rate was once ~2x too high after a resume).
  TallyFile timed(TallyFile f) const {
    f.wall_seconds =
        saved_.wall_seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    return f;
  }

  const RunPlan plan_;  ///< the shard's ids' plan, when a shard
  const Scene& scene_;
  RunOptions options_;
  const Note& note_;
  const Durability& durable_;
  const Team& team_;
  const std::uint64_t whole_;
  const std::string inputs_;
  std::pair<std::uint64_t, std::uint64_t> share_;
  fs::path path_;
  TallyFile saved_;
  IntervalSet todo_;
  const std::chrono::steady_clock::time_point started_ = std::chrono::steady_clock::now();
};

}  // namespace

namespace {

/// Splitting over initial conditions: one process runs the replicates one after the other (each on every thread),
/// no checkpoints; progress after each replicate.
RunSummary run_start_splitting_scene(const RunPlan& plan, const RunOptions& options, const Durability* durable) {
  const Scene& scene = plan.scene();
  const Team& team = durable && durable->team ? *durable->team : current_team();
  if (team.size() > 1)
    throw InputError("start_splitting.on", "true",
                     "runs in one process so far: its replicates are not yet shared "
                     "among MPI ranks (run it without mpirun)");
  if (durable && durable->ids) throw InputError("--ids", "", "does not apply to start_splitting.on = true");
  if (plan.engine() == Engine::gpu)
    throw InputError("--engine", "gpu", "start_splitting.on = true runs the scalar core on the CPU");
  const int threads = plan.threads() > 0 ? plan.threads() : omp_get_max_threads();
  const auto start = std::chrono::steady_clock::now();
  IcSplitRun run = run_start_splitting(scene, threads, [&](int done, int of) {
    if (options.progress) options.progress(static_cast<std::uint64_t>(done), static_cast<std::uint64_t>(of), 0, false);
  });
  RunResult result;
  result.tally.resize(scene);
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.threads = threads;
  result.engine = Engine::scalar;
  result.done = IntervalSet::range(0, block_count(scene.particles));
  if (options.progress) options.progress(scene.particles, scene.particles, run.collisions(), true);
  return summarise(scene, std::move(run), std::move(result));
}

}  // namespace

RunSummary run_scene(RunPlan plan, RunOptions options, const Note& note, const Durability* durable) {
  std::optional<std::string> choice = choose_auto_tier(plan, note);
  RunSummary s;
  if (plan.scene().start_splitting.on) {
    s = run_start_splitting_scene(plan, options, durable);
  } else if (durable) {
    s = DurableRun(plan, std::move(options), note, *durable).run();
  } else {
    const Scene& scene = plan.scene();
    RunResult result = run_ensemble(plan, options);
    if (!result.complete)  // stopped: a part of the ensemble is not a run to summarise
      throw RunInterrupted({}, particles_in(result.done, scene.particles), scene.particles);
    s = summarise(scene, std::move(result));
  }
  s.tier_choice = std::move(choice);
  // the audit's one rule on the tier's scalars: a run it would not trust says so (simulate, scans, ranks)
  s.precision_warning = scalar_rejection(s.scene, scalar_check(s.scene, to_string(s.scene.tier)));
  return s;
}

RunPlan checked_plan(const std::string& path, const std::vector<std::string>& overrides, const RunOptions& run,
                     const std::optional<std::string>& text) {
  // load_scene's InputError names the key and value; plan_run's the option or the key asking for most
  // memory; both before any directory is made
  return plan_run(text ? parse_scene(*text, overrides, path) : load_scene(path, overrides), run);
}

SimulateOutcome simulate(const SimulateRequest& req) {
  const Team& team = req.team ? *req.team : current_team();
  const RunPlan plan = req.plan ? *req.plan : checked_plan(req.scene_path, req.overrides, req.run, req.scene_text);
  const Scene& scene = plan.scene();
  if (req.ids && !(req.ids->first < req.ids->second && req.ids->second <= scene.particles))
    throw InputError("--ids", std::to_string(req.ids->first) + ":" + std::to_string(req.ids->second),
                     "must be A:B with 0 <= A < B <= ensemble.particles (" + std::to_string(scene.particles) + ")");
  Durability durable{checkpoint_path(req.out), req.resume, req.ids, &team};
  const fs::path mine = checkpoint_path(req.out, team.rank(), team.size());
  std::optional<RunDirectory> dir;
  std::exception_ptr failure;
  try {
    if (req.resume == Resume::yes && fs::exists(RunDirectory::normalise(req.out) / "summary.json")) {
      fs::remove(mine);  // left by a kill between the commit and its removal
      throw InputError("--resume", req.out.string(), "the run there is complete: nothing to resume");
    }
    if (req.resume == Resume::yes && !fs::exists(mine))
      throw InputError("--resume", req.out.string(), "no checkpoint " + mine.string() + ": nothing to resume");
    if (req.resume == Resume::no && fs::exists(mine) && !req.force)
      throw InputError("--out", req.out.string(),
                       "an unfinished run's checkpoint " + mine.string() +
                           " is there: add --resume to continue it, or --force to start over");
    if (team.rank() == 0) dir.emplace(req.out, req.force);  // validated and staged before any work
    if (req.resume == Resume::no) fs::remove(mine);
  } catch (...) {
    failure = std::current_exception();
  }
  agree(team, failure);
  SimulateOutcome out;
  out.summary = run_scene(plan, req.run, req.note, &durable);
  if (team.rank() == 0) {
    out.document = write_run(*dir, run_files(out.summary, scene.particles, req.ids.has_value()));
    out.dir = dir->final_path();
  }
  // after the commit: a kill in between leaves a complete run and a stale checkpoint
  team.all(true);
  fs::remove(mine);
  return out;
}

namespace {

struct Shard {
  fs::path dir;
  TallyFile f;
  json summary;
};

/// The shard directories read, each complete and made with the first one's inputs, in the order of their ids.
std::vector<Shard> read_shards(const std::vector<fs::path>& dirs) {
  std::vector<Shard> shards;
  for (const fs::path& d : dirs) {
    if (!fs::exists(d / "tally.bin"))
      throw InputError("DIR", d.string(), "is not a shard: no tally.bin (made by rotleak simulate --ids A:B)");
    Shard s{d, read_tally_file(d / "tally.bin"), json::parse(read_file(d / "summary.json"))};
    if (!s.f.complete()) throw InputError("DIR", d.string(), "holds an incomplete tally");
    if (!shards.empty()) {
      const std::string why = inputs_difference(shards[0].f.inputs, s.f.inputs);
      if (!why.empty())
        throw InputError("DIR", d.string(),
                         "was made with other inputs than " + shards[0].dir.string() + " (" + why + ")");
    }
    shards.push_back(std::move(s));
  }
  std::sort(shards.begin(), shards.end(), [](const Shard& a, const Shard& b) { return a.f.first_id < b.f.first_id; });
  return shards;
}

/// The shards must tile the ids 0:of exactly once (no overlap, no hole, nothing missing at the end).
void check_tiling(const std::vector<Shard>& shards, std::uint64_t of) {
  std::uint64_t at = 0;
  for (const Shard& s : shards) {
    const std::uint64_t lo = s.f.first_id, hi = lo + s.f.particles;
    const std::string range = "ids " + std::to_string(lo) + ":" + std::to_string(hi);
    if (lo < at)
      throw InputError("DIR", s.dir.string(), range + " overlap ids already covered up to " + std::to_string(at));
    if (lo > at)
      throw InputError("DIR", s.dir.string(),
                       range + " leave ids " + std::to_string(at) + ":" + std::to_string(lo) + " uncovered");
    at = hi;
  }
  if (at != of)
    throw InputError("DIR", shards.back().dir.string(),
                     "the shards end at id " + std::to_string(at) + " but the run has " + std::to_string(of) +
                         " particles: ids " + std::to_string(at) + ":" + std::to_string(of) + " are missing");
}

/// The shards' exact tallies merged into the whole run's result (the wall time summed, the most threads).
RunResult merged_result(const std::vector<Shard>& shards, const Scene& scene, Engine engine, std::uint64_t of) {
  RunResult result;
  result.tally.resize(scene);
  result.engine = engine;
  result.threads = 0;
  if (scene.escape_records) result.records.reserve(of);
  for (const Shard& s : shards) {
    result.tally.merge(s.f.tally);
    const json& how = s.summary.at("execution");
    result.wall_seconds += how.value("wall_seconds", 0.0);
    result.threads = std::max(result.threads, how.value("threads", 0));
    if (scene.escape_records) result.records.insert(result.records.end(), s.f.records.begin(), s.f.records.end());
  }
  result.done = IntervalSet::range(0, block_count(of));
  check_conservation(result.tally, result.done, of);
  return result;
}

}  // namespace

SimulateOutcome merge_shards(const MergeRequest& req) {
  if (req.shards.empty()) throw InputError("DIR", "(none)", "give the shard directories to merge");
  const std::vector<Shard> shards = read_shards(req.shards);
  const std::uint64_t of = shards[0].f.of;
  check_tiling(shards, of);
  // the whole run's scene: a shard's (tier as run) with the whole particle count; it must give the
  // inputs the shards carry
  Scene scene = load_scene((shards[0].dir / "scene.toml").string(), {"ensemble.particles=" + std::to_string(of)});
  scene.source = shards[0].summary.at("scene").value("source", scene.source);
  const Engine engine = saved_engine(shards[0].summary);
  check_tally_inputs(shards[0].f, scene, engine, shards[0].dir.string());
  RunDirectory dir(req.out, req.force);
  RunResult result = merged_result(shards, scene, engine, of);
  if (req.note) req.note("[rotleak] merged " + std::to_string(shards.size()) + " shards: ids 0:" + std::to_string(of));
  SimulateOutcome out;
  out.summary = summarise(scene, std::move(result));
  out.document = write_run(dir, run_files(out.summary, of, false));
  out.dir = dir.final_path();
  return out;
}

}  // namespace rotleak
