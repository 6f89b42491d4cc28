// Periodic orbits of the stadium as critical points of their length, written once for any number type
// R (double for the search, MPFR for the refinement, MPFI for the proof): docs/model.md, "Periodic
// orbits". An orbit of period n visits the pieces code[0..n-1] (cyclically) at points q_i(u_i): u_i is x
// on a straight edge and the angle on an arc. The length L(u) = sum |q_{i+1} - q_i| is stationary exactly
// where every bounce reflects: g_i = dL/du_i = t_i . (e_{i-1} - e_i) = 0 (t_i = dq_i/du_i, e_i the unit
// vector from q_i to q_{i+1}). Its Hessian is cyclic tridiagonal, and the same second derivatives of each
// segment's length (the billiard map's generating function) give the map's tangent map, hence the
// orbit's multiplier.
#pragma once

#include <cstddef>
#include <vector>

#include "geometry/stadium.hpp"
#include "geometry/vec2.hpp"

namespace rotleak::periodic {

/// The stadium as the orbit equations see it: half the straight length a = d/2, the radius r, and
/// pi/2 (the arcs' angles lie in (-pi/2, pi/2)). Rounded once from the exact values (enclosed in MPFI).
template <class R>
struct Shape {
  R a, r, half_pi;
  static Shape of(const ExactReal& d, const ExactReal& r) {
    const R two = R(2);
    return {round_exact<R>(d) / two, round_exact<R>(r), round_exact<R>(ExactReal::pi()) / two};
  }
  /// The bound of u on piece p: |u| < a on an edge, |u| < pi/2 on an arc.
  const R& bound(Piece p) const { return p == Piece::top || p == Piece::bottom ? a : half_pi; }
};

/// A bounce point q(u), its tangent dq/du and dq^2/du^2.
template <class R>
struct Point {
  Vec2<R> q, t, tt;
};

/// Point on piece p at parameter u: top (u, r), bottom (u, -r), right arc (a + r cos u, r sin u), left arc
/// (-a - r cos u, r sin u).
template <class R>
Point<R> point(const Shape<R>& s, Piece p, const R& u) {
  using std::cos;
  using std::sin;
  switch (p) {
    case Piece::top:
      return {{u, s.r}, {R(1), R(0)}, {R(0), R(0)}};
    case Piece::bottom:
      return {{u, R(-s.r)}, {R(1), R(0)}, {R(0), R(0)}};
    default: {
      const R c = cos(u), sn = sin(u), rc = s.r * c, rs = s.r * sn;
      if (p == Piece::right_arc) return {{s.a + rc, rs}, {R(-rs), rc}, {R(-rc), R(-rs)}};
      return {{R(-s.a) - rc, rs}, {rs, rc}, {rc, R(-rs)}};
    }
  }
}

/// One segment's length l(u, u') from q(u) to q'(u') and its derivatives: dl/du = -e.t, dl/du' = e.t',
/// and the second derivatives h11, h12, h22.
template <class R>
struct Segment {
  R length, d1, d2, h11, h12, h22;
};

/// x^2: for an interval the enclosure of the squares (x * x of an interval that holds 0 reaches below 0).
template <class R>
R square(const R& x) {
  if constexpr (requires { sqr(x); })
    return sqr(x);
  else
    return x * x;
}

template <class R>
Segment<R> segment(const Point<R>& p, const Point<R>& q) {
  using std::sqrt;
  const Vec2<R> v = q.q - p.q;
  const R l = sqrt(square(v.x) + square(v.y));
  const Vec2<R> e{v.x / l, v.y / l};
  const R ea = dot(e, p.t), eb = dot(e, q.t);
  Segment<R> s;
  s.length = l;
  s.d1 = -ea;
  s.d2 = eb;
  s.h11 = (square(p.t.x) + square(p.t.y) - square(ea)) / l - dot(e, p.tt);
  s.h12 = -(dot(p.t, q.t) - ea * eb) / l;
  s.h22 = (square(q.t.x) + square(q.t.y) - square(eb)) / l + dot(e, q.tt);
  return s;
}

/// The orbit equations at u: the length, the gradient g and the segments (segment i from bounce i to i+1).
template <class R>
struct Equations {
  R length;
  std::vector<R> g;
  std::vector<Segment<R>> seg;

  /// The Hessian of the length, dense (n x n, row-major): cyclic tridiagonal; for n = 2 both segments
  /// couple bounces 0 and 1.
  std::vector<R> hessian() const {
    const std::size_t n = seg.size();
    std::vector<R> h(n * n, R(0));
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = (i + 1) % n;
      h[i * n + i] = h[i * n + i] + seg[i].h11;
      h[j * n + j] = h[j * n + j] + seg[i].h22;
      h[i * n + j] = h[i * n + j] + seg[i].h12;
      h[j * n + i] = h[j * n + i] + seg[i].h12;
    }
    return h;
  }

  /// The trace of the billiard map's tangent map over the period, in (u, p) coordinates (p conjugate to u:
  /// p_i = -dl_i/du_i = dl_{i-1}/du_i). Each segment's matrix [[-h11/h12, -1/h12], [h12 - h22 h11/h12,
  /// -h22/h12]] has determinant 1, so the multipliers are Lambda and 1/Lambda with Lambda + 1/Lambda = trace.
  R trace() const {
    R m00 = R(1), m01 = R(0), m10 = R(0), m11 = R(1);
    for (const Segment<R>& s : seg) {
      const R a = -s.h11 / s.h12, b = R(-1) / s.h12, c = s.h12 - s.h22 * s.h11 / s.h12, d = -s.h22 / s.h12;
      const R n00 = a * m00 + b * m10, n01 = a * m01 + b * m11, n10 = c * m00 + d * m10, n11 = c * m01 + d * m11;
      m00 = n00, m01 = n01, m10 = n10, m11 = n11;
    }
    return m00 + m11;
  }
};

template <class R>
Equations<R> equations(const Shape<R>& s, const std::vector<Piece>& code, const std::vector<R>& u) {
  const std::size_t n = code.size();
  std::vector<Point<R>> pts;
  pts.reserve(n);
  for (std::size_t i = 0; i < n; ++i) pts.push_back(point(s, code[i], u[i]));
  Equations<R> e;
  e.length = R(0);
  e.g.assign(n, R(0));
  e.seg.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    e.seg.push_back(segment(pts[i], pts[j]));
    const Segment<R>& sg = e.seg.back();
    e.length = e.length + sg.length;
    e.g[i] = e.g[i] + sg.d1;
    e.g[j] = e.g[j] + sg.d2;
  }
  return e;
}

}  // namespace rotleak::periodic
