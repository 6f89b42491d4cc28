// Scene validation: every bad input is an InputError naming its key; overrides; round trip.
#include <gtest/gtest.h>

#include <cstdio>

#include "geometry/stadium.hpp"
#include "io/scene_file.hpp"
#include "leak/leak.hpp"
#include "names.hpp"
#include "scene_error.hpp"
#include "tests/paths.hpp"

using namespace rotleak;

TEST(Scene, DefaultsAndExactValues) {
  const Scene s = parse_scene("[leak]\nwidth = \"0.01\"\nomega = \"1008/1009\"\n");
  EXPECT_EQ(s.width.as_rational(), mpq_class(1, 100));
  EXPECT_EQ(s.omega.as_rational(), mpq_class(1008, 1009));
  EXPECT_EQ(s.particles, 1000000u);
  EXPECT_EQ(s.t_max, 20000);
  EXPECT_EQ(s.survival_bins(), 20000u);
  EXPECT_EQ(s.kappa_window.to, 300);
}

TEST(Scene, OverridesApplyBeforeValidation) {
  const Scene s = parse_scene("[leak]\nomega = \"0\"\n", {"leak.omega=2/3", "ensemble.particles=1234", "run.t_max=500",
                                                          "fit.kappa_window=[10, 200]", "ensemble.init=flow"});
  EXPECT_EQ(s.omega.as_rational(), mpq_class(2, 3));
  EXPECT_EQ(s.omega_text, "2/3");
  EXPECT_EQ(s.particles, 1234u);
  EXPECT_EQ(s.t_max, 500);
  EXPECT_EQ(s.kappa_window.from, 10);
  EXPECT_EQ(s.init, InitKind::flow);
  const Scene irr = parse_scene("", {"leak.omega=ln(19)"});
  EXPECT_FALSE(irr.omega.is_rational());
}

struct BadCase {
  const char* toml;
  const char* set;
  const char* key;  // must appear in the message
};

class SceneBadInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(SceneBadInput, IsRejectedWithItsKey) {
  const BadCase c = GetParam();
  std::vector<std::string> sets;
  if (c.set[0]) sets.push_back(c.set);
  const std::string msg = error_of(c.toml, sets);
  ASSERT_FALSE(msg.empty()) << "accepted: " << c.toml << " " << c.set;
  EXPECT_NE(msg.find(c.key), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line: " << msg;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, SceneBadInput,
    ::testing::Values(
        BadCase{"[leak]\nwdth = \"0.01\"\n", "", "leak.wdth"},  // unknown key
        BadCase{"[lek]\nwidth = \"0.01\"\n", "", "lek"},        // unknown section
        BadCase{"[leak]\nwidth = \"1\"\n", "", "leak.width"},   // width >= 1
        BadCase{"[leak]\nwidth = \"1.5\"\n", "", "leak.width"}, BadCase{"[leak]\nwidth = \"0\"\n", "", "leak.width"},
        BadCase{"[leak]\nwidth = \"-0.01\"\n", "", "leak.width"},
        BadCase{"[leak]\nwidth = 0.01\n", "", "leak.width"},            // float: not exact
        BadCase{"[leak]\nomega = \"two thirds\"\n", "", "leak.omega"},  // unparsable omega
        BadCase{"[leak]\nomega = \"nan\"\n", "", "leak.omega"}, BadCase{"[leak]\nomega = \"inf\"\n", "", "leak.omega"},
        BadCase{"[stadium]\nd = \"-2\"\n", "", "stadium.d"},  // negative size
        BadCase{"[stadium]\nr = \"0\"\n", "", "stadium.r"},
        BadCase{"[run]\nt_max = 0\n", "", "run.t_max"},  // t_max <= 0
        BadCase{"[run]\nt_max = -5\n", "", "run.t_max"}, BadCase{"[run]\nt_max = nan\n", "", "run.t_max"},
        BadCase{"[run]\nt_max = inf\n", "", "run.t_max"},
        BadCase{"[ensemble]\nparticles = 0\n", "", "ensemble.particles"},  // zero particles
        BadCase{"[ensemble]\nparticles = -3\n", "", "ensemble.particles"},
        BadCase{"[ensemble]\ninit = \"gaussian\"\n", "", "ensemble.init"},
        BadCase{"[observe]\nsurvival_dt = 0\n", "", "observe.survival_dt"},
        BadCase{"[observe]\ncollision_density = { bins = 0 }\n", "", "observe.collision_density.bins"},
        BadCase{"[observe]\ncollision_density = { windows = [[5, 1]] }\n", "", "observe.collision_density.windows"},
        BadCase{"[fit]\nkappa_window = [300, 0]\n", "", "fit.kappa_window"},
        BadCase{"[run]\ntier = \"quad\"\n", "", "run.tier"}, BadCase{"", "leak.omega=", "leak.omega"},
        BadCase{"", "leak.omgea=1", "leak.omgea"}, BadCase{"", "omega=1", "--set"}, BadCase{"[leak\n", "", "TOML"},
        // nonsense that was once accepted (a hang, an empty run, wrong physics)
        BadCase{"", "ensemble.creation_window=1e300", "ensemble.creation_window"},
        BadCase{"[observe]\ncollision_density = { windows = [[0, 30000]] }\n", "", "observe.collision_density.windows"},
        BadCase{"", "stadium.r=1e-300", "stadium.r"}, BadCase{"", "leak.omega=1e100000", "leak.omega"},
        BadCase{"", "stadium.d=pi-pi", "stadium.d"}, BadCase{"", "leak.start=1e100000+ln(2)", "leak.start"},
        // exact and positive, but 0 in double: d = 1e-400 ran as a circle
        BadCase{"", "stadium.d=1e-400", "stadium.d"}, BadCase{"", "leak.width=1e-400", "leak.width"},
        // sizes the doubles cannot resolve ran to a complete run with P = 1 (every flight of zero length) or as
        // a circle
        BadCase{"", "stadium.r=1e160", "stadium.r"}, BadCase{"", "stadium.r=1e300", "stadium.r"},
        BadCase{"", "stadium.d=1e-30", "stadium.d"},
        BadCase{"[stadium]\nd = \"1e101\"\nr = \"1e101\"\n", "", "stadium.d"},
        // an array was quoted over four lines
        BadCase{"", "fit.kappa_window=[0,1e300]", "fit.kappa_window = [0, 1e+300]"},
        // a section that is a value, then --set into it: a null dereference (fuzz_scene's first find)
        BadCase{"leak = \"2/3\"\n", "leak.start=2e30", "leak = \"2/3\": must be a table [leak]"}),
    rotleak::test::IndexedName());

// A default that fails its check given another key's value was reported through the key never given: a
// null dereference in the error path (t_max = 1 left the default creation window 4 outside [0, t_max]; the
// default split_every outside (0, t_max] or too fine for it). The message names the key and its default.
TEST(Scene, DefaultThatFailsItsCheckIsNamedNotDereferenced) {
  EXPECT_NE(error_of("", {"run.t_max=1"}).find("ensemble.creation_window = 4.0 (the default)"), std::string::npos)
      << error_of("", {"run.t_max=1"});
  const std::vector<std::string> split = {"run.splitting=true", "ensemble.sampling=mupo"};
  for (const char* t_max : {"run.t_max=100", "run.t_max=1e8"}) {
    std::vector<std::string> sets = split;
    sets.push_back(t_max);
    const std::string msg = error_of("", sets);
    EXPECT_EQ(msg.rfind("run.split_every = ", 0), 0u) << msg;
    EXPECT_NE(msg.find("(the default)"), std::string::npos) << msg;
  }
  for (const char* width : {"leak.width=1e-6", "leak.width=0.9"}) {
    std::vector<std::string> sets = split;
    sets.insert(sets.end(), {width, "run.t_max=1e6"});
    EXPECT_EQ(error_of("", sets).rfind("run.split_every = ", 0), 0u) << error_of("", sets);
  }
}

// [start_splitting]: each key refused with one line naming it, its value and what is allowed, at its edges; its
// parameters only with on = true; what it cannot run beside it named; and the scene as run read back the same.
TEST(Scene, StartSplittingKeysAreCheckedAtTheirEdges) {
  const std::string on = "start_splitting.on=true";
  const auto starts = [&](const std::vector<std::string>& more) {
    std::vector<std::string> sets = {on};
    sets.insert(sets.end(), more.begin(), more.end());
    return error_of("", sets);
  };
  EXPECT_EQ(starts({}), "");
  EXPECT_EQ(starts({"start_splitting.replicates=2", "start_splitting.factor=2", "start_splitting.moves=1",
                    "start_splitting.halvings=0", "start_splitting.window=0", "start_splitting.handover_bits=1",
                    "start_splitting.p=[0, 1]", "start_splitting.edges=true"}),
            "");
  EXPECT_EQ(starts({"start_splitting.halvings=100", "start_splitting.window=60", "start_splitting.handover_bits=52",
                    "start_splitting.deep_tier=\"float128\""}),
            "");
  for (const char* bad :
       {"start_splitting.replicates=1", "start_splitting.replicates=100001", "start_splitting.factor=1",
        "start_splitting.moves=0", "start_splitting.halvings=101", "start_splitting.window=61",
        "start_splitting.window=-1", "start_splitting.handover_bits=0", "start_splitting.handover_bits=53",
        "start_splitting.deep_tier=\"mpfr:100\"", "start_splitting.p=[0.5, 0.5]", "start_splitting.p=[-0.1, 0.5]",
        "start_splitting.p=[0, 1.5]", "start_splitting.edges=1"}) {
    const std::string key = std::string(bad).substr(0, std::string(bad).find('='));
    const std::string msg = starts({bad});
    EXPECT_EQ(msg.rfind(key + " = ", 0), 0u) << bad << ": " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
  EXPECT_EQ(error_of("", {"start_splitting.replicates=5"}).rfind("start_splitting.replicates = 5", 0), 0u);
  EXPECT_NE(error_of("", {"start_splitting.replicates=5"}).find("start_splitting.on = true only"), std::string::npos);
  for (const char* beside : {"run.splitting=true", "ensemble.sampling=mupo", "ensemble.init=flow", "run.tier=float",
                             "observe.escapes=true"}) {
    const std::string msg = starts({beside});
    EXPECT_EQ(msg.rfind("start_splitting.on = true", 0), 0u) << beside << ": " << msg;
  }
  EXPECT_EQ(error_of("[table]\nkind = \"circle\"\nradius = \"1\"\n", {on, "start_splitting.edges=true"})
                .rfind("start_splitting.edges = true", 0),
            0u);
  const Scene s = load_scene(std::string(rotleak::test::source_dir()) + "/data/scenes/stationary_sL_0.toml",
                             {on, "start_splitting.p=[1e-3, 1.06e-3]", "start_splitting.edges=true"});
  const Scene back = parse_scene(scene_to_toml(s), {}, "back");
  EXPECT_TRUE(back.start_splitting.on);
  EXPECT_EQ(back.start_splitting.p_lo, 1e-3);
  EXPECT_EQ(back.start_splitting.p_hi, 1.06e-3);
  EXPECT_TRUE(back.start_splitting.edges);
  EXPECT_EQ(back.start_splitting.replicates, 20);
  EXPECT_FALSE(parse_scene(scene_to_toml(load_scene(std::string(rotleak::test::source_dir()) +
                                                    "/data/scenes/stationary_sL_0.toml")),
                           {}, "back")
                   .start_splitting.on);
}

// The riding bands are a Birkhoff draw: with flow starts sampling_ride was accepted and ignored.
TEST(Scene, RidingBandsRefusedWithFlowStarts) {
  const std::vector<std::string> sets = {"ensemble.sampling=mupo", "ensemble.init=flow", "leak.omega=100/101",
                                         "ensemble.sampling_ride=0.5"};
  EXPECT_EQ(error_of("", sets).rfind("ensemble.sampling_ride = 0.5", 0), 0u) << error_of("", sets);
  EXPECT_NE(error_of("", sets).find("ensemble.init = \"birkhoff\""), std::string::npos) << error_of("", sets);
  EXPECT_EQ(error_of("", {"ensemble.sampling=mupo", "ensemble.init=flow", "ensemble.sampling_ride=0"}), "");
  EXPECT_EQ(error_of("", {"ensemble.sampling=mupo", "leak.omega=100/101", "ensemble.sampling_ride=0.5"}), "");
}

// t_max = 1e12 lies in run.t_max's range but makes 4.6e11 collisions a particle on the default stadium:
// refused as it should be, but the message blamed stadium.r, which the user never touched.
TEST(Scene, TooManyCollisionsBlameTheKeyGiven) {
  EXPECT_EQ(error_of("", {"run.t_max=1e12"}).rfind("run.t_max = ", 0), 0u) << error_of("", {"run.t_max=1e12"});
  EXPECT_EQ(error_of("", {"stadium.r=1e-9"}).rfind("stadium.r = ", 0), 0u) << error_of("", {"stadium.r=1e-9"});
  // t_max written in the scene file (as quickstart.toml writes it) is not what made the run too long
  const std::string file = "[run]\nt_max = 20000\n";
  EXPECT_EQ(error_of(file, {"stadium.r=1e-300"}).rfind("stadium.r = ", 0), 0u) << error_of(file, {"stadium.r=1e-300"});
  // the edges: the default stadium (mean free path 2.18) takes t_max up to 1e9 mean free paths and refuses more,
  // naming run.t_max; a smaller stadium refused at a t_max the default one would take names the stadium. Blaming
  // t_max above 1e9 time units instead of 1e9 default mean free paths (mutant
  // tests/mutants/blame-t-max-not-paths.patch, drawn by scripts/mutate.py) names run.t_max there.
  const double mfp = Stadium<double>(ExactReal::parse("2"), ExactReal::parse("1")).mean_free_path();
  char under[64], over[64];
  std::snprintf(under, sizeof under, "run.t_max=%.17g", 1e9 * mfp * (1 - 1e-9));
  std::snprintf(over, sizeof over, "run.t_max=%.17g", 1e9 * mfp * (1 + 1e-9));
  const std::string grid = "observe.survival_dt=1000";  // t_max / survival_dt bins at most 1e8
  EXPECT_EQ(error_of("", {under, grid}), "");
  EXPECT_EQ(error_of("", {over, grid}).rfind("run.t_max = ", 0), 0u) << error_of("", {over, grid});
  EXPECT_EQ(error_of("", {under, grid, "stadium.r=1/10"}).rfind("stadium.r = ", 0), 0u)
      << error_of("", {under, grid, "stadium.r=1/10"});
  EXPECT_EQ(error_of("", {over, grid, "stadium.r=1/10"}).rfind("run.t_max = ", 0), 0u)
      << error_of("", {over, grid, "stadium.r=1/10"});
}

// Counts through --set are read exactly, as --particles reads them (split_cap = 1e6 was refused as "must be
// an integer" while --particles 1e6 ran); in a file a float count is refused with the way to write it.
TEST(Scene, CountsReadExactlyThroughSet) {
  EXPECT_EQ(parse_scene("", {"ensemble.particles=2.5e5"}).particles, 250000u);
  EXPECT_EQ(parse_scene("", {"run.splitting=true", "ensemble.sampling=mupo", "run.split_cap=1e6"}).splitting.cap,
            1000000u);
  EXPECT_NE(error_of("[ensemble]\nparticles = 1e6\n").find("write 1000000"), std::string::npos);
  EXPECT_EQ(error_of("", {"ensemble.particles=1.5"}).rfind("ensemble.particles = ", 0), 0u);
}

// A number beyond double's range was "not a number" (1e400) or silently 0 (1e-400).
TEST(Scene, NumbersBeyondDoubleAreRefusedNotRounded) {
  const std::vector<std::string> split = {"run.splitting=true", "ensemble.sampling=mupo"};
  for (const char* bad : {"run.split_every=1e400", "run.split_delta=1e-400", "run.t_max=-1e999"}) {
    std::vector<std::string> sets = split;
    sets.push_back(bad);
    const std::string msg = error_of("", sets);
    EXPECT_NE(msg.find("beyond the range of a double"), std::string::npos) << bad << ": " << msg;
    EXPECT_EQ(msg.rfind(std::string(bad).substr(0, std::string(bad).find('=')), 0), 0u) << msg;
  }
  // the same in a scene file, where the TOML parser rounds silently
  const std::string file =
      "[run]\nsplitting = true\nsplit_delta = 1e-4_00\nsplit_every = 150.0\n[ensemble]\nsampling = "
      "\"mupo\"\n";
  EXPECT_EQ(error_of(file).rfind("run.split_delta = 1e-400: is beyond the range of a double", 0), 0u) << error_of(file);
  EXPECT_NE(error_of("[run]\nt_max = 1e999\n").find("line 2"), std::string::npos);  // the parser refuses overflow
  // .5 is not a TOML number but lies well within double's range: the key's own message, not "beyond the range"
  EXPECT_EQ(error_of("", {"run.t_max=.5"}).find("beyond the range"), std::string::npos)
      << error_of("", {"run.t_max=.5"});
  std::vector<std::string> zero = split;
  zero.push_back("run.split_delta=0e-400");  // zero written small is still zero
  EXPECT_EQ(parse_scene("", zero).splitting.delta, 0.0);
}

// An exact value quoted as in a scene file (--set 'leak.omega="2/3"') is the text inside the quotes.
TEST(Scene, QuotedExactValuesThroughSetAreTheTextInside) {
  EXPECT_EQ(parse_scene("", {"leak.omega=\"2/3\""}).omega_text, "2/3");
  EXPECT_EQ(parse_scene("", {"leak.omega=2/3"}).omega_text, "2/3");
}

// A large start is reduced modulo 1 exactly: 1e30 + 1/2 is the leak at 1/2 (it was once rounded
// with a 64-bit floor and no particle escaped).
TEST(Scene, LargeStartIsReducedExactly) {
  const Scene big = parse_scene("", {"leak.start=1e30+1/2"}), half = parse_scene("", {"leak.start=1/2"});
  const LeakSchedule<double> a(big.start, big.omega), b(half.start, half.omega);
  EXPECT_EQ(a.start(), b.start());
  const LeakSchedule<double> c(ExactReal::parse("1e30+ln(2)"), ExactReal::parse("0"));
  EXPECT_EQ(c.start(), round_exact<double>(ExactReal::parse("ln(2)")));
}

TEST(Scene, TomlRoundTrip) {
  const Scene a = parse_scene(
      "[leak]\nomega = \"2*ln(19)\"\nstart = \"0.1022\"\n[observe]\ncollision_density = { bins = 10, windows = "
      "[[0, 100], [50, 100]] }\n[run]\nt_max = 100\n[fit]\nkappa_window = [0, 50]\n");
  const Scene b = parse_scene(scene_to_toml(a));
  EXPECT_EQ(scene_to_toml(a), scene_to_toml(b));
  EXPECT_EQ(b.omega_text, "2*ln(19)");
  ASSERT_TRUE(b.collision_density.has_value());
  EXPECT_EQ(b.collision_density->windows.size(), 2u);
}
