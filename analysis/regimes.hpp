// What a rotating leak does to the tail: the geometry's predicted time scales, the measured jumps of
// the decay rate, and the tail classification (none / transient / persistent) and regime
// (stationary / low / mid / high) decided from the measured P(t), never from omega thresholds.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/fits.hpp"
#include "sim/model/scene.hpp"
#include "sim/tally/survival.hpp"

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

/// 2 r omega near a rational: P/Q, the best approximation of the first kind of x = 2 r omega with
/// Q <= kNearRationalQ, and eps = x - P/Q (what the leak pattern, seen at the bounces, drifts by per bounce
/// of a bouncing-ball orbit, in turns). Null for omega = 0 and where x is P/Q exactly.
struct NearRational {
  std::string rational;  ///< "P/Q" of 2 r omega
  long long q = 0;
  double eps = 0;
  std::string omega_rational;  ///< the rational omega near it, P / (2 r Q), as p/q when 2 r is rational
};
inline constexpr long kNearRationalQ = 30;
std::optional<NearRational> near_rational(const Scene& scene);

struct TailClass {
  std::string tail = "none";  ///< none, unresolved, transient, persistent
  std::string regime;  ///< stationary, low, mid, high, near-rational (a transient tail near a rational), undecided
  std::optional<double> tail_end;  ///< transient: the time the tail was gone (P = 0, or the steep end began)
  /// Where the rule locates the end, [lo, hi] (its error): P = 0 at tail_end, alive at the last resolved
  /// time before it; or the steep stretch [tail_end, t_e] whose local exponent called the tail removed.
  std::optional<std::pair<double, double>> tail_end_range;
  double end_exponent = 0;  ///< local -d ln P / d ln t over the last resolved stretch
  std::string note;         ///< the rule that decided it, in words
  /// unresolved: about how many particles (of this sampling) would keep min_survivors effective
  /// survivors through the first crossing, where alpha is read
  std::optional<std::uint64_t> resolve_particles;
  /// regime "near-rational" (a near-rational transient): the rational 2 r omega lies near, and eps
  std::optional<NearRational> near;
};

/// P over the exponential fit at which a tail near a rational is seen (classify_tail).
inline constexpr double kNearBump = 1.3;
/// Local exponent at the end of the resolved range above which a tail near a rational is being removed.
inline constexpr double kNearSteep = 2;

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
/// Near a rational (near_rational with Q >= 2: not an integer, whose pattern is a single spot like a slow
/// leak's), a tail that forms and dies is the pattern drifting off P/Q, and is looked for more closely:
/// - a tail is also seen where P rises kNearBump times above the fit (and sigma errors), not only factor
///   times: near 2/3 + 1e-4 a tail forms and dies with P at most 1.7 times the fit;
/// - the steep end that calls a tail removed is a local exponent above kNearSteep (a MUPO tail goes as
///   1/t; one steeper by 1 is being removed), not 6: near 1/5 + 2e-5, t P falls 60-fold from t = 3000 to
///   8000.
/// and a transient tail there has regime "near-rational" (a near-rational transient), never "low".
/// regime: stationary for omega = 0, else low (transient), mid (none, with alpha's upper bound below
/// scene.tail_floor), high (persistent), and undecided for an unresolved tail, for none with a bound
/// at or above tail_floor (a tail above the floor could hide below the bound; resolve_particles: about
/// N bound / tail_floor), and for a persistent tail when the leak's leading edge leaves the lower
/// straight edge (tau2) only after the last survivor: its removal could not have been seen.
/// One tail verdict with the amplitude: where alpha is not resolved but `amplitude` is (a flat 1/t stretch
/// with C more than 3 of its errors, stat. and drift, above 0), the tail is seen and its weight measured, so
/// the class is its fate from the start of C's stretch (persistent or transient, with that regime), never
/// `none` or `unresolved` beside a resolved C.
/// `fit`: the exponential fit alpha was read against (null: an unresolved tail is not looked for).
TailClass classify_tail(const Scene& scene, const SurvivalCurve& c, const AlphaResult& alpha,
                        const KappaFit* fit = nullptr, const TailAmplitude* amplitude = nullptr);

}  // namespace rotleak
