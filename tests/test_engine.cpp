// The ensemble engine: independence from the thread count, agreement with the reference loop,
// and the mean free path identity as a statistical check of the whole geometry.
#include <gtest/gtest.h>
#include <omp.h>

#include <chrono>
#include <cmath>

#include "analysis/output/run_output.hpp"
#include "io/scene_file.hpp"
#include "names.hpp"
#include "paths.hpp"
#include "same_text.hpp"
#include "sim/engine/engine.hpp"
#include "sim/kernel/simd_engine.hpp"
#include "sim/model/particle.hpp"

using namespace rotleak;

namespace {

Scene small_scene(const std::string& omega, const std::string& init = "birkhoff") {
  return parse_scene(
      "[leak]\nwidth = \"0.02\"\nstart = \"0.1\"\nomega = \"" + omega +
      "\"\n[ensemble]\nparticles = 20000\nseed = 42\ninit = \"" + init +
      "\"\n[run]\nt_max = 3000\n[observe]\nsurvival_dt = 0.5\nescapes = true\n"
      "collision_density = { bins = 64, windows = [[0, 3000], [100, 3000]] }\n[fit]\nkappa_window = [0, 200]\n");
}

}  // namespace

class EngineThreads : public ::testing::TestWithParam<std::pair<const char*, const char*>> {};

TEST_P(EngineThreads, OneAndTwoThreadsGiveIdenticalFiles) {
  const Scene scene = small_scene(GetParam().first, GetParam().second);
  RunOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const RunResult a = run_ensemble(scene, one), b = run_ensemble(scene, two);
  EXPECT_EQ(a.threads, 1);
  EXPECT_EQ(b.threads, 2);
  EXPECT_TRUE(
      test::same_text(survival_csv(survival_curve(scene, a.tally)), survival_csv(survival_curve(scene, b.tally))));
  EXPECT_TRUE(test::same_text(density_csv(scene, a.tally), density_csv(scene, b.tally)));
  EXPECT_TRUE(test::same_text(escapes_csv(0, a.records), escapes_csv(0, b.records)));
  EXPECT_EQ(a.tally.collisions, b.tally.collisions);
  EXPECT_EQ(a.tally.escaped + a.tally.survived + a.tally.stuck, scene.particles);
  EXPECT_GT(a.tally.escaped, 0u);
}

INSTANTIATE_TEST_SUITE_P(Leaks, EngineThreads,
                         ::testing::Values(std::pair{"0", "birkhoff"}, std::pair{"2/3", "birkhoff"},
                                           std::pair{"ln(19)", "flow"}),
                         rotleak::test::IndexedName());

// A failed bit-identity check between two large files says where they part, in a line, at once: two
// 5 MB texts that differ in line 100000 of 200000.
TEST(SameText, ABigDifferenceIsReportedByItsFirstLineAtOnce) {
  std::string a;
  for (int i = 0; i < 200000; ++i) a += std::to_string(i) + ",0.123456789012345,0.000123456789\n";
  std::string b = a;
  b[b.find("\n100000,") + 8] = '9';
  const auto t0 = std::chrono::steady_clock::now();
  const ::testing::AssertionResult r = test::same_text(a, b);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_FALSE(r);
  const std::string why = r.message();
  EXPECT_NE(why.find("from line 100001: \"100000,0.123456789012345,0.000123456789\" vs \"100000,9.123"),
            std::string::npos)
      << why;
  EXPECT_LT(why.size(), 600u) << why;
  EXPECT_LT(seconds, 1.0);  // a linear scan; the diff GoogleTest would build took minutes and gigabytes
  EXPECT_TRUE(test::same_text(a, a));
}

