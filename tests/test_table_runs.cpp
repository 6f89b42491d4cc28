// Scenes on any table with a list of leaks ([table], [[leaks]]): read, refused, written back; and the ensemble
// engine running them (docs/tables.md): the stadium given as a table runs the stadium's tallies bit for bit,
// per-leak escapes add up and split by symmetry, flow starts land inside, threads do not change a bit.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numeric>

#include "analysis/run_summary.hpp"
#include "io/scene_file.hpp"
#include "io/tally_file.hpp"
#include "resume.hpp"
#include "same_run.hpp"
#include "scene_error.hpp"
#include "sim/engine/engine.hpp"
#include "sim/kernel/simd_engine.hpp"
#include "sim/model/initial.hpp"

using namespace rotleak;

namespace {

const char* kMushroom = "[table]\nkind = \"mushroom\"\nradius = \"1\"\nstem_width = \"1/2\"\nstem_height = \"1\"\n";
const char* kTwoLeaks = "[[leaks]]\nwidth = \"0.02\"\nstart = \"0\"\n\n[[leaks]]\nwidth = \"0.02\"\nstart = \"1/2\"\n";

/// Every standard table but the stadium, as a scene's [table].
std::vector<std::string> other_tables() {
  return {
      "[table]\nkind = \"circle\"\nradius = \"1\"\n",
      "[table]\nkind = \"ellipse\"\na = \"3/2\"\nb = \"1\"\n",
      kMushroom,
      "[table]\nkind = \"sinai\"\nside = \"2\"\nradius = \"1/2\"\n",
      "[table]\nkind = \"annulus\"\nradius = \"1\"\ninner_radius = \"1/4\"\noffset = \"-1/3\"\n",
      "[table]\nkind = \"lemon\"\nradius = \"1\"\ndistance = \"1\"\n",
      "[table]\nkind = \"lorentz\"\nradius = \"0.45\"\n",
      "[table]\nkind = \"polygon\"\nvertices = [[\"0\", \"0\"], [\"0\", \"1\"], [\"2\", \"1/3\"]]\n",
  };
}

RunOptions threads(int n) {
  RunOptions o;
  o.threads = n;
  return o;
}

std::uint64_t leak_total(const Tally& t, std::size_t leak) {
  const std::size_t bins = t.escapes_per_bin.size();
  return std::accumulate(t.escapes_by_leak.begin() + static_cast<std::ptrdiff_t>(leak * bins),
                         t.escapes_by_leak.begin() + static_cast<std::ptrdiff_t>((leak + 1) * bins), std::uint64_t{0});
}

}  // namespace

TEST(TableScene, EveryStandardTableReadsAndWritesBack) {
  for (const std::string& t : other_tables()) {
    const Scene s = parse_scene(t + kTwoLeaks);
    ASSERT_TRUE(s.table.has_value()) << t;
    EXPECT_TRUE(s.on_table());
    EXPECT_EQ(s.leaks.size(), 2u);
    EXPECT_EQ(table_spec(s).name, s.table->kind);
    // written as TOML and read back: the same scene, to the text
    const std::string toml = scene_to_toml(s);
    EXPECT_EQ(scene_json(parse_scene(toml)).dump(), scene_json(s).dump()) << toml;
  }
  // a simple polygon whose two tops lie on one line (sides 2 and 6) is no crossing
  EXPECT_EQ(error_of("[table]\nkind = \"polygon\"\nvertices = [[\"0\", \"0\"], [\"0\", \"2\"], [\"1\", \"2\"], "
                     "[\"1\", \"1\"], [\"2\", \"1\"], [\"2\", \"2\"], [\"3\", \"2\"], [\"3\", \"0\"]]\n"),
            "");
  // the stadium given as [table] is the stadium of [stadium]; a list of one leak on the outer boundary is [leak]
  const Scene a = parse_scene("[table]\nkind = \"stadium\"\nd = \"3\"\nr = \"1/2\"\n[[leaks]]\nwidth = \"0.05\"\n");
  const Scene b = parse_scene("[stadium]\nd = \"3\"\nr = \"1/2\"\n[leak]\nwidth = \"0.05\"\n");
  EXPECT_FALSE(a.on_table());
  EXPECT_EQ(scene_json(a).dump(), scene_json(b).dump());
}

