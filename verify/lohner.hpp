// A trajectory's enclosure in mean-value form, after Lohner (and CAPD's C^1 Lohner method for ODEs): the
// state (x, y, vx, vy) at a collision lies in c + A r, with c a point, A a point matrix whose columns follow
// the directions the collision map stretches, and r an interval vector. One collision maps the set by
//   F(c + A r) in F(c) + DF(B) A r,    B the box that holds c + A r,
// with F(c) enclosed in MPFI at the working bits and DF(B) by first-order jets over B (numeric/jet.hpp)
// through the same shared formulas the core runs (geometry/formulas.hpp). The new A is the orthogonal factor
// of mid(DF(B) A), its columns ordered by how far each stretches the set, and r' = A'^-1 (DF(B) A) r +
// A'^-1 (F(c) - c'), with A'^-1 enclosed rigorously. Plain interval arithmetic wraps the set in a box at
// every collision, and the box's width grows by the norm of the collision map's Jacobian, not by its
// stretching along the set; the mean-value form grows at the Lyapunov rate plus a second-order term
// (docs/model.md, "Certified escapes"). Every branch of the formulas is decided on the whole box B, so
// each point of the set takes the branch the enclosure took; an undecided one throws UncertainDecision.
#pragma once

#include <array>
#include <cstddef>

#include "numeric/tiers.hpp"
#include "sim/model/initial.hpp"
#include "sim/model/particle.hpp"

namespace rotleak {

/// One collision as the enclosure reaches it.
struct EnclosedCollision {
  std::size_t k = 0;  ///< collision number, from 1
  Piece piece = Piece::top;
  Mpfi t;                 ///< its time
  Vec2<Mpfi> q;           ///< its point: the set's box, intersected with the direct interval image
  double log2_width = 0;  ///< log2 of the largest width of the box's four coordinates
  bool in_leak = false;
};

class LohnerEnclosure {
 public:
  /// The state of `draw` (initial_state at the current MPFR precision) as its first set.
  LohnerEnclosure(const Model<Mpfi>& model, const InitialDraw& draw);
  /// Maps the set through the next collision (UncertainDecision where a branch is undecided on the box).
  EnclosedCollision step();
  /// Moves the set by `by` in coordinate i (0, 1: x, y; 2, 3: vx, vy): another system's trajectory from here
  /// on (a test's perturbation of one reflection).
  void shift(int i, const Mpfi& by) { c_[static_cast<std::size_t>(i)] += by; }
  /// log2 of the largest width of the box of the current set.
  double log2_width() const;

 private:
  using Vec4 = std::array<Mpfi, 4>;
  using Mat4 = std::array<Vec4, 4>;
  Vec4 box() const;
  /// Row `row` of a Jacobian times column j of A.
  Mpfi dot_column(const std::array<Mpfi, 4>& row, int j) const;
  /// The set after the collision: M = DF(B) A, yc = F(c) (the new A, c and r).
  void move_to(const Mat4& m, const Vec4& yc);

  const Model<Mpfi>& model_;
  Vec4 c_, r_;
  Mat4 a_;
  Mpfi t_;
  std::size_t k_ = 0;
};

namespace lohner_detail {
/// An enclosure of q^-1 for a q held in doubles that is orthogonal up to rounding (the new A of a step): b =
/// q^T, e = I - b q, and q^-1 = (I - e)^-1 b, so |q^-1 - b| <= ||e|| / (1 - ||e||) ||b|| entrywise (infinity
/// norms, enclosed in MPFI). Throws UncertainDecision where ||e|| >= 1/2 (q too far from orthogonal for the
/// bound). Exposed for the tests.
std::array<std::array<Mpfi, 4>, 4> inverse_enclosure(const std::array<std::array<double, 4>, 4>& q);
}  // namespace lohner_detail

/// How a trajectory is enclosed: the mean-value set above, or plain MPFI (the core run in intervals).
enum class Enclosure { lohner, interval };

}  // namespace rotleak
