// Splitting over initial conditions: generalized splitting (Botev & Kroese, Statistics and Computing 22 (2012)
// 1-16) on the escape time T(x0) of a start x0 = (s, p, tau), for the tails that splitting in time cannot reach
// (orbits whose clones never separate: docs/model.md, "Splitting over initial conditions").
//
// A stage is a population of starts, each conditioned on T > its level. Stage 0 is `starts` independent draws
// of the stratum's uniform law; stage j + 1 is, for every start of stage j that outlives level j + 1, a
// Metropolis chain of `factor` states whose kernel leaves the law of x0 given T(x0) > level j + 1 invariant. For
// any kernel with that property, however slowly it mixes, the states of stage j that outlive t, over
// starts x factor^j, estimate P(T > t | stratum) without bias; replicates are independent, so their spread is
// the error. Everything is a function of (seed, replicate): the same bits for any thread count.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "numeric/tier.hpp"
#include "sim/tally/survival.hpp"

namespace rotleak {

struct Scene;

/// A start: the Birkhoff point (s a share of the whole boundary, p the sine of the angle to the normal) and the
/// creation time tau, each a double-double hi + lo (|lo| at most half an ulp of hi): the chains move starts below a
/// double's ulp, where only a clock in a wider tier tells them apart (a double clock runs hi).
struct IcPoint {
  double s = 0, p = 0, tau = 0;
  double s_lo = 0, p_lo = 0, tau_lo = 0;
};

/// The starts the sampler draws: s in a union of intervals of [0, 1], p in a union of intervals of [-1, 1], tau in
/// [tau_lo, tau_hi] (tau_lo == tau_hi: every start at that time); its law the billiard map's invariant measure,
/// uniform in (s, p), restricted to it, and tau uniform. Intervals are [lo, hi), disjoint and increasing.
struct IcStratum {
  std::vector<std::pair<double, double>> s, p;
  double tau_lo = 0, tau_hi = 0;
  /// The leak's turning rate, in turns of s per unit time (0: none). Where it is not 0 and tau spreads, two in three
  /// proposals move along the leak, s stepping `drift` times tau's step more (or less) beside its own step: on the
  /// circle a rotation and a delay are a symmetry, so the starts that outlive a level are slabs along (drift, 1) in
  /// (s, tau), thin across. ic_stratum sets it on the circle with one leak only (elsewhere those moves are wasted).
  double drift = 0;

