// A billiard table rounded into a tier: every value of a TableSpec (geometry/table_spec.hpp) rounded once from its
// exact value into R, held in fixed arrays (no allocation on a particle's path; Table<double> is plain data an
// engine or a device can copy), and the table's physics over R: the next hit over its pieces, the reflection,
// the boundary coordinate s of each loop, a boundary point's frame. Every expression is a formula of
// geometry/table_formulas.hpp (and of geometry/formulas.hpp, whose circle and reflection it shares), so a table
// built as the stadium computes the stadium's bits (tests/test_table.cpp; docs/model.md, "Tables").
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <utility>

#include "geometry/formulas.hpp"
#include "geometry/table_formulas.hpp"
#include "geometry/table_spec.hpp"
#include "geometry/vec2.hpp"
#include "numeric/atan2.hpp"
#include "numeric/device.hpp"
#include "numeric/exact.hpp"
#include "numeric/mpfi_ops.hpp"
#include "numeric/num_traits.hpp"
#include "numeric/sin_cos.hpp"

namespace rotleak {

/// Where a flight next meets the boundary: flight time, piece index (-1: nowhere, a flight through a gap the
/// rounding opened), point.
template <class R>
struct TableHit {
  R t{0};
  int piece = -1;
  Vec2<R> q;
};

/// A point of a loop with its unit tangent (the direction of travel, towards growing s) and inward normal.
template <class R>
struct TableFrame {
  int piece = 0;
  Vec2<R> q, tangent, normal;
};

template <class R>
class Table {
 public:
  explicit Table(const TableSpec& spec);

  ROTLEAK_HD int pieces() const { return n_pieces_; }
  ROTLEAK_HD int loops() const { return n_loops_; }
  ROTLEAK_HD const TablePiece<R>& piece(int k) const { return piece_[k]; }
  /// loop k's length, and its first piece and count
  ROTLEAK_HD const R& loop_length(int k) const { return loop_length_[k]; }
  ROTLEAK_HD int loop_first(int k) const { return loop_first_[k]; }
  ROTLEAK_HD int loop_count(int k) const { return loop_count_[k]; }
  /// 1 / loop k's length and the loops' lengths before it (rounded once from their exact values)
  ROTLEAK_HD const R& inv_loop_length(int k) const { return inv_loop_length_[k]; }
  ROTLEAK_HD const R& loop_offset(int k) const { return loop_offset_[k]; }
  /// the second look's widening of every span (kSpanSlack ulps of the scale), and 2 pi rounded once
  ROTLEAK_HD const R& slack() const { return slack_; }
  ROTLEAK_HD const R& two_pi() const { return two_pi_; }
  ROTLEAK_HD const R& area() const { return area_; }
  /// |boundary|: every loop's length
  ROTLEAK_HD const R& perimeter() const { return perimeter_; }
  /// The billiard flow's mean free path, pi area / |boundary| (Santalo), rounded once from its exact value.
  ROTLEAK_HD const R& mean_free_path() const { return mean_free_path_; }
  /// pi, rounded once.
  ROTLEAK_HD const R& pi() const { return pi_; }
  /// The largest |coordinate| of the table: the scale of its rounding errors.
  ROTLEAK_HD const R& scale() const { return scale_; }

  /// Where the flight from q along unit v (q inside the table or on its boundary) next meets the boundary: of the
  /// pieces it crosses outward, within each piece's span, the nearest. Where rounding leaves a flight between two
  /// pieces' spans (at a corner or a junction, within a few ulps) a second look widens every span by
  /// kSpanSlack ulps of the table's scale; piece -1 if that finds nothing either.
  ROTLEAK_HD TableHit<R> next_hit(const Vec2<R>& q, const Vec2<R>& v) const {
    TableHit<R> h = nearest(q, v, R(0));
    if (h.piece < 0) h = nearest(q, v, slack_);
    return h;
  }

  /// Specular reflection of v at q on piece k: about the radius vector as it is on an arc (formula::reflect_factor),
  /// about the inward normal (e.y, -e.x) as rounded on a segment (so |v'| = |v| whatever |n| is).
  ROTLEAK_HD Vec2<R> reflect(int k, const Vec2<R>& q, const Vec2<R>& v) const {
    return reflect_about(reflection_axis(piece_[k], q.x, q.y), v);
  }

