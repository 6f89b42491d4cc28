// Ordinary least squares of y on x: slope and R^2 (growth rates and growth laws of divergences).
#pragma once

#include <cstddef>
#include <vector>

namespace rotleak {

struct LineFit {
  double slope = 0, r2 = 0;
};

inline LineFit least_squares(const std::vector<double>& x, const std::vector<double>& y) {
  LineFit f;
  if (x.empty()) return f;
  const double n = static_cast<double>(x.size());
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) mx += x[i], my += y[i];
  mx /= n;
  my /= n;
  double sxx = 0, sxy = 0, syy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
    syy += (y[i] - my) * (y[i] - my);
  }
  if (!(sxx > 0)) return f;
  f.slope = sxy / sxx;
  f.r2 = syy > 0 ? sxy * sxy / (sxx * syy) : 0;  // 1 - SS_res / SS_tot for a fitted line
  return f;
}

}  // namespace rotleak
