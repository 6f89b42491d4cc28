// A scene: everything one run needs. Scene files are read and validated in io/scene_file.hpp,
// where every error names the key, the value and what is allowed.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "geometry/table_spec.hpp"
#include "leak/table_leak.hpp"
#include "numeric/exact.hpp"
#include "numeric/input.hpp"
#include "numeric/tier.hpp"

namespace rotleak {

enum class InitKind { birkhoff, flow };

std::string to_string(InitKind k);

struct TimeWindow {
  double from = 0, to = 0;
};

/// How initial conditions are drawn (sim/model/sampling.hpp): the invariant measure, or the defensive
/// mixture eps u + (1 - eps) g with g concentrated near the bouncing-ball family (|p| log-uniform in
/// [p_min, p_max] on the straight edges; for flow starts, directions that close to the edges' normal).
enum class SamplingKind { uniform, mupo };

struct SamplingSpec {
  SamplingKind kind = SamplingKind::uniform;
  /// Weight of the uniform component: no particle weighs more than 1 / eps (docs/model.md, "Small samples").
  double eps = 0.7;
  double p_min = 1e-12, p_max = 0.05;
  /// Share of g drawn on the riding bands of a moving leak (docs/model.md, "Riding orbits"; riding_bands in
  /// sim/model/sampling.hpp): bouncing-ball orbits whose drift keeps pace with the leak's pattern. 0: none.
  double ride = 0;

  /// Particles carry weights other than 1 (every scheme but the uniform one).
  bool weighted() const { return kind != SamplingKind::uniform; }
  /// The largest weight a particle can start with: 1 / eps for the mixture, 1 for uniform sampling.
  double max_weight() const { return weighted() ? 1 / eps : 1.0; }
};

std::string to_string(SamplingKind k);

/// Population splitting in time (sim/engine/population.hpp): every `every` time units each member that the
/// split rule picks is replaced by two of half its weight, the copy's direction turned by an angle
/// drawn from [-delta, delta]; a line (a starting particle and its descendants) holding more than
/// `cap` members at a split time is thinned by roulette (each kept with probability 1/2 at twice its
/// weight, until at most `cap` remain).
struct SplitSpec {
  bool on = false;
  double every = 0;  ///< the scene's default when not given: ln 2 over the small-hole rate (default_split_every)
  double delta = 1e-12;
  std::uint64_t cap = 64;
};

/// Splitting over initial conditions (sim/engine/ic_splitting.hpp, docs/model.md "Splitting over initial
/// conditions"): generalized splitting on the escape time of a start, for tails that splitting in time cannot draw.
/// P is that of the stratum drawn: starts with |p| in [p_lo, p_hi] (on the stadium's straight edges only, with edges),
/// uniform there as the billiard map's invariant measure, created uniformly over the creation window.
struct StartSplitSpec {
  bool on = false;
  int replicates = 20;  ///< independent replicates of ensemble.particles starts each: their spread is P's error
  int factor = 4;       ///< levels outlived by a share 1 / factor of the stage before
  int moves = 2;        ///< Metropolis moves between two kept states of a chain
  int halvings = 100;   ///< proposal scales 2^-j of a level's extent, j in 0 .. halvings
  int window = 5;       ///< j over 2 window + 1 halvings, centred where the pilot's chains moved most
  /// The clock past the level where double stops resolving the moves: dd, float128, or double (none).
  TierKind deep_tier = TierKind::dd;
  int handover_bits = 20;  ///< hand over where a level's moves fall below 2^handover_bits double ulps
  double p_lo = 0, p_hi = 1;
  bool edges = false;
};

struct CollisionDensitySpec {
  int bins = 1000;
  std::vector<TimeWindow> windows;
};

/// An exact input and the text the user wrote for it.
struct ExactInput {
  ExactReal value;
  std::string text;
};

/// A table other than the stadium of [stadium] (docs/tables.md): a standard kind (table_kinds()) with its exact
/// parameters in that kind's order, or a polygon's vertices.
struct TableInput {
  std::string kind;
  std::vector<ExactInput> params;
  std::vector<std::pair<ExactInput, ExactInput>> vertices;
};

/// One leak of a list ([[leaks]]): the loop it lies on (0: the outer boundary) and its exact width (a share of that
/// loop's length), start and omega.
struct LeakInput {
  int loop = 0;
  ExactInput width, start, omega;
};

struct Scene {
  // Exact inputs, with the text the user wrote: the stadium and its one leak (the table and leak of every
  // scene that names no other).
  ExactReal d = ExactReal::parse("2"), r = ExactReal::parse("1");
  ExactReal width = ExactReal::parse("0.01"), start = ExactReal::parse("0"), omega = ExactReal::parse("0");
  std::string d_text = "2", r_text = "1", width_text = "0.01", start_text = "0", omega_text = "0";

