// Leaks on any table: each an interval of width lambda in one loop's s whose centre moves as
// s_L(t) = s_L(0) + omega t mod 1 (LeakSchedule, leak/leak.hpp), and a list of them. A leak decides an escape at a
// collision as the stadium's Leak does, with the same two paths that must agree: a stationary leak's windows,
// precomputed per piece (a coordinate range on a segment, two half-planes from the centre on an arc: no
// transcendental function per hit), and a moving leak's phase and s test (leak_formulas.hpp). On the stadium built
// as a table (geometry/table.hpp) every window and every decision is the stadium Leak's, bit for bit
// (tests/test_table.cpp).
#pragma once

#include <cmath>

#include "geometry/table.hpp"
#include "leak/leak.hpp"
#include "leak/leak_formulas.hpp"
#include "leak/leak_window.hpp"
#include "numeric/exact.hpp"
#include "numeric/num_traits.hpp"

namespace rotleak {

/// The most leaks a table may have.
inline constexpr int kMaxLeaks = 8;

/// One leak's exact description: the loop it lies on (0: the outer boundary), its width in that loop's s, its
/// centre's s at t = 0 and its angular speed omega (>= 0 runs with s, < 0 against it).
struct LeakSpec {
  int loop = 0;
  ExactReal width, start, omega;
};

template <class R>
class TableLeak {
 public:
  /// A stationary window on one piece (leak/leak_window.hpp).
  using Window = LeakWindow<R>;
  /// Up to three windows per piece (the leak and its images one turn either side; an arc's window of more than
  /// a half turn in two).
  struct PieceWindows {
    Window w[6];
    int n = 0;
  };

  TableLeak() = default;
  TableLeak(const Table<R>& table, const LeakSpec& spec)
      : loop_(spec.loop),
        schedule_(spec.start, spec.omega),
        half_width_(round_exact<R>(spec.width / ExactReal::parse("2"))) {
    first_ = table.loop_first(loop_);
    count_ = table.loop_count(loop_);
    for (int k = first_; k < first_ + count_; ++k) {
      const TablePiece<R>& p = table.piece(k);
      mid_[k] = (p.s0 + p.s1) / 2;
      reach_[k] = (p.s1 - p.s0) / 2 + half_width_;
    }
    if (!schedule_.rotating()) build_windows(table);
  }

  int loop() const { return loop_; }
  const LeakSchedule<R>& schedule() const { return schedule_; }
  const R& half_width() const { return half_width_; }
  /// Piece k's middle in s and how far from it the leak's centre can be while touching it.
  const R& piece_mid(int k) const { return mid_[k]; }
  const R& reach(int k) const { return reach_[k]; }
  /// The stationary windows of piece k (none for a moving leak, or a piece of another loop).
  const PieceWindows& windows(int k) const { return windows_[k]; }

  /// Does the leak take a particle that hits piece k at q at time t? `s` gives the hit's s when the test needs it
  /// (a moving leak on a piece it may touch): table.s_of(k, q).
  template <class S>
  bool hit(const Table<R>& table, int k, const Vec2<R>& q, const R& t, const S& s) const {
    if (k < first_ || k >= first_ + count_) return false;
    if (!schedule_.rotating()) return in_windows(table, k, q);
    const R c = schedule_.phase(t);
    // on an arc, skip the s (an atan2) unless the leak overlaps this arc now
    if (table.piece(k).kind == PieceKind::arc && !formula::may_touch(mid_[k], c, reach_[k])) return false;
    return formula::in_leak(s(), c, half_width_);
  }
  bool hit(const Table<R>& table, int k, const Vec2<R>& q, const R& t) const {
    return hit(table, k, q, t, [&] { return table.s_of(k, q); });
  }

 private:
  void build_windows(const Table<R>& table) {
    const R c = schedule_.start();
    const R L = table.loop_length(loop_);
    for (int k = first_; k < first_ + count_; ++k) {
      const TablePiece<R>& p = table.piece(k);
      for (int shift = -1; shift <= 1; ++shift) {
        const R a = c - half_width_ + R(shift), b = c + half_width_ + R(shift);
        const R lo = a > p.s0 ? a : p.s0;
        const R hi = b < p.s1 ? b : p.s1;
        if (lo > hi) continue;
        PieceWindows& pw = windows_[k];
        if (p.kind == PieceKind::segment) {
          // the coordinate of the main axis at s: r + ((s - s_ref) L) e, monotone along the segment
          const R e = p.along_x ? p.ex : p.ey, r = p.along_x ? p.rx : p.ry;
          const R ca = r + ((lo - p.s_ref) * L) * e, cb = r + ((hi - p.s_ref) * L) * e;
          Window w;
          w.lo = ca < cb ? ca : cb;
          w.hi = ca < cb ? cb : ca;
          pw.w[pw.n++] = w;
          continue;
        }
        // the directions at the window's ends (TablePiece::arc_direction), at most a half turn apart (two
        // half-planes): a longer window in two. Clockwise from `from` to `to`: along the travel on a clockwise arc,
        // against it on an anticlockwise one.
        const R scale = L / p.rho;
        const R ta = (lo - p.s0) * scale, tb = (hi - p.s0) * scale;
        const bool split = tb - ta > num_traits<R>::pi();
        const R mid = split ? R((ta + tb) / 2) : tb;
        add_arc_window(pw, p, ta, mid);
        if (split) add_arc_window(pw, p, mid, tb);
      }
    }
  }

  /// The window of arc p from angle u to angle v along its travel.
  static void add_arc_window(PieceWindows& pw, const TablePiece<R>& p, const R& u, const R& v) {
    using std::cos;
    using std::sin;
    const Vec2<R> du = p.arc_direction(cos(u), sin(u)), dv = p.arc_direction(cos(v), sin(v));
    Window w;
    w.from = p.clockwise ? du : dv;
    w.to = p.clockwise ? dv : du;
    pw.w[pw.n++] = w;
  }

  bool in_windows(const Table<R>& table, int k, const Vec2<R>& q) const {
    const PieceWindows& pw = windows_[k];
    for (int i = 0; i < pw.n; ++i)
      if (in_window(table.piece(k), pw.w[i], q.x, q.y)) return true;
    return false;
  }

  int loop_ = 0, first_ = 0, count_ = 0;
  LeakSchedule<R> schedule_{ExactReal(), ExactReal()};
  R half_width_{0};
  R mid_[kMaxTablePieces], reach_[kMaxTablePieces];
  PieceWindows windows_[kMaxTablePieces];
};

/// A table's leaks, in order: a collision escapes through the first that takes it.
template <class R>
class LeakList {
 public:
  LeakList() = default;
  template <class Specs>
  LeakList(const Table<R>& table, const Specs& specs) {
    for (const LeakSpec& s : specs) leak_[n_++] = TableLeak<R>(table, s);
  }
  int size() const { return n_; }
  const TableLeak<R>& operator[](int i) const { return leak_[i]; }

  /// The leak that takes a particle hitting piece k at q at time t, or -1; the hit's s is computed once, if needed.
  int hit(const Table<R>& table, int k, const Vec2<R>& q, const R& t) const {
    bool have = false;
    R s{0};
    const auto s_of = [&]() -> const R& {
      if (!have) s = table.s_of(k, q), have = true;
      return s;
    };
    for (int i = 0; i < n_; ++i)
      if (leak_[i].hit(table, k, q, t, s_of)) return i;
    return -1;
  }

 private:
  TableLeak<R> leak_[kMaxLeaks];
  int n_ = 0;
};

}  // namespace rotleak
