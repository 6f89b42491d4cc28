// The covering model of the MUPO tail (docs/model.md, "Predicting the tail from omega"): from 2 r omega, the
// leak width and the stadium alone, whether a 1/t tail forms, its amplitude C (P ~ C / t), and, where omega
// lies off a rational, when the tail dies. No constant is fitted: the only numbers are the cap-passage mean
// <1/g> = (3/4) ln 3 (Dettmann & Georgiou 2009) and the chaotic sea's escape rate lambda L / (pi Area).
//
// The picture: a bouncing-ball orbit at x on the straight edges, with slow drift p, sees the leak at its
// top-edge hits on a lattice u + k / q' of s and at its bottom-edge hits on 1/2 - X - u + k / q' (X = P / Q
// the rational of 2 r omega, q' = Q / gcd(Q, 2), u the orbit's own phase, uniform). Lattice points on the
// edges cut them into free gaps; an orbit lives as long as its drift keeps it inside one. A gap of length h
// gives h^2 / (L t) between two leak intervals, (1 + <1/g>) h^2 / (L t) against a cap (it comes back once,
// slower by g), and (1 + <1/g>) / (1 - <1/g>) d^2 / (L t) when no lattice point lies on the edges (orbits
// pass from cap to cap until their p has grown out of the family). Off the rational by eps, both lattices
// slide (at +-eps in s per unit time) and sweep the gaps: the tail's end.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sim/model/scene.hpp"

namespace rotleak {

/// The model's own relative error on C, stated with every prediction: the spread of measured over predicted C on
/// the omega atlas's test half (docs/model.md, "Predicting the tail from omega").
inline constexpr double kModelAmplitudeError = 0.10;

/// <1/g> over a cap passage, g = 4s - 1 (s > 1/3) or 3 - 8s, s uniform (Dettmann & Georgiou 2009).
double cap_passage_mean();

/// What the lattice of one rational P / Q of 2 r omega leaves.
struct LatticeTail {
  std::string rational;        ///< "P/Q" of 2 r omega ("0" for a stationary leak)
  long long Q = 0;             ///< its denominator (1 for a stationary leak)
  long long lattice = 0;       ///< q' = Q / gcd(Q, 2): leak positions an orbit's top-edge hits see
  double eps = 0;              ///< omega - P / (2 r Q): the lattice slides at eps (s per unit time)
  double amplitude = 0;        ///< C: t P(t) of the tail before any sweep
  double free_fraction = 0;    ///< share of orbit phases that see no leak on either straight edge
  double crossing = 0;         ///< where C / t meets the chaotic part exp(-kappa0 t)
  std::optional<double> half;  ///< eps != 0: t P down to half of C
  std::optional<double> end;   ///< eps != 0: t P down to a tenth of C (the tail's end)
  bool forms = false;          ///< crossing < t_max and crossing < end
};

struct TailPrediction {
  bool forms = false;
  double amplitude = 0;        ///< C of the lattice that carries the tail (or the nearest to forming one)
  std::optional<double> end;   ///< when that tail dies (none: never, the rational is exact)
  std::optional<double> half;  ///< when t P is down to half of C
  std::string rational;        ///< its P/Q of 2 r omega
  long long Q = 0;
  double eps = 0;
  double crossing = 0;
  double kappa0 = 0;  ///< lambda L / (pi Area): the chaotic sea's escape rate the crossing uses
  double free_fraction = 0;
  std::string regime;  ///< stationary, low (slow leak, tail swept), near-rational (transient), high, mid
  std::string note;
  std::vector<LatticeTail> candidates;  ///< every rational considered (best approximations of 2 r omega)
  /// Off the rational: the model's t P(t) at 24 log-spaced times from the crossing to 1.5 x end (empty on it,
  /// where t P = C throughout)
  std::vector<std::pair<double, double>> curve;
};

/// The model's prediction for a scene (its stadium, leak width, start and omega; t_max decides "forms").
/// Throws InputError (naming leak.width) for a leak of width 1/2 or more, outside the model.
TailPrediction predict_tail(const Scene& scene);

}  // namespace rotleak
