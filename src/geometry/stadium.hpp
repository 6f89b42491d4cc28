// The Bunimovich stadium, written once for any number type R (double, long double, MPFR, ...).
// Conventions (docs/model.md, "The billiard"): straight edges at y = +-r for |x| <= d/2, arc centres (+-d/2, 0);
// s in [0,1) is arc length / L, clockwise from the midpoint of the top edge.
#pragma once

#include <cmath>
#include <type_traits>

#include "geometry/formulas.hpp"
#include "geometry/vec2.hpp"
#include "numeric/atan2.hpp"
#include "numeric/device.hpp"
#include "numeric/exact.hpp"
#include "numeric/num_traits.hpp"
#include "numeric/sin_cos.hpp"

namespace rotleak {

/// The four smooth pieces of the boundary, in the order s meets them (top is split by s = 0).
enum class Piece : int { top = 0, right_arc = 1, bottom = 2, left_arc = 3 };

template <class R>
struct Hit {
  R t{0};  ///< flight time (= length: speed 1)
  Piece piece{Piece::top};
  Vec2<R> q;  ///< collision point
};

/// A point of the boundary with its frame.
template <class R>
struct BoundaryPoint {
  Piece piece{Piece::top};
  Vec2<R> q;        ///< position
  Vec2<R> tangent;  ///< unit tangent towards increasing s
  Vec2<R> normal;   ///< unit inward normal
};

template <class R>
class Stadium {
 public:
  /// Every derived constant (L, the junctions) is rounded once from its exact value.
  Stadium(const ExactReal& d, const ExactReal& r)
      : d_(round_exact<R>(d)),
        r_(round_exact<R>(r)),
        half_d_(round_exact<R>(d / ExactReal::parse("2"))),
        inv_r_(round_exact<R>(ExactReal::parse("1") / r)) {
    const ExactReal pr = ExactReal::pi() * r;
    const ExactReal L = ExactReal::parse("2") * d + ExactReal::parse("2") * pr;
    const ExactReal hd = d / ExactReal::parse("2");
    L_ = round_exact<R>(L);
    inv_L_ = round_exact<R>(ExactReal::parse("1") / L);
    r_over_L_ = round_exact<R>(r / L);
    L_over_r_ = round_exact<R>(L / r);
    junction_[0] = round_exact<R>(hd / L);
    junction_[1] = round_exact<R>((hd + pr) / L);
    junction_[2] = round_exact<R>((ExactReal::parse("3") * hd + pr) / L);
    junction_[3] = round_exact<R>((ExactReal::parse("3") * hd + ExactReal::parse("2") * pr) / L);
    area_ = round_exact<R>(ExactReal::parse("2") * r * d + pr * r);
    mean_free_path_ = round_exact<R>(ExactReal::pi() * (ExactReal::parse("2") * r * d + pr * r) / L);
    pi_ = num_traits<R>::pi();
  }

  ROTLEAK_HD const R& d() const { return d_; }
  ROTLEAK_HD const R& r() const { return r_; }
  ROTLEAK_HD const R& half_d() const { return half_d_; }
  ROTLEAK_HD const R& perimeter() const { return L_; }
  /// 1 / L and r / L, each rounded once from its exact value (not 1 / fl(L)): s of a straight-edge point
  /// is (x +- ...) inv_perimeter(), of an arc point its angle times r_over_perimeter() (formula::straight_s,
  /// formula::arc_s). Every engine takes them from here, so that every engine computes the same s.
  ROTLEAK_HD const R& inv_perimeter() const { return inv_L_; }
  ROTLEAK_HD const R& r_over_perimeter() const { return r_over_L_; }
  /// L / r, an arc point's angle per unit of s (formula::arc_angle_of), rounded once from its exact value.
  ROTLEAK_HD const R& L_over_r() const { return L_over_r_; }
  ROTLEAK_HD const R& area() const { return area_; }
  /// The billiard flow's mean free path, pi area / L (Santalo), rounded once from its exact value.
  ROTLEAK_HD const R& mean_free_path() const { return mean_free_path_; }
  ROTLEAK_HD const R& pi() const { return pi_; }
  /// s of the start of piece k+1: right arc, bottom, left arc, top-left half of the top edge.
  ROTLEAK_HD const R& junction(int k) const { return junction_[k]; }
  /// Whether s in [0, 1) lies on a straight edge (the top: s < junction(0) or s >= junction(3); the bottom:
  /// junction(1) <= s < junction(2)), as at() places it.
  ROTLEAK_HD bool on_straight(const R& s) const {
    return s < junction_[0] || s >= junction_[3] || (s >= junction_[1] && s < junction_[2]);
  }

  /// Centre x of an arc piece.
  ROTLEAK_HD R arc_centre_x(Piece p) const { return p == Piece::right_arc ? half_d_ : R(-half_d_); }

