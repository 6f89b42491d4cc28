// The vectorised engine against the scalar core: bit-identical, per particle and in every tally, for
// stationary and rotating leaks, with and without f_c, weights and fast-forward (the vector atan2's
// near-edge cases are settled by the core), and statistically equivalent (two-sample
// Kolmogorov-Smirnov on escape times) as a second, independent check.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "analysis/fits.hpp"
#include "analysis/output/run_output.hpp"
#include "io/scene_file.hpp"
#include "kernel_widths.hpp"
#include "names.hpp"
#include "numeric/input.hpp"
#include "same_text.hpp"
#include "sim/engine/engine.hpp"
#include "sim/engine/kernel_adapter.hpp"
#include "sim/kernel/simd_engine.hpp"

using namespace rotleak;

namespace {

Scene scene(const std::string& start, const std::string& omega, std::uint64_t n = 20000,
            const std::string& width = "0.02") {
  return parse_scene("[leak]\nwidth = \"" + width + "\"\nstart = \"" + start + "\"\nomega = \"" + omega +
                     "\"\n[ensemble]\nparticles = " + std::to_string(n) +
                     "\nseed = 5\n[run]\nt_max = 3000\n[observe]\nescapes = true\n[fit]\nkappa_window = [0, 200]\n");
}

RunResult run(const Scene& s, Engine e, int threads = 2, int lanes = 0) {
  RunOptions o;
  o.engine = e;
  o.threads = threads;
  o.simd_lanes = lanes;
  return run_ensemble(s, o);
}

// Two-sample KS: the largest gap between the two empirical escape-time distributions, against the
// alpha = 1e-3 critical value c sqrt((n + m) / (n m)), c = sqrt(-ln(alpha / 2) / 2) = 1.95.
double ks_distance(std::vector<double> a, std::vector<double> b) {
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  std::size_t i = 0, j = 0;
  double d = 0;
  while (i < a.size() && j < b.size()) {
    const double x = std::min(a[i], b[j]);
    while (i < a.size() && a[i] <= x) ++i;
    while (j < b.size() && b[j] <= x) ++j;
    d = std::max(d, std::abs(static_cast<double>(i) / static_cast<double>(a.size()) -
                             static_cast<double>(j) / static_cast<double>(b.size())));
  }
  return d;
}

std::vector<double> escape_times(const RunResult& r) {
  std::vector<double> t;
  for (const auto& e : r.records) t.push_back(e.fate == Fate::escaped ? e.t : 1e300);
  return t;
}

}  // namespace

class SimdStationary : public ::testing::TestWithParam<const char*> {};

TEST_P(SimdStationary, BitIdenticalToTheScalarCore) {
  if (!simd::available()) GTEST_SKIP() << "no AVX2+FMA on this CPU";
  const Scene s = scene(GetParam(), "0");
  const RunResult a = run(s, Engine::scalar);
  for (int lanes : test::kernel_widths()) {
    const RunResult b = run(s, Engine::simd, 2, lanes);
    EXPECT_EQ(b.engine, Engine::simd);
    EXPECT_EQ(b.simd_lanes, lanes);
    EXPECT_TRUE(test::same_text(escapes_csv(0, a.records), escapes_csv(0, b.records))) << lanes << " lanes";
    EXPECT_TRUE(test::same_text(survival_csv(survival_curve(s, a.tally)), survival_csv(survival_curve(s, b.tally))))
        << lanes;
    EXPECT_EQ(a.tally.collisions, b.tally.collisions) << lanes;
  }
}

INSTANTIATE_TEST_SUITE_P(LeakPositions, SimdStationary,
                         ::testing::Values("0", "0.1022", "0.1024", "0.25", "0.5", "0.95"),
                         rotleak::test::IndexedName());

TEST(Simd, OneAndTwoThreadsGiveIdenticalFiles) {
  if (!simd::available()) GTEST_SKIP() << "no AVX2+FMA on this CPU";
  const Scene s = scene("0", "0");
  const RunResult a = run(s, Engine::simd, 1), b = run(s, Engine::simd, 2);
  EXPECT_TRUE(test::same_text(escapes_csv(0, a.records), escapes_csv(0, b.records)));
}

