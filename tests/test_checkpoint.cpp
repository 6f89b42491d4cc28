// Runs that outlive their process: block sets, tally files (checkpoints, shards, MPI ranks' tallies),
// epochs and stops in the engine, resume through the pipeline, shards merged, ids near 10^12. The
// standard in every test: the resumed, merged or cut run gives exactly the tallies (and the bytes of
// survival.csv) of the run done in one go; exact integer and fixed-point sums make that a bit-for-bit
// equality, never a tolerance.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <tuple>

#include "io/files.hpp"
#include "io/scene_file.hpp"
#include "io/tally_file.hpp"
#include "numeric/input.hpp"
#include "resume.hpp"
#include "run/pipeline.hpp"
#include "same_text.hpp"
#include "scratch.hpp"
#include "sim/kernel/simd_engine.hpp"

namespace rotleak {
namespace {

namespace fs = std::filesystem;

bool same(const Tally& a, const Tally& b) {
  return a.escapes_per_bin == b.escapes_per_bin && a.collision_density == b.collision_density &&
         a.collisions == b.collisions && a.escaped == b.escaped && a.survived == b.survived && a.stuck == b.stuck &&
         a.estimator == b.estimator && a.collision_density_w == b.collision_density_w;
}

/// omega = 2/3 (a rotating leak), importance-sampling weights, f_c and escape records: every tally.
Scene busy_scene(std::uint64_t particles) {
  return parse_scene(R"(
[leak]
omega = "2/3"
[ensemble]
particles = )" + std::to_string(particles) +
                     R"(
sampling = "mupo"
[run]
t_max = 3000
[observe]
collision_density = { bins = 50 }
escapes = true
)");
}

/// A test's own folder (tests/scratch.hpp), made empty, removed when the test ends.
struct TempDir : test::ScratchDir {
  TempDir()
      : ScratchDir(std::string("rotleak_ckpt_") + ::testing::UnitTest::GetInstance()->current_test_info()->name() +
                   "_") {
    fs::create_directories(path);
  }
};

TEST(IntervalSet, InsertJoinsAndRefusesOverlap) {
  IntervalSet s;
  EXPECT_TRUE(s.insert(5, 8));
  EXPECT_TRUE(s.insert(0, 2));
  EXPECT_TRUE(s.insert(2, 5));  // joins both neighbours
  EXPECT_EQ(s.text(), "0-8");
  EXPECT_TRUE(s.insert(10, 12));
  EXPECT_FALSE(s.insert(7, 9));    // 7 is in
  EXPECT_FALSE(s.insert(11, 15));  // 11 is in
  EXPECT_FALSE(s.insert(0, 1));
  EXPECT_EQ(s.text(), "0-8,10-12");
  EXPECT_EQ(s.size(), 10u);
  EXPECT_TRUE(s.contains(7));
  EXPECT_FALSE(s.contains(8));
  EXPECT_EQ(s.complement_in(0, 20).text(), "8-10,12-20");
  EXPECT_EQ(s.complement_in(3, 11).text(), "8-10");
  EXPECT_EQ(s.nth(8), 10u);
  EXPECT_EQ(s.slice(6, 9).text(), "6-8,10-11");
  // blocks of a 10^12-particle run
  const std::uint64_t blocks = block_count(1000000000000ull);
  EXPECT_EQ(blocks, 244140625u);
  IntervalSet big = IntervalSet::range(0, blocks);
  EXPECT_EQ(particles_in(big, 1000000000000ull), 1000000000000ull);
  EXPECT_EQ(particles_in(IntervalSet::range(blocks - 1, blocks), 1000000000001ull), kBlockSize);
  EXPECT_EQ(particles_in(IntervalSet::range(0, block_count(10)), 10), 10u);
}

TEST(TallyFile, RoundTripsBitForBitAndRefusesDamage) {
  Scene scene = busy_scene(20000);
  RunResult r = run_ensemble(scene, {});
  TallyFile f{simulation_inputs(scene, "scalar"), scene.particles, 7, scene.particles, r.done, r.tally, r.records};
  const std::string bytes = encode_tally_file(f);
  const TallyFile back = decode_tally_file(bytes, "mem");
  EXPECT_TRUE(same(back.tally, r.tally));
  EXPECT_EQ(back.done, r.done);
  EXPECT_TRUE(back.complete());
  EXPECT_EQ(back.first_id, 7u);
  EXPECT_EQ(back.inputs, f.inputs);
  ASSERT_EQ(back.records.size(), r.records.size());
  for (std::size_t i = 0; i < r.records.size(); i += 997) {
    EXPECT_EQ(back.records[i].t, r.records[i].t);
    EXPECT_EQ(back.records[i].fate, r.records[i].fate);
  }
  EXPECT_EQ(encode_tally_file(back), bytes);
  std::string bad = bytes;
  bad[bad.size() / 2] ^= 1;
  EXPECT_THROW(decode_tally_file(bad, "mem"), std::runtime_error);
  EXPECT_THROW(decode_tally_file(bytes.substr(0, bytes.size() - 9), "mem"), std::runtime_error);
  EXPECT_THROW(decode_tally_file("{}", "mem"), std::runtime_error);
  // damage behind a valid checksum (found by fuzz_tally): a float where a count belongs was converted with
  // undefined behaviour, and a size larger than the file was allocated before it was read
  const std::string body = bytes.substr(0, bytes.size() - 8);
  for (const auto& [from, to, why] :
       {std::tuple<std::string, std::string, std::string>{
            "\"records\":", "\"records\":5.7e54,\"x\":", "records is not a count"},
        {"\"survival_bins\":", "\"survival_bins\":1000000000000,\"x\":", "sizes larger than the file"},
        {"\"weighted\":", "\"weighted\":3,\"x\":", "weighted is not true or false"}}) {
    // the header edited and its length prefix with it ("rotleak-tallies 4\n<length>\n<header>"), so that
    // the reader gets past the JSON to the checks of its values
    const std::size_t magic = body.find('\n') + 1, nl = body.find('\n', magic);
    std::string header = body.substr(nl + 1, std::stoull(body.substr(magic, nl - magic)));
    const std::string rest = body.substr(nl + 1 + header.size());
    const auto at = header.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    header.replace(at, from.size(), to);
    const std::string edited = body.substr(0, magic) + std::to_string(header.size()) + "\n" + header + rest;
    try {
      decode_tally_file(sealed_tally_bytes(edited), "mem");
      ADD_FAILURE() << "accepted: " << to;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("header unreadable: " + why), std::string::npos) << e.what();
    }
  }
}

