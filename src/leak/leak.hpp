// The leak: an arc of width lambda (in s) whose centre moves as s_L(t) = s_L(0) + omega t mod 1.
#pragma once

#include <array>
#include <cmath>

#include "geometry/stadium.hpp"
#include "leak/leak_formulas.hpp"
#include "numeric/exact.hpp"
#include "numeric/num_traits.hpp"

namespace rotleak {

/// Centre of the leak at time t: frac(s0 + omega t), with omega carried as hi + lo and the product
/// hi*t split exactly by an FMA, so the phase keeps R's absolute precision however large omega*t
/// grows (until t itself stops being representable to that precision).
template <class R>
class LeakSchedule {
 public:
  LeakSchedule(const ExactReal& start, const ExactReal& omega)
      : omega_(two_term_of<R>(omega)), rotating_(omega.sign() != 0) {
    // s0 reduced exactly into [0,1) before rounding (a floor at any fixed precision is wrong for a
    // large s0: 1e30 + 1/2 once came out as 0 and no particle escaped)
    const ExactReal s = start - ExactReal::rational(mpq_class(floor_exact(start)));
    start_ = round_exact<R>(s);
    if (start_ >= 1) start_ -= 1;
    if (start_ < 0) start_ += 1;
  }

  bool rotating() const { return rotating_; }
  const two_term<R>& omega_terms() const { return omega_; }
  const R& start() const { return start_; }

  R phase(const R& t) const {
    if (!rotating_) return start_;
    return formula::leak_phase(omega_.hi, omega_.lo, start_, t, [](const R& a, const R& b, const R& prod) {
      return num_traits<R>::product_error(a, b, prod);  // exact: a b = prod + error
    });
  }

 private:
  two_term<R> omega_;
  R start_{0};
  bool rotating_;
};

using formula::circular_offset;

/// The leak on a given stadium: decides escape at a collision. Two paths that must agree (tests
/// check it): a precomputed per-piece window test for a stationary leak (no transcendental calls),
/// and the phase + s test for a moving one.
template <class R>
class Leak {
 public:
  Leak(const Stadium<R>& stadium, const ExactReal& width, const ExactReal& start, const ExactReal& omega)
      : stadium_(stadium), schedule_(start, omega), half_width_(round_exact<R>(width / ExactReal::parse("2"))) {
    // s-ranges of the pieces, with the top edge unwrapped to [j3 - 1, j0].
    piece_lo_ = {stadium.junction(3) - 1, stadium.junction(0), stadium.junction(1), stadium.junction(2)};
    piece_hi_ = {stadium.junction(0), stadium.junction(1), stadium.junction(2), stadium.junction(3)};
    for (int k = 0; k < 4; ++k) {
      piece_mid_[k] = (piece_lo_[k] + piece_hi_[k]) / 2;
      reach_[k] = (piece_hi_[k] - piece_lo_[k]) / 2 + half_width_;
    }
    if (!schedule_.rotating()) build_windows();
  }

  const LeakSchedule<R>& schedule() const { return schedule_; }
  const R& half_width() const { return half_width_; }
  /// Piece k's middle in s and how far from it the leak's centre can be while touching the piece.
  const R& piece_mid(int k) const { return piece_mid_[static_cast<std::size_t>(k)]; }
  const R& reach(int k) const { return reach_[static_cast<std::size_t>(k)]; }

  /// Escape test at a collision at point q of piece p at time t.
  bool hit(Piece p, const Vec2<R>& q, const R& t) const {
    if (!schedule_.rotating()) return in_windows(p, q);
    const R c = schedule_.phase(t);
    // on an arc, skip the atan2 unless the leak overlaps this arc now
    if ((p == Piece::right_arc || p == Piece::left_arc) &&
        !formula::may_touch(piece_mid_[static_cast<std::size_t>(p)], c, reach_[static_cast<std::size_t>(p)]))
      return false;
    return formula::in_leak(stadium_.s_of(p, q), c, half_width_);
  }

  /// A stationary leak's part on one piece: an x range (straight pieces) or the two directions from
  /// the arc's centre that bound the sub-arc, clockwise (arcs).
  struct Window {
    R lo{0}, hi{0};
    Vec2<R> from, to;
  };
  struct PieceWindows {
    std::array<Window, 3> w;
    int n = 0;
  };
  /// The stationary windows of piece p (empty for a moving leak).
  const PieceWindows& windows(Piece p) const { return windows_[static_cast<int>(p)]; }

 private:
  void build_windows() {
    using std::cos;
    using std::sin;
    const R c = schedule_.start();
    for (int k = 0; k < 4; ++k) {
      for (int shift = -1; shift <= 1; ++shift) {
        const R a = c - half_width_ + R(shift), b = c + half_width_ + R(shift);
        const R lo = a > piece_lo_[k] ? a : piece_lo_[k];
        const R hi = b < piece_hi_[k] ? b : piece_hi_[k];
        if (lo > hi) continue;
        Window w;
        const R L = stadium_.perimeter();
        switch (static_cast<Piece>(k)) {
          case Piece::top:
            w.lo = lo * L;
            w.hi = hi * L;
            break;
          case Piece::bottom:
            w.lo = stadium_.half_d() - (hi - piece_lo_[k]) * L;
            w.hi = stadium_.half_d() - (lo - piece_lo_[k]) * L;
            break;
          case Piece::right_arc:
          case Piece::left_arc: {
            const R scale = L / stadium_.r();
            const R ta = (lo - piece_lo_[k]) * scale, tb = (hi - piece_lo_[k]) * scale;
            const R sign = static_cast<Piece>(k) == Piece::right_arc ? R(1) : R(-1);
            w.from = {sign * sin(ta), sign * cos(ta)};
            w.to = {sign * sin(tb), sign * cos(tb)};
            break;
          }
        }
        windows_[k].w[windows_[k].n++] = w;
      }
    }
  }

  bool in_windows(Piece p, const Vec2<R>& q) const {
    const PieceWindows& pw = windows_[static_cast<int>(p)];
    if (pw.n == 0) return false;
    if (p == Piece::top || p == Piece::bottom) {
      for (int i = 0; i < pw.n; ++i)
        if (formula::in_x_window(q.x, pw.w[i].lo, pw.w[i].hi)) return true;
      return false;
    }
    const Vec2<R> rel{formula::from_centre(q.x, stadium_.arc_centre_x(p)), q.y};
    for (int i = 0; i < pw.n; ++i)  // each sub-arc spans at most pi: two half-plane tests
      if (formula::in_arc_window(rel, pw.w[i].from, pw.w[i].to)) return true;
    return false;
  }

  Stadium<R> stadium_;
  LeakSchedule<R> schedule_;
  R half_width_;
  std::array<R, 4> piece_lo_{}, piece_hi_{};
  std::array<R, 4> piece_mid_{}, reach_{};  ///< the leak centre can touch piece k only within reach_ of its middle
  std::array<PieceWindows, 4> windows_{};
};

}  // namespace rotleak
