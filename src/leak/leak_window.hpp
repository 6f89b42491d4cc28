// A table's leak in plain numbers (LeakView: what table_leak builds, leak/table_leak.hpp, and what the vectorised
// kernel copies) and the leak test of a hit, written once for one number of any tier and for a pack of lanes (the
// vectorised kernel): a stationary leak's windows -- a coordinate range on a segment (x where the segment runs more
// along x than y, else y), two half-planes from the centre on an arc (no transcendental function per hit) -- and a
// moving leak's exact phase, may_touch and the hit's s (leak/leak_formulas.hpp); first_leak walks a list of leaks as
// nearest_crossing walks the pieces (geometry/table_piece.hpp). Header-only, no container and no exact type: a
// device compiler can take it whole.
#pragma once

#include <type_traits>

#include "geometry/formulas.hpp"
#include "geometry/table_piece.hpp"
#include "geometry/vec2.hpp"
#include "leak/leak_formulas.hpp"
#include "numeric/device.hpp"
#include "numeric/select.hpp"

namespace rotleak {

/// The most leaks a table may have.
inline constexpr int kMaxLeaks = 8;
/// A window: the coordinate range [lo, hi] on a segment; on an arc the directions from its centre that bound the
/// sub-arc, clockwise from `from` to `to` (at most a half turn).
template <class R>
struct LeakWindow {
  R lo{0}, hi{0};
  Vec2<R> from, to;
};

/// A window on piece `piece`.
template <class R>
struct PieceWindow {
  int piece = 0;
  LeakWindow<R> w;
};

/// One leak of a table in plain numbers: the pieces of its loop [first, first + count), its schedule (omega as
/// hi + lo, its centre's s at t = 0 in [0, 1)), its half width, its windows when stationary (the windows of a piece
/// in the order they lie along it, and where each piece's begin: up to six a piece, the leak and its images one turn
/// either side, an arc's window of more than a half turn in two), and each piece's middle in s and how far from it
/// the leak's centre can be while touching it (may_touch) when it moves. P: the pieces it has room for (a table's
/// most; the stadium's four).
template <class R, int P = kMaxTablePieces>
struct LeakView {
  int first = 0, count = 0;
  bool by_s = false;  ///< decided by its phase and the hit's s (a moving leak; any leak on an ellipse), not by windows
  R omega_hi{0}, omega_lo{0}, start{0}, half_width{0};
  int n_windows = 0;
  PieceWindow<R> window[6 * P];
  int win_first[P], win_count[P];  ///< piece k's windows: [win_first, + win_count)
  R mid[P], reach[P];
};

/// Does window w of piece p hold the point (x, y) of that piece?
template <class T, class R>
ROTLEAK_HD inline mask_of<T> in_window(const TablePiece<R>& p, const LeakWindow<R>& w, const T& x, const T& y) {
  if (p.kind == PieceKind::segment) return formula::in_x_window(p.along_x ? x : y, T(w.lo), T(w.hi));
  const Vec2<T> rel{formula::from_centre(x, T(p.cx)), formula::from_centre(y, T(p.cy))};
  return formula::in_arc_window(rel, Vec2<T>{T(w.from.x), T(w.from.y)}, Vec2<T>{T(w.to.x), T(w.to.y)});
}

/// The lanes of `on` on piece k. `piece`: each lane's piece index (one number: its piece), or a function k -> the
/// mask of the lanes on piece k (a kernel that knows its pieces by cheaper masks than an index).
template <class M, class PieceOf>
[[gnu::always_inline]] ROTLEAK_HD inline M lanes_on(const PieceOf& piece, int k, const M& on) {
  if constexpr (std::is_invocable_v<const PieceOf&, int>)
    return M(on & piece(k));
  else
    return M(on & (piece == PieceOf(k)));
}

/// f(k, lanes) for each piece k of [first, first + count) that a lane of `on` lies on (the lanes that do): one
/// number calls f once, with its own piece.
template <class PieceOf, class M, class F>
[[gnu::always_inline]] ROTLEAK_HD inline void each_piece(const PieceOf& piece, int first, int count, const M& on,
                                                         const F& f) {
  if constexpr (std::is_same_v<M, bool>) {
    f(piece, on);
  } else {
    for (int k = first; k < first + count; ++k) {
      const M here = lanes_on(piece, k, on);
      if (!none(here)) f(k, here);
    }
  }
}

/// The leak test of one leak, written once for one number of any tier and for a pack of lanes: the lanes of `here`
/// (hits on the leak's loop, on piece `piece` -- see lanes_on -- at (x, y) at time t) that leak l takes. A stationary
/// leak decides by its windows of that piece; a moving one by its exact centre at t (formula::leak_phase, the exact
/// error of omega_hi t from `product_error`), then, on an arc, whether it can touch the arc now (formula::may_touch),
/// then the hit's s (formula::in_leak). `s_of(lanes, c, hw)` gives the hit's s for the lanes that ask, exact enough
/// that in_leak(s, c, hw) decides as with the exact s (the decision's edges are c -+ hw: a filtered s, such as the
/// stadium kernel's cascade of angles, refines only the lanes near them): one number computes it once, when first
/// asked; a pack each lane's once (its cache), for the lanes a moving leak asks. One number stops at the first window
/// that holds it (an interval's undecided comparison with a later window is never made).
template <class T, class R, int P, class PieceOf, class SOf, class ProductError>
[[gnu::always_inline]] ROTLEAK_HD inline mask_of<T> leak_takes(const LeakView<R, P>& l, const TablePiece<R>* pieces,
                                                               const PieceOf& piece, const T& x, const T& y, const T& t,
                                                               const mask_of<T>& here, SOf& s_of,
                                                               const ProductError& product_error) {
  using M = mask_of<T>;
  M in(false);
  if (!l.by_s) {
    // one number looks at its piece's windows only; a pack at every window, lane by lane
    int from = 0, to = l.n_windows;
    if constexpr (std::is_same_v<M, bool>) from = l.win_first[piece], to = from + l.win_count[piece];
    for (int i = from; i < to; ++i) {
      const PieceWindow<R>& w = l.window[i];
      const M on = lanes_on(piece, w.piece, here);  // one number: always its own piece's window
      in = M(in | (on & in_window(pieces[w.piece], w.w, x, y)));
      if constexpr (std::is_same_v<M, bool>)
        if (in) break;
    }
    return in;
  }
  const T c = formula::leak_phase(T(l.omega_hi), T(l.omega_lo), T(l.start), t, product_error);
  M asks(false);
  each_piece(piece, l.first, l.count, here, [&](int k, const M& on) {
    const bool arc = pieces[k].kind == PieceKind::arc;
    asks = M(asks | (arc ? M(on & formula::may_touch(T(l.mid[k]), c, T(l.reach[k]))) : on));
  });
  if (!none(asks)) {
    const T hw(l.half_width);
    in = M(asks & formula::in_leak(s_of(asks, c, hw), c, hw));
  }
  return in;
}

/// The leak test of a list, for one number of any tier (LeakList<R>::hit) and for a pack of lanes (the kernel's table
/// step): of leaks [0, n), the index of the first that takes a hit on piece `piece` (an index) at (x, y) at time t,
/// for the lanes of `look` (-1: none); each leak by leak_takes, asked only about the lanes on its loop that no earlier
/// leak took, so one number stops at the first leak that takes it, as an interval tier must (a later leak's
/// undecided comparison is never made).
template <class T, class R, int P, class SOf, class ProductError>
[[gnu::always_inline]] ROTLEAK_HD inline piece_index_of<T> first_leak(const LeakView<R, P>* leaks, int n,
                                                                      const TablePiece<R>* pieces,
                                                                      const piece_index_of<T>& piece, const T& x,
                                                                      const T& y, const T& t, const mask_of<T>& look,
                                                                      SOf& s_of, const ProductError& product_error) {
  using M = mask_of<T>;
  using I = piece_index_of<T>;
  I taken(-1);
  M open = look;
  for (int j = 0; j < n; ++j) {
    const LeakView<R, P>& l = leaks[j];
    const M here = M(open & (piece >= I(l.first)) & (piece < I(l.first + l.count)));
    if (none(here)) continue;
    const M in = leak_takes(l, pieces, piece, x, y, t, here, s_of, product_error);
    if constexpr (std::is_same_v<M, bool>) {
      if (in) return j;
    } else {
      taken = select(in, I(j), taken);
      open = M(open & !in);
    }
  }
  return taken;
}

}  // namespace rotleak