// A sum's limbs outside FixedSum's range are damage, refused at once: a split file's zero total at limb
// 2^50 hung the reader's comparison (found by fuzz_tally), and a merge would cover the span word by word.
TEST(TallyFile, RefusesASumOutsideTheLimbRange) {
  Scene scene = busy_scene(4096);
  RunResult r = run_ensemble(scene, {});
  auto* e = r.tally.get_if<WeightedEstimator>();
  ASSERT_NE(e, nullptr);
  for (const long base : {1L << 50, -(1L << 50), FixedSum::kLimbEnd, FixedSum::kLowestLimb - 1}) {
    e->total_w = FixedSum::from_limbs(base, {1});
    TallyFile f{simulation_inputs(scene, "scalar"), scene.particles, 0, scene.particles, r.done, r.tally, r.records};
    try {
      decode_tally_file(encode_tally_file(f), "mem");
      ADD_FAILURE() << "accepted a sum at limb " << base;
    } catch (const std::runtime_error& err) {
      EXPECT_NE(std::string(err.what()).find("outside [-64, 64)"), std::string::npos) << err.what();
    }
  }
  e->total_w = FixedSum::from_limbs(FixedSum::kLimbEnd - 1, {1});  // the range's last limb is read
  TallyFile f{simulation_inputs(scene, "scalar"), scene.particles, 0, scene.particles, r.done, r.tally, r.records};
  EXPECT_TRUE(decode_tally_file(encode_tally_file(f), "mem").tally.estimator == r.tally.estimator);
}

