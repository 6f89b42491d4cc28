#include "sim/tally/tally.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace rotleak {

void Tally::resize(const Scene& scene) {
  escapes_per_bin.assign(scene.survival_bins(), 0);
  escapes_by_leak.assign(leak_count(scene) > 1 ? leak_count(scene) * escapes_per_bin.size() : 0, 0);
  if (scene.collision_density)
    collision_density.assign(
        scene.collision_density->windows.size() * static_cast<std::size_t>(scene.collision_density->bins), 0);
  if (scene.splitting.on)
    estimator = LinesEstimator{};
  else if (scene.sampling.weighted())
    estimator = WeightedEstimator{};
  else
    estimator = CountingEstimator{};
  std::visit([&](auto& e) { e.resize(escapes_per_bin.size()); }, estimator);
  collision_density_w.assign(weighted() ? collision_density.size() : 0, FixedSum{});
}

void Tally::add_end(Fate fate, double t, std::uint64_t collisions_made, double w, double dt, int leak) {
  std::size_t b = 0;  // the escape bin (escapes only)
  switch (fate) {
    case Fate::escaped:
      b = std::min(static_cast<std::size_t>(t / dt), escapes_per_bin.size() - 1);
      ++escapes_per_bin[b];
      ++escaped;
      if (!escapes_by_leak.empty()) ++escapes_by_leak[static_cast<std::size_t>(leak) * escapes_per_bin.size() + b];
      break;
    case Fate::survived:
      ++survived;
      break;
    case Fate::stuck:
      ++stuck;
      break;
  }
  collisions += collisions_made;
  std::visit([&](auto& e) { e.add_end(fate, b, w); }, estimator);
}

std::uint64_t Tally::leak_escaped(std::size_t j) const {
  if (escapes_by_leak.empty()) return escaped;
  std::uint64_t n = 0;
  for (std::size_t k = 0; k < escapes_per_bin.size(); ++k) n += leak_escapes(j, k);
  return n;
}

void Tally::merge(const Tally& o) {
  for (std::size_t i = 0; i < escapes_per_bin.size(); ++i) escapes_per_bin[i] += o.escapes_per_bin[i];
  for (std::size_t i = 0; i < collision_density.size(); ++i) collision_density[i] += o.collision_density[i];
  if (escapes_by_leak.size() != o.escapes_by_leak.size())
    throw std::logic_error("merging tallies of different leak counts");
  for (std::size_t i = 0; i < escapes_by_leak.size(); ++i) escapes_by_leak[i] += o.escapes_by_leak[i];
  collisions += o.collisions;
  escaped += o.escaped;
  survived += o.survived;
  stuck += o.stuck;
  for (std::size_t i = 0; i < collision_density_w.size(); ++i) collision_density_w[i].merge(o.collision_density_w[i]);
  if (estimator.index() != o.estimator.index()) throw std::logic_error("merging tallies of different estimators");
  std::visit([&](auto& e) { e.merge(std::get<std::decay_t<decltype(e)>>(o.estimator)); }, estimator);
}

void check_conservation(const Tally& t, const IntervalSet& done, std::uint64_t n) {
  if (const auto* lines = t.get_if<LinesEstimator>()) {
    lines->check_conservation();
    return;
  }
  const std::uint64_t ran = particles_in(done, n), ended = t.escaped + t.survived + t.stuck;
  if (ended != ran)
    throw std::logic_error("tally does not add up: " + std::to_string(t.escaped) + " escaped + " +
                           std::to_string(t.survived) + " survived + " + std::to_string(t.stuck) + " stuck = " +
                           std::to_string(ended) + " particles, but the blocks done hold " + std::to_string(ran));
}

}  // namespace rotleak