  /// Boundary coordinate s in [0, 1) of a point q of piece k, in the piece's loop.
  ROTLEAK_HD R s_of(int k, const Vec2<R>& q) const {
    const TablePiece<R>& p = piece_[k];
    if (p.kind == PieceKind::segment) return segment_point_s(p, q.x, q.y, inv_length(p.loop));
    if (p.kind == PieceKind::ellipse) return ellipse_point_s(p, q.x, q.y, inv_length(p.loop));
    const Vec2<R> a = arc_angle_args(p, q.x, q.y);
    return arc_point_s(p, formula::tier_atan2(a.y, a.x), two_pi_);
  }

  /// The point of loop `loop` at s in [0, 1), with its frame.
  ROTLEAK_HD TableFrame<R> at(int loop, const R& s) const {
    const int k = piece_at(loop, s);
    const TablePiece<R>& p = piece_[k];
    const R u = s >= p.s1 ? R(s - R(1)) : s;  // unwrapped into [s0, s1)
    TableFrame<R> f;
    f.piece = k;
    if (p.kind == PieceKind::segment) {
      const R along = (u - p.s_ref) * loop_length_[p.loop];
      f.q = {p.rx + along * p.ex, p.ry + along * p.ey};
      if (p.horizontal) f.q.y = p.ry;
      if (p.vertical) f.q.x = p.rx;
      f.tangent = {p.ex, p.ey};
    } else if (p.kind == PieceKind::ellipse) {
      const formula::SinCos<R> sc = formula::tier_sin_cos(ellipse_angle(p, s));
      f.q = ellipse_point(p, sc.cos, sc.sin);
      f.tangent = ellipse_tangent(p, sc.cos, sc.sin);
    } else {
      const formula::SinCos<R> sc = formula::tier_sin_cos(formula::arc_angle_of(u, p.s0, p.L_over_rho));
      const Vec2<R> d = p.arc_direction(sc.cos, sc.sin);
      f.q = {p.cx + p.rho * d.x, p.cy + p.rho * d.y};
      f.tangent = p.arc_tangent(sc.cos, sc.sin);
    }
    f.normal = {f.tangent.y, R(-f.tangent.x)};
    return f;
  }

  /// The unit tangent (towards growing s) at a point q of piece k.
  ROTLEAK_HD Vec2<R> tangent(int k, const Vec2<R>& q) const {
    const TablePiece<R>& p = piece_[k];
    if (p.kind == PieceKind::segment) return {p.ex, p.ey};
    if (p.kind == PieceKind::ellipse) {  // the gradient (the reflection's axis) turned a quarter along the travel
      using std::sqrt;
      const Vec2<R> g = reflection_axis(p, q.x, q.y);
      const R n = sqrt(g.x * g.x + g.y * g.y);
      return p.clockwise ? Vec2<R>{R(g.y / n), R(-(g.x / n))} : Vec2<R>{R(-(g.y / n)), R(g.x / n)};
    }
    // as the stadium's: the radius vector times 1 / rho, turned a quarter along the travel
    const R rx = (q.x - p.cx) * p.inv_rho, ry = (q.y - p.cy) * p.inv_rho;
    return p.clockwise ? Vec2<R>{ry, R(-rx)} : Vec2<R>{R(-ry), rx};
  }

  /// Birkhoff momentum p = v_out . T of an outgoing velocity at a collision on piece k.
  ROTLEAK_HD R birkhoff_p(int k, const Vec2<R>& q, const Vec2<R>& v_out) const { return dot(v_out, tangent(k, q)); }

  /// The outgoing unit velocity of Birkhoff momentum p at a boundary point: sqrt(1 - p^2) n + p T.
  ROTLEAK_HD Vec2<R> velocity(const TableFrame<R>& f, const R& p) const {
    return formula::birkhoff_velocity(formula::Frame<R>{f.q, f.tangent, f.normal}, p);
  }

  /// The piece of loop `loop` that holds s in [0, 1).
  ROTLEAK_HD int piece_at(int loop, const R& s) const {
    const int first = loop_first_[loop], last = first + loop_count_[loop] - 1;
    for (int k = first; k <= last; ++k) {
      const TablePiece<R>& p = piece_[k];
      if ((s >= p.s0 && s < p.s1) || s >= p.s0 + R(1)) return k;
    }
    return last;  // s a rounding below 1 past the last piece's end
  }