TEST(TallyFile, InputsDifferenceNamesTheKey) {
  Scene a = busy_scene(100), b = busy_scene(100);
  b.width_text = "0.02";
  // the same scene read back from the scene.toml a run writes has the same inputs (what a resume or a
  // shard merge relies on): nothing the file leaves out, rounds or reorders may count as a difference
  const Scene back = parse_scene(scene_to_toml(a));
  EXPECT_EQ(inputs_difference(simulation_inputs(a, "simd"), simulation_inputs(back, "simd")), "");
  // and the scene with its fit keys changed, as `rotleak fit` would, is still the same run
  Scene refit = a;
  refit.alpha_factor = 5;
  EXPECT_EQ(inputs_difference(simulation_inputs(a, "simd"), simulation_inputs(refit, "simd")), "");
  // every other key is an input: one changed exact key, one number, one switch, each named
  Scene more = a;
  more.t_max = a.t_max + 1;
  EXPECT_NE(inputs_difference(simulation_inputs(a, "simd"), simulation_inputs(more, "simd")).find("run.t_max"),
            std::string::npos);
  more = a;
  more.fast_forward = !a.fast_forward;
  EXPECT_NE(inputs_difference(simulation_inputs(a, "simd"), simulation_inputs(more, "simd")).find("run.fast_forward"),
            std::string::npos);
  EXPECT_EQ(inputs_difference(simulation_inputs(a, "simd"), simulation_inputs(b, "simd")),
            "leak.width: \"0.01\" vs \"0.02\"");
  EXPECT_EQ(inputs_difference(simulation_inputs(a, "simd"), simulation_inputs(a, "scalar")), "engine: simd vs scalar");
  // the fit keys and the checkpoint interval are not inputs of the numbers
  b = a;
  b.kappa_window = {100, 500};
  b.checkpoint_seconds = 5;
  EXPECT_EQ(simulation_inputs(a, "simd"), simulation_inputs(b, "simd"));
}

TEST(Epochs, CheckpointsAndStopsLeaveTheTalliesUnchanged) {
  const Scene scene = busy_scene(60000);
  RunOptions plain;
  plain.threads = 2;
  const RunResult whole = run_ensemble(scene, plain);

  // a checkpoint after every block: each is the exact sum of the blocks it names
  RunOptions every;
  every.threads = 2;
  every.checkpoint_seconds = 1e-9;
  int checkpoints = 0;
  IntervalSet last;
  every.checkpoint = [&](const Tally& t, const IntervalSet& done, const std::vector<EscapeRecord>&) {
    ++checkpoints;
    for (const auto& [lo, hi] : last.intervals()) EXPECT_TRUE(done.contains(lo) && done.contains(hi - 1));  // grows
    EXPECT_GE(done.size(), last.size());
    EXPECT_EQ(t.escaped + t.survived + t.stuck, particles_in(done, scene.particles));
    last = done;
  };
  const RunResult cut = run_ensemble(scene, every);
  EXPECT_GE(checkpoints, 3);
  EXPECT_TRUE(cut.complete);
  EXPECT_TRUE(same(cut.tally, whole.tally));

  // stopped after the first checkpoint, then resumed from it on one thread
  const test::StopAndResume r = test::stop_and_resume(scene);
  EXPECT_FALSE(r.part.complete);
  EXPECT_LT(r.read.done.size(), block_count(scene.particles));
  EXPECT_EQ(r.read.done, r.part.done);
  const RunResult& resumed = r.resumed;
  EXPECT_TRUE(resumed.complete);
  EXPECT_TRUE(same(resumed.tally, whole.tally));
  for (std::size_t i = 0; i < whole.records.size(); ++i) {
    ASSERT_EQ(resumed.records[i].t, whole.records[i].t) << i;
    ASSERT_EQ(resumed.records[i].collisions, whole.records[i].collisions) << i;
  }
}

SimulateRequest request(const TempDir& d, const std::string& out, std::vector<std::string> overrides) {
  const fs::path scene = d.path / "scene.toml";
  if (!fs::exists(scene)) write_file_atomic(scene, scene_to_toml(busy_scene(30000)));
  SimulateRequest r;
  r.scene_path = scene.string();
  r.overrides = std::move(overrides);
  r.out = d.path / out;
  r.run.threads = 2;
  return r;
}

