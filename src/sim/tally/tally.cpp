#include "sim/tally/tally.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace rotleak {

void Tally::resize(const Scene& scene) {
  escapes_per_bin.assign(scene.survival_bins(), 0);
  if (scene.collision_density)
    collision_density.assign(
        scene.collision_density->windows.size() * static_cast<std::size_t>(scene.collision_density->bins), 0);
  split = scene.splitting.on;
  weighted = scene.sampling.weighted() || split;  // split members weigh 2^-level
  if (weighted && !split) {
    escaped_w.assign(escapes_per_bin.size(), FixedSum{});
    escaped_w2.assign(escapes_per_bin.size(), FixedSum{});
  }
  if (weighted) collision_density_w.assign(collision_density.size(), FixedSum{});
  if (split) {
    const std::size_t points = escapes_per_bin.size() + 1;
    for (auto* v : {&line_in, &line_out, &line2_in, &line2_out}) v->assign(points, FixedSum{});
    lines_ended.assign(points, 0);
    born_per_bin.assign(escapes_per_bin.size(), 0);
    culled_per_bin.assign(escapes_per_bin.size(), 0);
  }
}

void Tally::add_end(Fate fate, double t, std::uint64_t collisions_made, double w, double dt) {
  if (weighted) {
    total_w.add(w);
    total_w2.add(w * w);
  }
  switch (fate) {
    case Fate::escaped: {
      const std::size_t nbins = escapes_per_bin.size();
      std::size_t b = static_cast<std::size_t>(t / dt);
      if (b >= nbins) b = nbins - 1;
      ++escapes_per_bin[b];
      ++escaped;
      if (weighted) {
        escaped_w[b].add(w);
        escaped_w2[b].add(w * w);
      }
      break;
    }
    case Fate::survived:
      ++survived;
      break;
    case Fate::stuck:
      ++stuck;
      break;
  }
  collisions += collisions_made;
}

void Tally::merge(const Tally& o) {
  for (std::size_t i = 0; i < escapes_per_bin.size(); ++i) escapes_per_bin[i] += o.escapes_per_bin[i];
  for (std::size_t i = 0; i < collision_density.size(); ++i) collision_density[i] += o.collision_density[i];
  collisions += o.collisions;
  escaped += o.escaped;
  survived += o.survived;
  stuck += o.stuck;
  if (weighted) {
    for (std::size_t i = 0; i < escaped_w.size(); ++i) {
      escaped_w[i].merge(o.escaped_w[i]);
      escaped_w2[i].merge(o.escaped_w2[i]);
    }
    for (std::size_t i = 0; i < collision_density_w.size(); ++i) collision_density_w[i].merge(o.collision_density_w[i]);
    total_w.merge(o.total_w);
    total_w2.merge(o.total_w2);
  }
  if (split) {
    for (std::size_t i = 0; i < line_in.size(); ++i) {
      line_in[i].merge(o.line_in[i]);
      line_out[i].merge(o.line_out[i]);
      line2_in[i].merge(o.line2_in[i]);
      line2_out[i].merge(o.line2_out[i]);
      lines_ended[i] += o.lines_ended[i];
    }
    for (std::size_t i = 0; i < born_per_bin.size(); ++i) {
      born_per_bin[i] += o.born_per_bin[i];
      culled_per_bin[i] += o.culled_per_bin[i];
    }
    splits += o.splits;
    culls += o.culls;
    for (auto [a, b] : {std::pair{&w_start, &o.w_start},
                        {&w_gained, &o.w_gained},
                        {&w_escaped, &o.w_escaped},
                        {&w_removed, &o.w_removed},
                        {&w_alive_end, &o.w_alive_end}})
      a->merge(*b);
    for (std::size_t c = 0; c < unsplit_start.size(); ++c) unsplit_start[c].merge(o.unsplit_start[c]);
    for (const auto& [key, cell] : o.unsplit_left) unsplit_left[key].merge(cell);
    levels = std::max(levels, o.levels);
    max_population = std::max(max_population, o.max_population);
    max_line = std::max(max_line, o.max_line);
  }
}

void check_conservation(const Tally& t, const IntervalSet& done, std::uint64_t n) {
  if (!t.split) {
    const std::uint64_t ran = particles_in(done, n), ended = t.escaped + t.survived + t.stuck;
    if (ended != ran)
      throw std::logic_error("tally does not add up: " + std::to_string(t.escaped) + " escaped + " +
                             std::to_string(t.survived) + " survived + " + std::to_string(t.stuck) + " stuck = " +
                             std::to_string(ended) + " particles, but the blocks done hold " + std::to_string(ran));
    return;
  }
  FixedSum in = t.w_start, out = t.w_escaped;
  in.merge(t.w_gained);
  out.merge(t.w_removed);
  out.merge(t.w_alive_end);
  if (!(in == out)) {
    char why[200];
    std::snprintf(why, sizeof why,
                  "split run: weight not conserved (start + roulette gains %.17g, escaped + removed + alive %.17g)",
                  in.value(), out.value());
    throw std::logic_error(why);
  }
}

}  // namespace rotleak
