// Reference trajectories: a stored set of particles whose first K collisions were computed in MPFI
// interval arithmetic (every branch of the core decided by the enclosures, so each piece hit and each
// escape decision is proven), kept in data/trajectories/, and replayed through every tier and engine.
//
// Error model. For each collision k the reference stores a gain W_k: the error of a run at unit
// roundoff u is predicted to be u W_k in the metric max(|dt|, L |ds|, |dp|). W_k is measured once,
// at generation, from MPFR runs at the precisions kGainBits against the certified values (W_k = the
// running maximum over collisions and runs of divergence / 2^-bits, each run while its divergence is
// below kGainSaturation), and at least 1 + |t_k| + sum over collisions j <= k of 1 / cos(theta_j)
// (a near-tangent flight turns the rounding of its start into a long slide). A tier with unit roundoff u
//  - must follow the reference within kErrorModelSafety u W_k + (the reference's own radius and digits) through
//    its horizon: the last collision with u W_k <= kHorizonTolerance;
//  - must reproduce every escape decision of its horizon that its error cannot blur (the leak margin,
//    in length, above kErrorModelSafety u W_k (1 + |omega| L));
//  - and, for the tiers with stored fingerprints, must produce the same bits as the build that made
//    the reference (the core uses only correctly rounded operations, and no contraction, on its path).
// An interval tier must contain the reference wherever it answers, through the collisions its own
// width allows.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "geometry/stadium.hpp"
#include "io/json.hpp"
#include "sim/engine/engine.hpp"
#include "sim/model/initial.hpp"
#include "sim/model/scene.hpp"
#include "verify/orbit_replay.hpp"

namespace rotleak {

inline constexpr double kErrorModelSafety = 64;    ///< error-model safety factor (measured margin: see README)
inline constexpr double kHorizonTolerance = 1e-6;  ///< a tier's horizon: predicted error below this
/// precisions of the runs that measure the gains (none is a tier's own), and the divergence at
/// which a gain run stops counting (saturation is near 1)
inline constexpr long kGainBits[] = {72, 90, 110, 128, 150, 180, 220, 270, 330, 400, 512};
inline constexpr double kGainSaturation = 1e-4;
inline constexpr long kReferenceStartBits = 1024;    ///< MPFI precision tried first (doubled until certified)
inline constexpr long kReferenceMaxBits = 1L << 15;  ///< give up certifying collisions above this

/// One collision of the reference.
struct RefStep {
  std::size_t k = 0;
  Piece piece = Piece::top;
  std::string t, s, p, phase;  ///< decimal midpoints of the enclosures
  bool in_leak = false;        ///< the certified escape test at this collision
  double margin = 0;           ///< leak half-width minus |s - centre|, in s (> 0 inside; its sign is certified)
  double radius = 0;           ///< enclosure half-width in the metric max(t, L s, p)
  double gain = 1;             ///< W_k
};

struct RefCase {
  std::string name, kind, note;
  std::string scene_toml;  ///< the whole scene, so the reference does not depend on data/scenes
  Scene scene;
  InitialDraw draw;
  std::optional<std::uint64_t> id;  ///< the ensemble member it is, when it is one
  long bits = 0;                    ///< MPFI precision that certified it
  std::size_t requested = 0;        ///< collisions asked for (steps.size() may be fewer: not certifiable)
  std::vector<RefStep> steps;
  /// tier name -> (collision, chained hash of the exact bits of t, q, v through that collision)
  std::map<std::string, std::vector<std::pair<std::size_t, std::uint64_t>>> fingerprints;

