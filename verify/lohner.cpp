#include "verify/lohner.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "geometry/formulas.hpp"
#include "numeric/jet.hpp"
#include "numeric/mpfi_ops.hpp"

namespace rotleak {

namespace {

using J4 = Jet<Mpfi, 4>;
using Vec4 = std::array<Mpfi, 4>;
using Mat4 = std::array<Vec4, 4>;
using DMat = std::array<std::array<double, 4>, 4>;

/// The collision map of the shared formulas over a number type T: the exit, then the reflection.
template <class T>
struct Collision {
  formula::Exit<T> exit;
  Vec2<T> v;
};
template <class T>
Collision<T> collide(const T& r, const T& half_d, const std::array<T, 4>& s) {
  Collision<T> c{formula::next_exit(r, half_d, s[0], s[1], s[2], s[3]), {}};
  c.v = formula::reflect(c.exit.straight, c.exit.cx, c.exit.x, c.exit.y, s[2], s[3]);
  return c;
}

Piece piece_of(bool straight, bool up, bool right) {
  if (straight) return up ? Piece::top : Piece::bottom;
  return right ? Piece::right_arc : Piece::left_arc;
}

double mid_double(const Mpfi& x) { return 0.5 * (x.lo() + x.hi()); }

/// Householder QR of m (4 x 4, double): the orthogonal factor, full even where m is singular (the collision
/// map flattens the direction along the flight).
DMat orthogonal_factor(DMat m) {
  DMat q{};
  for (int i = 0; i < 4; ++i) q[i][i] = 1;
  for (int k = 0; k < 3; ++k) {
    double norm = 0;
    for (int i = k; i < 4; ++i) norm = std::hypot(norm, m[i][k]);
    if (norm == 0) continue;
    std::array<double, 4> u{};
    for (int i = k; i < 4; ++i) u[i] = m[i][k];
    u[k] += m[k][k] >= 0 ? norm : -norm;
    double uu = 0;
    for (int i = k; i < 4; ++i) uu += u[i] * u[i];
    if (uu == 0) continue;
    // m <- H m and q <- q H with H = I - 2 u u^T / u^T u
    for (int j = 0; j < 4; ++j) {
      double dot = 0;
      for (int i = k; i < 4; ++i) dot += u[i] * m[i][j];
      for (int i = k; i < 4; ++i) m[i][j] -= 2 * dot / uu * u[i];
    }
    for (int i = 0; i < 4; ++i) {
      double dot = 0;
      for (int j = k; j < 4; ++j) dot += q[i][j] * u[j];
      for (int j = k; j < 4; ++j) q[i][j] -= 2 * dot / uu * u[j];
    }
  }
  return q;
}

}  // namespace

namespace lohner_detail {

Mat4 inverse_enclosure(const DMat& q) {
  Mat4 e, inv;
  Mpfi e_norm(0), b_norm(0);
  for (int i = 0; i < 4; ++i) {
    Mpfi row(0), b_row(0);
    for (int j = 0; j < 4; ++j) {
      Mpfi s(i == j ? 1 : 0);
      for (int k = 0; k < 4; ++k) s -= Mpfi(q[k][i]) * Mpfi(q[k][j]);
      row += abs(s);
      b_row += abs(Mpfi(q[j][i]));
    }
    e_norm = Mpfi(std::max(e_norm.hi(), row.hi()));
    b_norm = Mpfi(std::max(b_norm.hi(), b_row.hi()));
  }
  if (!(e_norm.hi() < 0.5)) throw UncertainDecision();
  const double delta = (e_norm / (Mpfi(1) - e_norm) * b_norm).hi();
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) inv[i][j] = Mpfi(q[j][i]) + symmetric(delta);
  return inv;
}

}  // namespace lohner_detail

using lohner_detail::inverse_enclosure;

LohnerEnclosure::LohnerEnclosure(const Model<Mpfi>& model, const InitialDraw& draw) : model_(model) {
  const ParticleState<Mpfi> ps = initial_state(model.stadium, draw);
  const Vec4 x{ps.q.x, ps.q.y, ps.v.x, ps.v.y};
  for (int i = 0; i < 4; ++i) {
    c_[i] = midpoint(x[i]);
    r_[i] = x[i] - c_[i];
    for (int j = 0; j < 4; ++j) a_[i][j] = Mpfi(i == j ? 1 : 0);
  }
  t_ = ps.t;
}

