// The speed-accuracy trade, measured in one run: per tier the cost per collision of the generic core
// (as a ratio to double, timed in this process) beside its median trust horizon (shadow runs against
// the MPFR truth). Writes a Markdown table to stdout and CSV to the file named by the first argument.
//
// Usage: bench_tiers [out.csv] [--particles N]      (not a test: it reports, never fails on time)
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "io/scene_file.hpp"
#include "numeric/tier_dispatch.hpp"
#include "verify/shadow.hpp"
#include "verify/trace.hpp"

using namespace rotleak;

namespace {

// Nanoseconds per collision of tier R over the first 200 collisions of successive particles, for >= 0.4 s.
template <class R>
double cost_ns(const Scene& scene) {
  const Model<R> model = model_of<R>(scene);
  const InitialConditions ic(scene.seed, scene.init, 4, 1, 1);
  std::size_t collisions = 0;
  const auto t0 = std::chrono::steady_clock::now();
  double elapsed = 0;
  for (std::uint64_t id = 0; elapsed < 0.4; ++id) {
    try {
      collisions += trace(model, ic.draw(id), 200, [](const TraceStep<R>&) { return true; });
    } catch (const UncertainDecision&) {  // intervals stop where a branch is undecided; count what ran
    }
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return 1e9 * elapsed / static_cast<double>(collisions);
}

double cost_of(const std::string& tier, const Scene& scene) {
  return with_tier(tier, [&](auto type) { return cost_ns<typename decltype(type)::type>(scene); });
}

}  // namespace

int main(int argc, char** argv) {
  std::string csv_path;
  std::uint64_t particles = 100;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--particles") && i + 1 < argc)
      particles = std::stoull(argv[++i]);
    else
      csv_path = argv[i];
  }
  const Scene scene = parse_scene("[leak]\nwidth = \"0.01\"\nstart = \"0\"\n");  // the s_L = 0 stationary scene
  const std::vector<std::string> tiers{"float",    "double",   "long_double", "dd",
                                       "float128", "mpfr:128", "mpfr:256",    "mpfr:1024"};

  // Three rounds over all tiers, the fastest of each kept: the machine's noise only ever adds time,
  // and interleaving the rounds spreads a slow spell over every tier instead of one.
  std::vector<double> cost(tiers.size(), std::numeric_limits<double>::infinity());
  for (int round = 0; round < 3; ++round)
    for (std::size_t k = 0; k < tiers.size(); ++k) cost[k] = std::min(cost[k], cost_of(tiers[k], scene));
  const double base = cost[1];

  // horizons: shadows of `particles` ids over 900 collisions (past the escape: the leak does not stop a shadow)
  ShadowOptions opt;
  opt.tiers = tiers;
  opt.collisions = 900;
  std::vector<std::uint64_t> ids(particles);
  for (std::uint64_t i = 0; i < particles; ++i) ids[i] = i;
  const std::vector<ShadowResult> runs = shadow_many(scene, ids, opt);

  std::ofstream csv;
  if (!csv_path.empty()) csv.open(csv_path);
  if (csv) csv << "tier,bits,ns_per_collision,ratio_to_double,median_horizon_collisions,horizons_observed\n";
  std::printf(
      "| tier | ns / collision | cost vs double | median trust horizon (collisions) | observed "
      "|\n|---|---|---|---|---|\n");
  for (std::size_t k = 0; k < tiers.size(); ++k) {
    std::vector<double> h;
    for (const auto& r : runs)
      if (r.tiers[k].horizon) h.push_back(static_cast<double>(*r.tiers[k].horizon));
    std::sort(h.begin(), h.end());
    const double med = h.empty() ? 0 : h[h.size() / 2];
    std::printf("| %s | %.1f | %.2f | %.0f | %zu/%llu |\n", tiers[k].c_str(), cost[k], cost[k] / base, med, h.size(),
                static_cast<unsigned long long>(particles));
    if (csv)
      csv << tiers[k] << "," << tier_bits(tiers[k]) << "," << cost[k] << "," << cost[k] / base << "," << med << ","
          << h.size() << "\n";
  }
  std::printf("\nshadowed %llu particles x 900 collisions of the s_L = 0 scene; tolerance %.0e; %d threads\n",
              static_cast<unsigned long long>(particles), opt.tolerance, omp_get_max_threads());
  return 0;
}
