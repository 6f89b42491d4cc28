// Bit identity on four stadiums, not only d = 2, r = 1: every engine (the scalar core, the kernel at 4 and
// 8 lanes), 1 and 2 threads, with and without fast-forward, a resumed run and a split run give the same
// bits on d = 2, r = 1; d = 1, r = 1; d = 2, r = 2; d = 3, r = 0.7. The kernel once computed 1/L and r/L
// from the rounded perimeter (1 / fl(L)) where the core rounds them once from their exact values: for
// d = 1 and d = 2, r = 2 they differ by an ulp, and whole runs happened to agree: tests/test_kernel_probe.cpp
// looks where such an ulp decides. Whole runs are slow under the sanitizers: label slow.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "analysis/output/run_output.hpp"
#include "io/scene_file.hpp"
#include "kernel_widths.hpp"
#include "same_text.hpp"
#include "sim/engine/engine.hpp"
#include "sim/engine/kernel_adapter.hpp"
#include "sim/kernel/simd_engine.hpp"
#include "sim/tally/survival.hpp"
#include "stadium_sizes.hpp"

using namespace rotleak;
using test::kSizes;
using test::scene_of;
using test::Size;

namespace {

/// Everything a run's files are made of: survival.csv, the f_c table, the escape records, the collisions.
struct Bits {
  std::string survival, fc, escapes;
  std::uint64_t collisions = 0;
};

Bits bits_of(const Scene& s, const RunResult& r) {
  return {survival_csv(survival_curve(s, r.tally)), s.collision_density ? density_csv(s, r.tally) : "",
          s.escape_records ? escapes_csv(0, r.records) : "", r.tally.collisions};
}

void expect_same(const Bits& a, const Bits& b, const std::string& what) {
  EXPECT_TRUE(test::same_text(a.survival, b.survival)) << what;
  EXPECT_TRUE(test::same_text(a.fc, b.fc)) << what;
  EXPECT_TRUE(test::same_text(a.escapes, b.escapes)) << what;
  EXPECT_EQ(a.collisions, b.collisions) << what;
}

/// The scene run by the scalar core on one thread, then by every other engine, width and thread count,
/// and resumed (blocks 0 and 2, then block 1 from their tallies): all must give the first run's bits.
void check_every_engine(const Scene& s, const std::string& name) {
  RunOptions base;
  base.engine = Engine::scalar;
  base.threads = 1;
  const Bits ref = bits_of(s, run_ensemble(s, base));
  std::vector<std::pair<std::string, RunOptions>> others;
  RunOptions two = base;
  two.threads = 2;
  others.push_back({"scalar, 2 threads", two});
  for (int lanes : test::kernel_widths()) {
    RunOptions o = two;
    o.engine = Engine::simd;
    o.simd_lanes = lanes;
    others.push_back({"kernel, " + std::to_string(lanes) + " lanes", o});
  }
  for (const auto& [what, o] : others) expect_same(ref, bits_of(s, run_ensemble(s, o)), name + ": " + what);
  RunOptions first = others.back().second, rest = first;
  IntervalSet done_first = IntervalSet::range(0, 1);
  done_first.insert(2, 3);
  first.blocks = &done_first;
  const RunResult a = run_ensemble(s, first);
  const IntervalSet todo = IntervalSet::range(1, 2);
  rest.blocks = &todo;
  rest.start = &a.tally;
  rest.start_done = &done_first;
  rest.start_records = &a.records;
  expect_same(ref, bits_of(s, run_ensemble(s, rest)), name + ": resumed, " + others.back().first);
}

}  // namespace

class Stadiums : public ::testing::TestWithParam<Size> {};

TEST_P(Stadiums, StationaryAndMovingLeaksGiveTheSameBitsOnEveryEngine) {
  const Size z = GetParam();
  const std::string fc = "observe.collision_density={bins=64, windows=[[0,3000],[500,3000]]}";
  for (const char* omega : {"0", "2/3"})
    check_every_engine(scene_of(z, {"leak.omega=" + std::string(omega), "leak.width=0.02", "leak.start=0.3",
                                    "ensemble.particles=9000", "run.t_max=3000", "observe.escapes=true", fc}),
                       std::string(z.name) + ", omega " + omega);
  // slow leaks from the top edge: one that never reaches an arc before t_max (the kernel's first look then takes no
  // arc angle: KernelScene::arcs_reachable) and one that drifts onto the right arc on most stadiums
  for (const auto& [omega, start] : {std::pair{"1e-7", "0"}, std::pair{"2e-5", "0.05"}})
    check_every_engine(scene_of(z, {"leak.omega=" + std::string(omega), "leak.start=" + std::string(start),
                                    "ensemble.particles=9000", "run.t_max=3000", "observe.escapes=true", fc}),
                       std::string(z.name) + ", omega " + omega + " from " + start);
  // importance-sampled (weighted f_c) and fast-forwarded through the bouncing-ball stretches
  check_every_engine(scene_of(z, {"leak.omega=1e-4", "ensemble.sampling=mupo", "run.fast_forward=true",
                                  "ensemble.particles=9000", "run.t_max=3000", fc}),
                     std::string(z.name) + ", mupo, fast-forward");
}

TEST_P(Stadiums, SplitRunsGiveTheSameBitsOnEveryEngine) {
  const Size z = GetParam();
  check_every_engine(scene_of(z, {"ensemble.sampling=mupo", "run.splitting=true", "leak.omega=2/3", "run.t_max=3000",
                                  "run.fast_forward=true", "ensemble.particles=9000",
                                  "observe.collision_density={bins=40, windows=[[0,3000],[1500,3000]]}"}),
                     std::string(z.name) + ", split");
}

INSTANTIATE_TEST_SUITE_P(FourSizes, Stadiums, ::testing::ValuesIn(kSizes),
                         [](const ::testing::TestParamInfo<Size>& i) { return std::string(i.param.name); });
