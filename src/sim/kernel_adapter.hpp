// The vectorised kernel's adapter: the scene in the kernel's plain structs, the context a block of
// particles (or a split run's members) runs in, and the callbacks through which the kernel asks the
// core (s of an arc hit), hands over f_c counts, takes the next particle and reports an ended
// one. Also the f_c observer the scalar engine and the kernel's fast-forward hand-off share.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "numeric/fixed_sum.hpp"
#include "sim/particle.hpp"
#include "sim/sampling.hpp"
#include "sim/scene.hpp"
#include "sim/simd_engine.hpp"

namespace rotleak {

/// f_c(s): counts collision positions in each requested time window.
template <class R>
struct DensityObserver {
  static constexpr bool active = true;
  /// A stretch whose s moves at least this many bins a bounce (runs of about one bounce) is walked
  /// bounce by bounce; slower ones have their runs predicted and checked (run_end)
  static constexpr double kWalkBinsPerBounce = 0.25;
  const Stadium<R>* stadium;
  const std::vector<TimeWindow>* windows;
  int bins;
  std::uint64_t* counts;
  FixedSum* weighted_counts = nullptr;  ///< weighted runs: sums of the particle's weight
  double weight = 1;                    ///< of the particle in flight

  void operator()(Piece p, const Vec2<R>& q, const R& t) {
    const double tt = num_traits<R>::to_double(t);
    bool any = false;
    for (const auto& w : *windows) any |= (tt >= w.from && tt <= w.to);
    if (!any) return;
    const int b = bin(p, q);
    for (std::size_t i = 0; i < windows->size(); ++i)
      if (tt >= (*windows)[i].from && tt <= (*windows)[i].to) add(i, b, 1);
  }