// A list of one leak is the scene's [leak] only when it lies on the outer boundary (loop 0, given or by default);
// one leak on the Sinai table's disc stays a listed leak on loop 1 (its scene written and read back keeps it there),
// where folding it into [leak] (mutant tests/mutants/scatterer-leak-folded.patch) would move it onto the walls.
TEST(TableScene, OneListedLeakIsTheLeakOnlyOnTheOuterBoundary) {
  const std::string sinai = "[table]\nkind = \"sinai\"\nside = \"2\"\nradius = \"1/2\"\n";
  for (const char* loop : {"", "loop = 0\n"}) {
    const Scene walls = parse_scene(sinai + "[[leaks]]\n" + loop + "width = \"1/20\"\nomega = \"1/7\"\n");
    EXPECT_TRUE(walls.leaks.empty()) << loop;
    EXPECT_EQ(walls.width_text, "1/20");
    EXPECT_EQ(walls.omega.as_rational(), mpq_class(1, 7));
  }
  const Scene disc = parse_scene(sinai + "[[leaks]]\nloop = 1\nwidth = \"1/20\"\nomega = \"1/7\"\n");
  ASSERT_EQ(disc.leaks.size(), 1u);
  EXPECT_EQ(disc.leaks[0].loop, 1);
  EXPECT_EQ(disc.leaks[0].width.text, "1/20");
  EXPECT_EQ(leak_count(disc), 1u);
  const Scene back = parse_scene(scene_to_toml(disc));
  ASSERT_EQ(back.leaks.size(), 1u);
  EXPECT_EQ(back.leaks[0].loop, 1);
  EXPECT_EQ(scene_json(back).dump(), scene_json(disc).dump());
}

TEST(TableScene, BadTablesAndLeakListsAreRefusedWithTheirKey) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[table]\nkind = \"oval\"\n", "table.kind"},
      {"[table]\nkind = \"circle\"\n", "table.radius"},                              // a parameter missing
      {"[table]\nkind = \"circle\"\nradius = \"1\"\nside = \"2\"\n", "table.side"},  // another kind's
      {"[table]\nkind = \"circle\"\nradius = 1.5\n", "table.radius"},                // through double
      {"[table]\nkind = \"circle\"\nradius = \"-1\"\n", "table"},
      {"[table]\nkind = \"circle\"\nradius = \"1e-200\"\n", "table.radius"},
      {"[table]\nkind = \"sinai\"\nside = \"1\"\nradius = \"1/2\"\n", "table"},  // the disc touches the walls
      {"[table]\nkind = \"polygon\"\nvertices = [[\"0\", \"0\"], [\"1\", \"0\"]]\n", "table.vertices"},
      {"[table]\nkind = \"polygon\"\nvertices = [[\"0\", \"0\"], [\"1\", \"0\"], [\"0\", \"1\"]]\n",
       "table"},  // anticlockwise
      {"[table]\nkind = \"polygon\"\nvertices = [[\"0\", \"0\"], [\"0\", \"2\"], [\"2\", \"0\"], [\"2\", \"3\"]]\n",
       "table"},  // a bow tie: two sides cross
      {"[table]\nkind = \"circle\"\nradius = \"1\"\n[stadium]\nd = \"2\"\n", "stadium"},
      {"[table]\nkind = \"stadium\"\nd = \"2\"\n[stadium]\nr = \"2\"\n", "stadium"},
      {std::string("[leak]\nwidth = \"0.1\"\n") + kTwoLeaks, "leak"},
      {"[[leaks]]\nstart = \"0\"\n", "leaks.0.width"},
      {"[[leaks]]\nwidth = \"0.1\"\nloop = 1\n", "leaks.0.loop"},  // the stadium has one loop
      {"[[leaks]]\nwidth = \"1\"\n[[leaks]]\nwidth = \"0.1\"\n", "leaks.0.width"},
      {std::string(kTwoLeaks) + "[[leaks]]\nwidth = \"0.1\"\nside = 2\n", "leaks.2.side"},
      {std::string(kMushroom) + "[ensemble]\nsampling = \"mupo\"\n", "ensemble.sampling"},
      {std::string(kTwoLeaks) + "[run]\nfast_forward = true\n", "run.fast_forward"},
      {std::string(kMushroom) + "[run]\nsplitting = true\nsplit_every = 0\n", "run.split_every"},
  };
  for (const auto& [toml, key] : cases) {
    const std::string msg = error_of(toml);
    ASSERT_FALSE(msg.empty()) << "accepted: " << toml;
    EXPECT_EQ(msg.rfind(key + " = ", 0), 0u) << msg;
  }
  // --set reaches a listed leak's keys, and refuses one not listed
  const Scene s =
      parse_scene(kTwoLeaks, {"leaks.1.width=1/64", "leaks.1.omega=2/3", "table.kind=circle", "table.radius=2"});
  EXPECT_EQ(s.leaks[1].width.text, "1/64");
  EXPECT_EQ(s.leaks[1].omega.value.as_rational(), mpq_class(2, 3));
  EXPECT_EQ(s.table->kind, "circle");
  EXPECT_EQ(error_of(kTwoLeaks, {"leaks.2.width=0.1"}).rfind("leaks.2.width = ", 0), 0u);
  EXPECT_EQ(error_of(kTwoLeaks, {"leaks.0.size=0.1"}).rfind("leaks.0.size = ", 0), 0u);
}

