// The f_c observer: the collision density f_c(s) counted in time windows, by the scalar engine at each
// collision, by the fast-forward a bouncing-ball phase at a time (DensityObserver::ball_run), and by the
// vectorised engine once per time cell (DensityCells), all to the same integers and exact sums.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "numeric/fixed_sum.hpp"
#include "sim/kernel/simd_engine.hpp"
#include "sim/model/particle.hpp"
#include "sim/model/scene.hpp"
#include "sim/tally/density_bin.hpp"

namespace rotleak {

/// Where the bin of a straight edge's points changes, so that a bounce's bin on the edge comes from
/// comparisons of its x: bin(x) is the bin of s_of(x), as the f_c observer computes it, for x in
/// [-d/2, d/2]. Found once by bisection over the representable x: s is monotone in x on the bottom
/// edge and on each side of x = 0 on the top one, where it wraps from near 1 to 0, and the two sides'
/// bins are disjoint for bins >= 2 (above 0.75 and below 0.25), so a bin once left is not met again
/// along the edge.
template <class R>
struct EdgeBins {
  std::vector<R> x;        ///< ascending: x[k] is the first point of interval k + 1
  std::vector<int> bin;    ///< the bin of interval k: points in [x[k - 1], x[k]) (from -d/2, to d/2)
  std::vector<int> where;  ///< the interval of each bin on this edge (each bin is one interval)

  int changes() const { return static_cast<int>(x.size()); }

  /// The table of bin_at(x) over [lo, hi].
  template <class F>
  static EdgeBins build(const R& lo, const R& hi, const F& bin_at) {
    EdgeBins e;
    R from = lo;
    int b = bin_at(from);
    e.bin.push_back(b);
    const int b_end = bin_at(hi);
    while (b != b_end) {
      R to = hi;  // bin_at(from) == b != bin_at(to): the change lies in (from, to]
      for (;;) {
        R mid = from + (to - from) / 2;
        if (mid == from || mid == to) mid = std::nextafter(from, to);
        if (mid == to) break;
        (bin_at(mid) == b ? from : to) = mid;
      }
      e.x.push_back(to);
      b = bin_at(to);
      e.bin.push_back(b);
      from = to;
    }
    e.where.assign(static_cast<std::size_t>(*std::max_element(e.bin.begin(), e.bin.end()) + 1), -1);
    for (std::size_t k = 0; k < e.bin.size(); ++k) e.where[static_cast<std::size_t>(e.bin[k])] = static_cast<int>(k);
    return e;
  }
};

/// f_c by time cell: a cell is how many window edges a time has passed (t >= from_w, t > to_w), so it fixes
/// the set of windows that hold the time; the vectorised engine counts a collision once in its cell (the
/// kernel's hits and the fast-forward's phases alike) and folds the cells into the windows afterwards. The
/// counts are integers and the weighted sums exact (FixedSum), so the windows get what adding to each of
/// them would give, bit for bit.
struct DensityCells {
  int bins = 0;
  int n_windows = 0;
  double from[simd::kMaxDensityWindows] = {}, to[simd::kMaxDensityWindows] = {};  ///< window w: [from[w], to[w]]
  unsigned windows[2 * simd::kMaxDensityWindows + 1] = {};  ///< bit w: window w holds the cell's times

  /// The cells of `windows` time windows (at most simd::kMaxDensityWindows), f_c binned in `bins`.
  static DensityCells of(int bins, int windows, const double* from, const double* to);
  int cells() const { return 2 * n_windows + 1; }
  /// the cell of time t (formula::time_cell)
  std::size_t cell_of(double t) const { return static_cast<std::size_t>(formula::time_cell(t, from, to, n_windows)); }

