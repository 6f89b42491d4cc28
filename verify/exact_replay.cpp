#define CGAL_USE_CORE 1
#include "verify/exact_replay.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel_with_sqrt.h>

namespace rotleak {

namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel_with_sqrt;
using FT = K::FT;
using Point = K::Point_2;
using Vector = K::Vector_2;

FT from_q(const mpq_class& q) { return FT(CORE::BigRat(q.get_mpq_t())); }

// Decimal digits of an exact expression, from an approximation good to ~3.4 bits per digit.
std::string decimal(const FT& e, int digits) {
  const long bits = static_cast<long>(digits * 3.4) + 16;
  return e.approx(CORE::extLong(bits), CORE::extLong(bits)).toString(digits);
}

}  // namespace

std::vector<ExactStep> exact_replay(const mpq_class& d, const mpq_class& r, const mpq_class& x0, const mpq_class& y0,
                                    const mpq_class& ux, const mpq_class& uy, int collisions, int digits) {
  const FT R = from_q(r), HD = from_q(mpq_class(d / 2));
  Point q(from_q(x0), from_q(y0));
  Vector u(from_q(ux), from_q(uy));
  std::vector<ExactStep> out;
  for (int k = 0; k < collisions; ++k) {
    // the same decisions as Stadium::next_hit, decided exactly
    Piece piece;
    FT tau;
    bool straight = false;
    Piece arc = u.x() > 0 ? Piece::right_arc : Piece::left_arc;
    if (u.y() != 0) {
      const bool up = u.y() > 0;
      tau = ((up ? R : -R) - q.y()) / u.y();
      const FT x = q.x() + tau * u.x();
      if (x <= HD && x >= -HD) {
        straight = true;
        piece = up ? Piece::top : Piece::bottom;
      } else {
        arc = x > 0 ? Piece::right_arc : Piece::left_arc;
      }
    }
    if (!straight) {
      const Point c(arc == Piece::right_arc ? HD : -HD, 0);
      const Vector w = q - c;
      const FT a = u * u, b = w * u, cc = w * w - R * R;
      tau = (-b + CGAL::sqrt(b * b - a * cc)) / a;
      piece = arc;
    }
    q = q + tau * u;
    if (straight) {
      u = Vector(u.x(), -u.y());
    } else {
      const Vector w = q - Point(piece == Piece::right_arc ? HD : -HD, 0);
      u = u - (2 * (u * w) / (w * w)) * w;
    }
    const FT len = CGAL::sqrt(u * u);
    out.push_back({piece, decimal(q.x(), digits), decimal(q.y(), digits), decimal(u.x() / len, digits),
                   decimal(u.y() / len, digits)});
  }
  return out;
}

}  // namespace rotleak
