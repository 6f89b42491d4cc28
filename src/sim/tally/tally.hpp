// What a run counts: integer counts and exact sums that merge in any order (threads, ranks, shards,
// resumes), and the conservation law every run and merge checks.
#pragma once

#include <cstdint>
#include <variant>
#include <vector>

#include "sim/model/fate.hpp"
#include "sim/model/scene.hpp"
#include "sim/tally/blocks.hpp"
#include "sim/tally/estimators.hpp"

namespace rotleak {

/// One particle's end, kept only when escape records are asked for.
struct EscapeRecord {
  double t = 0;  ///< escape time (or t_max for survivors)
  double s = 0;  ///< boundary coordinate of the escape collision
  std::uint64_t collisions = 0;
  Fate fate = Fate::survived;
  int leak = 0;  ///< escaped: the leak that took it (its place in the scene's list; 0 for one leak)
};

/// Integer counts and exact fixed-point sums; merge() is exact and order-independent.
struct Tally {
  std::vector<std::uint64_t> escapes_per_bin;    ///< escapes with t in [k dt, (k+1) dt)
  std::vector<std::uint64_t> collision_density;  ///< windows x bins, row-major
  /// Scenes of several leaks: escapes through leak j with t in [k dt, (k+1) dt) at j bins + k (leaks x bins,
  /// row-major); empty for one leak (its escapes are escapes_per_bin).
  std::vector<std::uint64_t> escapes_by_leak;
  std::uint64_t collisions = 0, escaped = 0, survived = 0, stuck = 0;
  /// Runs whose particles carry weights (every estimator but counting): the weighted collision density.
  std::vector<FixedSum> collision_density_w;
  /// The survival estimator the scene's sampling asks for (resize() picks it).
  std::variant<CountingEstimator, WeightedEstimator, LinesEstimator> estimator;

  /// Sizes the arrays for the scene and picks its estimator: lines for a split run, weighted for a
  /// sampling scheme other than uniform, counting otherwise.
  void resize(const Scene& scene);
  /// Whether the particles carry weights (split members weigh w0 2^-level; sampled particles w).
  bool weighted() const { return !std::holds_alternative<CountingEstimator>(estimator); }
  /// The estimator of type E (std::bad_variant_access when the run has another); get_if: or nullptr.
  template <class E>
  E& as() {
    return std::get<E>(estimator);
  }
  template <class E>
  const E& as() const {
    return std::get<E>(estimator);
  }
  template <class E>
  E* get_if() {
    return std::get_if<E>(&estimator);
  }
  template <class E>
  const E* get_if() const {
    return std::get_if<E>(&estimator);
  }
  /// A particle's (or a split member's) end: its fate at time t (escapes binned by dt), its collisions,
  /// and its weight w, which the estimator books.
  /// `leak` is the leak it escaped through (ParticleEnd::leak), booked in escapes_by_leak when that is kept.
  void add_end(Fate fate, double t, std::uint64_t collisions_made, double w, double dt, int leak = 0);
  /// Escapes through leak j with t in bin k (escapes_per_bin's with one leak), and through leak j in all.
  std::uint64_t leak_escapes(std::size_t j, std::size_t k) const {
    return escapes_by_leak.empty() ? escapes_per_bin[k] : escapes_by_leak[j * escapes_per_bin.size() + k];
  }
  std::uint64_t leak_escaped(std::size_t j) const;
  /// Adds another tally of the same scene (the same estimator): exact, in any order.
  void merge(const Tally& other);
};

/// Throws std::logic_error unless the tally of the blocks `done` of a run of n particles adds up:
/// escaped + survived + stuck particles equal the particles of those blocks (runs without splitting),
/// and a split run's weights are conserved exactly (LinesEstimator::check_conservation). Every run checks its result.
void check_conservation(const Tally& t, const IntervalSet& done, std::uint64_t n);

}  // namespace rotleak