TEST(TableRun, TheStadiumGivenAsATableRunsTheStadiumsTalliesBitForBit) {
  // the stadium model (its convex shortcut, its Leak) and the table model (pieces, LeakList) on the same stadium:
  // the same draws, every tally equal, in every ensemble tier
  for (const char* tier : {"float", "double", "long_double"}) {
    Scene s = parse_scene(std::string("[stadium]\nd = \"2\"\nr = \"1\"\n[leak]\nwidth = \"0.03\"\nomega = \"2/3\"\n") +
                              "[run]\nt_max = 3000.0\n",
                          {"ensemble.particles=3000", std::string("run.tier=") + tier,
                           "observe.collision_density={ bins = 50, windows = [[0.0, 100.0]] }"});
    RunOptions scalar = threads(2);
    scalar.engine = Engine::scalar;
    const RunResult stadium = run_ensemble(s, scalar);
    ASSERT_FALSE(s.on_table());
    s.table = TableInput{"stadium", {{s.d, s.d_text}, {s.r, s.r_text}}, {}};
    ASSERT_TRUE(s.on_table());
    const RunResult table = run_ensemble(s, scalar);
    EXPECT_EQ(table.engine, Engine::scalar);
    EXPECT_EQ(table.tally.escapes_per_bin, stadium.tally.escapes_per_bin) << tier;
    EXPECT_EQ(table.tally.collision_density, stadium.tally.collision_density) << tier;
    EXPECT_EQ(table.tally.collisions, stadium.tally.collisions) << tier;
    EXPECT_EQ(table.tally.survived, stadium.tally.survived) << tier;
  }
}

