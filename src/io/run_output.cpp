#include "io/run_output.hpp"

#include "io/files.hpp"

namespace rotleak {

std::vector<double> survival_times(const Scene& scene) {
  const std::size_t bins = scene.survival_bins();
  std::vector<double> t(bins + 1);
  for (std::size_t k = 0; k <= bins; ++k) {
    const double tk = static_cast<double>(k) * scene.survival_dt;
    t[k] = tk < scene.t_max ? tk : scene.t_max;
  }
  return t;
}

std::string survival_csv(const Scene& scene, const Tally& tally) {
  const std::vector<double> t = survival_times(scene);
  const std::vector<std::uint64_t> alive = survivors_on_grid(scene, tally);
  std::string out = "t,survivors,P\n";
  out.reserve(alive.size() * 32);
  const double n = static_cast<double>(scene.particles);
  for (std::size_t k = 0; k < alive.size(); ++k) {
    out += shortest(t[k]);
    out += ',';
    out += std::to_string(alive[k]);
    out += ',';
    out += shortest(static_cast<double>(alive[k]) / n);
    out += '\n';
  }
  return out;
}

std::string density_csv(const Scene& scene, const Tally& tally) {
  const auto& spec = *scene.collision_density;
  const std::size_t bins = static_cast<std::size_t>(spec.bins);
  std::string out = "s";
  std::vector<std::uint64_t> totals(spec.windows.size(), 0);
  for (std::size_t w = 0; w < spec.windows.size(); ++w) {
    const std::string tag = "[" + shortest(spec.windows[w].from) + ":" + shortest(spec.windows[w].to) + "]";
    out += ",fc" + tag + ",count" + tag;
    for (std::size_t b = 0; b < bins; ++b) totals[w] += tally.collision_density[w * bins + b];
  }
  out += '\n';
  for (std::size_t b = 0; b < bins; ++b) {
    out += shortest((static_cast<double>(b) + 0.5) / static_cast<double>(bins));
    for (std::size_t w = 0; w < spec.windows.size(); ++w) {
      const std::uint64_t c = tally.collision_density[w * bins + b];
      const double density =
          totals[w] ? static_cast<double>(c) * static_cast<double>(bins) / static_cast<double>(totals[w]) : 0.0;
      out += ',' + shortest(density) + ',' + std::to_string(c);
    }
    out += '\n';
  }
  return out;
}

std::string escapes_csv(std::uint64_t first_id, const std::vector<EscapeRecord>& records) {
  std::string out = "id,fate,t,s,collisions\n";
  static const char* names[] = {"escaped", "survived", "stuck"};
  for (std::size_t i = 0; i < records.size(); ++i) {
    const EscapeRecord& r = records[i];
    out += std::to_string(first_id + i) + ',' + names[static_cast<int>(r.fate)] + ',' + shortest(r.t) + ',' +
           (r.fate == Fate::escaped ? shortest(r.s) : std::string()) + ',' + std::to_string(r.collisions) + '\n';
  }
  return out;
}

}  // namespace rotleak