TEST(Engine, MatchesTheReferenceLoopParticleByParticle) {
  const Scene scene = small_scene("1008/1009");
  RunOptions opt;
  opt.threads = 2;
  const RunResult res = run_ensemble(scene, opt);
  const Model<double> model = Model<double>::from(scene);
  const InitialConditions ic(scene.seed, scene.init, scene.creation_window, 1.0, 1.0);
  NoCollisionObserver<double> none;
  std::uint64_t total = 0;
  for (std::uint64_t id = 0; id < scene.particles; ++id) {
    const ParticleEnd e = run_particle(model, initial_state(model.stadium, ic.draw(id)), none);
    total += e.collisions;
    if (id < 500) {
      EXPECT_EQ(e.fate, res.records[id].fate);
      EXPECT_EQ(e.t, res.records[id].t);
      EXPECT_EQ(e.collisions, res.records[id].collisions);
    }
  }
  EXPECT_EQ(total, res.tally.collisions);
  const auto alive = survivors_on_grid(scene, res.tally);
  EXPECT_EQ(alive.back(), res.tally.survived + res.tally.stuck);
}

// Birkhoff-uniform (s, p) is the invariant measure of the billiard map, so the flight from a
// uniform draw has mean pi * Area / Perimeter exactly. Error model: i.i.d. flights, CLT; the test
// allows 4.5 standard errors (false alarm rate ~ 7e-6).
TEST(Engine, MeanFreePathIsPiAreaOverPerimeter) {
  const Stadium<double> st(ExactReal::parse("2"), ExactReal::parse("1"));
  const InitialConditions ic(2024, InitKind::birkhoff, 4, 1, 1);
  const int m = 1000000;
  double sum = 0, sum2 = 0;
  for (int i = 0; i < m; ++i) {
    const ParticleState<double> ps = initial_state(st, ic.draw(static_cast<std::uint64_t>(i)));
    const double len = st.next_hit(ps.q, ps.v).t;
    sum += len;
    sum2 += len * len;
  }
  const double mean = sum / m, var = sum2 / m - mean * mean, se = std::sqrt(var / m);
  const double expected = M_PI * (4 + M_PI) / (4 + 2 * M_PI);
  EXPECT_NEAR(mean, expected, 4.5 * se) << "seed 2024, " << m << " flights";
  EXPECT_LT(se / expected, 1e-3);  // the test has teeth: 0.1% resolution
}

// Flow initial conditions are uniform in the stadium: the share inside the rectangle is
// 2rd / Area (binomial, 4.5 sigma).
TEST(Engine, FlowInitIsUniformInTheStadium) {
  const InitialConditions ic(5, InitKind::flow, 4, 1, 1);
  const int m = 200000;
  int in_rect = 0;
  for (int i = 0; i < m; ++i) {
    const InitialDraw d = ic.draw(static_cast<std::uint64_t>(i));
    ASSERT_TRUE(std::abs(d.x) <= 1 || (std::abs(d.x) - 1) * (std::abs(d.x) - 1) + d.y * d.y < 1);
    in_rect += std::abs(d.x) <= 1;
  }
  const double p = 4 / (4 + M_PI);
  EXPECT_NEAR(static_cast<double>(in_rect) / m, p, 4.5 * std::sqrt(p * (1 - p) / m));
}

TEST(Engine, InitialDrawsDependOnlyOnSeedAndId) {
  const InitialConditions a(9, InitKind::birkhoff, 4, 1, 1), b(9, InitKind::birkhoff, 4, 1, 1),
      c(10, InitKind::birkhoff, 4, 1, 1);
  for (std::uint64_t id : {0ull, 1ull, 123456789ull, 1ull << 40}) {
    EXPECT_EQ(a.draw(id).s, b.draw(id).s);
    EXPECT_EQ(a.draw(id).p, b.draw(id).p);
    EXPECT_NE(a.draw(id).s, c.draw(id).s);
    EXPECT_GT(a.draw(id).p, -1.0);
    EXPECT_LT(a.draw(id).p, 1.0);
    EXPECT_GE(a.draw(id).tau, 0.0);
    EXPECT_LE(a.draw(id).tau, 4.0);
  }
}