  std::uint64_t particles = 1000000;
  std::uint64_t seed = 1;
  InitKind init = InitKind::birkhoff;
  double creation_window = 4;  ///< particles are created at times uniform in [0, creation_window]
  SamplingSpec sampling;
  /// Particles enter through this leak (its place in the list, from 0): Birkhoff starts uniform in the stationary
  /// leak's window and in p, the flux of a uniform gas outside the hole (-1: starts on the whole boundary).
  int enter_through = -1;

  double t_max = 20000;
  Tier tier = Tier::double_;  ///< an ensemble tier, or auto (chosen per scene by the audit before running)
  bool fast_forward = false;  ///< closed-form bouncing-ball phases (sim/model/particle.hpp fast_forward)
  SplitSpec splitting;
  StartSplitSpec start_splitting;
  double checkpoint_seconds =
      300;  ///< a checkpoint of the merged tallies this often (0: none); not an input of the numbers

  double survival_dt = 1;
  std::optional<CollisionDensitySpec> collision_density;
  bool escape_records = false;

  TimeWindow kappa_window{0, 300};
  /// alpha's rule (analysis/fits.hpp find_alpha): the crossing of alpha_factor x the fit counts when P
  /// lies alpha_sigma standard errors above the fit with at least min_survivors effective survivors.
  double alpha_factor = 10, alpha_sigma = 3;
  std::uint64_t min_survivors = 100;
  /// The weakest tail a regime claims to exclude: a rotating leak with no tail seen is "mid" only when
  /// alpha's upper bound lies below it; otherwise its regime is undecided (analysis/regimes.hpp).
  double tail_floor = 1e-4;

  /// A table other than the stadium d, r (unset: that stadium).
  std::optional<TableInput> table;
  /// Leaks given as a list: two or more, or one on a scatterer (empty: the one leak width, start, omega above on
  /// the outer boundary; a list of one such leak is read as that).
  std::vector<LeakInput> leaks;

  std::string source;  ///< file it came from, if any

  /// Whether the scene leaves the stadium with one leak: then it runs through any table's model (TableModel,
  /// sim/model/particle.hpp), and what only the stadium has (mupo draws, the fast-forward, the tail model) is
  /// refused.
  bool on_table() const { return table.has_value() || !leaks.empty(); }
  /// Whether a split run's rule splits every member at every split time (the rule on any table but the stadium with
  /// one leak: sim/engine/population.cpp). No line then stays unsplit past the first split time, so the allowance
  /// for unsplit lines not drawn (docs/model.md, "Splitting") has nothing to stand for.
  bool splits_every_member() const { return on_table(); }

  /// Number of survival bins, ceil(t_max / survival_dt).
  std::size_t survival_bins() const;
};

/// The scene's table, exact: its [table], or the stadium d, r.
TableSpec table_spec(const Scene& scene);
/// The scene's leaks: its list, or the one leak on the outer boundary.
std::vector<LeakSpec> leak_specs(const Scene& scene);
/// How many leaks the scene has.
inline std::size_t leak_count(const Scene& scene) { return scene.leaks.empty() ? 1 : scene.leaks.size(); }
/// Whether any of the scene's leaks moves (omega != 0): the one leak's omega, or any listed leak's.
bool any_leak_moves(const Scene& scene);

/// The small-hole escape rate of the chaotic sea, lambda L / (pi Area): the share lambda of collisions that land in
/// the leak, one collision per mean free path pi Area / L (0.004583 for d = 2, r = 1, lambda = 0.01). On any table
/// with any leaks: the leaks' lengths over pi Area.
double small_hole_rate(const Scene& scene);

/// ln 2 over the small-hole escape rate lambda L / (pi Area) (lambda L the leak's length): the time in
/// which a chaotic population halves, so that splitting in two at that pace keeps it about constant
/// (151.2 for d = 2, r = 1, lambda = 0.01).
double default_split_every(const Scene& scene);

}  // namespace rotleak