  /// A fast-forwarded stretch of n bounces (particle.hpp fast_forward), counted as n calls would count
  /// them, by bisection: bounces of one parity lie on one edge with t and x monotone in j, so a
  /// window's bounces are an interval of j, and so is each bin's within it (s is monotone in x on the
  /// bottom edge; on the top edge it is monotone on each side of x = 0, where it wraps from near 1 to
  /// 0, and the two sides' bins are disjoint for bins >= 2 since they lie above 0.75 and below 0.25).
  void stretch(const Stretch<R>& st) {
    const long n = st.n;
    const std::size_t nw = windows->size();
    // each window's bounces [from, to) among this parity's (on the stack: a fast-forward shows many
    // short stretches, one per binade of its sums)
    constexpr std::size_t kInline = 8;
    std::pair<long, long> inline_span[kInline];
    std::vector<std::pair<long, long>> heap_span(nw > kInline ? nw : 0);
    std::pair<long, long>* span = nw > kInline ? heap_span.data() : inline_span;
    for (long parity = 1; parity <= 2 && parity <= n; ++parity) {
      const long m = (n - parity) / 2 + 1;  // j = parity + 2 i, i = 0 .. m - 1
      const auto at = [&](long i) { return st(parity + 2 * i); };
      const auto time = [&](long i) { return num_traits<R>::to_double(at(i).t); };
      const auto s_at = [&](long i) {
        const Bounce<R> b = at(i);
        return num_traits<R>::to_double(stadium->s_of(b.piece, b.q));
      };
      // (a window usually holds the whole stretch: then the stretch's two end times say so)
      const double t_first = time(0), t_last = time(m - 1);
      long lo = m, hi = 0;
      for (std::size_t w = 0; w < nw; ++w) {
        const TimeWindow& win = (*windows)[w];
        long a = 0, e = m;
        if (t_last < win.from || t_first > win.to) {
          a = e = 0;
        } else if (!(t_first >= win.from && t_last <= win.to)) {
          a = first_true(0, m, [&](long i) { return time(i) >= win.from; });
          e = first_true(a, m, [&](long i) { return time(i) > win.to; });
        }
        span[w] = {a, e};
        if (a < e) lo = std::min(lo, a), hi = std::max(hi, e);
      }
      if (lo >= hi) continue;
      // Runs of equal bins over the windows' union, each added to every window it overlaps. x is
      // affine in the bounce index (a fixed increment, correctly rounded), so s is too, up to
      // rounding and the top edge's wrap at x = 0: each run's end is predicted from the mean step of
      // s, then checked exactly (two bins), and searched for only when the prediction misses.
      const double s_lo = s_at(lo), s_last = hi - 1 > lo ? s_at(hi - 1) : s_lo;
      const double step = hi - 1 > lo ? (s_last - s_lo) / static_cast<double>(hi - 1 - lo) : 0;
      if (bin_of(s_lo) == bin_of(s_last)) {  // one run (bins are monotone in i, the top edge's wrap aside,
        // and the two sides of the wrap never share a bin): nothing to search
        for (std::size_t w = 0; w < nw; ++w)
          if (span[w].first < span[w].second)
            add(w, bin_of(s_lo), static_cast<std::uint64_t>(span[w].second - span[w].first));
        continue;
      }
      // bounces [a, z) in bin b: added to every window they overlap
      const auto run = [&](long a, long z, int b) {
        for (std::size_t w = 0; w < nw; ++w) {
          const long from = std::max(a, span[w].first), to = std::min(z, span[w].second);
          if (from < to) add(w, b, static_cast<std::uint64_t>(to - from));
        }
      };
      if (std::abs(step) * bins >= kWalkBinsPerBounce) {
        // short runs (a fast orbit): walk the bounces. Within a stretch every x_j = x + j dx is exact
        // (Stretch), so x_j + 2 dx is x_(j+2) exactly: the walk gives each bounce's x bit for bit, one
        // addition a bounce instead of a search
        const Bounce<R> first = at(lo);
        const R dx = R(2) * st.dx;  // from one bounce of this parity to the next
        Vec2<R> q = first.q;
        long a = lo;
        int b = bin_of(s_lo);
        for (long i = lo + 1; i < hi; ++i) {
          q.x += dx;
          const int bi = bin_of(num_traits<R>::to_double(stadium->s_of(first.piece, q)));
          if (bi != b) run(a, i, b), a = i, b = bi;
        }
        run(a, hi, b);
        continue;
      }
      long a = lo;
      double s_a = s_lo;
      while (a < hi) {
        const int bin0 = bin_of(s_a);
        const auto moved = [&](long i) { return bin_of(s_at(i)) != bin0; };  // false, then true, in i
        const long z = run_end(a, hi, s_a, step, bin0, moved);
        run(a, z, bin0);
        a = z;
        if (a < hi) s_a = s_at(a);
      }
    }
  }

