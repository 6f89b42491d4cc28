// Bit identity on four stadiums, not only d = 2, r = 1: every engine (the scalar core, the kernel at 4 and
// 8 lanes), 1 and 2 threads, with and without fast-forward, a resumed run and a split run give the same
// bits on d = 2, r = 1; d = 1, r = 1; d = 2, r = 2; d = 3, r = 0.7. The kernel once computed 1/L and r/L
// from the rounded perimeter (1 / fl(L)) where the core rounds them once from their exact values: for
// d = 1 and d = 2, r = 2 they differ by an ulp, and whole runs happened to agree. The probe test below
// looks where such an ulp decides: at points within a few ulps of every f_c bin edge and of the moving
// leak's two ends, the kernel's bin and leak test must be the core's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "io/run_output.hpp"
#include "io/scene_file.hpp"
#include "kernel_widths.hpp"
#include "same_text.hpp"
#include "sim/engine/engine.hpp"
#include "sim/engine/kernel_adapter.hpp"
#include "sim/kernel/simd_engine.hpp"
#include "sim/tally/survival.hpp"

using namespace rotleak;

namespace {

struct Size {
  const char* d;
  const char* r;
  const char* name;
};
const Size kSizes[] = {{"2", "1", "d2_r1"}, {"1", "1", "d1_r1"}, {"2", "2", "d2_r2"}, {"3", "0.7", "d3_r07"}};

Scene scene_of(const Size& z, std::vector<std::string> sets) {
  sets.push_back(std::string("stadium.d=") + z.d);
  sets.push_back(std::string("stadium.r=") + z.r);
  return load_scene(std::string(ROTLEAK_SOURCE_DIR) + "/data/scenes/stationary_sL_0.toml", sets);
}

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

namespace {

/// The core's own s of an arc point, as the kernel asks it (simd::Exact::s_of), with the stadium as ctx.
double core_s(void* ctx, int piece, double x, double y) {
  return static_cast<const Stadium<double>*>(ctx)->s_of(static_cast<Piece>(piece), {x, y});
}
void no_density(void*, const simd::DensityHit*, int) {}

/// Points on the boundary around s: the point at() places there and its neighbours a few ulps away (in x
/// on a straight edge, in x and y on an arc), each at time t.
void points_near(const Stadium<double>& st, double s, double t, std::vector<simd::Probe>& out) {
  s -= std::floor(s);
  const BoundaryPoint<double> b = st.at(s);
  const bool straight = b.piece == Piece::top || b.piece == Piece::bottom;
  for (int k = -4; k <= 4; ++k) {
    double x = b.q.x, y = b.q.y;
    for (int i = 0; i < std::abs(k); ++i) {
      x = std::nextafter(x, k > 0 ? 1e300 : -1e300);
      if (!straight) y = std::nextafter(y, k > 0 ? 1e300 : -1e300);
    }
    if (straight && std::abs(x) > st.half_d()) continue;  // off the edge
    out.push_back({static_cast<int>(b.piece), x, y, t});
  }
}

}  // namespace

TEST_P(Stadiums, KernelDecidesAsTheCoreWithinAnUlpOfBinEdgesAndLeakEnds) {
  if (!simd::available()) GTEST_SKIP() << "no AVX2+FMA on this CPU";
  const Size z = GetParam();
  const Scene s = scene_of(z, {"leak.omega=2/3", "leak.width=0.02", "leak.start=0.3"});
  const Model<double> model = Model<double>::from(s);
  const Stadium<double>& st = model.stadium;
  constexpr int kBins = 1000;
  std::vector<simd::Probe> points;
  for (int k = 0; k < kBins; ++k) points_near(st, static_cast<double>(k) / kBins, 0, points);
  for (int i = 0; i < 2000; ++i) {  // the leak's two ends at 2000 times
    const double t = 0.37 * i;
    const double c = model.leak.schedule().phase(t), hw = model.leak.half_width();
    points_near(st, c - hw, t, points);
    points_near(st, c + hw, t, points);
  }
  std::size_t near_bin_edge = 0;
  for (const simd::Probe& p : points) {
    const double sb = st.s_of(static_cast<Piece>(p.piece), {p.x, p.y}) * kBins;
    near_bin_edge += std::abs(sb - std::nearbyint(sb)) < 1e-12;
  }
  EXPECT_GT(near_bin_edge, static_cast<std::size_t>(kBins));  // the probe does look at the edges
  const simd::Exact exact{core_s, no_density};
  for (int lanes : test::kernel_widths()) {
    simd::KernelScene ks = simd_scene(model);
    ks.lanes = lanes;
    ks.bins = kBins;
    std::vector<simd::ProbeResult> got(points.size());
    simd::probe(ks, points.data(), got.data(), points.size(), const_cast<Stadium<double>*>(&st), exact);
    std::size_t bins_differ = 0, leak_differs = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const simd::Probe& p = points[i];
      const Piece piece = static_cast<Piece>(p.piece);
      const double bin = formula::density_bin(st.s_of(piece, {p.x, p.y}), static_cast<double>(kBins));
      bins_differ += got[i].bin != bin;
      leak_differs += got[i].in_leak != model.leak.hit(piece, {p.x, p.y}, p.t);
    }
    EXPECT_EQ(bins_differ, 0u) << z.name << ", " << lanes << " lanes, of " << points.size() << " points";
    EXPECT_EQ(leak_differs, 0u) << z.name << ", " << lanes << " lanes, of " << points.size() << " points";
  }
}

INSTANTIATE_TEST_SUITE_P(FourSizes, Stadiums, ::testing::ValuesIn(kSizes),
                         [](const ::testing::TestParamInfo<Size>& i) { return std::string(i.param.name); });
