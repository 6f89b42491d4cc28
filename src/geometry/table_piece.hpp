// One piece of a billiard table rounded into a number type R (Table<R>, geometry/table.hpp), and what a flight does
// there, written once for one number of any tier and for a pack of lanes (the vectorised kernel): the outward
// crossing of the piece within its span (crossing), the axis a reflection there takes and the reflection
// (reflection_axis, reflect_about), and the boundary coordinate s of a point of it (segment_point_s, arc_angle_args,
// arc_point_s). T is the flight's number type: R itself, or a pack whose lanes share the piece's numbers (R = double).
// Branches on lanes go through the selection hook (numeric/select.hpp); `none(m)` asks whether no lane (or the one
// number) holds, so one number skips what a pack computes for all its lanes. Every expression is a formula of
// geometry/table_formulas.hpp or geometry/formulas.hpp, so the stadium built as a table computes the stadium's bits.
// Header-only, no container and no exact type: a device compiler can take it whole.
#pragma once

#include <type_traits>

#include "geometry/formulas.hpp"
#include "geometry/table_formulas.hpp"
#include "geometry/vec2.hpp"
#include "numeric/carlson.hpp"
#include "numeric/device.hpp"
#include "numeric/select.hpp"

namespace rotleak {

/// The most pieces and loops a table may have (a polygon of up to 30 sides, up to 7 scatterers): the engines
/// hold a table in fixed arrays, with no allocation on the path a particle takes.
inline constexpr int kMaxTablePieces = 32;
inline constexpr int kMaxTableLoops = 8;

enum class PieceKind : int { segment = 0, arc = 1, ellipse = 2 };

/// One piece rounded into R (the fields of its kind; the others stay 0).
template <class R>
struct TablePiece {
  PieceKind kind = PieceKind::segment;
  int loop = 0;
  bool clockwise = true, full = false;
  bool wide = false;    ///< arc: more than a half turn
  bool along_x = true;  ///< segment: runs at least as much along x as along y (its span test is on x)
  bool horizontal = false, vertical = false;  ///< segment: parallel to an axis (the hit keeps that coordinate)
  R ax{0}, ay{0}, bx{0}, by{0};               ///< its ends
  R ex{0}, ey{0};                             ///< segment: unit direction of travel (rounded from the exact one)
  R lo{0}, hi{0};                             ///< segment: the span test's range (x or y of its ends, in order)
  R rx{0}, ry{0}, s_ref{0};                   ///< segment: where s is s_ref (its start, or the loop's origin)
  R cx{0}, cy{0}, rho{0}, inv_rho{0};         ///< arc
  R fx{0}, fy{0};                             ///< arc: the direction of its start from the centre
  R cw_fx{0}, cw_fy{0}, cw_gx{0}, cw_gy{0};   ///< arc: its ends' directions in clockwise order (on_arc)
  R span{0}, rho_over_L{0}, L_over_rho{0};
  R ea{0}, eb{0};          ///< ellipse (centre cx, cy): its semi-axes along x and y
  R inv_ea{0}, inv_eb{0};  ///< ellipse: 1 / its semi-axes
  R ea2{0}, eb2{0};        ///< ellipse: the semi-axes squared
  R ga{0}, gb{0};          ///< ellipse: 1 / ea^2, 1 / eb^2 (its gradient's scale: the reflection's axis)
  R s0{0}, s1{0};          ///< its s range in its loop, unwrapped (s0 < 0 for the piece that holds the origin)

  /// Arc: the direction from the centre at angle a along the travel, f cos a + h sin a (h = f turned a quarter along
  /// the travel), from cs = cos a and sn = sin a; and the unit tangent there, h cos a - f sin a.
  ROTLEAK_HD Vec2<R> arc_direction(const R& cs, const R& sn) const {
    const Vec2<R> h = turned();
    return {fx * cs + h.x * sn, fy * cs + h.y * sn};
  }
  ROTLEAK_HD Vec2<R> arc_tangent(const R& cs, const R& sn) const {
    const Vec2<R> h = turned();
    return {h.x * cs - fx * sn, h.y * cs - fy * sn};
  }