 private:
  int bin(Piece p, const Vec2<R>& q) const { return bin_of(num_traits<R>::to_double(stadium->s_of(p, q))); }
  int bin_of(double s) const { return static_cast<int>(formula::density_bin(s, static_cast<double>(bins))); }
  /// The first i in (a, hi) where moved(i) holds (hi if none), moved being false at a and then true
  /// from some i on: first where s, moving by about `step` an index from s_a, crosses the edge of
  /// bin0 it moves towards; then that guess checked and, if it missed, corrected by search.
  template <class P>
  long run_end(long a, long hi, double s_a, double step, int bin0, const P& moved) const {
    long z = hi;
    if (step > 0 || step < 0) {
      const double edge = static_cast<double>(step > 0 ? bin0 + 1 : bin0) / bins;
      const double k = step > 0 ? std::ceil((edge - s_a) / step) : std::floor((s_a - edge) / -step) + 1;
      z = k >= static_cast<double>(hi - a) ? hi : a + std::max(1L, static_cast<long>(k));
    }
    if (z > a + 1 && moved(z - 1)) return first_true(a + 1, z, moved);  // guessed long
    if (z < hi && !moved(z)) return gallop(z + 1, hi, moved);           // guessed short
    return z;
  }
  void add(std::size_t window, int b, std::uint64_t n) {
    const std::size_t k = window * static_cast<std::size_t>(bins) + static_cast<std::size_t>(b);
    counts[k] += n;
    if (weighted_counts) weighted_counts[k].add_times(weight, n);
  }
  /// As first_true(), for an answer likely near lo (pred(lo - 1) false): probes lo, lo + 1, lo + 3, ...
  /// then bisects the last gap.
  template <class P>
  static long gallop(long lo, long hi, const P& pred) {
    long known_false = lo - 1;
    for (long step = 1;; step *= 2) {
      const long probe = known_false + step;
      if (probe >= hi) return first_true(known_false + 1, hi, pred);
      if (pred(probe)) return first_true(known_false + 1, probe + 1, pred);
      known_false = probe;
    }
  }
};

/// The initial data of particle i of a run: the scene's draw of id first_id + i (by its sampling
/// scheme), or a given list (weight 1); and its weight.
struct DrawSource {
  const Sampler* sampler;
  std::uint64_t first_id;
  const std::vector<InitialDraw>* draws;
  InitialDraw operator()(std::uint64_t i) const { return draws ? (*draws)[i] : sampler->draw(first_id + i); }
  double weight(const InitialDraw& d) const { return draws ? 1.0 : sampler->weight(d); }
};

/// The vectorised kernel's view of a double model.
simd::Scene simd_scene(const Model<double>& m);

/// The f_c observer's windows and bins for the kernel.
void simd_density(simd::Scene& s, const Scene& scene);

/// The kernel's f_c counts by time cell (simd::DensityHit), folded into the windows' counts.
struct DensityCells {
  int bins = 0;
  unsigned windows[2 * simd::kMaxDensityWindows + 1] = {};  ///< bit w: window w holds the cell's times

  /// counts[c bins + b] into density[w bins + b] for each window w of cell c; counts zeroed
  void fold(std::uint64_t* counts, std::uint64_t* density, std::size_t cells) const {
    const auto nb = static_cast<std::size_t>(bins);
    for (std::size_t c = 0; c < cells; ++c)
      for (unsigned m = windows[c]; m; m &= m - 1) {
        const auto w = static_cast<std::size_t>(__builtin_ctz(m));
        for (std::size_t b = 0; b < nb; ++b) density[w * nb + b] += counts[c * nb + b];
      }
    std::fill(counts, counts + cells * nb, 0);
  }
};

struct SimdContext {
  const Model<double>* model;
  DrawSource draw;
  std::uint64_t next, hi;
  std::function<void(std::uint64_t, const ParticleEnd&)> record;
  std::vector<std::pair<std::uint64_t, simd::Start>> resume;  ///< back from the fast-forward
  bool weights = false;                                       ///< lanes carry their weight (weighted f_c)
  std::uint64_t* density = nullptr;                           ///< this thread's f_c counts
  FixedSum* density_w = nullptr;                              ///< and weighted sums
  DensityObserver<double>* observer = nullptr;                ///< f_c of the fast-forwarded bounces
  const DensityCells* cells = nullptr;                        ///< the kernel's time cells
  /// A split run's members: particle i (next .. hi) starts from (*members)[i] instead of a draw
  const std::vector<simd::Start>* members = nullptr;
};

/// The kernel's questions to the core and its f_c sink (the callbacks below, for a SimdContext).
extern const simd::Exact kSimdExact;

/// simd::NextParticle for a SimdContext: the fast-forward's returns first, then its members (split runs)
/// or the draws of its ids.
bool simd_next(void* c, simd::Start* start, std::uint64_t* id);
/// simd::Finish for a SimdContext: a handed-back lane is fast-forwarded and queued again, an ended one
/// recorded.
void simd_finish(void* c, std::uint64_t id, const simd::End& e);

}  // namespace rotleak