// A moving leak computes atan2 (SLEEF's in the kernel, formula::atan2_of in the core); lanes within 1e-12 of a
// leak end ask the core, so the runs are the same particle by particle. The escape-time
// distributions are compared too (KS, alpha = 1e-3), and kappa.
TEST(Simd, RotatingLeaksBitIdenticalToTheScalarCore) {
  if (!simd::available()) GTEST_SKIP() << "no AVX2+FMA on this CPU";
  for (const char* omega : {"2/3", "ln(19)", "1008/1009", "1e-4"}) {
    const Scene s = scene("0.3", omega, 40000);
    const RunResult a = run(s, Engine::scalar);
    for (int lanes : test::kernel_widths()) {
      const RunResult c = run(s, Engine::simd, 2, lanes);
      EXPECT_TRUE(test::same_text(escapes_csv(0, a.records), escapes_csv(0, c.records)))
          << omega << ", " << lanes << " lanes";
      EXPECT_EQ(a.tally.collisions, c.tally.collisions) << omega << ", " << lanes << " lanes";
    }
    const RunResult b = run(s, Engine::simd);
    EXPECT_TRUE(test::same_text(escapes_csv(0, a.records), escapes_csv(0, b.records))) << omega;
    EXPECT_EQ(a.tally.collisions, b.tally.collisions) << omega;
    const auto ta = escape_times(a), tb = escape_times(b);
    const double n = static_cast<double>(ta.size());
    EXPECT_LT(ks_distance(ta, tb), 1.95 * std::sqrt(2 / n)) << omega;
    const SurvivalCurve ca = survival_curve(s, a.tally);
    const SurvivalCurve cb = survival_curve(s, b.tally);
    EXPECT_TRUE(test::same_text(survival_csv(ca), survival_csv(cb))) << omega;
    const KappaFit ka = fit_kappa(ca, 0, 200), kb = fit_kappa(cb, 0, 200);
    EXPECT_EQ(ka.value, kb.value) << omega;
  }
}

// f_c in the kernel: every collision inside a window binned by s, arc hits near a bin edge binned by
// the core; with importance-sampling weights and fast-forward (whose skipped bounces f_c must see,
// as stepping shows them), on a stationary and a rotating leak.
TEST(Simd, CollisionDensityBitIdenticalToTheScalarCore) {
  if (!simd::available()) GTEST_SKIP() << "no AVX2+FMA on this CPU";
  for (const char* omega : {"0", "2/3", "70/71"}) {
    for (const bool weighted : {false, true}) {
      Scene s = scene("0", omega, 20000, "0.01");
      s.collision_density = CollisionDensitySpec{250, {{0, 3000}, {500, 3000}, {1000, 2000}}};
      s.fast_forward = weighted;
      if (weighted) s.sampling.kind = SamplingKind::mupo;
      const RunResult a = run(s, Engine::scalar), b = run(s, Engine::simd);
      ASSERT_EQ(b.engine, Engine::simd);
      for (int lanes : test::kernel_widths()) {
        const RunResult c = run(s, Engine::simd, 2, lanes);
        EXPECT_EQ(a.tally.collision_density, c.tally.collision_density) << omega << ", " << lanes << " lanes";
        EXPECT_TRUE(a.tally.collision_density_w == c.tally.collision_density_w) << omega << ", " << lanes;
      }
      EXPECT_TRUE(test::same_text(density_csv(s, a.tally), density_csv(s, b.tally)))
          << omega << " weighted " << weighted;
      EXPECT_EQ(a.tally.collision_density, b.tally.collision_density) << omega;
      EXPECT_TRUE(a.tally.collision_density_w == b.tally.collision_density_w) << omega;
      std::uint64_t counted = 0;
      for (std::size_t i = 0; i < 250; ++i) counted += b.tally.collision_density[i];  // the window [0, t_max]
      EXPECT_EQ(counted, b.tally.collisions) << omega << ": every collision is in the first window";
    }
  }
}