  /// Point and frame at boundary coordinate s in [0,1) (the formulas of geometry/formulas.hpp; an arc's sine
  /// and cosine by sin_cos below).
  ROTLEAK_HD BoundaryPoint<R> at(const R& s) const {
    BoundaryPoint<R> b;
    formula::Frame<R> f;
    if (s < junction_[0] || s >= junction_[3]) {
      b.piece = Piece::top;
      f = formula::top_frame(s < junction_[0], s, L_, r_);
    } else if (s < junction_[1]) {
      b.piece = Piece::right_arc;
      const auto sc = sin_cos(formula::arc_angle_of(s, junction_[0], L_over_r_));
      f = formula::arc_frame(true, half_d_, r_, sc.sin, sc.cos);
    } else if (s < junction_[2]) {
      b.piece = Piece::bottom;
      f = formula::bottom_frame(s, L_, half_d_, r_, junction_[1]);
    } else {
      b.piece = Piece::left_arc;
      const auto sc = sin_cos(formula::arc_angle_of(s, junction_[2], L_over_r_));
      f = formula::arc_frame(false, half_d_, r_, sc.sin, sc.cos);
    }
    b.q = f.q;
    b.tangent = f.tangent;
    b.normal = f.normal;
    return b;
  }

  /// sin and cos of an angle in [0, 2 pi] (formula::tier_sin_cos: the shared formula in the double tier, which
  /// the vectorised kernel evaluates too, the tier's own in every other).
  ROTLEAK_HD static formula::SinCos<R> sin_cos(const R& angle) { return formula::tier_sin_cos(angle); }

  /// Boundary coordinate s in [0,1) of a point q on piece p (the formulas of geometry/formulas.hpp).
  [[gnu::always_inline]] ROTLEAK_HD R s_of(Piece p, const Vec2<R>& q) const {
    if (p == Piece::top || p == Piece::bottom)
      return formula::straight_s(p == Piece::top, q.x, half_d_, inv_L_, junction_[1]);
    const bool right = p == Piece::right_arc;
    const R angle = formula::tier_atan2(formula::arc_angle_y(right, q.x, half_d_), formula::arc_angle_x(right, q.y));
    return formula::arc_s(angle, right ? junction_[0] : junction_[2], r_over_L_, pi_);
  }

  ROTLEAK_HD Vec2<R> tangent(Piece p, const Vec2<R>& q) const {
    switch (p) {
      case Piece::top:
        return {R(1), R(0)};
      case Piece::bottom:
        return {R(-1), R(0)};
      default:
        return {q.y * inv_r_, R(-(q.x - arc_centre_x(p)) * inv_r_)};
    }
  }
  ROTLEAK_HD Vec2<R> inward_normal(Piece p, const Vec2<R>& q) const {
    switch (p) {
      case Piece::top:
        return {R(0), R(-1)};
      case Piece::bottom:
        return {R(0), R(1)};
      default:
        return {R((arc_centre_x(p) - q.x) * inv_r_), R(-q.y * inv_r_)};
    }
  }

  /// Where the ray q + t v (|v| = 1, q inside or on the boundary) next meets the boundary
  /// (formula::next_exit: the straight edges decide first, at most one quadratic is solved).
  ROTLEAK_HD Hit<R> next_hit(const Vec2<R>& q, const Vec2<R>& v) const {
    const formula::Exit<R> e = formula::next_exit(r_, half_d_, q.x, q.y, v.x, v.y);
    Hit<R> h;
    h.t = e.t;
    h.piece = e.straight ? (e.up ? Piece::top : Piece::bottom) : (e.right ? Piece::right_arc : Piece::left_arc);
    h.q = {e.x, e.y};
    return h;
  }

  /// Specular reflection of velocity v at point q of piece p (formula::reflect: about the radius
  /// vector as it is, on an arc).
  ROTLEAK_HD Vec2<R> reflect(Piece p, const Vec2<R>& q, const Vec2<R>& v) const {
    const bool straight = p == Piece::top || p == Piece::bottom;
    return formula::reflect(straight, straight ? R(0) : arc_centre_x(p), q.x, q.y, v.x, v.y);
  }

  /// Birkhoff momentum p = sin(theta) = v_out . T of an outgoing velocity at a collision.
  ROTLEAK_HD R birkhoff_p(Piece p, const Vec2<R>& q, const Vec2<R>& v_out) const { return dot(v_out, tangent(p, q)); }

  /// Outgoing unit velocity for Birkhoff (s, p): sqrt(1-p^2) n_in + p T (formula::birkhoff_velocity).
  ROTLEAK_HD Vec2<R> velocity(const BoundaryPoint<R>& b, const R& p) const {
    return formula::birkhoff_velocity(formula::Frame<R>{b.q, b.tangent, b.normal}, p);
  }

 private:
  R d_, r_, half_d_, inv_r_;
  R L_, inv_L_, r_over_L_, L_over_r_, area_, mean_free_path_, pi_;
  R junction_[4];
};

}  // namespace rotleak
