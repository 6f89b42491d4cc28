#include "sim/tally/density.hpp"

#include <algorithm>

#include "geometry/formulas.hpp"

namespace rotleak {

// With c(x) the cell of time x (non-decreasing in x), t >= from_w exactly when c(t) >= c(from_w)
// (below from_w, from_w's own edge is not passed), and t <= to_w exactly when c(t) <= c(to_w).
DensityCells DensityCells::of(int bins, int windows, const double* from, const double* to) {
  DensityCells d;
  d.bins = bins;
  d.n_windows = windows;
  std::copy(from, from + windows, d.from);
  std::copy(to, to + windows, d.to);
  density_cells(windows, from, to, d.windows);
  return d;
}

void density_cells(int windows, const double* from, const double* to, unsigned* cells) {
  const auto cell_of = [&](double x) { return static_cast<int>(formula::time_cell(x, from, to, windows)); };
  for (int c = 0; c <= 2 * windows; ++c) {
    cells[c] = 0;
    for (int w = 0; w < windows; ++w)
      if (cell_of(from[w]) <= c && c <= cell_of(to[w])) cells[c] |= 1u << w;
  }
}

}  // namespace rotleak
