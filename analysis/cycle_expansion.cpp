#include "analysis/cycle_expansion.hpp"

#include <cmath>
#include <cstdint>

namespace rotleak {

namespace {

/// A coefficient of the expansion and its derivatives in beta and s.
struct Dual {
  double v = 0, db = 0, ds = 0;
};

/// F(beta, s) = 1/zeta cut at z^order, at z = 1, with its derivatives; `time` true: T_p the length, else n_p.
Dual zeta(const std::vector<PrimeCycle>& cycles, int order, double beta, double s, bool time) {
  std::vector<Dual> c(static_cast<std::size_t>(order) + 1);
  c[0].v = 1;
  for (const PrimeCycle& p : cycles) {
    if (p.period > order) continue;
    const double T = time ? p.length : p.period;
    const double t = std::exp(beta * p.log_multiplier - s * T - p.log_multiplier);
    const Dual tp{t, p.log_multiplier * t, -T * t};
    for (int copy = 0; copy < p.weight; ++copy)
      for (int k = order; k >= p.period; --k) {  // c[k] -= t_p c[k - n_p], from the top down
        const Dual& lo = c[static_cast<std::size_t>(k - p.period)];
        Dual& hi = c[static_cast<std::size_t>(k)];
        hi.v -= tp.v * lo.v;
        hi.db -= tp.db * lo.v + tp.v * lo.db;
        hi.ds -= tp.ds * lo.v + tp.v * lo.ds;
      }
  }
  Dual f;
  for (const Dual& x : c) f.v += x.v, f.db += x.db, f.ds += x.ds;
  return f;
}

/// s(0) by Newton from 0, and ds/dbeta there.
std::pair<double, double> leading_zero(const std::vector<PrimeCycle>& cycles, int order, bool time) {
  double s = 0;
  for (int it = 0; it < 50; ++it) {
    const Dual f = zeta(cycles, order, 0, s, time);
    const double step = f.v / f.ds;
    s -= step;
    if (std::abs(step) < 1e-15 * (1 + std::abs(s))) break;
  }
  const Dual f = zeta(cycles, order, 0, s, time);
  return {s, -f.db / f.ds};
}

/// The smallest positive zero of prod_p (1 - z^{n_p}) cut at z^order (bisection on (0, 1]; 1 when none).
double topological_zero(const std::vector<PrimeCycle>& cycles, int order) {
  std::vector<double> c(static_cast<std::size_t>(order) + 1, 0.0);
  c[0] = 1;
  for (const PrimeCycle& p : cycles) {
    if (p.period > order) continue;
    for (int copy = 0; copy < p.weight; ++copy)
      for (int k = order; k >= p.period; --k)
        c[static_cast<std::size_t>(k)] -= c[static_cast<std::size_t>(k - p.period)];
  }
  const auto poly = [&](double z) {
    double v = 0;
    for (std::size_t k = c.size(); k-- > 0;) v = v * z + c[k];
    return v;
  };
  // the first sign change on a fine grid, then bisection
  const int steps = 4000;
  double lo = 0, hi = 1;
  for (int i = 1; i <= steps; ++i) {
    const double z = static_cast<double>(i) / steps;
    if (poly(z) <= 0) {
      lo = static_cast<double>(i - 1) / steps, hi = z;
      break;
    }
  }
  for (int it = 0; it < 60; ++it) {
    const double mid = (lo + hi) / 2;
    (poly(mid) > 0 ? lo : hi) = mid;
  }
  return hi;
}

}  // namespace

std::vector<CycleAverages> cycle_averages(const std::vector<PrimeCycle>& cycles, int max_order) {
  std::vector<CycleAverages> out;
  for (int order = 2; order <= max_order; ++order) {
    CycleAverages a;
    a.order = order;
    a.entropy = -std::log(topological_zero(cycles, order));
    double points = 0;  // N_order = sum over m | order of m P_m
    for (const PrimeCycle& p : cycles)
      if (p.period <= order && order % p.period == 0) points += static_cast<double>(p.period) * p.weight;
    a.entropy_count = points > 0 ? std::log(points) / order : 0;
    const auto [s_time, lyap_time] = leading_zero(cycles, order, true);
    const auto [s_coll, lyap_coll] = leading_zero(cycles, order, false);
    a.escape_time = -s_time;
    a.lyapunov_time = lyap_time;
    a.lyapunov_collision = lyap_coll;
    a.mean_free_path = lyap_coll / lyap_time;
    out.push_back(a);
  }
  return out;
}

}  // namespace rotleak
