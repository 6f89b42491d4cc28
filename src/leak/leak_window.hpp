// A stationary leak's window on one piece of a table (TableLeak, leak/table_leak.hpp), and the test whether a hit
// lies in it, written once for one number of any tier and for a pack of lanes (the vectorised kernel): a coordinate
// range on a segment (x where the segment runs more along x than y, else y), two half-planes from the centre on an
// arc (no transcendental function per hit). Header-only, no container and no exact type.
#pragma once

#include "geometry/formulas.hpp"
#include "geometry/table_piece.hpp"
#include "geometry/vec2.hpp"
#include "numeric/select.hpp"

namespace rotleak {

/// A window: the coordinate range [lo, hi] on a segment; on an arc the directions from its centre that bound the
/// sub-arc, clockwise from `from` to `to` (at most a half turn).
template <class R>
struct LeakWindow {
  R lo{0}, hi{0};
  Vec2<R> from, to;
};

/// Does window w of piece p hold the point (x, y) of that piece?
template <class T, class R>
inline mask_of<T> in_window(const TablePiece<R>& p, const LeakWindow<R>& w, const T& x, const T& y) {
  if (p.kind == PieceKind::segment) return formula::in_x_window(p.along_x ? x : y, T(w.lo), T(w.hi));
  const Vec2<T> rel{formula::from_centre(x, T(p.cx)), formula::from_centre(y, T(p.cy))};
  return formula::in_arc_window(rel, Vec2<T>{T(w.from.x), T(w.from.y)}, Vec2<T>{T(w.to.x), T(w.to.y)});
}

}  // namespace rotleak
