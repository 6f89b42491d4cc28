// Certified escapes for a whole sample: a scene's first N particles, each followed in mean-value MPFI
// sets (verify/lohner.hpp) with its bits doubled until its escape (or its survival past the time cap) is
// proven or a precision cap is hit; the survival curve of that sample with a rigorous bracket; and the
// point tiers' curves of the same ids judged against it (docs/model.md, "Certified escapes").
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "sim/model/scene.hpp"
#include "verify/certify.hpp"

namespace rotleak {

struct SampleOptions {
  std::uint64_t sample = 10000;  ///< particles 0 .. sample - 1 of the scene
  double t_cap = 0;              ///< follow each particle to this time (0: the scene's t_max)
  long start_bits = 64, max_bits = 16384;
  double time_width = 1e-9;  ///< a proven escape time wider than this is proven again with twice the bits
  int threads = 0;           ///< 0: OpenMP's default
  std::vector<std::string> tiers{"double", "long_double", "dd"};
  double dt = 0;  ///< the bracket's grid step (0: t_cap / 400)
  bool progress = true;
  /// Where the run keeps its checkpoint (empty: none): read if it is there, written whole at most every
  /// checkpoint_seconds; the caller removes it when the directory is complete.
  std::filesystem::path checkpoint;
  double checkpoint_seconds = 30;
  /// Certify only the ids i with i % ranks == rank (an MPI rank's share; run/certify_shared.hpp).
  std::uint64_t rank = 0, ranks = 1;
};

enum class EscapeStatus { proven, survives, undecided };
const char* status_name(EscapeStatus s);

/// One particle's certificate: a proven escape (its collision, its time in [t_lo, t_hi]), a proven survival
/// past the cap (t_lo = t_hi = the cap), or undecided at the precision cap (alive until t_lo, proven).
struct ParticleEscape {
  std::uint64_t id = 0;
  EscapeStatus status = EscapeStatus::undecided;
  double t_lo = 0, t_hi = 0;
  std::size_t collisions = 0;  ///< the escape collision, or the collisions certified
  long bits = 0;               ///< the precision of the last attempt
  double seconds = 0;
};

/// A point tier's escape times for the same ids (t_max and the cap as the certificates'); a survivor's
/// time is +inf.
struct TierEscapes {
  std::string tier;
  std::vector<double> t;
  double seconds = 0;
};

/// The bracket on the grid: lower(t) counts the particles proven alive at t, upper(t) those not proven
/// escaped by t; each tier's P(t) for the same ids beside it.
struct SampleBracket {
  std::vector<double> t, lower, upper;
  std::vector<std::vector<double>> tier_p;  ///< [tier][grid point]
};

/// How a tier's curve stands against the bracket.
struct TierJudgement {
  std::string tier;
  std::size_t grid_points = 0;
  std::size_t outside = 0;            ///< grid points where P lies outside [lower, upper]
  std::size_t outside_beyond_3s = 0;  ///< ... by more than 3 of the difference's standard errors
  std::size_t tight = 0;              ///< grid points where the bracket is narrower than that error
  std::size_t outside_where_tight = 0;
  double ks_d = 0, ks_p = 1;              ///< two-sample Kolmogorov-Smirnov on escape times up to the cap
  std::size_t same_escape_collision = 0;  ///< proven particles whose tier escape is at the same collision
};

struct SampleCertificate {
  std::vector<ParticleEscape> particles;
  std::vector<TierEscapes> tiers;
  std::vector<std::size_t> tier_collisions;  ///< [tier * N + id]: the tier's escape collision
  double t_cap = 0;
  int threads = 0;
  double seconds = 0;
};

/// The certificates of a share of the sample (opt.rank of opt.ranks), marked done; the rest left empty.
struct SampleParticles {
  std::vector<ParticleEscape> particles;
  std::vector<char> done;
  int threads = 0;
  double seconds = 0;
};
SampleParticles certify_particles(const Scene& scene, const SampleOptions& opt);
/// The sample from every particle's certificate: the point tiers run on the same ids.
SampleCertificate complete_sample(const Scene& scene, const SampleOptions& opt, SampleParticles p);
/// Certifies the sample (threads over particles; the result does not depend on them).
SampleCertificate certify_sample(const Scene& scene, const SampleOptions& opt);

/// What a sample's certificates add up to (the summary's and the printed lines' one count).
struct SampleTotals {
  std::size_t proven = 0, survives = 0, undecided = 0;
  long bits_max = 0;
  double cpu_seconds = 0;        ///< the certificates' own seconds, summed over the particles
  double escape_width_max = 0;   ///< the widest proven escape time
  double bracket_width_max = 0;  ///< the widest upper - lower on the grid
  double bracket_widest_at = 0;  ///< where
};
SampleBracket bracket_of(const SampleCertificate& c, double dt);
SampleTotals totals_of(const SampleCertificate& c, const SampleBracket& b);
std::vector<TierJudgement> judge_tiers(const SampleCertificate& c, const SampleBracket& b);

/// DIR/escapes.csv, DIR/bracket.csv, then DIR/summary.json (last: the directory is complete when it is
/// there); schemas in docs/output.md.
void write_sample_certificate(const std::filesystem::path& dir, const Scene& scene, const SampleOptions& opt,
                              const SampleCertificate& c);

}  // namespace rotleak