  /// Whether q lies inside the table (inside the outer loop, outside every scatterer): the parity of the
  /// boundary's crossings by the ray from q along +x. Points on the boundary may go either way (a start drawn at
  /// random lands on one with probability 0).
  ROTLEAK_HD bool contains(const Vec2<R>& q) const {
    using std::sqrt;
    bool inside = false;
    for (int k = 0; k < n_pieces_; ++k) {
      const TablePiece<R>& p = piece_[k];
      if (p.kind == PieceKind::segment) {
        if ((p.ay > q.y) == (p.by > q.y)) continue;  // half-open in y: a vertex on the ray counts once
        const R x = p.ax + (q.y - p.ay) * (p.bx - p.ax) / (p.by - p.ay);
        inside ^= x > q.x;
        continue;
      }
      if (p.kind == PieceKind::ellipse) {
        const R dy = (q.y - p.cy) * p.inv_eb, h2 = R(1) - dy * dy;
        if (!(h2 > R(0))) continue;
        const R h = p.ea * sqrt(h2);
        for (const R dx : {R(-h), h}) inside ^= p.cx + dx > q.x;
        continue;
      }
      const R dy = q.y - p.cy, h2 = p.rho * p.rho - dy * dy;
      if (!(h2 > R(0))) continue;  // the ray misses the circle (or touches it)
      const R h = sqrt(h2);
      for (const R dx : {R(-h), h})
        if (p.cx + dx > q.x && (p.full || formula::on_arc(dx, dy, p.cw_fx, p.cw_fy, p.cw_gx, p.cw_gy, p.wide, R(0))))
          inside = !inside;
    }
    return inside;
  }

  /// The outer loop's bounding box: lo, hi corners (a start drawn from the flow is drawn in it and kept if inside).
  ROTLEAK_HD const Vec2<R>& box_lo() const { return box_lo_; }
  ROTLEAK_HD const Vec2<R>& box_hi() const { return box_hi_; }

  /// A share sigma in [0, 1) of the whole boundary (the loops laid end to end, in order) as a loop and its s:
  /// sigma itself on a table of one loop.
  ROTLEAK_HD std::pair<int, R> loop_s(const R& sigma) const {
    if (n_loops_ == 1) return {0, sigma};
    const R x = sigma * perimeter_;
    int l = 0;
    while (l + 1 < n_loops_ && x >= loop_offset_[l + 1]) ++l;
    R s = (x - loop_offset_[l]) * inv_loop_length_[l];
    if (!(s < R(1))) s = R(0);
    return {l, s};
  }
  /// The inverse: the share of the boundary before s of loop `loop` (s itself on a table of one loop).
  ROTLEAK_HD R boundary_share(int loop, const R& s) const {
    if (n_loops_ == 1) return s;
    return (loop_offset_[loop] + s * loop_length_[loop]) / perimeter_;
  }

  /// The nearest outward crossing within the pieces' spans widened by tol (next_hit's first look: tol 0; its
  /// second: slack()).
  ROTLEAK_HD TableHit<R> nearest(const Vec2<R>& q, const Vec2<R>& v, const R& tol) const {
    NearestCrossing<R> n{};
    n.piece = -1, n.found = false;
    nearest_crossing(piece_, n_pieces_, q.x, q.y, v.x, v.y, tol, true, n);
    TableHit<R> best;
    if (n.found) best = {n.t, n.piece, {n.x, n.y}};
    return best;
  }