// run_scene runs the engine its options ask for: it once replaced RunOptions::engine with a string
// argument that defaulted to "auto", so a library caller asking for the scalar core got the kernel.
TEST(Pipeline, RunSceneRunsTheEngineItsOptionsAskFor) {
  const Scene scene = busy_scene(5000);
  for (Engine e : {Engine::scalar, Engine::simd}) {
    if (e == Engine::simd && !simd::available()) {
      std::printf("[ skipped  ] simd: this CPU lacks AVX2 and FMA\n");
      continue;
    }
    RunOptions o;
    o.engine = e;
    EXPECT_EQ(run_scene(plan_run(scene, o), o).result.engine, e) << to_string(e);
  }
  RunOptions bad;
  bad.engine = Engine::simd;
  Scene flt = scene;
  flt.tier = Tier::float_;
  EXPECT_THROW(run_scene(plan_run(flt, bad), bad), InputError);  // the kernel runs the double tier only
}

TEST(Pipeline, ResumeFromACheckpointWritesTheSameRun) {
  TempDir d;
  const SimulateOutcome whole = simulate(request(d, "whole", {}));
  // stopped at the first checkpoint: a RunInterrupted, the checkpoint beside the target, no directory
  std::atomic<bool> stop{false};
  SimulateRequest cut = request(d, "cut", {"run.checkpoint_seconds=1e-9"});
  cut.run.stop = &stop;
  cut.run.progress = [&](std::uint64_t done, std::uint64_t, std::uint64_t, bool) {
    if (done > 0) stop = true;
  };
  EXPECT_THROW(simulate(cut), RunInterrupted);
  EXPECT_TRUE(fs::exists(d.path / "cut.checkpoint"));
  EXPECT_FALSE(fs::exists(d.path / "cut"));
  // --out on it is refused; a resume with other inputs is refused naming the key
  try {
    simulate(request(d, "cut", {}));
    ADD_FAILURE() << "a fresh run over a checkpoint was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--resume"), std::string::npos) << e.what();
  }
  SimulateRequest other = request(d, "cut", {"leak.width=0.02"});
  other.resume = Resume::yes;
  try {
    simulate(other);
    ADD_FAILURE() << "a resume with other inputs was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("leak.width"), std::string::npos) << e.what();
  }
  // the checkpoint keeps the time spent; the resumed run reports it with its own (its rate was once ~2x too
  // high: this part's seconds over the whole run's collisions). 1000 s stands in for a long first part.
  TallyFile saved = read_tally_file(d.path / "cut.checkpoint");
  EXPECT_GT(saved.wall_seconds, 0.0);
  saved.wall_seconds = 1000;
  write_tally_file(d.path / "cut.checkpoint", saved);
  SimulateRequest resume = request(d, "cut", {});
  resume.resume = Resume::yes;
  resume.run.threads = 1;
  simulate(resume);
  const json how = json::parse(read_file(d.path / "cut" / "summary.json")).at("execution");
  EXPECT_GE(how.at("wall_seconds").get<double>(), 1000.0);
  EXPECT_LE(how.at("collisions_per_second").get<double>(),
            json::parse(read_file(d.path / "cut" / "summary.json")).at("collisions").get<double>() / 1000.0);
  EXPECT_FALSE(fs::exists(d.path / "cut.checkpoint"));
  for (const char* f : {"survival.csv", "fc.csv", "escapes.csv"})
    EXPECT_TRUE(test::same_text(read_file(d.path / "cut" / f), read_file(d.path / "whole" / f))) << f;
  EXPECT_EQ(whole.document.at("kappa"), json::parse(read_file(d.path / "cut" / "summary.json")).at("kappa"));
  try {
    simulate(resume);
    ADD_FAILURE() << "a resume of a complete run was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("complete"), std::string::npos) << e.what();
  }
}