  /// counts[c bins + b] (and sums[c bins + b], when not null) into density[w bins + b] (density_w) for
  /// each window w of cell c; the cells are left zero
  void fold(std::uint64_t* counts, FixedSum* sums, std::uint64_t* density, FixedSum* density_w) const {
    const auto nb = static_cast<std::size_t>(bins);
    for (std::size_t c = 0; c < static_cast<std::size_t>(cells()); ++c)
      for (std::size_t b = 0; b < nb; ++b) {
        const std::size_t k = c * nb + b;
        if (counts[k] == 0) continue;  // nothing added to the cell's bin (a sum grows only with its count)
        for (unsigned m = windows[c]; m; m &= m - 1) {
          const auto w = static_cast<std::size_t>(__builtin_ctz(m));
          density[w * nb + b] += counts[k];
          if (sums) density_w[w * nb + b].merge(sums[k]);
        }
        counts[k] = 0;
        if (sums) sums[k] = FixedSum{};
      }
  }
};

/// f_c(s): counts collision positions in each requested time window.
template <class R>
struct DensityObserver {
  static constexpr bool active = true;
  const Stadium<R>* stadium;
  const std::vector<TimeWindow>* windows;
  int bins;
  std::uint64_t* counts;
  FixedSum* weighted_counts = nullptr;  ///< weighted runs: sums of the particle's weight
  double weight = 1;                    ///< of the particle in flight
  EdgeBins<R> edges[2] = {};            ///< bottom, top: built at the first ball_run()
  /// When set (the vectorised engine), a bounce is counted once, in its time cell: counts and
  /// weighted_counts are then by cell (cells x bins; DensityCells::fold gives the windows). Else by
  /// window (windows x bins).
  const DensityCells* cells = nullptr;

  void operator()(Piece p, const Vec2<R>& q, const R& t) {
    const double tt = num_traits<R>::to_double(t);
    bool any = false;
    for (const auto& w : *windows) any |= (tt >= w.from && tt <= w.to);
    if (!any) return;
    const int b = bin(p, q);
    if (cells) {  // once, in the time cell of tt
      add(cells->cell_of(tt), b, 1);
      return;
    }
    for (std::size_t i = 0; i < windows->size(); ++i)
      if (tt >= (*windows)[i].from && tt <= (*windows)[i].to) add(i, b, 1);
  }

  /// A fast-forward's phase of n bounces (particle.hpp fast_forward), counted as n calls would count
  /// them. Bounces of one parity lie on one edge (|x| <= d/2) with t and x monotone in j, so a
  /// window's bounces are an interval of j, found by bisection, and so is each bin's within it: its
  /// ends are where x passes the edge's bin changes (EdgeBins), found from the affine x of a stretch
  /// and checked on exact bounce positions. The work is per stretch and per bin change, not per bounce.
  void ball_run(const BallRun<R>& st) {
    const long n = st.n;
    const std::size_t nw = windows->size();
    if (edges[0].bin.empty()) build_edges();
    // each window's bounces [from, to) among this parity's (on the stack: a fast-forward shows many phases)
    constexpr std::size_t kInline = 8;
    std::pair<long, long> inline_span[kInline];
    std::vector<std::pair<long, long>> heap_span(nw > kInline ? nw : 0);
    std::pair<long, long>* span = nw > kInline ? heap_span.data() : inline_span;
    for (long parity = 1; parity <= 2 && parity <= n; ++parity) {
      const long m = (n - parity) / 2 + 1;  // j = parity + 2 i, i = 0 .. m - 1
      const auto at = [&](long i) { return st(parity + 2 * i); };
      const auto [lo, hi] = window_spans(st, parity, m, span);
      if (lo >= hi) continue;
      const auto run = [&](long a, long z, int b) { count_run(span, a, z, b); };
      const Bounce<R> first = at(lo);
      const EdgeBins<R>& e = edges[first.piece == Piece::top ? 1 : 0];
      const R x_last = at(hi - 1).q.x;
      const int b_first = bin(first.piece, first.q);
      if (b_first == bin(first.piece, Vec2<R>{x_last, first.q.y})) {  // one bin (monotone in i): no search
        run(lo, hi, b_first);
        continue;
      }
      const int k = e.where[static_cast<std::size_t>(b_first)];
      if (x_last > first.q.x)
        sweep<true>(st, parity, lo, hi, e, k, run);
      else
        sweep<false>(st, parity, lo, hi, e, k, run);
    }
  }

