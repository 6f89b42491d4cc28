// The fast-forward of bouncing-ball phases against stepping: the same escape collision and the same
// escape time, bit for bit, over many particles, long-lived MUPOs included.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "analysis/output/run_output.hpp"
#include "geometry/formulas.hpp"
#include "io/scene_file.hpp"
#include "names.hpp"
#include "same_text.hpp"
#include "sim/engine/engine.hpp"
#include "sim/engine/kernel_adapter.hpp"
#include "sim/model/particle.hpp"

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

namespace {

/// f_c of one particle's life, weighted (0.3) and not, in every window.
struct Density {
  std::vector<std::uint64_t> counts;
  std::vector<FixedSum> sums;
  DensityObserver<double> observer;
  Density(const Stadium<double>& st, const std::vector<TimeWindow>& windows, int bins)
      : counts(windows.size() * static_cast<std::size_t>(bins)), sums(counts.size()) {
    observer = {&st, &windows, bins, counts.data(), sums.data()};
    observer.weight = 0.3;
  }
};

/// The same counts taken once per time cell (DensityCells, as the vectorised engine takes them) and
/// folded into the windows by fold().
struct CellDensity {
  DensityCells cells;
  std::vector<std::uint64_t> cell_counts;
  std::vector<FixedSum> cell_sums;
  Density windows;
  DensityObserver<double> observer;
  CellDensity(const Stadium<double>& st, const std::vector<TimeWindow>& w, int bins) : windows(st, w, bins) {
    std::vector<double> from, to;
    for (const TimeWindow& x : w) from.push_back(x.from), to.push_back(x.to);
    cells = DensityCells::of(bins, static_cast<int>(w.size()), from.data(), to.data());
    cell_counts.assign(static_cast<std::size_t>(cells.cells()) * static_cast<std::size_t>(bins), 0);
    cell_sums.assign(cell_counts.size(), FixedSum{});
    observer = {&st, &w, bins, cell_counts.data(), cell_sums.data()};
    observer.weight = 0.3;
    observer.cells = &cells;
  }
  void fold() { cells.fold(cell_counts.data(), cell_sums.data(), windows.counts.data(), windows.sums.data()); }
};

/// Passes on what it is shown, and notes the most stretches one ball_run() held.
struct Phases {
  static constexpr bool active = true;
  DensityObserver<double>* to;
  int most = 0;
  void operator()(Piece p, const Vec2<double>& q, const double& t) { (*to)(p, q, t); }
  void ball_run(const BallRun<double>& ph) {
    most = std::max(most, ph.count);
    to->ball_run(ph);
  }
};

/// The f_c bin of a point x on a straight edge, as the observer computes it (s_of, then the bin).
auto edge_bin(const Stadium<double>& st, Piece p, int bins) {
  return [&st, p, bins](double x) {
    const double y = p == Piece::top ? st.r() : -st.r();
    return static_cast<int>(formula::density_bin(st.s_of(p, {x, y}), static_cast<double>(bins)));
  };
}

}  // namespace

// The f_c observer counts a fast-forward's phase from its stretches (DensityObserver::ball_run: window
// ends by bisection, bin changes from the edge's table, EdgeBins): the counts and the weighted sums
// of whole lives are those of stepping, bit for bit. Orbits from x = -0.9 on the top edge, slow and
// fast (|dx| ~ 2 p a bounce, about 0.6 bins of 1000 for p = 3e-3), across x = 0 (where the top edge's
// s wraps from near 1 to 0), with 2, 7 and 1000 bins and windows that end inside the phases; p = 1e-7
// crosses x = 0 within 10^-6 of it, so its phase spans more binades of x and t than one ball_run()
// holds (Phase::kMax stretches) and is shown in parts.
TEST(FastForwardOrbit, PhasesCountWhatSteppingCounts) {
  const Scene s = mupo_scene("0", "0.25");  // the leak on the right arc
  Model<double> stepping(s.d, s.r, s.width, s.start, s.omega, 5e7), jumping = stepping;
  jumping.fast_forward = true;
  const Stadium<double>& st = stepping.stadium;
  const std::vector<TimeWindow> windows{{0, 5e7}, {1000, 3e6}, {8e6, 8.0001e6}};
  for (double p : {3e-3, -1e-4, 2.5e-5, 1e-7}) {
    ParticleState<double> ps;
    const BoundaryPoint<double> b = st.at(1 - 0.9 / st.perimeter());
    ps.q = b.q;
    ps.v = st.velocity(b, p);
    for (int bins : {2, 7, 1000}) {
      Density by_step(st, windows, bins), by_phase(st, windows, bins);
      Phases phases{&by_phase.observer};
      const ParticleEnd a = run_particle(stepping, ps, by_step.observer);
      const ParticleEnd c = run_particle(jumping, ps, phases);
      ASSERT_EQ(a.collisions, c.collisions) << "p " << p;
      EXPECT_EQ(by_step.counts, by_phase.counts) << "p " << p << ", " << bins << " bins";
      EXPECT_TRUE(by_step.sums == by_phase.sums) << "p " << p << ", " << bins << " bins";
      // by time cell, as the vectorised engine counts (phases cross the windows' edges): folded, the same
      CellDensity cell_step(st, windows, bins), cell_phase(st, windows, bins);
      Phases cell_phases{&cell_phase.observer};
      run_particle(stepping, ps, cell_step.observer);
      run_particle(jumping, ps, cell_phases);
      cell_step.fold(), cell_phase.fold();
      for (const CellDensity* d : {&cell_step, &cell_phase}) {
        EXPECT_EQ(by_step.counts, d->windows.counts) << "p " << p << ", " << bins << " bins";
        EXPECT_TRUE(by_step.sums == d->windows.sums) << "p " << p << ", " << bins << " bins";
      }
      EXPECT_TRUE(std::all_of(cell_phase.cell_counts.begin(), cell_phase.cell_counts.end(), [](std::uint64_t n) {
        return n == 0;
      })) << "fold leaves the cells zero";
      EXPECT_GT(phases.most, 0) << "p " << p;
      if (p == 1e-7) {
        EXPECT_EQ(phases.most, BallRun<double>::kMax) << "shown in parts";
        EXPECT_GT(a.collisions, 5000000u);
      }
    }
  }
}