TEST(Pipeline, ShardsMergeIntoTheWholeRunAndBadTilingsAreRefused) {
  TempDir d;
  simulate(request(d, "whole", {}));
  auto shard = [&](const std::string& name, std::uint64_t a, std::uint64_t b, std::vector<std::string> o = {}) {
    SimulateRequest r = request(d, name, std::move(o));
    r.ids = {{a, b}};
    return simulate(r);
  };
  const SimulateOutcome s1 = shard("s1", 0, 10000);
  shard("s2", 10000, 20001);
  shard("s3", 20001, 30000);
  EXPECT_EQ(s1.document.at("ids").at("of"), 30000);
  EXPECT_EQ(s1.document.at("particles"), 10000);
  MergeRequest m;
  m.shards = {d.path / "s3", d.path / "s1", d.path / "s2"};
  m.out = d.path / "merged";
  merge_shards(m);
  for (const char* f : {"survival.csv", "fc.csv", "escapes.csv"})
    EXPECT_TRUE(test::same_text(read_file(d.path / "merged" / f), read_file(d.path / "whole" / f))) << f;
  const json a = json::parse(read_file(d.path / "whole" / "summary.json"));
  const json b = json::parse(read_file(d.path / "merged" / "summary.json"));
  for (const char* k : {"kappa", "alpha", "tail_exponent", "particles", "collisions", "escaped", "sampling"})
    EXPECT_EQ(a.at(k), b.at(k)) << k;

  shard("other", 20001, 30000, {"leak.width=0.02"});
  const std::vector<std::pair<std::vector<std::string>, std::string>> bad = {
      {{"s1", "s3"}, "uncovered"},            // a gap
      {{"s1", "s1", "s2", "s3"}, "overlap"},  // twice
      {{"s1", "s2"}, "missing"},              // short of the end
      {{"s1", "s2", "other"}, "leak.width"},  // other inputs
      {{"whole"}, "not a shard"}};
  for (const auto& [dirs, why] : bad) {
    MergeRequest r;
    for (const auto& x : dirs) r.shards.push_back(d.path / x);
    r.out = d.path / "refused";
    try {
      merge_shards(r);
      ADD_FAILURE() << "merged " << why;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(d.path / "refused"));
  }
}

TEST(Pipeline, GpuShardsMergeIntoTheWholeRun) {
  // shards run on the GPU engine (emulated on the cores here) merge into the CPU's whole run: a shard's tally.bin
  // names the engine that ran it, and merge once read "gpu" back as "scalar" and refused its own shards
  TempDir d;
  simulate(request(d, "whole", {}));
  setenv("ROTLEAK_GPU_EMULATE", "1", 1);
  for (const auto& [name, ids] : std::vector<std::pair<std::string, std::pair<std::uint64_t, std::uint64_t>>>{
           {"g1", {0, 12288}}, {"g2", {12288, 30000}}}) {
    SimulateRequest r = request(d, name, {});
    r.ids = ids;
    r.run.engine = Engine::gpu;
    simulate(r);
  }
  unsetenv("ROTLEAK_GPU_EMULATE");
  MergeRequest m;
  m.shards = {d.path / "g1", d.path / "g2"};
  m.out = d.path / "merged";
  merge_shards(m);
  EXPECT_EQ(json::parse(read_file(d.path / "merged" / "summary.json")).at("execution").at("engine"), "gpu");
  for (const char* f : {"survival.csv", "fc.csv", "escapes.csv"})
    EXPECT_TRUE(test::same_text(read_file(d.path / "merged" / f), read_file(d.path / "whole" / f))) << f;
}

TEST(Pipeline, IdsNearTenToTheTwelfth) {
  // the last 8192 ids of a 10^12-particle run: 64-bit ids, counts and block indices; memory does not
  // grow with the whole run's size
  TempDir d;
  SimulateRequest r = request(d, "tail", {"ensemble.particles=1000000000000", "observe.escapes=false"});
  r.ids = {{999999991808ull, 1000000000000ull}};
  const SimulateOutcome out = simulate(r);
  EXPECT_EQ(out.document.at("particles"), 8192);
  EXPECT_EQ(out.document.at("ids").at("first"), 999999991808ull);
  const TallyFile f = read_tally_file(d.path / "tail" / "tally.bin");
  EXPECT_EQ(f.of, 1000000000000ull);
  EXPECT_EQ(f.tally.escaped + f.tally.survived + f.tally.stuck, 8192u);
  // the same ids as the start of a run of their own draw other particles: ids, not positions, decide
  SimulateRequest s = request(d, "head", {"ensemble.particles=8192", "observe.escapes=false"});
  simulate(s);
  EXPECT_NE(read_file(d.path / "tail" / "survival.csv"), read_file(d.path / "head" / "survival.csv"));
}

}  // namespace
}  // namespace rotleak