 private:
  /// Each edge's bin changes (EdgeBins), built at the first ball_run().
  void build_edges() {
    for (int top = 0; top < 2; ++top) {
      const Piece p = top ? Piece::top : Piece::bottom;
      const R y = top ? stadium->r() : R(-stadium->r());
      edges[top] = EdgeBins<R>::build(R(-stadium->half_d()), stadium->half_d(), [&](const R& x) {
        return bin(p, Vec2<R>{x, y});
      });
    }
  }

  /// Each window's bounces span[w] = [from, to) among the m bounces of this parity (bounce i is j = parity
  /// + 2 i): from the first with t >= from to the first with t > to, so bounce i has passed edge
  /// positions as its time has passed the window's edges. Returns the union's hull [lo, hi).
  std::pair<long, long> window_spans(const BallRun<R>& st, long parity, long m, std::pair<long, long>* span) const {
    const auto time = [&](long i) { return num_traits<R>::to_double(st(parity + 2 * i).t); };
    // (a window usually holds the whole phase: then its two end times say so)
    const double t_first = time(0), t_last = time(m - 1);
    long lo = m, hi = 0;
    for (std::size_t w = 0; w < windows->size(); ++w) {
      const TimeWindow& win = (*windows)[w];
      long a = 0, e = m;
      if (t_last < win.from) {
        a = e = m;
      } else if (t_first > win.to) {
        a = e = 0;
      } else if (!(t_first >= win.from && t_last <= win.to)) {
        a = first_true(0, m, [&](long i) { return time(i) >= win.from; });
        e = first_true(a, m, [&](long i) { return time(i) > win.to; });
      }
      span[w] = {a, e};
      if (a < e) lo = std::min(lo, a), hi = std::max(hi, e);
    }
    return {lo, hi};
  }

  /// Bounces [a, z) in bin b: added to every window they overlap, or once to each time cell among them.
  void count_run(const std::pair<long, long>* span, long a, long z, int b) {
    const std::size_t nw = windows->size();
    if (!cells) {
      for (std::size_t w = 0; w < nw; ++w) {
        const long from = std::max(a, span[w].first), to = std::min(z, span[w].second);
        if (from < to) add(w, b, static_cast<std::uint64_t>(to - from));
      }
      return;
    }
    while (a < z) {  // the cell of bounce a, and the next window edge after it
      std::size_t c = 0;
      long next = z;
      for (std::size_t w = 0; w < nw; ++w)
        for (const long edge : {span[w].first, span[w].second}) {
          if (a >= edge)
            ++c;
          else if (edge < next)
            next = edge;
        }
      if (cells->windows[c]) add(c, b, static_cast<std::uint64_t>(next - a));
      a = next;
    }
  }