// The edge's bin table (EdgeBins) against the bin of s_of itself: each change at the first x of its
// new bin (the x below it still in the old one), each bin one interval, and 2 * 10^5 points of the
// edge -- random, the ends, 0, -0 and the tiny negative x whose s rounds up to 1 and wraps to 0 --
// in the interval of their bin. Two stadiums, 1 to 4096 bins, both edges, each with as many
// changes as its length holds bins.
TEST(EdgeBins, EachChangeIsWhereTheBinChanges) {
  std::mt19937_64 gen(5);
  for (auto [d, r] : {std::pair{"2", "1"}, std::pair{"0.3", "1.7"}}) {
    const Stadium<double> st(ExactReal::parse(d), ExactReal::parse(r));
    const double hd = st.half_d();
    std::uniform_real_distribution<double> ux(-hd, hd);
    for (int bins : {1, 2, 3, 7, 1000, 4096})
      for (Piece p : {Piece::top, Piece::bottom}) {
        const auto bin_at = edge_bin(st, p, bins);
        const EdgeBins<double> e = EdgeBins<double>::build(-hd, hd, bin_at);
        ASSERT_EQ(e.bin.size(), e.x.size() + 1);
        for (std::size_t k = 0; k < e.x.size(); ++k) {
          EXPECT_EQ(bin_at(e.x[k]), e.bin[k + 1]) << bins << " bins, change " << k;
          EXPECT_EQ(bin_at(std::nextafter(e.x[k], -hd)), e.bin[k]) << bins << " bins, change " << k;
          if (k > 0) {
            EXPECT_LT(e.x[k - 1], e.x[k]);
          }
        }
        for (std::size_t k = 0; k < e.bin.size(); ++k)
          EXPECT_EQ(e.where[static_cast<std::size_t>(e.bin[k])], static_cast<int>(k));
        std::vector<double> xs{-hd, hd, 0.0, -0.0, -1e-17, -1e-16, -5e-16, 1e-300};
        for (int i = 0; i < 100000; ++i) xs.push_back(ux(gen));
        for (double x : xs) {
          const auto k = static_cast<std::size_t>(std::upper_bound(e.x.begin(), e.x.end(), x) - e.x.begin());
          EXPECT_EQ(e.bin[k], bin_at(x)) << bins << " bins, x " << x;
        }
        // an edge of length d holds about bins d / L of them
        const double on_edge = bins * 2 * hd / st.perimeter();
        EXPECT_GE(static_cast<double>(e.x.size()) + 2, on_edge) << bins << " bins";
      }
  }
}