TEST(TableRun, PerLeakEscapesAddUpAndSplitBySymmetry) {
  // two equal leaks that a symmetry of the table swaps (the stadium's s = 0 and 1/2: the top and bottom edges'
  // middles; the circle's 0 and 1/4): each takes half the escapes. Error model: given the escapes E, leak 0's
  // count is binomial(E, 1/2) (the particles are independent), so |n0 - E/2| <= 5 sqrt(E / 4).
  const std::vector<std::string> tables = {"", "[table]\nkind = \"circle\"\nradius = \"1\"\n"};
  for (const std::string& t : tables) {
    const std::string second = t.empty() ? "1/2" : "1/4";
    const Scene s = parse_scene(t + "[[leaks]]\nwidth = \"0.02\"\n[[leaks]]\nwidth = \"0.02\"\nstart = \"" + second +
                                    "\"\n[run]\nt_max = 2000.0\n",
                                {"ensemble.particles=20000"});
    const RunResult r = run_ensemble(s, threads(2));
    ASSERT_EQ(r.tally.escapes_by_leak.size(), 2 * r.tally.escapes_per_bin.size());
    const std::uint64_t n0 = leak_total(r.tally, 0), n1 = leak_total(r.tally, 1);
    EXPECT_EQ(n0 + n1, r.tally.escaped);
    for (std::size_t k = 0; k < r.tally.escapes_per_bin.size(); ++k)  // bin by bin
      ASSERT_EQ(r.tally.escapes_by_leak[k] + r.tally.escapes_by_leak[r.tally.escapes_per_bin.size() + k],
                r.tally.escapes_per_bin[k]);
    const double e = static_cast<double>(r.tally.escaped);
    EXPECT_GT(e, 10000) << t;
    EXPECT_LE(std::abs(static_cast<double>(n0) - e / 2), 5 * std::sqrt(e / 4)) << t << ": " << n0 << " of " << e;
    // the same run on one thread: every count equal
    const RunResult one = run_ensemble(s, threads(1));
    EXPECT_EQ(one.tally.escapes_by_leak, r.tally.escapes_by_leak);
    EXPECT_EQ(one.tally.collisions, r.tally.collisions);
  }
}

TEST(TableRun, FlowStartsLieInsideAndTheTallyFileKeepsTheLeaks) {
  // flow starts on the Sinai table: inside the square, outside the disc (Table::contains), about as many draws as
  // the table's share of its box (1 - pi / 16 of the square here) -- none rejected wrongly
  const Scene s = parse_scene(std::string("[table]\nkind = \"sinai\"\nside = \"2\"\nradius = \"1/2\"\n") + kTwoLeaks +
                                  "[ensemble]\ninit = \"flow\"\n[run]\nt_max = 500.0\n",
                              {"ensemble.particles=2000"});
  const InitialConditions ic = initial_conditions(s);
  for (std::uint64_t id = 0; id < 2000; ++id) {
    const InitialDraw d = ic.draw(id);
    ASSERT_TRUE(d.flow);
    ASSERT_LT(std::abs(d.x), 1.0);
    ASSERT_LT(std::abs(d.y), 1.0);
    ASSERT_GT(d.x * d.x + d.y * d.y, 0.25) << id;
  }
  const RunResult r = run_ensemble(s, threads(2));
  EXPECT_EQ(r.tally.escaped + r.tally.survived + r.tally.stuck, 2000u);
  EXPECT_EQ(r.tally.stuck, 0u);
  // a checkpoint's tally file holds the per-leak counts and reads them back
  TallyFile f;
  f.tally = r.tally;
  f.particles = 2000;
  f.done = r.done;
  f.inputs = simulation_inputs(s, "scalar");
  const TallyFile back = decode_tally_file(encode_tally_file(f), "test");
  EXPECT_EQ(back.tally.escapes_by_leak, r.tally.escapes_by_leak);
  EXPECT_EQ(back.tally.escapes_per_bin, r.tally.escapes_per_bin);
}

