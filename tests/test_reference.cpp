// The reference trajectories (data/trajectories) and their replay: the stored set reads back as
// written and is reproducible from cases.toml; the error model has teeth at each tier's own
// precision (a change far below double's resolution fails mpfr:256 and only it); a wrong fingerprint
// fails the bit check; an engine is held to the reference's escape.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>

#include "numeric/input.hpp"
#include "paths.hpp"
#include "scratch.hpp"
#include "verify/reference.hpp"

namespace rotleak {
namespace {

const std::string kDir = std::string(rotleak::test::source_dir()) + "/data/trajectories";

const ReferenceSet& stored() {
  static const ReferenceSet set = read_reference(kDir);
  return set;
}

const RefCase& find_case(const std::string& name) {
  for (const RefCase& c : stored().cases)
    if (c.name == name) return c;
  throw std::runtime_error("no case " + name);
}

TEST(Reference, ReadsBackWhatItWrites) {
  const test::ScratchDir scratch("rotleak_ref_");
  const auto& dir = scratch.path;
  write_reference(dir.string(), stored());
  const ReferenceSet again = read_reference(dir.string());
  ASSERT_EQ(again.cases.size(), stored().cases.size());
  for (std::size_t i = 0; i < again.cases.size(); ++i) {
    const RefCase &a = again.cases[i], &b = stored().cases[i];
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.scene_toml, b.scene_toml);
    EXPECT_EQ(a.draw.s, b.draw.s);
    EXPECT_EQ(a.draw.p, b.draw.p);
    EXPECT_EQ(a.fingerprints, b.fingerprints);
    ASSERT_EQ(a.steps.size(), b.steps.size());
    for (std::size_t k = 0; k < a.steps.size(); ++k) {
      EXPECT_EQ(a.steps[k].t, b.steps[k].t);
      EXPECT_EQ(a.steps[k].gain, b.steps[k].gain);
      EXPECT_EQ(a.steps[k].in_leak, b.steps[k].in_leak);
    }
  }
  std::filesystem::remove_all(dir);
}

TEST(Reference, IsReproducibleFromItsCaseList) {
  // Rebuild two stored cases (an ensemble member and a searched near-edge escape) from cases.toml:
  // the same particle, the same certified collisions, the same fingerprints.
  const auto specs = read_case_specs(kDir + "/cases.toml");
  for (const std::string name : {"omega_ln19_id0", "edge_escape_sL0.1022"}) {
    const auto spec = std::find_if(specs.begin(), specs.end(), [&](const CaseSpec& s) { return s.name == name; });
    ASSERT_NE(spec, specs.end()) << name;
    const RefCase built = build_case(*spec), &kept = find_case(name);
    EXPECT_EQ(built.id, kept.id) << name;
    ASSERT_EQ(built.steps.size(), kept.steps.size()) << name;
    for (std::size_t k = 0; k < built.steps.size(); ++k) {
      EXPECT_EQ(built.steps[k].piece, kept.steps[k].piece) << name << " collision " << k + 1;
      EXPECT_EQ(built.steps[k].in_leak, kept.steps[k].in_leak) << name << " collision " << k + 1;
      EXPECT_EQ(built.steps[k].t, kept.steps[k].t) << name << " collision " << k + 1;
    }
    EXPECT_EQ(built.fingerprints, kept.fingerprints) << name;
  }
}

TEST(Reference, CoversTheHardCases) {
  std::map<std::string, int> kinds;
  int escapes = 0;
  for (const RefCase& c : stored().cases) {
    ++kinds[c.kind];
    escapes += c.escape().has_value();
    EXPECT_GE(c.steps.size(), 100u) << c.name << ": certified through too few collisions";
  }
  for (const char* k : {"generic", "grazing", "junction", "corner", "bouncing_ball", "rotating", "near_edge_escape"})
    EXPECT_GE(kinds[k], 2) << k;
  EXPECT_GE(escapes, 10);
}

TEST(Verify, EveryTierFollowsTheReferenceWithinItsErrorModel) {
  for (const std::string& tier : reference_tiers())
    for (const RefCase& c : stored().cases) {
      const TierCheck r = check_tier(c, tier, true);
      EXPECT_TRUE(r.pass) << tier << " " << c.name << ": matched through " << r.matched_through << " of "
                          << r.must_reach << ", bits " << r.bits;
    }
}

// verify --tier mpfr:300 and mpfr:1024 printed worst = 6.9e10 and 6.1e228 beside "pass": the ratio left out
// the reference's own radius, which is what a tier finer than the reference is compared within. Worst is in
// units of the whole bound / 64, so a pass has worst <= 64 whatever the tier's precision.
TEST(Verify, WorstIsWithinTheBoundForTiersFinerThanTheReference) {
  for (const char* tier : {"double", "mpfr:300", "mpfr:1024"})
    for (const RefCase& c : stored().cases) {
      const TierCheck r = check_tier(c, tier, false);
      EXPECT_TRUE(r.pass) << tier << " " << c.name;
      EXPECT_LE(r.worst_ratio, 64.0) << tier << " " << c.name;
    }
}

TEST(Verify, AChangeBelowDoublesResolutionFailsOnlyTheFinerTiers) {
  // t at collision 3 moved by ~1e-55 (a digit far beyond double's 16 and within mpfr:256's 77):
  // mpfr:256's tolerance there is 64 * 2^-256 * W_3 ~ 1e-74, double's ~1e-13.
  RefCase c = find_case("sL0_id0");
  std::string& t = c.steps[2].t;
  const std::size_t digit = t.find('.') + 55;
  ASSERT_LT(digit, t.find('e'));
  t[digit] = t[digit] == '5' ? '6' : '5';
  EXPECT_FALSE(check_tier(c, "mpfr:256", false).pass);
  EXPECT_EQ(check_tier(c, "mpfr:256", false).matched_through, 2u);
  EXPECT_TRUE(check_tier(c, "double", false).pass);
  EXPECT_TRUE(check_tier(c, "dd", false).pass);
}

TEST(Verify, AWrongFingerprintFailsTheBitCheckOnly) {
  RefCase c = find_case("sL0_id1");
  auto& fp = c.fingerprints.at("double");
  fp.at(3).second ^= 1;  // collision 8
  const TierCheck strict = check_tier(c, "double", true);
  EXPECT_FALSE(strict.pass);
  EXPECT_FALSE(strict.bits_ok);
  EXPECT_NE(strict.bits.find("collision 8"), std::string::npos) << strict.bits;
  EXPECT_TRUE(check_tier(c, "double", false).pass);
}

TEST(Verify, AnEngineIsHeldToTheReferencesEscape) {
  const RefCase& kept = find_case("sL0_id0");
  ASSERT_TRUE(kept.escape());
  for (Engine e : {Engine::scalar, Engine::simd}) {
    if (e == Engine::simd && !check_engine(kept, e, false).checked) continue;  // no AVX2 here
    const EngineCheck ok = check_engine(kept, e, false);
    EXPECT_TRUE(ok.checked && ok.pass) << ok.expected << " / " << ok.got;
    // a reference that says the particle stays: the engine's escape now disagrees
    RefCase c = kept;
    c.steps[*kept.escape() - 1].in_leak = false;
    const EngineCheck bad = check_engine(c, e, false);
    EXPECT_TRUE(bad.checked);
    EXPECT_FALSE(bad.pass) << bad.expected << " / " << bad.got;
  }
}

TEST(Verify, IntervalsContainTheReference) {
  for (const RefCase& c : stored().cases) {
    const TierCheck r = check_tier(c, "mpfi:256", true);
    EXPECT_TRUE(r.pass) << c.name << ": " << r.stopped;
    EXPECT_GE(r.matched_through, r.must_reach) << c.name;
  }
  // a reference moved outside the enclosure is caught
  RefCase c = find_case("sL0_id2");
  std::string& p = c.steps[0].p;
  const std::size_t digit = p.find('.') + 40;
  p[digit] = p[digit] == '5' ? '6' : '5';
  EXPECT_FALSE(check_tier(c, "mpfi:256", true).pass);
}

TEST(CaseSpecs, BadEntriesNameTheCase) {
  const test::ScratchDir scratch("rotleak_cases_");
  const auto& dir = scratch.path;
  std::filesystem::create_directories(dir);
  auto attempt = [&](const std::string& body) {
    std::ofstream(dir / "cases.toml") << body;
    try {
      read_case_specs((dir / "cases.toml").string());
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string scene =
      "scene = \"" + std::string(rotleak::test::source_dir()) + "/data/scenes/quickstart.toml\"\n";
  EXPECT_NE(attempt("[[case]]\nname = \"a/b\"\n" + scene + "particle = 1\n").find("a/b"), std::string::npos);
  EXPECT_NE(attempt("[[case]]\nname = \"two\"\n" + scene + "particle = 1\nsearch = \"grazing\"\n").find("case two"),
            std::string::npos);
  EXPECT_NE(attempt("[[case]]\nname = \"odd\"\n" + scene + "search = \"spiral\"\n").find("spiral"), std::string::npos);
  EXPECT_NE(attempt("[[case]]\nname = \"noscene\"\nparticle = 1\n").find("noscene"), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace rotleak