  /// The piece nearest a point q (a collision's point, where a split copy's turn needs the normal:
  /// sim/engine/population.cpp) and its distance from q: the least distance from q to each piece (a segment's nearest
  /// point; an arc's circle where q lies within its span, else its nearer end); the first piece on a tie (a corner).
  std::pair<int, R> piece_nearest(const Vec2<R>& q) const {
    using std::sqrt;
    int best = 0;
    R best_d(0);
    for (int k = 0; k < n_pieces_; ++k) {
      const TablePiece<R>& p = piece_[k];
      const R ex = p.bx - p.ax, ey = p.by - p.ay;
      const R to_a = sqrt((q.x - p.ax) * (q.x - p.ax) + (q.y - p.ay) * (q.y - p.ay));
      const R to_b = sqrt((q.x - p.bx) * (q.x - p.bx) + (q.y - p.by) * (q.y - p.by));
      R d = to_a < to_b ? to_a : to_b;
      if (p.kind == PieceKind::ellipse) {  // |F| / |grad F| of F = X^2 + Y^2 - 1 (X, Y scaled): first order
        const R X = (q.x - p.cx) * p.inv_ea, Y = (q.y - p.cy) * p.inv_eb, f = X * X + Y * Y - R(1);
        const Vec2<R> g = reflection_axis(p, q.x, q.y);
        d = (f < R(0) ? R(-f) : f) / (R(2) * sqrt(g.x * g.x + g.y * g.y));
      } else if (p.kind == PieceKind::segment) {
        const R u = ((q.x - p.ax) * ex + (q.y - p.ay) * ey) / (ex * ex + ey * ey);
        if (u > R(0) && u < R(1)) {
          const R dx = q.x - (p.ax + u * ex), dy = q.y - (p.ay + u * ey);
          d = sqrt(dx * dx + dy * dy);
        }
      } else {
        const R rx = q.x - p.cx, ry = q.y - p.cy;
        if (p.full || formula::on_arc(rx, ry, p.cw_fx, p.cw_fy, p.cw_gx, p.cw_gy, p.wide, R(0))) {
          const R off = sqrt(rx * rx + ry * ry) - p.rho;
          d = off < R(0) ? R(-off) : off;
        }
      }
      if (k == 0 || d < best_d) best = k, best_d = d;
    }
    return {best, best_d};
  }

  /// The angle psi from its top, in the direction of travel, of the point of ellipse p at s in [0, 1) (its loop's):
  /// psi lies in the quarter [k, k + 1] pi / 2 with k = floor(4 s) (the quarters' ends are the vertices, at s = k / 4
  /// exactly); Newton's method on ellipse_point_s from the circle's angle 2 pi s, kept in the quarter by bisection,
  /// to a few ulps. An interval tier iterates on midpoints, then encloses the root by the mean value theorem: the arc
  /// grows at a speed between the semi-axes, so psi* lies in psi - (s(psi) - s) L [1 / max, 1 / min].
  ROTLEAK_HD R ellipse_angle(const TablePiece<R>& p, const R& s) const {
    using std::abs;
    using std::floor;
    using std::sqrt;
    constexpr bool interval = carlson::is_interval<R>;
    const auto mid = [](const R& x) -> R {  // the comparisons' value: an interval's midpoint
      if constexpr (interval)
        return midpoint(x);
      else
        return x;
    };
    const R L = loop_length_[p.loop], inv_L = inv_loop_length_[p.loop], quarter = pi_ / R(2);
    const R k = floor(mid(s * R(4)));
    const R lo = mid(k * quarter), hi = mid(lo + quarter);
    const auto offset = [&](const formula::SinCos<R>& sc) {  // s(psi) - s from psi's sine and cosine, in [-1/2, 1/2)
      const Vec2<R> q = ellipse_point(p, sc.cos, sc.sin);
      R d = ellipse_point_s(p, q.x, q.y, inv_L) - s;
      if (mid(d) >= R(0.5))
        d = d - R(1);
      else if (mid(d) < R(-0.5))
        d = d + R(1);
      return d;
    };
    const R tol = R(4) * num_traits<R>::epsilon();
    R psi = mid(lo + (s * R(4) - k) * quarter);
    for (int i = 0; i < 200; ++i) {
      const formula::SinCos<R> sc = formula::tier_sin_cos(psi);
      const R d = mid(offset(sc));
      R next = mid(psi - d * L / sqrt(p.ea2 * (sc.cos * sc.cos) + p.eb2 * (sc.sin * sc.sin)));
      if (next < lo || next > hi) next = mid((psi + (d > R(0) ? lo : hi)) / R(2));
      const R step = mid(abs(next - psi));
      psi = next;
      if (step <= mid(tol * (R(1) + psi))) break;
    }
    if constexpr (interval) psi = psi - offset(formula::tier_sin_cos(psi)) * L * hull(p.inv_ea, p.inv_eb);
    return psi;
  }

  /// How many ulps of the table's scale the second look widens every span by.
  static constexpr int kSpanSlack = 64;

