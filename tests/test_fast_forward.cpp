// The fast-forward of bouncing-ball phases against stepping: the same escape collision and the same
// escape time, bit for bit, over many particles, long-lived MUPOs included.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "io/run_output.hpp"
#include "io/scene_file.hpp"
#include "names.hpp"
#include "same_text.hpp"
#include "sim/engine.hpp"
#include "sim/particle.hpp"

using namespace rotleak;

TEST(RepeatedSum, RunsReproduceRepeatedRoundedAdditions) {
  const std::uint64_t seed = 77;
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> ux(-1, 1), ud(-1e-3, 1e-3);
  for (int trial = 0; trial < 200; ++trial) {
    double x = ux(gen), d = ud(gen) * std::pow(10.0, -static_cast<double>(trial % 7));
    double stepped = x, jumped = x;
    long done = 0;
    const long total = 20000;
    while (done < total) {
      const SumRun<double> r = next_run(jumped, d, total - done);
      jumped = std::fma(static_cast<double>(r.len), r.inc, jumped);
      done += r.len;
    }
    for (long k = 0; k < total; ++k) stepped += d;
    EXPECT_EQ(stepped, jumped) << "x " << x << " d " << d << " seed " << seed;
  }
}

namespace {

Scene mupo_scene(const std::string& omega, const std::string& start) {
  return parse_scene("[leak]\nwidth = \"0.01\"\nstart = \"" + start + "\"\nomega = \"" + omega +
                     "\"\n[ensemble]\nparticles = 100000\nseed = 3\n[run]\nt_max = 20000\n[observe]\nsurvival_dt = 10\n"
                     "escapes = true\n[fit]\nkappa_window = [0, 300]\n");
}

}  // namespace

// Whole ensembles (10^5 particles to t = 2e4, ~160 of them in long MUPO tails at s_L = 0): the
// per-particle records of stepping and fast-forward, scalar and vectorised, are the same file.
class FastForward : public ::testing::TestWithParam<std::pair<const char*, const char*>> {};

TEST_P(FastForward, SameEscapeCollisionAndTimeAsStepping) {
  const Scene base = mupo_scene(GetParam().first, GetParam().second);
  RunOptions scalar;
  scalar.engine = Engine::scalar;
  const RunResult stepped = run_ensemble(base, scalar);
  Scene ff = base;
  ff.fast_forward = true;
  const RunResult jumped = run_ensemble(ff, scalar);
  EXPECT_TRUE(test::same_text(escapes_csv(0, stepped.records), escapes_csv(0, jumped.records)));
  EXPECT_EQ(stepped.tally.collisions, jumped.tally.collisions);  // skipped bounces count
  const RunResult vectorised = run_ensemble(ff, RunOptions{});
  EXPECT_TRUE(test::same_text(escapes_csv(0, stepped.records), escapes_csv(0, vectorised.records)))
      << to_string(vectorised.engine);
  std::size_t long_lived = 0;
  for (const auto& r : stepped.records) long_lived += r.t > 2000;
  EXPECT_GT(long_lived, 5u);
}

INSTANTIATE_TEST_SUITE_P(Leaks, FastForward,
                         ::testing::Values(std::pair{"0", "0"}, std::pair{"0", "0.5"}, std::pair{"0", "0.1022"},
                                           std::pair{"1", "0"}, std::pair{"2/3", "0.3"}),
                         rotleak::test::IndexedName());

// One orbit built to bounce: p = 1e-4 from x = -0.9 on the top edge, thousands of bounces in one jump.
TEST(FastForwardOrbit, LongBouncingPhaseInOneJump) {
  const Scene s = mupo_scene("0", "0.5");  // leak in the middle of the bottom edge
  Model<double> stepping(s.d, s.r, s.width, s.start, s.omega, 2e5), jumping = stepping;
  jumping.fast_forward = true;
  const Stadium<double>& st = stepping.stadium;
  ParticleState<double> ps;
  const BoundaryPoint<double> b = st.at(1 - 0.9 / st.perimeter());
  ps.q = b.q;
  ps.v = st.velocity(b, 1e-4);
  NoCollisionObserver<double> none;
  const ParticleEnd a = run_particle(stepping, ps, none), c = run_particle(jumping, ps, none);
  EXPECT_EQ(a.fate, c.fate);
  EXPECT_EQ(a.t, c.t);
  EXPECT_EQ(a.collisions, c.collisions);
  EXPECT_GT(a.collisions, 1000u);
}