  bool contains(const IcPoint& x) const;
  /// Its share of the billiard map's measure ds dp / 2 (1 for the whole boundary and every p).
  double share() const;
  /// The uniform draw from three uniform doubles in [0, 1).
  IcPoint at(double us, double up, double ut) const;
  /// The lengths of s's and of p's intervals laid end to end, and a point's place there.
  double s_length() const;
  double p_length() const;
  double s_packed(double x) const;
  double p_packed(double x) const;
};

/// The scene's stratum: s over the whole boundary (or, with `edges`, the stadium's two straight edges), |p| in
/// [p_lo, p_hi] of both signs (p_lo = 0: the whole of (-p_hi, p_hi)), tau over the scene's creation window.
IcStratum ic_stratum(const Scene& scene, double p_lo, double p_hi, bool edges);

struct IcSplitSpec {
  std::uint64_t starts = 10000;  ///< stage 0's draws (and the pilot's), per replicate
  int factor = 4;                ///< the pilot's levels: each outlived by a share 1 / factor of the stage before
  int replicates = 20;           ///< independent runs: their spread is P's error
  /// Proposal scales: a level's extent in each coordinate (the spread of the pilot's starts that outlive it) times
  /// 2^-j, j uniform over a window of 2 window + 1 halvings within 0 .. scale_halvings (100: thirty decades), centred
  /// where the pilot's chains at that level moved most (an accepted move that changed T by more than 1); drawn
  /// independently of the state, and frozen from the pilot, so the proposal stays symmetric.
  int scale_halvings = 100;
  int window = 5;
  int moves = 2;         ///< Metropolis moves between two states a chain keeps
  int max_levels = 200;  ///< the pilot stops adding levels here
  int threads = 0;       ///< OpenMP threads of each stage (0: OpenMP's default)
  /// The tier of the deep clock (ic_split's `deep`; its bits decide where the moves are resolved), double: none.
  TierKind deep_tier = TierKind::double_;
  /// The hand-over: from the first level whose window's central steps fall below 2^handover_bits double ulps.
  int handover_bits = 20;
};

/// A start's end: its escape time (infinity for a survivor of t_max) and its collisions.
struct IcEnd {
  double t = std::numeric_limits<double>::infinity();
  std::uint64_t collisions = 0;
  bool stuck = false;  ///< ended stuck (counted as escaped then: it is not known to live on)
};
using EscapeClock = std::function<IcEnd(const IcPoint&)>;

/// The escape clock of a scene: its table and leaks in `tier` (double, dd or float128), its fast-forward, to its t_max
/// (thread-safe).
EscapeClock scene_clock(const Scene& scene, TierKind tier = TierKind::double_);
/// A tier's significand bits: 53, 106 (dd) or 113 (float128).
int ic_tier_bits(TierKind tier);

/// A level's proposal scales: an extent in each coordinate (s and p laid end to end over the stratum's intervals) and
/// the halvings j in lo .. halvings below it. The replicates' are frozen from the pilot: a kernel that depends on the
/// pilot only, never on the state it moves nor on the population it is part of, keeps the estimator unbiased.
struct IcScales {
  double s = 1, p = 2, tau = 0;
  double u = 1;  ///< the extent of s - drift tau (mod the s length), the moves along the leak's own step in s
  int lo = 0, halvings = 20;
  /// The halving a proposal takes from its first uniform draw u0: uniform over lo .. halvings.
  int halving(double u0) const;
  /// The step 2^-j of an extent, at the window's centre.
  double step(double extent) const;
  /// Whether the centre's steps are at least 2^margin ulps, in a tier of `bits` significand bits, of the stratum's
  /// largest s, |p| and tau in each coordinate. The chains find their moves where a move just changes the trajectory
  /// by the level, so a step of 2^margin ulps says the trajectory's stretch to the level times the tier's unit
  /// roundoff is about 2^-margin: margin 8, resolved (below it T(x0) in that tier is no longer a function of x0 alone,
  /// docs/model.md); IcSplitSpec::handover_bits, where a double clock hands over to a wider one.
  bool holds(const IcStratum& stratum, int bits, int margin) const;
  bool resolved(const IcStratum& stratum, int bits = 53) const { return holds(stratum, bits, 8); }
};

/// A proposal kernel: the next proposal from state x and four uniform doubles u[0..3] in [0, 1). Its default is the
/// symmetric one described at IcSplitSpec; a test passes another.
using IcPropose = std::function<IcPoint(const IcStratum&, const IcScales&, const IcPoint& x, const double* u)>;
IcPoint symmetric_proposal(const IcStratum& stratum, const IcScales& scales, const IcPoint& x, const double* u);
/// The move a proposal makes from its first uniform draw u0: its kind (0: each coordinate its own step; 1 and 2:
/// along the leak, s's step drift times tau's more, or less; always 0 where the stratum's drift is 0 or tau is
/// fixed) and its halving (IcScales::halving of what u0 leaves once the kind is drawn). A mixture of symmetric
/// proposals drawn independently of the state is symmetric.
struct IcMove {
  int kind = 0, halving = 0;
};
IcMove ic_move(const IcStratum& stratum, const IcScales& scales, double u0);

/// One replicate on the grid t: at grid time t[i], stage[i] is the latest stage whose level is at most t[i], and
/// alive[i] its states that outlive t[i], alive_w[i] the same weighted by 2^(roulette halvings) (alive[i] itself
/// until a stage outgrows its budget); P(t[i]) = alive_w[i] / (starts f_1 ... f_stage[i]), f_j level j's factor.
struct IcReplicate {
  std::vector<int> stage;
  std::vector<std::uint64_t> alive;
  std::vector<double> alive_w;
  std::vector<std::uint64_t> population;  ///< each stage's states
  /// Each stage's chains' proposals and accepted moves (0 for stage 0), and the distinct stage-0 starts its states
  /// descend from: where that falls to a few, the stages' P rests on a few independent draws (the genealogy
  /// collapses) and the replicates' spread, still honest, grows.
  std::vector<std::uint64_t> stage_proposals, stage_accepted, ancestors;
  std::uint64_t collisions = 0, stuck = 0, proposals = 0, accepted = 0;
  /// At the hand-over to the deep clock: the starts outliving the level in double that the deep clock timed again,
  /// and those of them it found not to (dropped: past the hand-over T is the deep clock's).
  std::uint64_t handed_over = 0, handover_disagreed = 0;
};

/// A replicate's stage budget, in starts: where the starts outliving a level would seed more states than this many
/// times ensemble.particles, they are thinned by roulette first (levels closer than the pilots saw them, or a family
/// whose starts all live on, would grow the stages without end). A stage beyond kIcPopulationCap starts is refused.
inline constexpr std::uint64_t kIcThinAbove = 4;
inline constexpr std::uint64_t kIcPopulationCap = 64;

struct IcSplitRun {
  IcSplitSpec spec;
  IcStratum stratum;           ///< the starts drawn
  std::vector<double> levels;  ///< frozen from the pilot: level j + 1 of stage j + 1, increasing, below t_max
  /// Level j + 1's splitting factor: each start that outlives it seeds a chain of that many states on average (one
  /// over the share outliving it in a second pilot on the frozen levels, so that a stage holds about `starts`).
  std::vector<double> factors;
  std::vector<IcScales> scales;  ///< level j + 1's chains' proposal scales, frozen from the pilot
  /// The first level timed by the deep clock (levels.size(): none): from there on every start's T is the deep tier's.
  std::size_t handover = 0;
  std::vector<double> t;  ///< the grid
  std::vector<IcReplicate> replicates;
  std::uint64_t pilot_collisions = 0;