// Bounces that land exactly on a bin change, where the sweep's estimate of the crossing bounce is
// an integer up to rounding (DensityObserver::ball_run settles it on exact positions, both ways): a
// stretch of 41 bounces with x_j = x + j dx exactly, dx = +-1..7 ulps, bounce 1 + 2 G on the change
// (G = 3 .. 17), for changes across both edges; the phase counts what its bounces one by one count.
TEST(FastForwardOrbit, BouncesOnABinChangeCountOnce) {
  const Stadium<double> st(ExactReal::parse("2"), ExactReal::parse("1"));
  const std::vector<TimeWindow> windows{{0, 1e9}};
  const int bins = 1000;
  std::size_t checked = 0;
  for (Piece p : {Piece::top, Piece::bottom}) {
    const auto bin_at = edge_bin(st, p, bins);
    const EdgeBins<double> e = EdgeBins<double>::build(-st.half_d(), st.half_d(), bin_at);
    for (std::size_t k = 0; k < e.x.size(); k += 7)
      for (int ulps = -7; ulps <= 7; ++ulps)
        for (long G = 3; G <= 17; G += 7) {
          const double edge = e.x[k];
          if (ulps == 0 || edge == 0) continue;
          const double dx = ulps * (std::nextafter(std::abs(edge), 4.0) - std::abs(edge));
          const long n = 41, land = 1 + 2 * G;  // bounce `land` (parity 1) sits on the change
          const double x = edge - static_cast<double>(land) * dx;
          const double x_n = x + static_cast<double>(n) * dx;
          if (std::ilogb(x) != std::ilogb(x_n) || std::ilogb(x) != std::ilogb(edge) || (x > 0) != (x_n > 0)) continue;
          Stretch<double> s{n, x, dx, 1100, 2, st.r(), p == Piece::bottom};  // bounce 1 on p
          ASSERT_EQ(s(land).q.x, edge);
          ASSERT_EQ(s(land).piece, p);
          BallRun<double> ph;
          ph.push(s);
          Density whole(st, windows, bins), each(st, windows, bins);
          whole.observer.ball_run(ph);
          for (long j = 1; j <= n; ++j) {
            const Bounce<double> b = ph(j);
            each.observer(b.piece, b.q, b.t);
          }
          EXPECT_EQ(whole.counts, each.counts) << "change " << k << ", " << ulps << " ulps, G " << G;
          ++checked;
        }
  }
  EXPECT_GT(checked, 2000u);
}

// Long stretches (1.6 * 10^7 bounces) with steps of ~10^8 ulps, where the sweep's estimate of a
// crossing bounce carries rounding of the order of its distance from the next integer: bounce 1 + 2 G
// (G ~ 10^6 .. 10^7) on a bin change or one ulp either side of it, moving up and down, both edges;
// the two steps (100000147 and 5^11 ulps) round the estimate of an exact landing above and below G.
// Reference: each bin's bounces found by bisection on exact positions (bins are monotone in the
// bounce index), without the estimate or the edge table.
TEST(FastForwardOrbit, LongStretchesCountWhatBisectionFinds) {
  const Stadium<double> st(ExactReal::parse("2"), ExactReal::parse("1"));
  const std::vector<TimeWindow> windows{{0, 1e12}};
  const int bins = 1000;
  std::size_t checked = 0;
  for (Piece p : {Piece::top, Piece::bottom}) {
    const auto bin_at = edge_bin(st, p, bins);
    const auto other_bin_at = edge_bin(st, p == Piece::top ? Piece::bottom : Piece::top, bins);  // even bounces
    const EdgeBins<double> e = EdgeBins<double>::build(-st.half_d(), st.half_d(), bin_at);
    for (std::size_t k = 0; k < e.x.size(); k += 11)
      for (int dir : {1, -1})
        for (int off : {0, 1, -1})
          for (long G : {999999L, 3000001L, 7777777L})
            for (double step_ulps : {100000147.0, 48828125.0}) {
              const double edge = e.x[k], ulp = std::nextafter(std::abs(edge), 4.0) - std::abs(edge);
              const double dx = dir * step_ulps * ulp;
              const long n = 16000001, land = 1 + 2 * G;
              const double x = edge - static_cast<double>(land) * dx + off * ulp;
              const double x_n = x + static_cast<double>(n) * dx;
              if (std::ilogb(x) != std::ilogb(x_n) || std::ilogb(x) != std::ilogb(edge) || (x > 0) != (x_n > 0) ||
                  std::abs(x_n) > st.half_d())
                continue;
              Stretch<double> s{n, x, dx, 1e10, 2, st.r(), p == Piece::bottom};
              BallRun<double> ph;
              ph.push(s);
              Density whole(st, windows, bins);
              whole.observer.ball_run(ph);
              std::vector<std::uint64_t> ref(static_cast<std::size_t>(bins), 0);
              for (long parity = 1; parity <= 2; ++parity) {
                const long m = (n - parity) / 2 + 1;
                const auto bin_i = [&](long i) {
                  const double xi = x + static_cast<double>(parity + 2 * i) * dx;
                  return parity == 1 ? bin_at(xi) : other_bin_at(xi);
                };
                for (long a = 0; a < m;) {
                  const int b = bin_i(a);
                  const long z = first_true(a, m, [&](long i) { return bin_i(i) != b; });
                  ref[static_cast<std::size_t>(b)] += static_cast<std::uint64_t>(z - a);
                  a = z;
                }
              }
              EXPECT_EQ(whole.counts, ref) << "change " << k << ", dir " << dir << ", off " << off << ", G " << G
                                           << ", step " << step_ulps << " ulps";
              ++checked;
            }
  }
  EXPECT_GT(checked, 100u);
}
