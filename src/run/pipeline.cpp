#include "run/pipeline.hpp"

#include <algorithm>
#include <utility>

#include "io/files.hpp"
#include "io/run_output.hpp"
#include "io/scene_file.hpp"
#include "io/tally_file.hpp"
#include "verify/auto_tier.hpp"

namespace rotleak {

namespace fs = std::filesystem;

namespace {

std::string particles_text(std::uint64_t done, std::uint64_t total) {
  return std::to_string(done) + " of " + std::to_string(total) + " particles";
}

/// Particles in a set of blocks of a run of n.
std::uint64_t particles_in(const IntervalSet& blocks, std::uint64_t n) {
  std::uint64_t count = 0;
  for (const auto& [lo, hi] : blocks.intervals()) count += std::min(n, hi * kBlockSize) - std::min(n, lo * kBlockSize);
  return count;
}

}  // namespace

RunInterrupted::RunInterrupted(fs::path path, std::uint64_t d, std::uint64_t t)
    : std::runtime_error("interrupted after " + particles_text(d, t) + "; checkpoint " + path.string()),
      checkpoint(std::move(path)),
      done(d),
      total(t) {}

fs::path checkpoint_path(const fs::path& out) {
  const fs::path p = RunDirectory::normalise(out);
  return p.parent_path() / (p.filename().string() + ".checkpoint");
}

std::string run_inputs(const Scene& whole, Engine ran) { return simulation_inputs(whole, to_string(ran)); }

RunSummary run_scene(Scene scene, RunOptions options, const std::string& engine, const Note& note,
                     const Durability* durable) {
  std::optional<std::string> choice;
  if (scene.tier.automatic()) {
    if (note) note("[rotleak] run.tier = auto: auditing float, double, long double on this scene...");
    TierChoice c = choose_tier(scene, options.threads);
    scene.tier = c.tier;
    choice = std::move(c.reason);
  }
  options.engine = engine_from_name("--engine", engine, scene);
  if (!durable) {
    RunSummary s = summarise(scene, run_ensemble(scene, options));
    s.tier_choice = std::move(choice);
    return s;
  }

  const std::uint64_t whole = scene.particles;
  const std::string inputs = run_inputs(scene, resolve_engine(options.engine, scene));
  if (durable->ids) {
    scene.particles = durable->ids->second - durable->ids->first;
    options.first_id = durable->ids->first;
  }
  TallyFile saved;
  IntervalSet todo;
  const fs::path& path = durable->path;
  const bool have = !path.empty() && fs::exists(path);
  if (durable->resume == Resume::yes && !have)
    throw InputError("--resume", path.parent_path().string().empty() ? "." : path.string(),
                     "no checkpoint there: nothing to resume (the run finished, or never wrote one)");
  if (durable->resume != Resume::no && have) {
    saved = read_tally_file(path);
    std::string why = inputs_difference(saved.inputs, inputs);
    if (why.empty() && (saved.particles != scene.particles || saved.first_id != options.first_id))
      why = "ids [" + std::to_string(saved.first_id) + ", " + std::to_string(saved.first_id + saved.particles) +
            ") vs [" + std::to_string(options.first_id) + ", " + std::to_string(options.first_id + scene.particles) +
            ")";
    if (!why.empty() && durable->resume == Resume::yes)
      throw InputError("--resume", path.string(), "the checkpoint was made with other inputs (" + why + ")");
    if (why.empty()) {
      todo = saved.done.complement_in(0, block_count(scene.particles));
      options.blocks = &todo;
      options.start = &saved.tally;
      options.start_records = &saved.records;
      if (note)
        note("[rotleak] resuming from " + path.string() + ": " +
             particles_text(particles_in(saved.done, scene.particles), scene.particles) + " done");
    } else if (note) {
      note("[rotleak] " + path.string() + " was made with other inputs (" + why + "): starting over");
    }
  }
  const std::uint64_t first = options.first_id, n = scene.particles;
  if (!path.empty()) {
    options.checkpoint_seconds = scene.checkpoint_seconds;
    options.checkpoint = [&, first, n](const Tally& t, const IntervalSet& done, const std::vector<EscapeRecord>& rec) {
      write_tally_file(path, TallyFile{inputs, n, first, whole, done, t, rec});
    };
  }
  RunResult result = run_ensemble(scene, options);
  if (!result.complete) throw RunInterrupted(path, particles_in(result.done, n), n);
  if (durable->ids) result.of = whole;
  RunSummary s = summarise(scene, std::move(result));
  s.tier_choice = std::move(choice);
  return s;
}

SimulateOutcome simulate(const SimulateRequest& req) {
  const Scene scene = load_scene(req.scene_path, req.overrides);
  check_resources(scene, req.run.threads);                                       // before any directory is made
  if (!scene.tier.automatic()) engine_from_name("--engine", req.engine, scene);  // a bad engine fails before any work
  if (req.ids && !(req.ids->first < req.ids->second && req.ids->second <= scene.particles))
    throw InputError("--ids", std::to_string(req.ids->first) + ":" + std::to_string(req.ids->second),
                     "must be A:B with 0 <= A < B <= ensemble.particles (" + std::to_string(scene.particles) + ")");
  Durability durable{checkpoint_path(req.out), req.resume, req.ids};
  if (req.resume == Resume::yes && !fs::exists(durable.path))
    throw InputError("--resume", req.out.string(),
                     fs::exists(RunDirectory::normalise(req.out) / "summary.json")
                         ? "the run there is complete: nothing to resume"
                         : "no checkpoint " + durable.path.string() + ": nothing to resume");
  if (req.resume == Resume::no && fs::exists(durable.path)) {
    if (!req.force)
      throw InputError("--out", req.out.string(),
                       "an unfinished run's checkpoint " + durable.path.string() +
                           " is there: add --resume to continue it, or --force to start over");
  }
  // a resumed run's directory was never committed; --force replaces a complete one
  RunDirectory dir(req.out, req.force);  // validated and staged before any work
  if (req.resume == Resume::no) fs::remove(durable.path);
  SimulateOutcome out;
  out.summary = run_scene(scene, req.run, req.engine, req.note, &durable);
  std::vector<std::string> extra;
  if (req.ids) {  // the shard's exact tallies, for rotleak merge
    Scene whole = out.summary.scene;
    whole.particles = scene.particles;
    const RunResult& r = out.summary.result;
    write_tally_file(dir.file("tally.bin"), TallyFile{run_inputs(whole, r.engine), out.summary.scene.particles,
                                                      r.first_id, scene.particles, r.done, r.tally, r.records});
    extra.push_back("tally.bin");
  }
  out.document = write_run(dir, out.summary, extra);
  fs::remove(durable.path);  // after the commit: a kill in between leaves a complete run and a stale checkpoint
  out.dir = dir.final_path();
  return out;
}

SimulateOutcome merge_shards(const MergeRequest& req) {
  if (req.shards.empty()) throw InputError("DIR", "(none)", "give the shard directories to merge");
  struct Shard {
    fs::path dir;
    TallyFile f;
    json summary;
  };
  std::vector<Shard> shards;
  for (const fs::path& d : req.shards) {
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
  const std::uint64_t of = shards[0].f.of;
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

  // the whole run's scene: a shard's (tier as run) with the whole particle count; it must give the
  // inputs the shards carry
  Scene scene = load_scene((shards[0].dir / "scene.toml").string(), {"ensemble.particles=" + std::to_string(of)});
  scene.source = shards[0].summary.at("scene").value("source", scene.source);
  const Engine engine = shards[0].summary.at("engine").get<std::string>() == "simd" ? Engine::simd : Engine::scalar;
  const std::string why = inputs_difference(shards[0].f.inputs, run_inputs(scene, engine));
  if (!why.empty())
    throw InputError("DIR", shards[0].dir.string(), "its scene.toml does not match its tally.bin (" + why + ")");
  RunDirectory dir(req.out, req.force);
  RunResult result;
  result.tally.resize(scene);
  result.engine = engine;
  result.threads = 0;
  if (scene.escape_records) result.records.reserve(of);
  for (const Shard& s : shards) {
    result.tally.merge(s.f.tally);
    result.wall_seconds += s.summary.value("wall_seconds", 0.0);
    result.threads = std::max(result.threads, s.summary.value("threads", 0));
    if (scene.escape_records) result.records.insert(result.records.end(), s.f.records.begin(), s.f.records.end());
  }
  result.done = IntervalSet::range(0, block_count(of));
  if (req.note) req.note("[rotleak] merged " + std::to_string(shards.size()) + " shards: ids 0:" + std::to_string(of));
  SimulateOutcome out;
  out.summary = summarise(scene, std::move(result));
  out.document = write_run(dir, out.summary);
  out.dir = dir.final_path();
  return out;
}

}  // namespace rotleak