// Windows with a gap between them (times in the gap are counted nowhere) and windows that start late.
TEST(Simd, CollisionDensityWithGapsBitIdentical) {
  if (!simd::available()) GTEST_SKIP() << "no AVX2+FMA on this CPU";
  for (const bool weighted : {false, true}) {
    Scene s = scene("0", "2/3", 20000, "0.01");
    s.collision_density = CollisionDensitySpec{200, {{100, 400}, {1000, 2000}, {1500, 1600}}};
    if (weighted) s.sampling.kind = SamplingKind::mupo;
    const RunResult a = run(s, Engine::scalar);
    for (int lanes : test::kernel_widths()) {
      const RunResult b = run(s, Engine::simd, 2, lanes);
      EXPECT_EQ(a.tally.collision_density, b.tally.collision_density) << lanes << " lanes, weighted " << weighted;
      EXPECT_TRUE(a.tally.collision_density_w == b.tally.collision_density_w) << lanes << " lanes";
    }
    std::uint64_t first = 0;
    for (std::size_t i = 0; i < 200; ++i) first += a.tally.collision_density[i];
    EXPECT_GT(first, 0u);
    EXPECT_LT(first, a.tally.collisions);  // the gap's collisions are not in the first window
  }
}

// The kernel counts each f_c collision once, in its time cell, and the engine adds the cell to every
// window that holds its times. Checked here at the edges themselves (from and to are inclusive),
// with windows that share edges, nest, touch and repeat, at the times a collision is counted at (within
// the windows' span: the kernel's cell leaves out the edges the span decides).
TEST(Simd, TimeCellsGiveEachTimeItsWindows) {
  const std::vector<std::vector<std::pair<double, double>>> sets = {{{0, 20000}, {2000, 20000}},
                                                                    {{0, 1000}, {1000, 2000}, {500, 1500}, {0, 2000}},
                                                                    {{10, 20}, {10, 20}, {5, 10}, {20, 30}, {0, 40}},
                                                                    {{0, 3000}, {500, 3000}, {1000, 2000}}};
  for (const auto& set : sets) {
    const int n = static_cast<int>(set.size());
    std::vector<double> from, to, times;
    for (const auto& [a, b] : set) {
      from.push_back(a), to.push_back(b);
      for (double x : {a, b}) times.insert(times.end(), {std::nextafter(x, -1e9), x, std::nextafter(x, 1e9), x + 0.5});
    }
    std::vector<unsigned> cells(static_cast<std::size_t>(2 * n + 1));
    density_cells(n, from.data(), to.data(), cells.data());
    for (int lanes : {4, 8}) {
      if (!simd::lanes_available(lanes)) {
        std::printf("[ skipped  ] the %d-lane kernel: this CPU does not run it\n", lanes);
        continue;
      }
      simd::KernelScene ks{};  // the kernel's own cell of each time
      ks.lanes = lanes;
      set_density_windows(ks, n, from.data(), to.data());
      std::vector<double> cell(times.size());
      simd::time_cells(ks, times.data(), cell.data(), times.size());
      for (std::size_t i = 0; i < times.size(); ++i) {
        const double t = times[i];
        if (t < ks.win_span_from || t > ks.win_span_to) continue;  // never counted: no cell asked for
        unsigned want = 0;
        for (int w = 0; w < n; ++w)
          if (t >= from[static_cast<std::size_t>(w)] && t <= to[static_cast<std::size_t>(w)]) want |= 1u << w;
        ASSERT_GE(cell[i], 0.0);
        ASSERT_LE(cell[i], 2.0 * n);
        EXPECT_EQ(cells[static_cast<std::size_t>(cell[i])], want)
            << "t = " << t << ", " << n << " windows, " << lanes << " lanes";
      }
    }
  }
}