  /// Runs of equal bins among bounces [lo, hi) of one parity (bounce i is j = parity + 2 i of the
  /// phase), x moving up (or down) from interval k of the edge's table: x leaves interval k where it
  /// passes x[k] (moving up) or falls below x[k - 1] (moving down). Within a stretch bounce j is
  /// x + j dx exactly, so the bounce that passes is estimated by one multiplication and settled by
  /// comparing exact bounce positions. run(a, z, b) takes each run, in order.
  template <bool Up, class Run>
  static void sweep(const BallRun<R>& st, long parity, long lo, long hi, const EdgeBins<R>& e, int k, const Run& run) {
    long a = lo;                        // the open run's first bounce; bounce i lies in interval k
    int g = st.index(parity + 2 * lo);  // the stretch of bounce i
    for (long i = lo; i < hi; ++g) {
      const long j = parity + 2 * i;
      while (st.end[g] < j) ++g;  // stretches too short to hold a bounce of this parity
      const Stretch<R>& part = st.part[g];
      const long i_end = std::min(hi, (st.end[g] - parity) / 2 + 1);  // past this stretch's last
      if (part.dx == 0) {                                             // x stands still in this stretch
        i = i_end;
        continue;
      }
      long jl = j - st.start(g);                                        // bounce i in the stretch
      const auto x_at = [&](long u) { return part.x_at(jl + 2 * u); };  // exact (Stretch::x_at)
      const R per_bounce = R(0.5) / part.dx;  // 1 / (x's step from one bounce of this parity to the next)
      for (;;) {
        if (Up ? k == e.changes() : k == 0) {  // no bin change left in this direction
          i = i_end;
          break;
        }
        const R edge = e.x[static_cast<std::size_t>(Up ? k : k - 1)];
        const auto passed = [&](long u) {
          const R v = x_at(u);
          return Up ? v >= edge : v < edge;
        };
        const long room = i_end - i;
        const R guess = (edge - x_at(0)) * per_bounce;  // bounces of this parity to the change
        long c = room;
        if (guess < R(static_cast<double>(room))) c = guess > R(0) ? static_cast<long>(std::ceil(guess)) : 0;
        while (c > 0 && passed(c - 1)) --c;
        while (c < room && !passed(c)) ++c;
        if (c == room) {  // the run goes on into the next stretch
          i = i_end;
          break;
        }
        const R v = x_at(c);
        const int b = e.bin[static_cast<std::size_t>(k)];
        if constexpr (Up)
          while (k < e.changes() && e.x[static_cast<std::size_t>(k)] <= v) ++k;
        else
          while (k > 0 && e.x[static_cast<std::size_t>(k - 1)] > v) --k;
        i += c, jl += 2 * c;
        run(a, i, b);
        a = i;
      }
    }
    run(a, hi, e.bin[static_cast<std::size_t>(k)]);
  }

  int bin(Piece p, const Vec2<R>& q) const { return density_bin_of(*stadium, p, q, bins); }
  int bin_of(double s) const { return density_bin_of(s, bins); }
  /// n bounces into bin b of row `row` (a window, or a time cell when `cells` is set)
  void add(std::size_t row, int b, std::uint64_t n) {
    const std::size_t k = row * static_cast<std::size_t>(bins) + static_cast<std::size_t>(b);
    counts[k] += n;
    if (weighted_counts) weighted_counts[k].add_times(weight, n);
  }
};

/// f_c on any table (and on the stadium with several leaks, which runs as a table): collisions counted by their
/// share of the whole boundary, Table::boundary_share (the loops laid end to end in order; on a table of one loop
/// that is s), in every time window that holds them.
template <class R>
struct TableDensityObserver {
  static constexpr bool active = true;
  const Table<R>* table = nullptr;
  const std::vector<TimeWindow>* windows = nullptr;
  int bins = 0;
  std::uint64_t* counts = nullptr;
  FixedSum* weighted_counts = nullptr;  ///< weighted runs (a split run's members): sums of the particle's weight
  double weight = 1;                    ///< of the particle in flight

  void operator()(int piece, const Vec2<R>& q, const R& t) {
    const double tt = num_traits<R>::to_double(t);
    int b = -1;  // the bin, worked out at the first window that holds t
    for (std::size_t i = 0; i < windows->size(); ++i) {
      if (!(tt >= (*windows)[i].from && tt <= (*windows)[i].to)) continue;
      if (b < 0) b = density_bin_of(*table, piece, q, bins);
      const std::size_t k = i * static_cast<std::size_t>(bins) + static_cast<std::size_t>(b);
      ++counts[k];
      if (weighted_counts) weighted_counts[k].add(weight);
    }
  }
};

/// The vectorised kernel's f_c time cells (simd::DensityHit): bit w of cells[c] (c = 0 .. 2 windows)
/// says window w = [from[w], to[w]] holds the times t of cell c = #{v: t >= from[v]} + #{v: t > to[v]}.
void density_cells(int windows, const double* from, const double* to, unsigned* cells);

}  // namespace rotleak