LohnerEnclosure::Vec4 LohnerEnclosure::box() const {
  Vec4 b;
  for (int i = 0; i < 4; ++i) {
    b[i] = c_[i];
    for (int j = 0; j < 4; ++j) b[i] += a_[i][j] * r_[j];
  }
  return b;
}

double LohnerEnclosure::log2_width() const {
  const Vec4 b = box();
  double w = -INFINITY;
  for (const Mpfi& x : b) w = std::max(w, rotleak::log2_width(x));
  return w;
}

EnclosedCollision LohnerEnclosure::step() {
  const Stadium<Mpfi>& st = model_.stadium;
  // the Jacobian on the box (jets), and the map at the centre (thin intervals): the same branches, since
  // the centre lies in the box and every branch was decided on the whole box
  std::array<J4, 4> xb;
  const Vec4 b = box();
  for (int i = 0; i < 4; ++i) xb[i] = J4::variable(b[i], i);
  const Collision<J4> fb = collide(J4(st.r()), J4(st.half_d()), xb);
  const Collision<Mpfi> fc = collide(st.r(), st.half_d(), c_);
  if (fb.exit.straight != fc.exit.straight || fb.exit.up != fc.exit.up || fb.exit.right != fc.exit.right)
    throw std::logic_error("Lohner enclosure: the centre took another branch than its box");
  const std::array<const J4*, 4> out{&fb.exit.x, &fb.exit.y, &fb.v.x, &fb.v.y};
  Mat4 m;  // DF(B) A
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m[i][j] = dot_column(out[i]->d, j);
  Mpfi tau = fc.exit.t;  // tau(c) + grad tau(B) A r
  for (int j = 0; j < 4; ++j) tau += dot_column(fb.exit.t.d, j) * r_[j];
  t_ += tau;
  move_to(m, {fc.exit.x, fc.exit.y, fc.v.x, fc.v.y});

  EnclosedCollision e;
  e.k = ++k_;
  e.piece = piece_of(fb.exit.straight, fb.exit.up, fb.exit.right);
  e.t = t_;
  const Vec4 nb = box();
  e.q = {intersect(nb[0], fb.exit.x.v), intersect(nb[1], fb.exit.y.v)};
  e.log2_width = -INFINITY;
  for (const Mpfi& x : nb) e.log2_width = std::max(e.log2_width, rotleak::log2_width(x));
  e.in_leak = model_.leak.hit(e.piece, e.q, e.t);
  return e;
}

Mpfi LohnerEnclosure::dot_column(const std::array<Mpfi, 4>& row, int j) const {
  Mpfi s(0);
  for (int k = 0; k < 4; ++k) s += row[static_cast<std::size_t>(k)] * a_[k][j];
  return s;
}

void LohnerEnclosure::move_to(const Mat4& m, const Vec4& yc) {
  // A' = the orthogonal factor of mid(M), its columns taken in order of how far each stretches the set
  std::array<int, 4> order{0, 1, 2, 3};
  std::array<double, 4> reach{};
  for (int j = 0; j < 4; ++j) {
    double col = 0;
    for (int i = 0; i < 4; ++i) col = std::hypot(col, mid_double(m[i][j]));
    reach[j] = col * magnitude(r_[j]);
  }
  std::stable_sort(order.begin(), order.end(), [&](int p, int q) { return reach[p] > reach[q]; });
  DMat mid{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      mid[i][j] = mid_double(m[i][order[j]]);
      if (!std::isfinite(mid[i][j])) throw UncertainDecision();
    }
  const DMat q = orthogonal_factor(mid);
  const Mat4 q_inv = inverse_enclosure(q);
  // c' = mid F(c); r' = (A'^-1 M) r + A'^-1 (F(c) - c')
  Vec4 c_next, r_next;
  for (int i = 0; i < 4; ++i) c_next[i] = midpoint(yc[i]);
  for (int i = 0; i < 4; ++i) {
    Mpfi acc(0);
    for (int j = 0; j < 4; ++j) {
      Mpfi qm(0);
      for (int k = 0; k < 4; ++k) qm += q_inv[i][k] * m[k][j];
      acc += qm * r_[j];
      acc += q_inv[i][j] * (yc[j] - c_next[j]);
    }
    r_next[i] = acc;
  }
  c_ = c_next;
  r_ = r_next;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) a_[i][j] = Mpfi(q[i][j]);
}

}  // namespace rotleak