// bench_scale's ceiling (simd::flights_only: the kernel's next hit and reflection alone) flies the
// core's flights: the sum of each lane's flight times over 2000 collisions, summed over the lanes in
// order, equals the scalar core's (Stadium<double>::next_hit and reflect) bit for bit, for both widths.
TEST(Simd, FlightsOnlyFollowTheCore) {
  const Scene s = scene("0", "0", 20000, "0.01");
  const Model<double> model = Model<double>::from(s);
  const InitialConditions ic = initial_conditions(s);
  constexpr std::uint64_t kSteps = 2000;
  for (int lanes : {4, 8}) {
    if (!simd::lanes_available(lanes)) {
      std::printf("[ skipped  ] the %d-lane kernel: this CPU does not run it\n", lanes);
      continue;
    }
    simd::KernelScene ks = simd_scene(model);
    ks.lanes = lanes;
    std::vector<simd::Start> starts;
    double want = 0;
    for (int k = 0; k < simd::pack_lanes(lanes); ++k) {
      const ParticleState<double> ps = initial_state(model.stadium, ic.draw(static_cast<std::uint64_t>(k)));
      starts.push_back({ps.q.x, ps.q.y, ps.v.x, ps.v.y, 0, 0, 1});
      Vec2<double> q = ps.q, v = ps.v;
      double sum = 0;
      for (std::uint64_t n = 0; n < kSteps; ++n) {
        const Hit<double> h = model.stadium.next_hit(q, v);
        v = model.stadium.reflect(h.piece, h.q, v);
        q = h.q, sum += h.t;
      }
      want += sum;
    }
    EXPECT_EQ(simd::flights_only(ks, starts.data(), kSteps), want) << lanes << " lanes";
  }
}

// Fast-forward shows each skipped bounce to the observer: f_c with it equals f_c by stepping.
TEST(Simd, FastForwardedBouncesAreCountedInTheDensity) {
  Scene s = scene("0", "0", 20000, "0.01");
  s.sampling.kind = SamplingKind::mupo;  // many long bouncing-ball phases
  s.collision_density = CollisionDensitySpec{100, {{0, 3000}}};
  const RunResult stepped = run(s, Engine::scalar);
  s.fast_forward = true;
  const RunResult jumped = run(s, Engine::scalar);
  EXPECT_EQ(stepped.tally.collision_density, jumped.tally.collision_density);
  EXPECT_EQ(stepped.tally.collisions, jumped.tally.collisions);
}

// First collisions: a leak of 0.999 takes nearly every particle at its first hit, so the escape
// records are the first collisions themselves; they agree exactly (no ulps to allow).
TEST(Simd, FirstCollisionsAgreeExactly) {
  if (!simd::available()) GTEST_SKIP() << "no AVX2+FMA on this CPU";
  const Scene s = scene("0.5", "0", 20000, "0.999");
  const RunResult a = run(s, Engine::scalar), b = run(s, Engine::simd, 2, 4);
  std::size_t first = 0;
  for (std::size_t i = 0; i < a.records.size(); ++i) {
    if (a.records[i].collisions != 1) continue;
    ++first;
    EXPECT_EQ(a.records[i].t, b.records[i].t) << i;
    EXPECT_EQ(a.records[i].s, b.records[i].s) << i;
  }
  EXPECT_GT(first, 19000u);
}

