// The leak: an arc of width lambda (in s) whose centre moves as s_L(t) = s_L(0) + omega t mod 1.
#pragma once

#include <array>
#include <cmath>

#include "geometry/stadium.hpp"
#include "geometry/table_piece.hpp"
#include "leak/leak_formulas.hpp"
#include "leak/leak_window.hpp"
#include "numeric/device.hpp"
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

  ROTLEAK_HD bool rotating() const { return rotating_; }
  ROTLEAK_HD const two_term<R>& omega_terms() const { return omega_; }
  ROTLEAK_HD const R& start() const { return start_; }

  ROTLEAK_HD R phase(const R& t) const {
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
/// and the phase + s test for a moving one. Its windows are the stadium's own (built here from the stadium's
/// junctions); the test is the one every table's leak takes (leak_takes, leak/leak_window.hpp), on the
/// stadium's four pieces as that test reads them (a straight edge's x, an arc's centre).
template <class R>
class Leak {
 public:
  Leak(const Stadium<R>& stadium, const ExactReal& width, const ExactReal& start, const ExactReal& omega)
      : stadium_(stadium), schedule_(start, omega) {
    view_.first = 0, view_.count = 4;
    view_.by_s = schedule_.rotating();
    view_.omega_hi = schedule_.omega_terms().hi, view_.omega_lo = schedule_.omega_terms().lo;
    view_.start = schedule_.start();
    view_.half_width = round_exact<R>(width / ExactReal::parse("2"));
    // s-ranges of the pieces, with the top edge unwrapped to [j3 - 1, j0].
    piece_lo_ = {stadium.junction(3) - 1, stadium.junction(0), stadium.junction(1), stadium.junction(2)};
    piece_hi_ = {stadium.junction(0), stadium.junction(1), stadium.junction(2), stadium.junction(3)};
    for (int k = 0; k < 4; ++k) {
      view_.mid[k] = (piece_lo_[k] + piece_hi_[k]) / 2;
      view_.reach[k] = (piece_hi_[k] - piece_lo_[k]) / 2 + view_.half_width;
      TablePiece<R>& p = piece_[k];
      p.kind = k == 0 || k == 2 ? PieceKind::segment : PieceKind::arc;
      p.along_x = true;
      if (p.kind == PieceKind::arc) p.cx = stadium.arc_centre_x(static_cast<Piece>(k));
    }
    if (!schedule_.rotating()) build_windows();
  }

  ROTLEAK_HD const LeakSchedule<R>& schedule() const { return schedule_; }
  ROTLEAK_HD const R& half_width() const { return view_.half_width; }
  /// The leak and the stadium's four pieces as leak_takes reads them (what the vectorised kernel copies).
  ROTLEAK_HD const LeakView<R, 4>& view() const { return view_; }
  ROTLEAK_HD const TablePiece<R>* pieces() const { return piece_; }

  /// Escape test at a collision at point q of piece p at time t (leak_takes on this one leak; the hit's s, the
  /// stadium's, only where a moving leak asks for it).
  [[gnu::always_inline]] ROTLEAK_HD bool hit(Piece p, const Vec2<R>& q, const R& t) const {
    const auto s_of = [&](bool, const R&, const R&) { return stadium_.s_of(p, q); };  // asked once at most
    const auto product_error = [](const R& a, const R& b, const R& prod) {
      return num_traits<R>::product_error(a, b, prod);  // exact: a b = prod + error
    };
    return leak_takes(view_, piece_, static_cast<int>(p), q.x, q.y, t, true, s_of, product_error);
  }

  /// A stationary leak's part on one piece (empty for a moving leak): an x range (straight pieces) or the two
  /// directions from the arc's centre that bound the sub-arc, clockwise (arcs), in the order they lie along it.
  struct PieceWindows {
    const PieceWindow<R>* first;
    int n;
    ROTLEAK_HD const LeakWindow<R>& operator[](int i) const { return first[i].w; }
  };
  ROTLEAK_HD PieceWindows windows(Piece p) const {
    const int k = static_cast<int>(p);
    return {view_.window + view_.win_first[k], view_.win_count[k]};
  }

 private:
  ROTLEAK_HD void build_windows() {
    using std::cos;
    using std::sin;
    const R& c = view_.start;
    const R& hw = view_.half_width;
    for (int k = 0; k < 4; ++k) {
      view_.win_first[k] = view_.n_windows;
      for (int shift = -1; shift <= 1; ++shift) {
        const R a = c - hw + R(shift), b = c + hw + R(shift);
        const R lo = a > piece_lo_[k] ? a : piece_lo_[k];
        const R hi = b < piece_hi_[k] ? b : piece_hi_[k];
        if (lo > hi) continue;
        PieceWindow<R>& pw = view_.window[view_.n_windows++];
        pw.piece = k;
        LeakWindow<R>& w = pw.w;
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
      }
      view_.win_count[k] = view_.n_windows - view_.win_first[k];
    }
  }

  Stadium<R> stadium_;
  LeakSchedule<R> schedule_;
  std::array<R, 4> piece_lo_{}, piece_hi_{};
  LeakView<R, 4> view_{};   ///< the leak as leak_takes reads it (its windows: at most 3 a piece here)
  TablePiece<R> piece_[4];  ///< the four pieces as the test reads them: kind, x along the edges, arc centres
};

}  // namespace rotleak