 private:
  ROTLEAK_HD const R& inv_length(int loop) const { return inv_loop_length_[loop]; }
  /// scale_ = max(scale_, x) (x >= 0).
  void grow_scale(const R& x);
  /// Rounds piece e (of `loop`, whose length before it is `before`; `first` in its loop) into p, and grows scale_.
  void round_piece(TablePiece<R>& p, const PieceSpec& e, const LoopSpec& loop, const ExactReal& before, bool first);

  int n_pieces_ = 0, n_loops_ = 0;
  TablePiece<R> piece_[kMaxTablePieces];
  int loop_first_[kMaxTableLoops]{}, loop_count_[kMaxTableLoops]{};
  R loop_length_[kMaxTableLoops], inv_loop_length_[kMaxTableLoops];
  R loop_offset_[kMaxTableLoops];  ///< the loops' lengths before each
  R area_, perimeter_, mean_free_path_, scale_, slack_, two_pi_, pi_;
  Vec2<R> box_lo_, box_hi_;
};

template <class R>
Table<R>::Table(const TableSpec& spec) {
  const ExactReal two = ExactReal::parse("2");
  n_pieces_ = static_cast<int>(spec.pieces.size());
  n_loops_ = static_cast<int>(spec.loops.size());
  area_ = round_exact<R>(spec.area);
  perimeter_ = round_exact<R>(spec.perimeter);
  mean_free_path_ = round_exact<R>(ExactReal::pi() * spec.area / spec.perimeter);
  two_pi_ = round_exact<R>(two * ExactReal::pi());
  pi_ = round_exact<R>(ExactReal::pi());
  scale_ = R(0);
  for (int l = 0; l < n_loops_; ++l) {
    const LoopSpec& loop = spec.loops[static_cast<std::size_t>(l)];
    loop_first_[l] = loop.first;
    loop_count_[l] = loop.count;
    loop_length_[l] = round_exact<R>(loop.length);
    inv_loop_length_[l] = round_exact<R>(ExactReal::parse("1") / loop.length);
    ExactReal offset;  // the loops' lengths before this one
    for (int m = 0; m < l; ++m) offset = offset + spec.loops[static_cast<std::size_t>(m)].length;
    loop_offset_[l] = round_exact<R>(offset);
    ExactReal before;  // the loop's length before piece k
    for (int k = loop.first; k < loop.first + loop.count; ++k) {
      const PieceSpec& e = spec.pieces[static_cast<std::size_t>(k)];
      round_piece(piece_[k], e, loop, before, k == loop.first);
      before = before + e.length;
    }
  }
  slack_ = R(kSpanSlack) * num_traits<R>::epsilon() * scale_;
  // the outer loop's box: its pieces' ends, and each arc's whole circle (a box a little large only costs draws);
  // flow starts are drawn in double, so an interval tier (whose equal ends cannot be ordered) keeps none
  if constexpr (requires(const R& r) { r.hi(); }) return;
  box_lo_ = {piece_[0].ax, piece_[0].ay}, box_hi_ = box_lo_;
  for (int k = loop_first_[0]; k < loop_first_[0] + loop_count_[0]; ++k) {
    const TablePiece<R>& p = piece_[k];
    const bool arc = p.kind == PieceKind::arc, ellipse = p.kind == PieceKind::ellipse;
    const R rx = ellipse ? p.ea : p.rho, ry = ellipse ? p.eb : p.rho;
    const R lx = arc || ellipse ? R(p.cx - rx) : std::min(p.ax, p.bx);
    const R hx = arc || ellipse ? R(p.cx + rx) : std::max(p.ax, p.bx);
    const R ly = arc || ellipse ? R(p.cy - ry) : std::min(p.ay, p.by);
    const R hy = arc || ellipse ? R(p.cy + ry) : std::max(p.ay, p.by);
    box_lo_ = {std::min(box_lo_.x, lx), std::min(box_lo_.y, ly)};
    box_hi_ = {std::max(box_hi_.x, hx), std::max(box_hi_.y, hy)};
  }
}

template <class R>
void Table<R>::round_piece(TablePiece<R>& p, const PieceSpec& e, const LoopSpec& loop, const ExactReal& before,
                           bool first) {
  using std::abs;
  p.kind = e.kind;
  p.loop = e.loop;
  p.clockwise = e.clockwise;
  p.full = e.full;
  p.ax = round_exact<R>(e.ax), p.ay = round_exact<R>(e.ay), p.bx = round_exact<R>(e.bx), p.by = round_exact<R>(e.by);
  const ExactReal s0 = (before - loop.origin) / loop.length;
  // the piece that holds the origin starts below 0: its start is rounded where it lies, a turn on (as the
  // stadium's junction 3 is), and brought back by an exact - 1, so that s0 + 1 is that junction's bits
  const bool holds_origin = first && loop.origin.sign() != 0;
  p.s0 = holds_origin ? R(round_exact<R>(s0 + ExactReal::parse("1")) - R(1)) : round_exact<R>(s0);
  p.s1 = round_exact<R>((before + e.length - loop.origin) / loop.length);
  const R ends[] = {p.ax, p.ay, p.bx, p.by};
  for (const R& x : ends) grow_scale(abs(x));
  if (e.kind == PieceKind::segment) {
    const ExactReal ex = (e.bx - e.ax) / e.length, ey = (e.by - e.ay) / e.length;
    p.ex = round_exact<R>(ex), p.ey = round_exact<R>(ey);
    p.horizontal = ey.is_rational() && ey.as_rational() == 0;
    p.vertical = ex.is_rational() && ex.as_rational() == 0;
    p.along_x = abs(ex.to_double()) >= abs(ey.to_double());
    const R ca = p.along_x ? p.ax : p.ay, cb = p.along_x ? p.bx : p.by;
    p.lo = ca < cb ? ca : cb;
    p.hi = ca < cb ? cb : ca;
    if (holds_origin) {  // the origin's point, at s = 0
      p.rx = round_exact<R>(e.ax + loop.origin * ex), p.ry = round_exact<R>(e.ay + loop.origin * ey);
      p.s_ref = R(0);
    } else {
      p.rx = p.ax, p.ry = p.ay, p.s_ref = p.s0;
    }
    return;
  }
  if (e.kind == PieceKind::ellipse) {
    const ExactReal one = ExactReal::parse("1");
    p.cx = round_exact<R>(e.cx), p.cy = round_exact<R>(e.cy);
    p.ea = round_exact<R>(e.ea), p.eb = round_exact<R>(e.eb);
    p.inv_ea = round_exact<R>(one / e.ea), p.inv_eb = round_exact<R>(one / e.eb);
    p.ea2 = round_exact<R>(e.ea * e.ea), p.eb2 = round_exact<R>(e.eb * e.eb);
    p.ga = round_exact<R>(one / (e.ea * e.ea)), p.gb = round_exact<R>(one / (e.eb * e.eb));
    p.span = round_exact<R>(e.span);
    for (const R& x : {R(abs(p.cx) + p.ea), R(abs(p.cy) + p.eb)}) grow_scale(x);
    return;
  }
  p.cx = round_exact<R>(e.cx), p.cy = round_exact<R>(e.cy), p.rho = round_exact<R>(e.rho);
  p.inv_rho = round_exact<R>(ExactReal::parse("1") / e.rho);
  const ExactReal fx = (e.ax - e.cx) / e.rho, fy = (e.ay - e.cy) / e.rho;
  const R gx = round_exact<R>((e.bx - e.cx) / e.rho), gy = round_exact<R>((e.by - e.cy) / e.rho);
  p.fx = round_exact<R>(fx), p.fy = round_exact<R>(fy);
  p.cw_fx = e.clockwise ? p.fx : gx, p.cw_fy = e.clockwise ? p.fy : gy;
  p.cw_gx = e.clockwise ? gx : p.fx, p.cw_gy = e.clockwise ? gy : p.fy;
  p.span = round_exact<R>(e.span);
  p.wide = e.span.to_double() > M_PI;
  p.rho_over_L = round_exact<R>(e.rho / loop.length);
  p.L_over_rho = round_exact<R>(loop.length / e.rho);
  for (const R& x : {R(abs(p.cx) + p.rho), R(abs(p.cy) + p.rho)}) grow_scale(x);
}

template <class R>
void Table<R>::grow_scale(const R& x) {
  if constexpr (requires(const R& r) { r.hi(); }) {
    // an interval tier: equal coordinates (the lemon's corners) cannot be ordered, and need not be: the scale is a
    // tolerance's size, so the larger upper end serves
    if (x.hi() > scale_.hi()) scale_ = R(x.hi());
  } else if (x > scale_) {
    scale_ = x;
  }
}

}  // namespace rotleak
