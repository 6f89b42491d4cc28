// The stadium's physics, written once: every expression of a flight, a collision and a boundary
// coordinate, over a number type T that is one number of any tier (Stadium<R>, the generic core) or a
// pack of lanes (the vectorised kernel, sim/kernel/simd_kernel.ipp). Branches go through the selection hook
// (numeric/select.hpp): a plain branch for one number, so an interval tier still refuses an undecided
// one; a lane select for a pack. Each expression is evaluated in one order with one rounding per
// operation, which is what makes the kernel's bits the core's (with -ffp-contract=off, no FMA is
// formed from these products and sums).
// Header-only and templates only, with no other dependency: the kernel's translation units, compiled
// for AVX2 or AVX-512, instantiate these on their own (internal) pack types alone, so no vector copy of
// a function the scalar code uses can reach the linker (ctest Layers.KernelObjectsShareNoInlineCode).
// Conventions (docs/model.md, "The billiard"): straight edges y = +-r for |x| <= d/2, arc centres
// (+-d/2, 0), s in [0, 1) clockwise from the midpoint of the top edge.
#pragma once

#include <cmath>

#include "geometry/vec2.hpp"
#include "numeric/device.hpp"
#include "numeric/select.hpp"

namespace rotleak::formula {

/// Time of the flight from height qy with vertical speed vy to the line y = ey.
template <class T>
ROTLEAK_HD inline T line_flight(const T& ey, const T& qy, const T& vy) {
  return (ey - qy) / vy;
}

/// How far a coordinate moves in time t at speed v.
template <class T>
ROTLEAK_HD inline T displacement(const T& v, const T& t) {
  return v * t;
}

/// A coordinate of the flight at time t: q + v t.
template <class T>
ROTLEAK_HD inline T along(const T& q, const T& v, const T& t) {
  return q + displacement(v, t);
}

/// A point's x relative to an arc's centre (its y is already: the centres lie on y = 0).
template <class T>
ROTLEAK_HD inline T from_centre(const T& x, const T& cx) {
  return x - cx;
}

/// The flight from (dx, qy), relative to an arc's centre, along unit v meets the circle of radius r where
/// t^2 + 2bt + c = 0: its b, its c, and sq, the square root of its discriminant (a grazing flight's,
/// pushed below zero by rounding, counts as zero).
template <class T>
ROTLEAK_HD inline T arc_b(const T& dx, const T& qy, const T& vx, const T& vy) {
  return dx * vx + qy * vy;
}
template <class T>
ROTLEAK_HD inline T arc_c(const T& dx, const T& qy, const T& r) {
  return (dx - r) * (dx + r) + qy * qy;
}
template <class T>
ROTLEAK_HD inline T arc_sq(const T& b, const T& c) {
  using std::sqrt;
  const T disc = b * b - c;
  return sqrt(select(disc < T(0), T(0), disc));
}
/// Its larger root, in the form without cancellation: sq - b where b <= 0 (nearly always: a flight
/// towards the far side of the circle), else -c / (b + sq).
template <class T>
ROTLEAK_HD inline T larger_root_near(const T& b, const T& sq) {
  return sq - b;
}
template <class T>
ROTLEAK_HD inline T larger_root_far(const T& b, const T& c, const T& sq) {
  return -c / (b + sq);
}
/// When the flight leaves the circle (the larger root).
template <class T>
ROTLEAK_HD inline T arc_exit(const T& dx, const T& qy, const T& vx, const T& vy, const T& r) {
  const T b = arc_b(dx, qy, vx, vy), c = arc_c(dx, qy, r), sq = arc_sq(b, c);
  return choose(
      b <= T(0), [&] { return larger_root_near(b, sq); }, [&] { return larger_root_far(b, c, sq); });
}

/// The next collision of a flight: its time, its point, and which of the four pieces it is on.
template <class T>
struct Exit {
  T t, x, y;
  T cx;                   ///< centre x of the arc on the side the flight leaves |x| <= d/2 (arc hits)
  mask_of<T> straight{};  ///< on a straight edge
  mask_of<T> up{};        ///< moving up (on the top edge, for a straight hit)
  mask_of<T> right{};     ///< on the right arc (for an arc hit)
};

/// The straight edges decide first: a flight that is not horizontal (flat) and crosses the line of its
/// edge at xl inside |x| <= d/2 hits that edge.
template <class T>
ROTLEAK_HD inline mask_of<T> hits_straight_edge(const mask_of<T>& flat, const T& xl, const T& half_d) {
  using std::abs;
  return both(!flat, [&] { return mask_of<T>(abs(xl) <= half_d); });
}
/// Otherwise it leaves through the arc on the side where it crosses that line (convexity), or, flat,
/// the side it moves to: is that the right arc?
template <class T>
ROTLEAK_HD inline mask_of<T> leaves_right(const mask_of<T>& straight, const mask_of<T>& flat, const T& vx,
                                          const T& xl) {
  using Mask = mask_of<T>;
  return both(!straight, [&] {
    return choose(
        flat, [&] { return Mask(vx > T(0)); }, [&] { return Mask(xl > T(0)); });
  });
}

/// Where the flight from q along unit v (q inside or on the boundary) next meets the boundary:
/// hits_straight_edge, else leaves_right and the arc's larger root, so at most one quadratic is solved.
/// (The kernel's next_hit composes the same pieces with its selects made per register.)
template <class T>
ROTLEAK_HD inline Exit<T> next_exit(const T& r, const T& half_d, const T& qx, const T& qy, const T& vx, const T& vy) {
  using Mask = mask_of<T>;
  Exit<T> h;
  const Mask flat = vy == T(0);
  h.up = vy > T(0);
  const T ey = select(h.up, r, T(-r));
  // the flight to the line y = ey (a horizontal one divides by zero: no comparison looks at its tl, xl)
  const T tl = line_flight(ey, qy, vy);
  const T xl = along(qx, vx, tl);
  h.straight = hits_straight_edge(flat, xl, half_d);
  h.right = leaves_right(h.straight, flat, vx, xl);
  h.cx = select(h.right, half_d, T(-half_d));
  h.t = choose(
      h.straight, [&] { return tl; }, [&] { return arc_exit(from_centre(qx, h.cx), qy, vx, vy, r); });
  h.x = choose(
      h.straight, [&] { return xl; }, [&] { return along(qx, vx, h.t); });
  h.y = choose(
      h.straight, [&] { return ey; }, [&] { return along(qy, vy, h.t); });
  return h;
}

/// Specular reflection of velocity v at (x, y): the vertical component flips on a straight edge; on an
/// arc, v is reflected about the radius vector w = (x - cx, y) as it is (not w / r): v' = v - k w with
/// k = 2 (w . v) / (w . w), so |v'| = |v| whatever |w| is, and a point a few ulps off the circle cannot
/// feed back into the speed (with w / r it does, and chaos amplifies it to a blow-up within a few dozen
/// collisions).
template <class T>
ROTLEAK_HD inline T reflect_factor(const T& wx, const T& wy, const T& vx, const T& vy) {
  return T(2) * (wx * vx + wy * vy) / (wx * wx + wy * wy);
}
/// One component of v - k w.
template <class T>
ROTLEAK_HD inline T reflected(const T& v, const T& k, const T& w) {
  return v - k * w;
}
template <class T>
ROTLEAK_HD inline Vec2<T> reflect(const mask_of<T>& straight, const T& cx, const T& x, const T& y, const T& vx,
                                  const T& vy) {
  return choose(
      straight,
      [&] {
        return Vec2<T>{vx, T(-vy)};
      },
      [&] {
        const T wx = from_centre(x, cx);
        const T k = reflect_factor(wx, y, vx, vy);
        return Vec2<T>{reflected(vx, k, wx), reflected(vy, k, y)};
      });
}

/// Does a flight just reflected off a straight edge at x cross between the straight edges at least n
/// times before it reaches an arc? Each crossing moves x by 2r |vx| / |vy|, so: (room to the arc) |vy|
/// >= n 2r |vx|, without a division. An estimate that chooses when to jump a bouncing-ball phase
/// (fast_forward, the kernel's hand-off), never what the jump computes.
template <class T>
ROTLEAK_HD inline mask_of<T> straight_run_at_least(const T& x, const T& vx, const T& vy, const T& half_d, const T& r,
                                                   const T& n) {
  using std::abs;
  const T room = select(vx > T(0), T(half_d - x), T(half_d + x));
  return room * abs(vy) >= T(2) * n * r * abs(vx);
}

/// s of a point x on the top edge: x / L, wrapped into [0, 1).
template <class T>
ROTLEAK_HD inline T top_s(const T& x, const T& inv_L) {
  T s = x * inv_L;
  s = select(s < T(0), T(s + T(1)), s);
  return select(s >= T(1), T(0), s);
}

/// s of a point x on the bottom edge, which starts at junction1 (its right end, x = d/2).
template <class T>
ROTLEAK_HD inline T bottom_s(const T& x, const T& half_d, const T& inv_L, const T& junction1) {
  return junction1 + (half_d - x) * inv_L;
}

/// s of a point x on a straight edge: the top one when `up`, else the bottom one.
template <class T>
ROTLEAK_HD inline T straight_s(const mask_of<T>& up, const T& x, const T& half_d, const T& inv_L, const T& junction1) {
  return choose(
      up, [&] { return top_s(x, inv_L); }, [&] { return bottom_s(x, half_d, inv_L, junction1); });
}

/// The arguments of the atan2(y, x) that gives an arc point's angle from the arc's start, clockwise:
/// from the top of the right arc atan2(x - d/2, y), from the bottom of the left one atan2(-(x + d/2), -y).
template <class T>
ROTLEAK_HD inline T arc_angle_y(const mask_of<T>& right, const T& x, const T& half_d) {
  return select(right, T(x - half_d), T(-(x + half_d)));
}
template <class T>
ROTLEAK_HD inline T arc_angle_x(const mask_of<T>& right, const T& y) {
  return select(right, y, T(-y));
}

/// s of an arc point from its angle (clamped to [0, pi]) and the arc's start in s.
template <class T>
ROTLEAK_HD inline T arc_s(T angle, const T& start, const T& r_over_L, const T& pi) {
  angle = select(angle < T(0), T(0), angle);
  angle = select(angle > pi, pi, angle);
  return start + angle * r_over_L;
}

/// f_c's bin of boundary coordinate s among `bins` equal bins of [0, 1): floor(s bins), clamped to
/// [0, bins - 1] (as an integer-valued T).
template <class T>
ROTLEAK_HD inline T density_bin(const T& s, const T& bins) {
  using std::floor;
  const T b = floor(s * bins);
  return select(b < T(0), T(0), select(b > T(bins - T(1)), T(bins - T(1)), b));
}

/// f_c's time cell of t among `windows` time windows [from[w], to[w]]: how many of their edges t has
/// passed, counting from[w] when t >= from[w] and to[w] when t > to[w] (0 .. 2 windows, as an
/// integer-valued T). The cell fixes the set of windows that hold t, so a collision is counted once, in
/// its cell, and each cell is added to its windows afterwards.
template <class T>
ROTLEAK_HD inline T time_cell(const T& t, const double* from, const double* to, int windows) {
  const T one(1.0), zero(0.0);
  T cell(0.0);
  for (int w = 0; w < windows; ++w) cell = cell + select(t >= T(from[w]), one, zero) + select(t > T(to[w]), one, zero);
  return cell;
}

/// A stationary leak's window on a straight edge: x in [lo, hi].
template <class T>
ROTLEAK_HD inline mask_of<T> in_x_window(const T& x, const T& lo, const T& hi) {
  return both(x >= lo, [&] { return mask_of<T>(x <= hi); });
}

/// A stationary leak's window on an arc, the sub-arc clockwise from direction `from` to `to` (at most pi)
/// seen from the arc's centre: the point rel (relative to the centre) between them, two half-plane tests.
template <class T>
ROTLEAK_HD inline mask_of<T> in_arc_window(const Vec2<T>& rel, const Vec2<T>& from, const Vec2<T>& to) {
  return both(cross(from, rel) <= T(0), [&] { return mask_of<T>(cross(rel, to) <= T(0)); });
}

// ---- a boundary point from its coordinate s, and a Birkhoff start's velocity (the initial states) ----

/// A point of the boundary, its unit tangent towards growing s and its unit inward normal.
template <class T>
struct Frame {
  Vec2<T> q, tangent, normal;
};

/// The top edge's point at s (s < junction 0, or s >= junction 3 for its left half): x = s L or (s - 1) L.
template <class T>
ROTLEAK_HD inline Frame<T> top_frame(const mask_of<T>& right_half, const T& s, const T& L, const T& r) {
  return {{select(right_half, T(s * L), T((s - T(1)) * L)), r}, {T(1), T(0)}, {T(0), T(-1)}};
}

/// The bottom edge's point at s: x = d/2 - (s - junction 1) L.
template <class T>
ROTLEAK_HD inline Frame<T> bottom_frame(const T& s, const T& L, const T& half_d, const T& r, const T& junction1) {
  return {{half_d - (s - junction1) * L, T(-r)}, {T(-1), T(0)}, {T(0), T(1)}};
}

/// The angle of an arc point from the arc's start (the top of the right arc, the bottom of the left one),
/// clockwise: (s - start) L / r.
template <class T>
ROTLEAK_HD inline T arc_angle_of(const T& s, const T& start, const T& L_over_r) {
  return (s - start) * L_over_r;
}

/// An arc's point at that angle, from its sine sn and cosine cs: the right arc's when `right`, else the
/// left one's.
template <class T>
ROTLEAK_HD inline Frame<T> arc_frame(const mask_of<T>& right, const T& half_d, const T& r, const T& sn, const T& cs) {
  return {{select(right, T(half_d + r * sn), T(T(-half_d) - r * sn)), select(right, T(r * cs), T(-(r * cs)))},
          {select(right, cs, T(-cs)), select(right, T(-sn), sn)},
          {select(right, T(-sn), sn), select(right, T(-cs), cs)}};
}

/// A flow start's direction angle 2 pi u, u in [0, 1).
template <class T>
ROTLEAK_HD inline T flow_angle(const T& pi, const T& u) {
  return T(2) * pi * u;
}

/// The outgoing unit velocity of Birkhoff momentum p at a boundary point: sqrt(1 - p^2) n + p T.
template <class T>
ROTLEAK_HD inline Vec2<T> birkhoff_velocity(const Frame<T>& f, const T& p) {
  using std::sqrt;
  const T c = sqrt((T(1) - p) * (T(1) + p));
  return {c * f.normal.x + p * f.tangent.x, c * f.normal.y + p * f.tangent.y};
}

}  // namespace rotleak::formula
