// Where an ulp of the kernel's constants decides (tests/test_stadiums.cpp runs whole runs): at points within a
// few ulps of every f_c bin edge, of the moving leak's two ends, and of the junctions while a leak end sits on
// one, on four stadiums, the kernel's own bin and
// leak test (simd::probe: the functions run() uses) must be the core's. With 1/L and r/L computed from the
// rounded perimeter, as the kernel once did, 58 bins and 174 leak decisions differ on d = 1, r = 1.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "kernel_widths.hpp"
#include "sim/engine/kernel_adapter.hpp"
#include "sim/kernel/simd_engine.hpp"
#include "stadium_sizes.hpp"

using namespace rotleak;
using test::kSizes;
using test::scene_of;
using test::Size;

namespace {

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

/// The probe on stadium z with the leak turning at `omega` (exact text, its double `omega_d`): every bin and leak
/// decision the kernel makes must be the core's. `rough`: whether the kernel's first look takes the rough phase
/// (KernelScene::phase_bound > 0) or, its bound too wide at this omega, the exact phase at every hit.
void decides_as_the_core(const Size& z, const std::string& omega, double omega_d, bool rough) {
  const Scene s = scene_of(z, {"leak.omega=" + omega, "leak.width=0.02", "leak.start=0.3"});
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
  // the leak's ends on the junctions: there the leak's centre lies at the edge of may_touch (whether it can
  // reach an arc at all), the other decision the kernel's first look settles from a rough phase
  const double start = 0.3, hw = model.leak.half_width();
  for (int j = 0; j < 4; ++j)
    for (const double side : {-1.0, 1.0})
      for (int turn = 0; turn < 3; ++turn) {
        const double c = st.junction(j) + side * hw - start;
        const double t = (c - std::floor(c) + turn) / omega_d;
        points_near(st, st.junction(j), t, points);
        points_near(st, st.junction(j) + 1e-9, t, points);
        points_near(st, st.junction(j) - 1e-9, t, points);
      }
  // the arcs' four corners as arc hits (x = +-d/2 exactly), the leak sweeping over them: there the core's angle
  // hangs on the sign of a zero (at x = -d/2 its -0 gives the angle 0, so the core puts the top-left corner at the
  // left arc's start), which the kernel's rough s must share
  for (int i = 0; i < 4000; ++i)
    for (const double sx : {-1.0, 1.0})
      for (const double sy : {-1.0, 1.0}) points.push_back({sx > 0 ? 1 : 3, sx * st.half_d(), sy * st.r(), 0.011 * i});
  std::size_t near_bin_edge = 0;
  for (const simd::Probe& p : points) {
    const double sb = st.s_of(static_cast<Piece>(p.piece), {p.x, p.y}) * kBins;
    near_bin_edge += std::abs(sb - std::nearbyint(sb)) < 1e-12;
  }
  EXPECT_GT(near_bin_edge, static_cast<std::size_t>(kBins));  // the probe does look at the edges
  for (int lanes : test::kernel_widths()) {
    simd::KernelScene ks = simd_scene(model);
    ks.lanes = lanes;
    ks.bins = kBins;
    EXPECT_EQ(ks.phase_bound > 0, rough) << "omega = " << omega << ": phase bound " << ks.phase_bound;
    std::vector<simd::ProbeResult> got(points.size());
    simd::probe(ks, points.data(), got.data(), points.size());
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

}  // namespace

class Stadiums : public ::testing::TestWithParam<Size> {};

TEST_P(Stadiums, KernelDecidesAsTheCoreWithinAnUlpOfBinEdgesAndLeakEnds) {
  if (!simd::available()) GTEST_SKIP() << "no AVX2+FMA on this CPU";
  decides_as_the_core(GetParam(), "2/3", 2.0 / 3.0, true);
  // omega t_max = 2 * 10^12: the rough phase's bound (4.4e-4) is wider than the leak allows, the exact phase decides
  decides_as_the_core(GetParam(), "1e8", 1e8, false);
}

INSTANTIATE_TEST_SUITE_P(FourSizes, Stadiums, ::testing::ValuesIn(kSizes),
                         [](const ::testing::TestParamInfo<Size>& i) { return std::string(i.param.name); });