TEST(TableRun, TheVectorisedEngineRunsEveryTableAsTheScalarOneBitForBit) {
  // every standard table with a stationary leak and a moving one (on the scatterer where there is one), f_c and
  // escape records, Birkhoff and flow starts: the kernel of every width this CPU runs against the scalar engine
  if (!simd::available()) GTEST_SKIP() << "this CPU has no AVX2: the vectorised engine does not run here";
  std::vector<std::string> tables = other_tables();
  tables.push_back("[table]\nkind = \"stadium\"\nd = \"2\"\nr = \"1\"\n");
  std::vector<int> widths = {4};
  if (simd::lanes_available(8)) widths.push_back(8);
  for (const std::string& t : tables) {
    const bool scatterer = t.find("sinai") != std::string::npos || t.find("annulus") != std::string::npos;
    for (const char* init : {"birkhoff", "flow"}) {
      const Scene s = parse_scene(t + "[[leaks]]\nwidth = \"0.03\"\nstart = \"0.1\"\n[[leaks]]\nwidth = \"0.05\"\n" +
                                      "omega = \"2/3\"\n" + (scatterer ? "loop = 1\n" : "start = \"1/2\"\n") +
                                      "[ensemble]\ninit = \"" + init + "\"\n[run]\nt_max = 400.0\n",
                                  {"ensemble.particles=1500", "observe.escapes=true",
                                   "observe.collision_density={ bins = 40, windows = [[0.0, 50.0], [20.0, 400.0]] }"});
      ASSERT_TRUE(s.on_table());
      RunOptions scalar = threads(2);
      scalar.engine = Engine::scalar;
      const RunResult a = run_ensemble(s, scalar);
      EXPECT_GT(a.tally.escaped, 300u) << t;
      for (int lanes : widths) {
        RunOptions o = threads(2);
        o.engine = Engine::simd;
        o.simd_lanes = lanes;
        const RunResult b = run_ensemble(s, o);
        ASSERT_EQ(b.engine, Engine::simd);
        test::expect_same_run(a, b, t + init + " lanes " + std::to_string(lanes));
      }
    }
  }
}

TEST(TableRun, TheVectorisedEngineTakesTheSecondLookAtCornersAsTheScalarOne) {
  // flights aimed at the polygon's and the lemon's corners from random points: rounding leaves some of them
  // between two pieces' spans, where Table::next_hit takes its second look (the spans widened by the slack); the
  // kernel must take it for the same lanes and find the same piece
  if (!simd::available()) GTEST_SKIP() << "this CPU has no AVX2: the vectorised engine does not run here";
  for (const char* table :
       {"[table]\nkind = \"polygon\"\nvertices = [[\"0\", \"0\"], [\"0\", \"1\"], [\"2\", \"1/3\"]]\n",
        "[table]\nkind = \"lemon\"\nradius = \"1\"\ndistance = \"1\"\n"}) {
    const Scene s = parse_scene(std::string(table) + "[[leaks]]\nwidth = \"0.05\"\n[[leaks]]\nwidth = \"0.05\"\n" +
                                    "start = \"1/2\"\nomega = \"1/3\"\n[run]\nt_max = 200.0\n",
                                {"ensemble.particles=20000"});
    const TableSpec spec = table_spec(s);
    const Table<double> t(spec);
    const auto tab = std::make_shared<const Table<double>>(spec);
    const InitialConditions flow(11, InitKind::flow, 0, tab);  // random points inside the table
    std::vector<InitialDraw> draws;
    int second = 0;
    for (std::uint64_t i = 0; draws.size() < s.particles; ++i) {
      InitialDraw d = flow.draw(i);
      const TablePiece<double>& corner = t.piece(static_cast<int>(i % static_cast<std::uint64_t>(t.pieces())));
      double u = std::atan2(corner.ay - d.y, corner.ax - d.x) / (2 * M_PI);
      d.u = u < 0 ? u + 1 : u;
      const ParticleState<double> ps = initial_state(t, d);
      second += t.nearest(ps.q, ps.v, 0.0).piece < 0;
      draws.push_back(d);
    }
    EXPECT_GE(second, 20) << table << ": too few flights needed the second look to test it";
    RunOptions scalar = threads(1), vector = threads(1);
    scalar.engine = Engine::scalar, vector.engine = Engine::simd;
    scalar.draws = vector.draws = &draws;
    const RunResult a = run_ensemble(s, scalar), b = run_ensemble(s, vector);
    ASSERT_EQ(b.engine, Engine::simd);
    test::expect_same_run(a, b, std::string(table) + " (" + std::to_string(second) + " second looks)");
  }
}

