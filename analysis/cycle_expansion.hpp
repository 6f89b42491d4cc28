// Cycle expansions (ChaosBook, "Cycle expansions" and "Why cycle?"): averages of the closed stadium from
// its prime cycles (verify/orbits.hpp), truncated at a topological length N (docs/model.md, "Periodic
// orbits"). The dynamical zeta function 1/zeta(beta, s) = prod_p (1 - t_p), t_p = exp(beta A_p - s T_p) /
// |Lambda_p|, expanded as a polynomial in the bookkeeping variable z^{n_p} and cut at z^N, vanishes at s(beta);
// the average of A = ln|Lambda| per unit of T is ds/dbeta = -(dF/dbeta) / (dF/ds) at beta = 0 (T the cycle's
// length: the Lyapunov exponent a unit time; T = n_p: a collision). The topological zeta function prod_p
// (1 - z^{n_p}) has its smallest zero at z = exp(-h), h the topological entropy of the billiard map.
#pragma once

#include <vector>

namespace rotleak {

/// One prime cycle: its period (bounces), its length (time at unit speed), ln|Lambda| and how many
/// distinct cycles it stands for (2 when its time reverse is another cycle not listed).
struct PrimeCycle {
  int period = 0;
  double length = 0, log_multiplier = 0;
  int weight = 1;
};

struct CycleAverages {
  int order = 0;                  ///< cycles of period <= order, the expansion cut at z^order
  double entropy = 0;             ///< -ln z0, z0 the smallest zero of the truncated topological zeta function
  double entropy_count = 0;       ///< ln(N_order) / order, N_n = sum_{m | n} m P_m the periodic points of period n
  double escape_time = 0;         ///< -s(0) with T the length: 0 for a closed billiard, up to truncation
  double lyapunov_time = 0;       ///< <ln|Lambda|> / <T> a unit time
  double lyapunov_collision = 0;  ///< ... a collision (T_p = n_p)
  double mean_free_path = 0;      ///< <T> / <n>: the cycles' mean length a collision (the billiard's: pi A / P)
};

/// The averages cut at each order 2 .. max_order (cycles of larger period are ignored).
std::vector<CycleAverages> cycle_averages(const std::vector<PrimeCycle>& cycles, int max_order);

}  // namespace rotleak