// The scene's tier runs the same ensemble through the same core at another precision. Individual
// chaotic trajectories part ways after some tens of collisions, the statistics must not: the number
// escaped by t = 300 agrees with double within 5 binomial standard errors of one sample (conservative:
// the two runs share their initial conditions, so their difference is smaller than that of
// independent samples).
TEST(Engine, OtherTiersGiveTheSameStatistics) {
  Scene base = small_scene("0");
  base.escape_records = false;
  auto escaped_by = [](const Scene& s, double t) {
    const RunResult r = run_ensemble(s, RunOptions{});
    const auto alive = survivors_on_grid(s, r.tally);
    return static_cast<double>(s.particles - alive[static_cast<std::size_t>(t / s.survival_dt)]);
  };
  const double n = static_cast<double>(base.particles), ref = escaped_by(base, 300);
  const double p = ref / n, sigma = std::sqrt(n * p * (1 - p));
  for (Tier tier : {Tier::float_, Tier::long_double}) {
    Scene s = base;
    s.tier = tier;
    EXPECT_NEAR(escaped_by(s, 300), ref, 5 * sigma) << to_string(tier);
  }
}

// A run is checked in one place, plan_run: a tier of auto leaves the engine open until with_tier settles
// it (a kernel that cannot run the chosen tier is an InputError naming --engine then, not later in the
// engine), and a shard's plan keeps what was checked.
TEST(Plan, AutoTierIsSettledOnceChosen) {
  Scene scene = small_scene("0");
  scene.tier = Tier::auto_;
  RunOptions o;
  o.engine = Engine::simd;
  const RunPlan plan = plan_run(scene, o);
  EXPECT_EQ(plan.engine(), Engine::automatic);
  EXPECT_THROW(run_ensemble(plan, o), std::logic_error);  // the tier must be chosen first
  try {
    (void)plan.with_tier(Tier::float_);
    FAIL() << "the kernel runs the double tier only";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "--engine");
  }
  if (!simd::available()) return;
  const RunPlan settled = plan.with_tier(Tier::double_);
  EXPECT_EQ(settled.engine(), Engine::simd);
  EXPECT_GT(settled.simd_lanes(), 0);
  EXPECT_EQ(settled.with_tier(Tier::float_).scene().tier, Tier::double_);  // settled once: kept
}

TEST(Plan, AShardsPlanRunsItsIdsOnTheSameStadium) {
  const Scene scene = small_scene("2/3");
  RunOptions o;
  o.engine = Engine::scalar;
  const RunPlan plan = plan_run(scene, o);
  const RunPlan part = plan.with_particles(5000);
  EXPECT_EQ(part.scene().particles, 5000u);
  EXPECT_EQ(&part.stadium(), &plan.stadium());  // built once, shared
  // the shard's ids [5000, 10000) give the whole run's records of those ids
  RunOptions shard = o;
  shard.first_id = 5000;
  const RunResult whole = run_ensemble(plan, o), some = run_ensemble(part, shard);
  ASSERT_EQ(some.records.size(), 5000u);
  for (std::size_t i = 0; i < some.records.size(); ++i) {
    EXPECT_EQ(some.records[i].t, whole.records[5000 + i].t) << i;
    EXPECT_EQ(some.records[i].collisions, whole.records[5000 + i].collisions) << i;
  }
}

TEST(Plan, ASplitRunIsRefusedOutsideTheDoubleTier) {
  Scene scene = load_scene(std::string(rotleak::test::source_dir()) + "/data/scenes/stationary_sL_0.toml",
                           {"ensemble.sampling=mupo", "run.splitting=true", "ensemble.particles=1000"});
  scene.tier = Tier::long_double;
  EXPECT_THROW(plan_run(scene, RunOptions{}), std::invalid_argument);
  scene.tier = Tier::auto_;
  const RunPlan plan = plan_run(scene, RunOptions{});
  EXPECT_THROW((void)plan.with_tier(Tier::float_), std::invalid_argument);
}