TEST(TableRun, TheKernelsTableStepOnTheStadiumIsItsStadiumStep) {
  // the stadium's own kernel path (its convex next hit, its filtered angles and phase) and the table step on the
  // stadium given as a table: the same tallies, bit for bit, stationary and moving
  if (!simd::available()) GTEST_SKIP() << "this CPU has no AVX2: the vectorised engine does not run here";
  for (const char* omega : {"0", "2/3"}) {
    Scene s =
        parse_scene(std::string("[stadium]\nd = \"2\"\nr = \"1\"\n[leak]\nwidth = \"0.03\"\nomega = \"") + omega +
                        "\"\n[run]\nt_max = 3000.0\n",
                    {"ensemble.particles=3000", "observe.collision_density={ bins = 50, windows = [[0.0, 100.0]] }"});
    RunOptions o = threads(2);
    o.engine = Engine::simd;
    const RunResult stadium = run_ensemble(s, o);
    s.table = TableInput{"stadium", {{s.d, s.d_text}, {s.r, s.r_text}}, {}};
    ASSERT_TRUE(s.on_table());
    const RunResult table = run_ensemble(s, o);
    ASSERT_EQ(table.engine, Engine::simd);
    test::expect_same_run(stadium, table, std::string("omega ") + omega);
  }
}

TEST(TableRun, StoppedAtACheckpointAndResumedThroughItsFileIsTheWholeRun) {
  // the Sinai table with a leak on the square and one on the disc, with f_c and escape records: stopped after its
  // first checkpoint, the tallies through the tally file's bytes, resumed on one thread -- every count equal
  const Scene s = parse_scene(std::string("[table]\nkind = \"sinai\"\nside = \"2\"\nradius = \"1/2\"\n") +
                                  "[[leaks]]\nwidth = \"0.02\"\n[[leaks]]\nloop = 1\nwidth = \"0.05\"\n" +
                                  "[run]\nt_max = 1000.0\n[observe]\nescapes = true\n",
                              {"ensemble.particles=40000", "observe.collision_density={ bins = 40 }"});
  const RunResult whole = run_ensemble(s, threads(2));
  const test::StopAndResume r = test::stop_and_resume(s);
  ASSERT_FALSE(r.part.complete);
  const RunResult& resumed = r.resumed;
  ASSERT_TRUE(resumed.complete);
  EXPECT_EQ(resumed.tally.escapes_by_leak, whole.tally.escapes_by_leak);
  EXPECT_EQ(resumed.tally.escapes_per_bin, whole.tally.escapes_per_bin);
  EXPECT_EQ(resumed.tally.collision_density, whole.tally.collision_density);
  EXPECT_EQ(resumed.tally.collisions, whole.tally.collisions);
  EXPECT_GT(leak_total(whole.tally, 1), 0u);  // the disc's leak takes particles
  for (std::size_t i = 0; i < whole.records.size(); ++i) ASSERT_EQ(resumed.records[i].t, whole.records[i].t) << i;
}

TEST(TableRun, TheRegimeSeesAListedLeakMove) {
  // a list of leaks keeps [leak]'s omega at 0: the regime once read that alone and called a run whose second leak
  // turns at omega = 2/3 "stationary"; and a scan's omega_value is the one leak's omega, none for several
  const std::string moving = "[[leaks]]\nwidth = \"0.02\"\n\n[[leaks]]\nwidth = \"0.02\"\nomega = \"2/3\"\n";
  const std::vector<std::string> small = {"ensemble.particles=2000", "run.t_max=400.0"};
  const RunSummary turning = summarise(parse_scene(moving, small), run_ensemble(parse_scene(moving, small), {}));
  EXPECT_NE(turning.tail_class.regime, "stationary");
  const Scene still = parse_scene(kTwoLeaks, small);
  EXPECT_EQ(summarise(still, run_ensemble(still, {})).tail_class.regime, "stationary");
  EXPECT_FALSE(any_leak_moves(still));
  EXPECT_TRUE(any_leak_moves(parse_scene(moving)));
  EXPECT_TRUE(any_leak_moves(parse_scene("", {"leak.omega=1/3"})));
}
