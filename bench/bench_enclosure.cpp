// How fast a trajectory's certified enclosure widens: bits lost a collision by the mean-value (Lohner)
// enclosure against plain MPFI, on the same particles, the leak ignored, in one run. For each particle and
// method, log2(width after n collisions / width at the start) / n, at the n both methods reach (the
// interval one needs far more bits to get as far). Reports, never fails on time.
//
// Usage: bench_enclosure [--particles N] [--collisions K] [--bits B] [--interval-bits B2] [--json FILE]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/scene_file.hpp"
#include "sim/model/sampling.hpp"
#include "verify/certify.hpp"

using namespace rotleak;

namespace {

struct Growth {
  std::size_t reached = 0;  ///< collisions enclosed before a branch was undecided (or the cap)
  double seconds = 0;
  std::vector<double> widths;  ///< log2 of the enclosure's width, at the start and after each collision
  double bits_per_collision(std::size_t n) const { return (widths[n] - widths[0]) / static_cast<double>(n); }
};

Growth measure(const Scene& scene, const InitialDraw& draw, long bits, std::size_t collisions, Enclosure method) {
  Growth g;
  const auto t0 = std::chrono::steady_clock::now();
  g.widths = enclosure_log2_widths(scene, draw, bits, collisions, method);
  g.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  g.reached = g.widths.size() - 1;
  return g;
}

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t particles = 8;
  std::size_t collisions = 1000;
  long bits = 1600, interval_bits = 4600;
  std::string json_path;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--particles")
      particles = std::stoull(value);
    else if (key == "--collisions")
      collisions = std::stoul(value);
    else if (key == "--bits")
      bits = std::stol(value);
    else if (key == "--interval-bits")
      interval_bits = std::stol(value);
    else if (key == "--json")
      json_path = value;
    else {
      std::fprintf(stderr, "bench_enclosure: unknown option %s\n", key.c_str());
      return 2;
    }
  }
  const Scene scene = parse_scene("[leak]\nwidth = \"0.01\"\nstart = \"0\"\n");  // d = 2, r = 1
  const auto sampler = make_sampler(scene);
  nlohmann::json rows = nlohmann::json::array();
  double sum_l = 0, sum_i = 0;
  std::size_t counted = 0;
  std::printf("%8s %10s %10s %8s %12s %12s %10s %10s\n", "particle", "lohner n", "interval n", "n", "lohner b/c",
              "interval b/c", "lohner s", "interval s");
  for (std::uint64_t id = 0; id < particles; ++id) {
    const InitialDraw draw = sampler->draw(id);
    const Growth l = measure(scene, draw, bits, collisions, Enclosure::lohner);
    const Growth v = measure(scene, draw, interval_bits, collisions, Enclosure::interval);
    const std::size_t n = std::min(l.reached, v.reached);
    const double bl = n ? l.bits_per_collision(n) : std::nan(""), bv = n ? v.bits_per_collision(n) : std::nan("");
    std::printf("%8llu %10zu %10zu %8zu %12.3f %12.3f %10.2f %10.2f\n", static_cast<unsigned long long>(id), l.reached,
                v.reached, n, bl, bv, l.seconds, v.seconds);
    rows.push_back({{"particle", id},
                    {"lohner_collisions", l.reached},
                    {"interval_collisions", v.reached},
                    {"n", n},
                    {"lohner_bits_per_collision", bl},
                    {"interval_bits_per_collision", bv},
                    {"lohner_bits_per_collision_full", l.reached ? l.bits_per_collision(l.reached) : std::nan("")},
                    {"lohner_seconds", l.seconds},
                    {"interval_seconds", v.seconds}});
    if (n >= collisions) {
      sum_l += bl;
      sum_i += bv;
      ++counted;
    }
  }
  const double mean_l = counted ? sum_l / static_cast<double>(counted) : std::nan("");
  const double mean_i = counted ? sum_i / static_cast<double>(counted) : std::nan("");
  std::printf(
      "mean over the %zu particles both enclose for %zu collisions: lohner %.3f, interval %.3f bits a collision\n",
      counted, collisions, mean_l, mean_i);
  if (!json_path.empty()) {
    nlohmann::json doc{{"collisions", collisions},
                       {"lohner_bits", bits},
                       {"interval_bits", interval_bits},
                       {"particles", rows},
                       {"counted", counted},
                       {"lohner_mean_bits_per_collision", mean_l},
                       {"interval_mean_bits_per_collision", mean_i}};
    std::ofstream(json_path) << doc.dump(2) << "\n";
  }
  return 0;
}
