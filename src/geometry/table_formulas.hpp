// A billiard table's pieces, written once: the flight to a straight segment or a circular arc, the hit's
// place on its piece, the reflection, and the boundary coordinate, over a number type T that is one number of
// any tier (Table<R>) or a pack of lanes (a vectorised engine). A piece's own data (its ends, centre,
// directions) is the same for every lane: plain numbers, converted with T(x). Branches on lanes go through the
// selection hook (numeric/select.hpp), as in geometry/formulas.hpp, whose circle formulas (arc_b, arc_c,
// arc_sq, the two roots, reflect_factor) these reuse: on the stadium's pieces every expression here is the
// stadium's own, operation for operation, so a table built as the stadium computes the stadium's bits
// (tests/test_table.cpp checks it ray by ray; docs/model.md, "Tables").
// Conventions (docs/model.md, "Tables"): every loop of the boundary is traversed with the table on its right
// (the outer boundary clockwise, a scatterer anticlockwise), so the inward normal is the direction of travel
// turned clockwise, n = (e.y, -e.x); a flight leaves the table through a piece where it crosses it outward.
// Header-only, templates only, no containers and no other dependency: a device compiler can take it whole.
#pragma once

#include <cmath>

#include "geometry/formulas.hpp"
#include "numeric/device.hpp"
#include "numeric/select.hpp"

namespace rotleak::formula {

/// The flight from q along v meets the line through a with unit direction e where
/// t cross(v, e) = cross(a - q, e); it crosses outward where cross(v, e) = v . n < 0 (n = (e.y, -e.x)).
/// On a line parallel to x (e = (+-1, 0)) the two are -+(a.y - q.y) and -+v.y exactly: the stadium's
/// (ey - qy) / vy (line_flight) to the bit.
template <class T, class P>
ROTLEAK_HD inline T segment_den(const T& vx, const T& vy, const P& ex, const P& ey) {
  return vx * T(ey) - vy * T(ex);
}
template <class T, class P>
ROTLEAK_HD inline T segment_num(const T& qx, const T& qy, const P& ax, const P& ay, const P& ex, const P& ey) {
  return (T(ax) - qx) * T(ey) - (T(ay) - qy) * T(ex);
}

/// Is coordinate c of a hit on the segment, whose ends have that coordinate lo <= hi (x where the segment runs
/// more along x than y, else y), within tol of it?
template <class T, class P>
ROTLEAK_HD inline mask_of<T> in_span(const T& c, const P& lo, const P& hi, const P& tol) {
  return both(c >= T(P(lo - tol)), [&] { return mask_of<T>(c <= T(P(hi + tol))); });
}

/// The entry root of a circle (t^2 + 2bt + c = 0, b < 0: the flight approaches it), the smaller one, without
/// cancellation: c / (sq - b). A dispersing piece (the table outside its circle) is met there.
template <class T>
ROTLEAK_HD inline T smaller_root(const T& b, const T& c, const T& sq) {
  return c / (sq - b);
}

/// The exit root, the larger one, as the stadium's arc_exit takes it: sq - b where b <= 0, else -c / (b + sq).
/// A focusing piece (the table inside its circle) is met there.
template <class T>
ROTLEAK_HD inline T larger_root(const T& b, const T& c, const T& sq) {
  return choose(
      b <= T(0), [&] { return larger_root_near(b, sq); }, [&] { return larger_root_far(b, c, sq); });
}

/// Is the point rel (relative to an arc's centre) on the arc that runs clockwise from direction f to direction
/// g, within tol (in units of |rel| |f|)? At most a half turn: two half-planes, cross(f, rel) <= 0 and
/// cross(rel, g) <= 0 (as in_arc_window); more: not strictly inside the rest, the arc clockwise from g to f.
template <class T, class P>
ROTLEAK_HD inline mask_of<T> on_arc(const T& rx, const T& ry, const P& fx, const P& fy, const P& gx, const P& gy,
                                    bool wide, const P& tol) {
  const T a = T(fx) * ry - T(fy) * rx;  // cross(f, rel)
  const T b = rx * T(gy) - ry * T(gx);  // cross(rel, g)
  if (!wide) return both(a <= T(tol), [&] { return mask_of<T>(b <= T(tol)); });
  return !both(a > T(tol), [&] { return mask_of<T>(b > T(tol)); });
}

/// The arguments (y, x) of the atan2 that gives a point's angle along an arc from its start direction f, in the
/// direction of travel: (cross(rel, f), rel . f) clockwise, (cross(f, rel), rel . f) anticlockwise. With f = (0, 1)
/// (the stadium's right arc) these are (rel.x, rel.y), with f = (0, -1) (its left arc) (-rel.x, -rel.y): the
/// stadium's arc_angle_y and arc_angle_x to the bit.
template <class T, class P>
ROTLEAK_HD inline T arc_param_y(const T& rx, const T& ry, const P& fx, const P& fy, bool clockwise) {
  return clockwise ? T(rx * T(fy) - ry * T(fx)) : T(T(fx) * ry - T(fy) * rx);
}
template <class T, class P>
ROTLEAK_HD inline T arc_param_x(const T& rx, const T& ry, const P& fx, const P& fy) {
  return rx * T(fx) + ry * T(fy);
}

/// s of an arc point from its angle along the arc (from atan2, in (-pi, pi]): an arc of at most a half turn
/// clamps it to [0, span] (the stadium's arc_s); a longer one first takes a negative angle below the middle of
/// the gap, (span - 2 pi) / 2, as a turn further on.
template <class T, class P>
ROTLEAK_HD inline T arc_piece_s(T angle, const P& start, const P& span, const P& rho_over_L, bool wide,
                                const P& two_pi) {
  if (wide) angle = select(angle < T(P((span - two_pi) / 2)), T(angle + T(two_pi)), angle);
  angle = select(angle < T(0), T(0), angle);
  angle = select(angle > T(span), T(span), angle);
  return T(start) + angle * T(rho_over_L);
}

/// s of a segment point: s_ref + ((x - rx) e.x + (y - ry) e.y) / L, from the segment's reference point (rx, ry)
/// at s_ref (its start, or the loop's origin where the segment holds it); wrapped into [0, 1) as top_s.
template <class T, class P>
ROTLEAK_HD inline T segment_piece_s(const T& x, const T& y, const P& rx, const P& ry, const P& ex, const P& ey,
                                    const P& s_ref, const P& inv_L) {
  T s = T(s_ref) + ((x - T(rx)) * T(ex) + (y - T(ry)) * T(ey)) * T(inv_L);
  s = select(s < T(0), T(s + T(1)), s);
  return select(s >= T(1), T(0), s);
}

/// Wraps an arc's s into [0, 1) (an arc that holds the loop's origin starts below 0).
template <class T>
ROTLEAK_HD inline T wrap_unit(const T& s) {
  const T w = select(s < T(0), T(s + T(1)), s);
  return select(w >= T(1), T(w - T(1)), w);
}

}  // namespace rotleak::formula