  /// Replicate r's P(T > t[i] | stratum).
  double P(std::size_t r, std::size_t i) const;
  /// The replicates' mean and its standard error (their standard deviation over sqrt(R); 0 for one replicate).
  double mean(std::size_t i) const;
  double error(std::size_t i) const;
  /// Replicates whose P(t[i]) is not 0.
  int nonzero(std::size_t i) const;
  /// The first level whose moves double cannot resolve (IcScales::resolved), or infinity: P past it is the double
  /// clock's, whose digits for a given start are not the trajectory's.
  double unresolved_from() const;
  std::uint64_t collisions() const;
  /// Level k's chains (stage k + 1) over the replicates that reached it: their proposals and accepted moves, and the
  /// fewest and mean distinct stage-0 starts behind the stage (reached 0: none did).
  struct LevelChains {
    std::uint64_t proposals = 0, accepted = 0, fewest = 0, reached = 0;
    double mean_ancestors = 0;
  };
  LevelChains chains(std::size_t k) const;
  /// The fewest distinct stage-0 starts behind a stage past stage 0 in any replicate, and the level that stage
  /// begins at ({0, 0}: no replicate passed its first level).
  std::pair<std::uint64_t, double> fewest_ancestors() const;
};

/// What the pilots freeze: levels, each level's proposal scales and splitting factor, and the level from which the
/// deep clock times the starts (levels.size(): none).
struct IcPilot {
  std::vector<double> levels, factors;
  std::vector<IcScales> scales;
  std::size_t handover = 0;
  std::uint64_t collisions = 0;
};

/// Levels and scales from a pilot of fixed effort (replicate index -1 of the seed's streams: every stage `starts`
/// states, the chains spread evenly over the starts that outlive the level): each level the T that a share 1 / factor
/// of the stage before outlives, until that share outlives t_max, the stage dies out or max_levels; each level's
/// extents the spread of the starts outliving it, its window centred where its chains moved most (the first level's
/// chains try every halving, each later level's start from the window of the level before). Then the factors: one
/// over each level's share outliving it in a second fixed-effort pilot on the frozen levels and scales (replicate
/// index -2); the levels it did not reach are dropped.
/// With a `deep` clock the starts are timed by it from the first level whose window's steps fall below
/// 2^handover_bits double ulps (IcScales::holds): in the first pilot from the level after the one that fell below, in
/// the second pilot and the replicates from that level itself, the starts outliving it in double timed again by the
/// deep clock.
IcPilot ic_pilot(const EscapeClock& clock, const IcStratum& stratum, const IcSplitSpec& spec, double t_max,
                 std::uint64_t seed, const IcPropose& propose = symmetric_proposal, const EscapeClock& deep = {});

/// Replicate r with the pilot's frozen levels, scales and factors, on grid t: generalized splitting proper, each start
/// outliving level j seeding floor(f_j) or floor(f_j) + 1 chain states (the latter with probability frac(f_j)).
IcReplicate ic_replicate(const EscapeClock& clock, const IcStratum& stratum, const IcSplitSpec& spec,
                         const IcPilot& pilot, const std::vector<double>& t, std::uint64_t seed, std::uint64_t r,
                         const IcPropose& propose = symmetric_proposal, const EscapeClock& deep = {});

/// The run's survival curve (SurvivalCurve::replicated) on its grid: the replicates' mean and error, their states
/// alive, G.
SurvivalCurve ic_curve(const IcSplitRun& run);

/// Pilot, then every replicate; `progress` (may be empty) after each replicate: done, of.
IcSplitRun ic_split(const EscapeClock& clock, const IcStratum& stratum, const IcSplitSpec& spec,
                    const std::vector<double>& t, double t_max, std::uint64_t seed,
                    const std::function<void(int, int)>& progress = {}, const IcPropose& propose = symmetric_proposal,
                    const EscapeClock& deep = {});

/// A scene's run (scene.start_splitting on): its stratum, ensemble.particles starts a replicate, its seed, the
/// survival grid to its t_max, on `threads` (0: OpenMP's default); `progress` after each replicate.
IcSplitRun run_start_splitting(const Scene& scene, int threads = 0, const std::function<void(int, int)>& progress = {});

}  // namespace rotleak
