// Exact replay of the first collisions from rational initial data with CGAL's exact kernel with
// square roots (CORE::Expr): every comparison is decided exactly, so the piece hit and the
// reflected direction are the true ones. Tests hold the generic core at MPFR against it.
#pragma once

#include <gmpxx.h>

#include <string>
#include <vector>

#include "geometry/stadium.hpp"

namespace rotleak {

struct ExactStep {
  Piece piece = Piece::top;
  std::string x, y;    ///< collision point, `digits` significant digits
  std::string ux, uy;  ///< outgoing unit direction
};

/// Stadium (d, r); the particle leaves (x0, y0) (on the boundary or inside) along (ux, uy) (any length).
std::vector<ExactStep> exact_replay(const mpq_class& d, const mpq_class& r, const mpq_class& x0, const mpq_class& y0,
                                    const mpq_class& ux, const mpq_class& uy, int collisions, int digits = 80);

}  // namespace rotleak
