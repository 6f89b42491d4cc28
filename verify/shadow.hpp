// Shadow runs: one particle rebuilt bit-exactly from (seed, id), followed in several tiers, each
// compared collision by collision with the truth -- an MPFR run whose precision, doubled, no longer
// changes the trace beyond truth_tolerance over the horizon.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "numeric/tier.hpp"
#include "sim/model/initial.hpp"
#include "sim/model/scene.hpp"

namespace rotleak {

struct ShadowOptions {
  std::vector<std::string> tiers{"float", "double", "long_double", "dd", "float128", "mpfr:256"};
  std::size_t collisions = 0;  ///< 0: until the truth escapes (or t_max), at most max_collisions
  std::size_t max_collisions = 20000;
  double tolerance = 1e-6;         ///< a tier is trusted while its divergence stays below this
  double truth_tolerance = 1e-40;  ///< B and 2B bits must agree this well for the 2B run to be the truth
  long start_bits = 256, max_bits = 1L << 17;
  double mupo_p = 0.1;  ///< |p| below this on consecutive straight-edge hits: MUPO phase
};

/// The truth, per collision (doubles for reporting; divergences are computed at the truth's precision).
struct TruthTrace {
  long bits = 0;         ///< precision of the truth run
  double agreement = 0;  ///< max divergence between the B and 2B runs over the horizon
  std::vector<long> bits_tried;
  std::vector<double> t, s, p;
  std::vector<unsigned char> in_leak, straight, mupo;
  std::optional<std::size_t> escape;  ///< first collision in the leak (1-based)
};

struct TierShadow {
  std::string name;
  std::size_t collisions = 0;
  std::vector<double> divergence;      ///< max-norm of (t, x, y, vx, vy) minus the truth, per collision
  std::vector<double> t, s, p;         ///< this tier's own values per collision
  std::optional<std::size_t> horizon;  ///< first collision with divergence > tolerance
  double horizon_time = 0;
  std::optional<std::size_t> decision;  ///< first collision whose escape decision differs from the truth
  std::optional<std::size_t> escape;    ///< first collision in the leak, per this tier
  double escape_time = 0;
  bool escape_exact = false;                             ///< same escape collision as the truth, time within tolerance
  double growth_per_collision = 0, growth_per_time = 0;  ///< slope of ln(divergence) in its growth range
  std::size_t growth_points = 0;
  std::string stopped;  ///< why it stopped early (interval tiers: an undecided branch)
  double seconds = 0;
};

struct ShadowResult {
  std::uint64_t id = 0;
  InitialDraw draw;
  double weight = 1;  ///< its importance weight under the scene's sampling scheme (1: uniform)
  std::size_t horizon_collisions = 0;
  TruthTrace truth;
  std::vector<TierShadow> tiers;
};

/// Throws std::invalid_argument for an unknown tier, std::runtime_error when no truth is found below max_bits.
ShadowResult shadow(const Scene& scene, std::uint64_t id, const ShadowOptions& options);
/// The same from explicit binary initial data (a chosen orbit rather than an ensemble member).
ShadowResult shadow_from(const Scene& scene, const InitialDraw& draw, const ShadowOptions& options);
/// Shadows of many ids in parallel (threads 0: all cores), in the order of `ids`; progress(done, of
/// = ids.size()) from the first thread now and then.
std::vector<ShadowResult> shadow_many(const Scene& scene, const std::vector<std::uint64_t>& ids,
                                      const ShadowOptions& options, int threads = 0,
                                      const std::function<void(std::size_t done, std::size_t of)>& progress = {});

/// Shadow results as bytes (doubles as their bits, so a result read back is the one written), for
/// the ranks of an MPI audit to send theirs to rank 0. decode_shadows throws std::runtime_error
/// naming `where` on bytes that are not such a list.
std::string encode_shadows(const std::vector<ShadowResult>& runs);
std::vector<ShadowResult> decode_shadows(const std::string& bytes, const std::string& where);

}  // namespace rotleak