// The first look of the moving leak and of f_c takes an arc hit's rough angle and trusts it to
// kRoughAngleError (1e-5 rad; the cascade settles every lane within twice that of an edge by SLEEF's
// angle or the core's s).
TEST(Simd, RoughArcAngleWithinItsBound) {
  // Arc points (ay >= 0, at distance r from the centre, as formula::arc_angle_y / _x give them) over the whole
  // arc, on four radii, the arc's two ends and its middle exactly, and points a rounding off its ends (ay < 0
  // or -0): the kernel's rough s on an arc starting at s = 0 against libm's atan2 clamped to [0, pi], as
  // formula::arc_s clamps it, times r / L (1: the angle; the default stadium's 0.0973; a small 0.01). The bound
  // is the kernel's kRoughAngleError r / L, 1e-5 r / L (the polynomial's own error is 3.4e-6 doubled by the half
  // angle; a failure here means the cascade could keep a rough s that decides differently from the core).
  if (!simd::available()) GTEST_SKIP() << "no AVX2+FMA on this CPU";
  constexpr std::size_t n = 1000000;
  for (const double r : {1.0, 0.7, 2.0, 0.3}) {
    std::vector<double> ay, ax;
    for (std::size_t i = 0; i < n; ++i) {
      const double th = M_PI * static_cast<double>(i) / static_cast<double>(n - 1);
      ay.push_back(r * std::sin(th)), ax.push_back(r * std::cos(th));
    }
    for (const double y : {0.0, -0.0, -1e-17, -1e-300}) {  // the ends exactly and a rounding beyond them
      ay.push_back(y), ax.push_back(r);
      ay.push_back(y), ax.push_back(-r);
    }
    ay.push_back(r), ax.push_back(0);
    std::vector<double> out(ay.size());
    for (const double scale : {1.0, 1 / (4 + 2 * M_PI), 0.01})
      for (int lanes : test::kernel_widths()) {
        simd::rough_arc_s(lanes, r, scale, ay.data(), ax.data(), out.data(), ay.size());
        double worst = 0;
        for (std::size_t i = 0; i < ay.size(); ++i) {
          const double want = std::clamp(std::atan2(ay[i], ax[i]), 0.0, M_PI) * scale;
          worst = std::max(worst, std::abs(out[i] - want) / scale);
        }
        EXPECT_LT(worst, 1e-5) << lanes << " lanes, r = " << r << ", r / L = " << scale;
        std::printf("rough arc s, %d lanes, r = %g, r / L = %.3g: largest error / (r / L) %.3g\n", lanes, r, scale,
                    worst);
      }
  }
}

// ROTLEAK_SIMD_LANES forces the width (both kernels run on an AVX-512 machine), and a width that is
// not 4 or 8, or that this CPU cannot run, is refused with the variable's name.
TEST(Simd, EnvironmentForcesTheWidth) {
  const char* before = std::getenv("ROTLEAK_SIMD_LANES");
  const std::string saved = before ? before : "";
  for (int lanes : {4, 8}) {
    ::setenv("ROTLEAK_SIMD_LANES", std::to_string(lanes).c_str(), 1);
    if (simd::lanes_available(lanes)) {
      EXPECT_EQ(default_simd_lanes(), lanes);
      if (lanes == 4) {
        EXPECT_EQ(run(scene("0", "0", 2000), Engine::simd).simd_lanes, 4);
      }
    } else {
      EXPECT_THROW(default_simd_lanes(), InputError) << lanes;
    }
  }
  for (const char* bad : {"5", "avx2", "16"}) {
    ::setenv("ROTLEAK_SIMD_LANES", bad, 1);
    try {
      (void)default_simd_lanes();
      ADD_FAILURE() << bad << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(std::string("ROTLEAK_SIMD_LANES = ") + bad + ": 4 (AVX2) or 8", 0), 0u)
          << e.what();
    }
  }
  ::unsetenv("ROTLEAK_SIMD_LANES");
  EXPECT_EQ(default_simd_lanes(), simd::widest_lanes());
  if (before) ::setenv("ROTLEAK_SIMD_LANES", saved.c_str(), 1);
}

TEST(Simd, RefusesWhatItCannotRun) {
  Scene s = scene("0", "0");
  s.collision_density = CollisionDensitySpec{};
  s.collision_density->windows.assign(simd::kMaxDensityWindows, TimeWindow{0, 100});
  if (simd::available()) {
    EXPECT_EQ(resolve_engine(Engine::automatic, s), Engine::simd);  // f_c runs vectorised
  }
  s.collision_density->windows.push_back({0, 100});
  EXPECT_EQ(resolve_engine(Engine::automatic, s), Engine::scalar);  // more windows than the kernel takes
  EXPECT_THROW(resolve_engine(Engine::simd, s), std::runtime_error);
  s.collision_density.reset();
  s.tier = Tier::long_double;
  EXPECT_EQ(resolve_engine(Engine::automatic, s), Engine::scalar);
}