  std::optional<std::size_t> escape() const;  ///< first collision in the leak
};

struct ReferenceSet {
  std::string provenance_json;  ///< command, version, compiler, date (JSON object text)
  std::vector<RefCase> cases;
};

/// Tiers whose fingerprints the reference stores ("all" for --tier).
std::vector<std::string> reference_tiers();

/// How one case is to be chosen (a line of data/trajectories/cases.toml).
struct CaseSpec {
  std::string name, kind, note;
  Scene scene;
  std::size_t collisions = 200;
  std::optional<std::uint64_t> id;   ///< an ensemble member
  std::optional<std::string> s, p;   ///< explicit Birkhoff start (a double, "junctionK" for junction K)
  std::string search;                ///< grazing, junction, bouncing_ball, near_edge_escape
  std::uint64_t search_ids = 20000;  ///< ensemble ids searched
  /// collisions a search looks at: the event must happen where double still follows the true orbit,
  /// or the certified trajectory would not have it (bouncing_ball: all `collisions`)
  std::size_t search_collisions = 20;
};

/// Reads cases.toml (scenes relative to its directory). InputError on a bad entry.
std::vector<CaseSpec> read_case_specs(const std::string& path);
/// Builds one reference case (search, certification, gains, fingerprints).
RefCase build_case(const CaseSpec& spec);

/// Writes DIR/reference.json and DIR/steps/NAME.csv (each atomically).
void write_reference(const std::string& dir, const ReferenceSet& set);
/// Reads DIR/reference.json and its step files; std::runtime_error naming the file on a bad one.
ReferenceSet read_reference(const std::string& dir);

/// One tier's replay of one case.
struct TierCheck {
  std::string tier, case_name;
  std::size_t collisions = 0;       ///< the reference's
  std::size_t must_reach = 0;       ///< its horizon under the error model
  std::size_t matched_through = 0;  ///< last collision within the error model (all before it too)
  double worst_ratio = 0;           ///< max over its horizon of 64 divergence / (64 u W_k + the reference's radius)
  std::size_t decisions_required = 0, decisions_reproduced = 0;
  std::optional<std::size_t> first_wrong_decision;
  std::string bits;  ///< "identical", "differ by collision K", "not stored", "not checked"
  bool bits_ok = true;
  bool bits_compared = false;  ///< fingerprints of this tier were stored and compared
  std::string stopped;         ///< interval tiers: where an undecided branch stopped it
  bool pass = false;
};

/// One engine's replay of one case: the particle's end, run by the ensemble engine, against the reference.
struct EngineCheck {
  std::string engine, case_name;
  std::size_t horizon = 0;  ///< t_max set between collisions horizon and horizon + 1
  std::string expected, got;
  bool checked = false;  ///< false: the outcome is not decidable in double (reason in `expected`)
  bool pass = true;
};

TierCheck check_tier(const RefCase& c, const std::string& tier, bool check_bits);
EngineCheck check_engine(const RefCase& c, Engine engine, bool fast_forward);

/// The proven periodic orbits `rotleak verify` replays by default (d = 2, r = 1; none on a symmetry axis,
/// where a tier may compute the orbit exactly): the diamond and three off-axis orbits of periods 3, 7, 10.
std::vector<std::string> default_orbit_codes();

/// What `rotleak verify` runs.
struct VerifyOptions {
  std::vector<std::string> tiers = reference_tiers();
  std::vector<std::pair<Engine, bool>> engines;                  ///< (engine, fast_forward)
  std::vector<std::string> orbit_codes = default_orbit_codes();  ///< each code's first orbit, replayed (point tiers)
  bool check_bits = true;
  int threads = 0;  ///< 0: all cores
};

struct VerifyReport {
  std::string reference_dir, provenance_json;
  std::size_t cases = 0;
  std::vector<TierCheck> tiers;      ///< tier-major, cases in set order
  std::vector<EngineCheck> engines;  ///< engine-major
  std::vector<OrbitReplay> orbits;   ///< orbit-major, the point tiers of `tiers` in order
  bool pass = true;
};

/// Every case through every tier and engine asked for (in parallel; the report's order is fixed).
VerifyReport verify_reference(const ReferenceSet& set, const VerifyOptions& options);
json verify_json(const VerifyReport& report);
std::string verify_text(const VerifyReport& report);

/// Builds every case (in parallel, results in spec order); progress(done, total) from one thread.
ReferenceSet build_reference(const std::vector<CaseSpec>& specs, const std::string& provenance_json, int threads,
                             const std::function<void(std::size_t, std::size_t)>& progress = {});

/// Same-set comparison for regeneration: one line per case that changed, was added or removed.
std::vector<std::string> compare_references(const ReferenceSet& before, const ReferenceSet& after);

}  // namespace rotleak