 private:
  ROTLEAK_HD Vec2<R> turned() const { return clockwise ? Vec2<R>{fy, R(-fx)} : Vec2<R>{R(-fy), fx}; }
};

/// A flight's crossing of one piece: its time, point, and the reflection's axis there (reflection_axis).
template <class T>
struct Crossing {
  T t, x, y, wx, wy;
};

/// The axis a reflection at (x, y) on piece p takes (formula::reflect_factor's w): the segment's inward normal
/// (e.y, -e.x) as rounded, the arc's radius vector, the ellipse's gradient (x / a^2, y / b^2) from its centre.
template <class T, class R>
ROTLEAK_HD inline Vec2<T> reflection_axis(const TablePiece<R>& p, const T& x, const T& y) {
  if (p.kind == PieceKind::segment) return {T(p.ey), T(-p.ex)};
  const T dx = formula::from_centre(x, T(p.cx)), dy = formula::from_centre(y, T(p.cy));
  if (p.kind == PieceKind::ellipse) return {T(dx * T(p.ga)), T(dy * T(p.gb))};
  return {dx, dy};
}

/// Specular reflection of v about the axis w (|v'| = |v| whatever |w| is).
template <class T>
ROTLEAK_HD inline Vec2<T> reflect_about(const Vec2<T>& w, const Vec2<T>& v) {
  const T k = formula::reflect_factor(w.x, w.y, v.x, v.y);
  return {formula::reflected(v.x, k, w.x), formula::reflected(v.y, k, w.y)};
}

/// Does the flight from q along unit v cross piece p outward within its span widened by tol? Where it does, c holds
/// the crossing (the lanes that do not: junk). A segment is crossed where the flight meets its line going out
/// (cross(v, e) < 0) at t >= 0; a focusing arc (the table inside its circle) where the flight leaves the circle, a
/// dispersing one where it enters it (b < 0), on the arc's part of the circle. The discriminant comes before c's
/// sign: from a point on the circle (c = 0 up to rounding: an interval tier cannot decide c's sign) it is clearly
/// positive, and decides alone. An ellipse is a unit circle in the coordinates scaled by its semi-axes: the same
/// quadratic there, t^2 + 2 b t + c = 0 divided by |V|^2 (V the scaled velocity), crossed as an arc is.
template <class T, class R>
[[gnu::always_inline]] ROTLEAK_HD inline mask_of<T> crossing(const TablePiece<R>& p, const T& qx, const T& qy,
                                                             const T& vx, const T& vy, const R& tol, Crossing<T>& c) {
  using M = mask_of<T>;
  const T zero(0);
  if (p.kind == PieceKind::segment) {
    const T den = formula::segment_den(vx, vy, p.ex, p.ey);
    M ok = den < zero;  // outward
    if (none(ok)) return ok;
    c.t = formula::segment_num(qx, qy, p.ax, p.ay, p.ex, p.ey) / den;
    ok = both(ok, [&] { return M(c.t >= zero); });
    if (none(ok)) return ok;
    c.x = p.vertical ? T(p.ax) : formula::along(qx, vx, c.t);
    c.y = p.horizontal ? T(p.ay) : formula::along(qy, vy, c.t);
    c.wx = T(p.ey), c.wy = T(-p.ex);
    return both(ok, [&] { return formula::in_span(p.along_x ? c.x : c.y, p.lo, p.hi, tol); });
  }
  const T dx = formula::from_centre(qx, T(p.cx)), dy = formula::from_centre(qy, T(p.cy));
  T b, cc;
  if (p.kind == PieceKind::ellipse) {
    const T X = dx * T(p.inv_ea), Y = dy * T(p.inv_eb), VX = vx * T(p.inv_ea), VY = vy * T(p.inv_eb);
    const T vv = VX * VX + VY * VY;
    b = formula::arc_b(X, Y, VX, VY) / vv, cc = formula::arc_c(X, Y, T(1)) / vv;
  } else {
    b = formula::arc_b(dx, dy, vx, vy), cc = formula::arc_c(dx, dy, T(p.rho));
  }
  M ok;
  if (p.clockwise) {  // focusing: from outside the circle, and missing it, no crossing
    ok = !both(M(b * b - cc < zero), [&] { return M(cc > zero); });
    if (none(ok)) return ok;
    c.t = formula::larger_root(b, cc, formula::arc_sq(b, cc));
  } else {  // dispersing: approaching the circle, and meeting it
    ok = both(M(b < zero), [&] { return M(!(b * b - cc < zero)); });
    if (none(ok)) return ok;
    c.t = formula::smaller_root(b, cc, formula::arc_sq(b, cc));
  }
  ok = both(ok, [&] { return M(c.t >= zero); });
  if (none(ok)) return ok;
  c.x = formula::along(qx, vx, c.t), c.y = formula::along(qy, vy, c.t);
  const Vec2<T> w = reflection_axis(p, c.x, c.y);
  c.wx = w.x, c.wy = w.y;
  if (p.full) return ok;
  return both(ok,
              [&] { return formula::on_arc(c.wx, c.wy, p.cw_fx, p.cw_fy, p.cw_gx, p.cw_gy, p.wide, R(tol * p.rho)); });
}

/// A piece's index as a flight's number type holds it: an int for one number, a pack of lane values for a pack.
template <class T>
using piece_index_of = std::conditional_t<std::is_same_v<mask_of<T>, bool>, int, T>;

/// The nearest crossing so far: time, point, reflection axis (Crossing's), the piece (-1: none) and whether one was
/// found.
template <class T>
struct NearestCrossing {
  T t, x, y, wx, wy;
  piece_index_of<T> piece;
  mask_of<T> found;
};

/// Table::nearest, written once for one number of any tier (Table<R>::next_hit) and for a pack of lanes (the
/// vectorised kernel's table step): for the lanes of `want`, every piece's outward crossing within its span widened
/// by tol, the nearest kept in `best` (the first piece on a tie: a later one only when strictly nearer). `best`
/// comes in with found false (or with what an earlier look found). One number asks every piece (`want` true).
template <class T, class R>
[[gnu::always_inline]] ROTLEAK_HD inline void nearest_crossing(const TablePiece<R>* pieces, int n, const T& qx,
                                                               const T& qy, const T& vx, const T& vy, const R& tol,
                                                               const mask_of<T>& want, NearestCrossing<T>& best) {
  using M = mask_of<T>;
  using I = piece_index_of<T>;
  for (int k = 0; k < n; ++k) {
    Crossing<T> c;  // set where a lane crosses (one number: set in full first; a pack's zeroing costs time)
    if constexpr (std::is_same_v<M, bool>) c = {};
    const M ok = M(want & crossing(pieces[k], qx, qy, vx, vy, tol, c));  // a lambda here: a call per piece
    if (none(ok)) continue;
    const M take = both(ok, [&] {
      return choose(
          best.found, [&] { return M(c.t < best.t); }, [] { return M(true); });
    });
    best.t = select(take, c.t, best.t), best.x = select(take, c.x, best.x), best.y = select(take, c.y, best.y);
    best.wx = select(take, c.wx, best.wx), best.wy = select(take, c.wy, best.wy);
    best.piece = select(take, I(k), best.piece);
    best.found = M(best.found | take);
  }
}

/// s of a point of segment p (its loop's 1 / length inv_L), in [0, 1).
template <class T, class R>
ROTLEAK_HD inline T segment_point_s(const TablePiece<R>& p, const T& x, const T& y, const R& inv_L) {
  return formula::segment_piece_s(x, y, p.rx, p.ry, p.ex, p.ey, p.s_ref, inv_L);
}

/// The arguments (y, x) of the atan2 that gives the angle of (x, y) along arc p from its start.
template <class T, class R>
ROTLEAK_HD inline Vec2<T> arc_angle_args(const TablePiece<R>& p, const T& x, const T& y) {
  const T rx = formula::from_centre(x, T(p.cx)), ry = formula::from_centre(y, T(p.cy));
  return {formula::arc_param_x(rx, ry, p.fx, p.fy), formula::arc_param_y(rx, ry, p.fx, p.fy, p.clockwise)};
}

/// s in [0, 1) of the point of arc p at `angle` (atan2 of arc_angle_args) along it.
template <class T, class R>
ROTLEAK_HD inline T arc_point_s(const TablePiece<R>& p, const T& angle, const R& two_pi) {
  return formula::wrap_unit(formula::arc_piece_s(angle, p.s0, p.span, p.rho_over_L, p.wide, two_pi));
}

/// s in [0, 1) of a point (x, y) of ellipse p (its loop's 1 / length inv_L), s = 0 at its top, the quarters 1/4,
/// 1/2, 3/4 at its vertices (exactly: each quarter is a quarter of the length) in the direction of travel, for one
/// number of any tier (a pack's lanes call it one by one). In the scaled coordinates (X, Y) = (dx / a, dy / b) the
/// point is (sin psi, cos psi), psi its angle from the top clockwise; the arc is measured from the nearer vertex in
/// psi (from the top or bottom where |sin psi| <= |cos psi|, with P = a, Q = b and u = |sin psi|; else from the side
/// vertex, P = b, Q = a, u = |cos psi|), so u <= 1/sqrt(2) and the arc (carlson::ellipse_arc) is well conditioned.
template <class T, class R>
ROTLEAK_HD inline T ellipse_point_s(const TablePiece<R>& p, const T& x, const T& y, const R& inv_L) {
  using std::abs;
  using std::sqrt;
  const T X = formula::from_centre(x, T(p.cx)) * T(p.inv_ea), Y = formula::from_centre(y, T(p.cy)) * T(p.inv_eb);
  const T n = sqrt(X * X + Y * Y);
  const T sn = abs(X) / n, cs = abs(Y) / n;
  const bool polar = sn <= cs;  // nearer the top or the bottom
  const T J =
      polar ? carlson::ellipse_arc(sn, cs, T(p.ea2), T(p.eb2)) : carlson::ellipse_arc(cs, sn, T(p.eb2), T(p.ea2));
  const T share = J * T(inv_L);
  // travel clockwise: top (s = 0), right vertex (1/4), bottom (1/2), left vertex (3/4); anticlockwise mirrored in x
  const bool right = p.clockwise ? !(X < T(0)) : X < T(0), upper = !(Y < T(0));
  T s;
  if (polar)
    s = upper ? (right ? share : T(T(1) - share)) : (right ? T(T(0.5) - share) : T(T(0.5) + share));
  else
    s = right ? (upper ? T(T(0.25) - share) : T(T(0.25) + share)) : (upper ? T(T(0.75) + share) : T(T(0.75) - share));
  return s >= T(1) ? T(s - T(1)) : s;
}

/// The point of ellipse p at angle psi from its top in the direction of travel, from cs = cos psi and sn = sin psi,
/// and the unit tangent there (the direction of travel).
template <class R>
ROTLEAK_HD inline Vec2<R> ellipse_point(const TablePiece<R>& p, const R& cs, const R& sn) {
  const R x = p.clockwise ? R(p.ea * sn) : R(-(p.ea * sn));
  return {p.cx + x, p.cy + p.eb * cs};
}
template <class R>
ROTLEAK_HD inline Vec2<R> ellipse_tangent(const TablePiece<R>& p, const R& cs, const R& sn) {
  using std::sqrt;
  const R tx = p.ea * cs, ty = -(p.eb * sn);
  const R n = sqrt(tx * tx + ty * ty);
  return {p.clockwise ? R(tx / n) : R(-(tx / n)), R(ty / n)};
}

}  // namespace rotleak
