// What a rotating leak does to the tail: the geometry's predicted time scales, the measured jumps of
// the decay rate, and the tail classification (none / transient / persistent) and regime
// (stationary / low / mid / high) decided from the measured P(t), never from omega thresholds.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "analysis/fits.hpp"
#include "sim/scene.hpp"
#include "sim/survival.hpp"

namespace rotleak {

/// Predictions from the geometry alone, for a leak s_L(t) = s_L(0) + omega t moving towards +s.
struct LeakTimes {
  bool rotating = false;
  /// The leak's leading edge s_L + lambda/2 reaches the start of the lower straight edge (tau1) and
  /// its end (tau2), the first time after t = 0 (mod one turn); null for a stationary leak.
  std::optional<double> tau1, tau2;
  /// omega above which the leak advances more than its width lambda between two bounces of a
  /// bouncing-ball orbit (flight 2r): lambda / (2r). Below it the leak cannot step over such an orbit.
  double omega_sweep = 0;
};
LeakTimes leak_times(const Scene& scene);

/// A time where the local decay rate -d ln P / dt jumps up: the rate over [t, t + w] exceeds the rate
/// over [t - w, t] by a factor of at least 2 and by 3 standard errors (P's covariance), at a local
/// maximum of the ratio (one jump per 2w).
struct RateJump {
  double t = 0, rate_before = 0, rate_after = 0;
};
std::vector<RateJump> decay_rate_jumps(const SurvivalCurve& c, double window, double min_effective = 100);

struct TailClass {
  std::string tail = "none";       ///< none, unresolved, transient, persistent
  std::string regime;              ///< stationary, low, mid, high
  std::optional<double> tail_end;  ///< transient: the time the tail was gone (P = 0, or the steep end began)
  double end_exponent = 0;         ///< local -d ln P / d ln t over the last resolved stretch
  std::string note;                ///< the rule that decided it, in words
  /// unresolved: about how many particles (of this sampling) would keep min_survivors effective
  /// survivors through the first crossing, where alpha is read
  std::optional<std::uint64_t> resolve_particles;
};

/// The effective survivors (lines, for split runs) at which a tail above the fit is seen and called
/// `unresolved` when alpha itself, which asks for fit.min_survivors, is not resolved: below about 10 the
/// sample's own spread is no error estimate.
inline constexpr double kSeeTail = 10;

/// The documented rule (docs/output.md):
/// - none: alpha has no significant crossing (find_alpha), and nowhere later does P lie `sigma`
///   errors above factor x the fit with min(kSeeTail, min_survivors) effective survivors;
/// - unresolved: no significant crossing where alpha is read (the first one), but later P does lie
///   significantly above factor x the fit: a tail is seen, its weight is not resolved. It names the
///   particle count that would keep min_survivors effective survivors through the crossing
///   (resolve_particles: N min_survivors / the fewest effective survivors between the fit window and
///   the time the tail is seen); regime undecided (stationary for omega = 0);
/// - transient: a significant crossing at t_c, and later the tail is removed: either P reaches 0 at
///   t_0 < t_max where the algebraic continuation from the last resolved time (local exponent at most
///   3) would still have kept at least 6 effective survivors (Poisson: 0 seen with 6 expected has
///   probability 0.25%), or the local exponent over the last resolved stretch exceeds 6 by 3
///   standard errors;
/// - persistent: a significant crossing and neither of those.
/// regime: stationary for omega = 0, else low (transient), mid (none, with alpha's upper bound below
/// scene.tail_floor), high (persistent), and undecided for an unresolved tail, for none with a bound
/// at or above tail_floor (a tail above the floor could hide below the bound; resolve_particles: about
/// N bound / tail_floor), and for a persistent tail when the leak's leading edge leaves the lower
/// straight edge (tau2) only after the last survivor: its removal could not have been seen.
/// `fit`: the exponential fit alpha was read against (null: an unresolved tail is not looked for).
TailClass classify_tail(const Scene& scene, const SurvivalCurve& c, const AlphaResult& alpha,
                        const KappaFit* fit = nullptr);

}  // namespace rotleak
