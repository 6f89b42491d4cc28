// Leaks on any table: each an interval of width lambda in one loop's s whose centre moves as
// s_L(t) = s_L(0) + omega t mod 1 (LeakSchedule, leak/leak.hpp), built from its exact description into plain numbers
// (LeakView, leak/leak_window.hpp), and a list of them. A leak decides an escape at a collision as the stadium's Leak
// does, with the same two paths that must agree: a stationary leak's windows, precomputed per piece (a coordinate
// range on a segment, two half-planes from the centre on an arc: no transcendental function per hit), and a moving
// leak's phase and s test (leak_formulas.hpp); the test itself is first_leak (leak/leak_window.hpp), which the
// vectorised kernel runs on its lanes. On the stadium built as a table (geometry/table.hpp) every window and every
// decision is the stadium Leak's, bit for bit (tests/test_table.cpp).
#pragma once

#include <cmath>

#include "geometry/table.hpp"
#include "leak/leak.hpp"
#include "leak/leak_formulas.hpp"
#include "leak/leak_window.hpp"
#include "numeric/device.hpp"
#include "numeric/exact.hpp"
#include "numeric/num_traits.hpp"

namespace rotleak {

/// One leak's exact description: the loop it lies on (0: the outer boundary), its width in that loop's s, its
/// centre's s at t = 0 and its angular speed omega (>= 0 runs with s, < 0 against it).
struct LeakSpec {
  int loop = 0;
  ExactReal width, start, omega;
};

namespace detail {

/// The window of arc p from angle u to angle v along its travel.
template <class R>
void add_arc_window(LeakView<R>& v, int k, const TablePiece<R>& p, const R& u, const R& w) {
  using std::cos;
  using std::sin;
  const Vec2<R> du = p.arc_direction(cos(u), sin(u)), dw = p.arc_direction(cos(w), sin(w));
  PieceWindow<R>& pw = v.window[v.n_windows++];
  pw.piece = k;
  pw.w.from = p.clockwise ? du : dw;
  pw.w.to = p.clockwise ? dw : du;
}

/// A stationary leak's windows on each piece of its loop: the leak and its images one turn either side, cut to the
/// piece's s range; on a segment a coordinate range, on an arc the directions at the window's ends (at most a half
/// turn apart: two half-planes; a longer window in two). Clockwise from `from` to `to`: along the travel on a
/// clockwise arc, against it on an anticlockwise one.
template <class R>
void build_windows(const Table<R>& table, int loop, LeakView<R>& v) {
  const R& c = v.start;
  const R L = table.loop_length(loop);
  for (int k = v.first; k < v.first + v.count; ++k) {
    const TablePiece<R>& p = table.piece(k);
    v.win_first[k] = v.n_windows;
    for (int shift = -1; shift <= 1; ++shift) {
      const R a = c - v.half_width + R(shift), b = c + v.half_width + R(shift);
      const R lo = a > p.s0 ? a : p.s0;
      const R hi = b < p.s1 ? b : p.s1;
      if (lo > hi) continue;
      if (p.kind == PieceKind::segment) {
        // the coordinate of the main axis at s: r + ((s - s_ref) L) e, monotone along the segment
        const R e = p.along_x ? p.ex : p.ey, r = p.along_x ? p.rx : p.ry;
        const R ca = r + ((lo - p.s_ref) * L) * e, cb = r + ((hi - p.s_ref) * L) * e;
        PieceWindow<R>& pw = v.window[v.n_windows++];
        pw.piece = k;
        pw.w.lo = ca < cb ? ca : cb;
        pw.w.hi = ca < cb ? cb : ca;
        continue;
      }
      const R scale = L / p.rho;
      const R ta = (lo - p.s0) * scale, tb = (hi - p.s0) * scale;
      const bool split = tb - ta > num_traits<R>::pi();
      const R mid = split ? R((ta + tb) / 2) : tb;
      add_arc_window(v, k, p, ta, mid);
      if (split) add_arc_window(v, k, p, mid, tb);
    }
    v.win_count[k] = v.n_windows - v.win_first[k];
  }
}

}  // namespace detail

/// A leak on a table rounded into R, as plain numbers (leak/leak_window.hpp): its schedule rounded as the
/// stadium's Leak rounds it (LeakSchedule: the start reduced exactly into [0, 1), omega as hi + lo), its half width
/// rounded once, its pieces' middles and reaches, and its windows when stationary.
template <class R>
LeakView<R> table_leak(const Table<R>& table, const LeakSpec& spec) {
  const LeakSchedule<R> schedule(spec.start, spec.omega);
  LeakView<R> v{};
  v.first = table.loop_first(spec.loop);
  v.count = table.loop_count(spec.loop);
  // a leak on an ellipse decides by the hit's s even when it stands still (its phase is then its start, exactly):
  // an ellipse's windows would need their ends' points, the inverse of its arc length, for no gain
  const bool on_ellipse = table.piece(v.first).kind == PieceKind::ellipse;
  v.by_s = schedule.rotating() || on_ellipse;
  v.omega_hi = schedule.omega_terms().hi, v.omega_lo = schedule.omega_terms().lo;
  v.start = schedule.start();
  v.half_width = round_exact<R>(spec.width / ExactReal::parse("2"));
  for (int k = v.first; k < v.first + v.count; ++k) {
    const TablePiece<R>& p = table.piece(k);
    v.mid[k] = (p.s0 + p.s1) / 2;
    v.reach[k] = (p.s1 - p.s0) / 2 + v.half_width;
  }
  if (!v.by_s) detail::build_windows(table, spec.loop, v);
  return v;
}

/// A table's leaks, in order: a collision escapes through the first that takes it.
template <class R>
class LeakList {
 public:
  LeakList() = default;
  template <class Specs>
  LeakList(const Table<R>& table, const Specs& specs) {
    for (const LeakSpec& s : specs) leak_[n_++] = table_leak(table, s);
  }
  ROTLEAK_HD int size() const { return n_; }
  ROTLEAK_HD const LeakView<R>& operator[](int i) const { return leak_[i]; }

  /// The leak that takes a particle hitting piece k at q at time t, or -1 (first_leak, leak/leak_window.hpp: the
  /// kernel's own test); the hit's s is computed once, if a moving leak asks for it.
  ROTLEAK_HD int hit(const Table<R>& table, int k, const Vec2<R>& q, const R& t) const {
    bool have = false;
    R s{0};
    const auto s_of = [&](bool, const R&, const R&) -> const R& {
      if (!have) s = table.s_of(k, q), have = true;
      return s;
    };
    return first_leak(leak_, n_, &table.piece(0), k, q.x, q.y, t, true, s_of, [](const R& a, const R& b, const R& p) {
      return num_traits<R>::product_error(a, b, p);  // exact: a b = p + error
    });
  }

 private:
  LeakView<R> leak_[kMaxLeaks];
  int n_ = 0;
};

}  // namespace rotleak
