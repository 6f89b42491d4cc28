// Scene validation: every bad input is an InputError naming its key; overrides; round trip.
#include <gtest/gtest.h>

#include "io/scene_file.hpp"
#include "leak/leak.hpp"
#include "names.hpp"

using namespace rotleak;

namespace {

std::string error_of(const std::string& toml, const std::vector<std::string>& sets = {}) {
  try {
    parse_scene(toml, sets);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

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
        BadCase{"", "stadium.d=pi-pi", "stadium.d"}, BadCase{"", "leak.start=1e100000+ln(2)", "leak.start"}),
    rotleak::test::IndexedName());

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
