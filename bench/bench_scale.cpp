// The default engine against the plain scalar simulator (bench/plain.hpp), both on all cores, in one
// process, rounds interleaved so that a noisy machine slows both alike: collisions per second on
// s_L = 0, s_L = 0.25, omega = 2/3, omega = 1e-4 and the quick-start scene with its f_c; and the
// cost of checkpoints (every 0.2 s, written to disk) on omega = 2/3; and the kernel's ceiling: its flights
// alone, and with the draws every particle needs, measured in every round beside each scene, so that a scene's
// share of the ceiling compares two rates of one moment (the machine's speed drifts between minutes by more
// than the shares differ). Reports, never fails.
// Usage: bench_scale [PARTICLES (default 10^6)] [ROUNDS (default 3)] [THREADS (default all)]
//        [LANES (the vectorised kernel: 0 the widest this CPU runs (default), 4 AVX2, 8 AVX-512)] [JSON]
// With JSON, the figures are also written there (scripts/performance_report.py writes docs/performance.md's
// current table from them; its schema is in docs/output.md).
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "bench/plain.hpp"
#include "io/files.hpp"
#include "io/json.hpp"
#include "io/scene_file.hpp"
#include "io/tally_file.hpp"
#include "sim/engine/engine.hpp"
#include "sim/engine/kernel_adapter.hpp"
#include "sim/kernel/simd_engine.hpp"
#include "sim/model/initial.hpp"
#include "sim/model/particle.hpp"

using namespace rotleak;

namespace {

using Clock = std::chrono::steady_clock;

struct Case {
  const char* name;
  std::string toml;
};

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

/// The plain simulator over the scene's particles (same initial conditions), OpenMP over ids.
double plain_rate(const Scene& s, int threads, std::uint64_t& collisions) {
  const Model<double> model = Model<double>::from(s);
  const InitialConditions ic = initial_conditions(s);
  bench::PlainScene base;
  base.omega = s.omega.to_double();
  base.start = s.start.to_double();
  base.width = s.width.to_double();
  base.t_max = s.t_max;
  if (s.collision_density) {
    base.bins = s.collision_density->bins;
    for (const auto& w : s.collision_density->windows) base.add_window(w.from, w.to);
  }
  collisions = 0;
  const auto t0 = Clock::now();
  std::uint64_t total = 0;
#pragma omp parallel num_threads(threads) reduction(+ : total)
  {
    bench::PlainScene p = base;
    std::vector<std::uint64_t> density(static_cast<std::size_t>(p.n_windows) *
                                       static_cast<std::size_t>(std::max(p.bins, 1)));
    if (s.collision_density) p.density = density.data();
#pragma omp for schedule(dynamic, 4096)
    for (std::uint64_t id = 0; id < s.particles; ++id) {
      const ParticleState<double> ps = initial_state(model.stadium, ic.draw(id));
      total += bench::plain_particle(ps.q.x, ps.q.y, ps.v.x, ps.v.y, ps.t, p);
    }
  }
  const double sec = seconds_since(t0);
  collisions = total;
  return static_cast<double>(total) / sec;
}

/// The kernel's ceiling at one moment: its flights alone (simd::flights_only: next hit and reflection, no clock,
/// leak, fate or refill) on every thread, and the draws and initial states of `draw_particles` particles of the
/// s_L = 0 scene as the kernel's runs make them (draw_starts: the sampler's draws, then the states vectorised,
/// kStartBatch at a time) and, for comparison, one at a time through the scalar core (initial_state).
struct Ceiling {
  double flights_rate = 0;   ///< collisions/s of the flights alone
  double draw_seconds = 0;   ///< the draws, wall time on every thread
  double scalar_ns = 0;      ///< the draws through the scalar core, ns a particle per thread
  double flight_time = 0;    ///< the flights' summed flight times (kept, so that nothing is optimised away)
  double sinks[2] = {0, 0};  ///< the draws' summed x velocities (likewise)
  /// With the flights at the ceiling and nothing else, the kernel could reach at most this rate on a run of
  /// `collisions` collisions over the draw_particles particles.
  double with_draws(double collisions) const { return 1 / (1 / flights_rate + draw_seconds / collisions); }
};

Ceiling measure_ceiling(int lanes, int threads, std::uint64_t draw_particles) {
  Ceiling c;
  const Scene s = parse_scene("[ensemble]\nparticles = 1000\n");
  const Model<double> model = Model<double>::from(s);
  simd::KernelScene ks = simd_scene(model);
  ks.lanes = lanes;
  const InitialConditions ic = initial_conditions(s);
  const int per_pack = simd::pack_lanes(lanes);
  const std::uint64_t steps = 4000000;
  const auto t0 = Clock::now();
  double sink = 0;
#pragma omp parallel num_threads(threads) reduction(+ : sink)
  {
    std::vector<simd::Start> starts(static_cast<std::size_t>(per_pack));
    for (int k = 0; k < per_pack; ++k) {
      const auto id = static_cast<std::uint64_t>(omp_get_thread_num() * per_pack + k);
      const ParticleState<double> ps = initial_state(model.stadium, ic.draw(id));
      starts[static_cast<std::size_t>(k)] = {ps.q.x, ps.q.y, ps.v.x, ps.v.y, 0, 0, 1};
    }
    sink += simd::flights_only(ks, starts.data(), steps);
  }
  c.flights_rate = static_cast<double>(threads) * per_pack * static_cast<double>(steps) / seconds_since(t0);
  c.flight_time = sink;

  const Scene sl0 =
      parse_scene("[leak]\nstart = \"0\"\n[ensemble]\nparticles = " + std::to_string(draw_particles) + "\n");
  const InitialConditions ic0 = initial_conditions(sl0);
  const auto sampler = make_sampler(sl0, model.stadium);
  const DrawSource source{sampler.get(), 0, nullptr};
  const auto t1 = Clock::now();
  double sink0 = 0;
#pragma omp parallel num_threads(threads) reduction(+ : sink0)
  {
    std::vector<simd::Start> batch(kStartBatch);
#pragma omp for schedule(static)
    for (std::uint64_t lo = 0; lo < draw_particles; lo += kStartBatch) {
      const std::size_t k = static_cast<std::size_t>(std::min<std::uint64_t>(kStartBatch, draw_particles - lo));
      draw_starts(source, ks, false, lo, k, batch.data());
      for (std::size_t i = 0; i < k; ++i) sink0 += batch[i].vx;
    }
  }
  c.draw_seconds = seconds_since(t1);
  const auto t2 = Clock::now();
  double sink1 = 0;
#pragma omp parallel for num_threads(threads) reduction(+ : sink1) schedule(static)
  for (std::uint64_t id = 0; id < draw_particles; ++id) sink1 += initial_state(model.stadium, ic0.draw(id)).v.x;
  c.scalar_ns = 1e9 * seconds_since(t2) * threads / static_cast<double>(draw_particles);
  c.sinks[0] = sink0, c.sinks[1] = sink1;
  return c;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const std::uint64_t particles = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 1000000;
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 3;
  const int threads = argc > 3 ? std::atoi(argv[3]) : omp_get_max_threads();
  const int lanes = argc > 4 ? std::atoi(argv[4]) : 0;
  const std::string json_path = argc > 5 ? argv[5] : "";
  const std::string n = std::to_string(particles);
  json doc = {{"particles", particles}, {"rounds", rounds}, {"threads", threads}, {"scenes", json::array()}};
  const std::vector<Case> cases = {
      {"s_L = 0", "[leak]\nstart = \"0\"\n"},
      {"s_L = 0.25", "[leak]\nstart = \"0.25\"\n"},
      {"omega = 2/3", "[leak]\nomega = \"2/3\"\n"},
      {"omega = 1e-4", "[leak]\nomega = \"1e-4\"\n"},
      {"quick-start with f_c",
       "[observe]\ncollision_density = { bins = 1000, windows = [[0, 20000], [2000, 20000]] }\n"}};
  std::printf(
      "bench_scale: %s particles, %d threads, %d interleaved rounds, kernel lanes %s; median of the per-round "
      "ratios\n\n",
      n.c_str(), threads, rounds, lanes > 0 ? std::to_string(lanes).c_str() : "widest");
  // the ceiling beside every round of every scene (where this CPU runs the kernel): each scene's share of it is
  // the median of its rounds' engine rate over the ceiling with draws of the same round
  const int w = lanes > 0 ? lanes : simd::widest_lanes();
  const bool kernel = w > 0 && simd::lanes_available(w);
  std::printf("| scene | engine | engine collisions/s | plain collisions/s | ratio (median) | ratios |%s\n",
              kernel ? " share of the ceiling with draws (median) |" : "");
  std::printf("|---|---|---|---|---|---|%s\n", kernel ? "---|" : "");
  double collisions_sl0 = 0;  // the collisions of s_L = 0's particles, for the draws' share of a collision
  std::vector<double> flights_ratio, draws_ratio, draws_share, draw_ns, scalar_ns;  // s_L = 0's rounds / all
  Ceiling last;
  for (const Case& c : cases) {
    const Scene s = parse_scene(c.toml + "[ensemble]\nparticles = " + n + "\n");
    RunOptions o;
    o.threads = threads;
    o.simd_lanes = lanes;
    std::vector<double> ratios, er, pr, shares;
    Engine ran = Engine::scalar;
    for (int k = 0; k < rounds; ++k) {
      std::uint64_t pc = 0;
      const double p = plain_rate(s, threads, pc);
      const RunResult r = run_ensemble(s, o);
      ran = r.engine;
      if (collisions_sl0 == 0) collisions_sl0 = static_cast<double>(r.tally.collisions);
      const double e = static_cast<double>(r.tally.collisions) / r.wall_seconds;
      er.push_back(e);
      pr.push_back(p);
      ratios.push_back(e / p);
      if (!kernel) continue;
      last = measure_ceiling(w, threads, particles);
      const double bound = last.with_draws(collisions_sl0);
      shares.push_back(e / bound);
      draws_share.push_back(bound / last.flights_rate);
      draw_ns.push_back(1e9 * last.draw_seconds * threads / static_cast<double>(particles));
      scalar_ns.push_back(last.scalar_ns);
      if (&c == &cases.front()) flights_ratio.push_back(last.flights_rate / p), draws_ratio.push_back(bound / p);
    }
    std::string all;
    for (double x : ratios) all += (all.empty() ? "" : ", ") + std::to_string(x).substr(0, 5);
    std::printf("| %s | %s | %.3g | %.3g | %.2f | %s |", c.name, to_string(ran).c_str(), median(er), median(pr),
                median(ratios), all.c_str());
    if (kernel) std::printf(" %.0f%% |", 100 * median(shares));
    std::printf("\n");
    json row = {{"scene", c.name},          {"engine", to_string(ran)}, {"engine_rate", median(er)},
                {"plain_rate", median(pr)}, {"ratio", median(ratios)},  {"ratios", ratios}};
    if (kernel) row["ceiling_share"] = median(shares), row["ceiling_shares"] = shares;
    doc["scenes"].push_back(row);
    std::fflush(stdout);
  }

  if (kernel) {
    std::printf(
        "\nceiling, the kernel's next hit and reflection alone (%d lanes, no clock, leak, fate or refill), measured "
        "beside every round: %.2fx the plain loop on s_L = 0 (median of its rounds; flight time %.3g)\n",
        w, median(flights_ratio), last.flight_time);
    std::printf(
        "draws and initial states alone (s_L = 0, %d threads): %.0f ns a particle per thread (one at a time through "
        "the scalar core %.0f ns); the ceiling with them: %.2fx the plain loop on s_L = 0, %.1f%% of the flights "
        "alone (median of every round's; sums of x velocities %.3g, %.3g)\n",
        threads, median(draw_ns), median(scalar_ns), median(draws_ratio), 100 * median(draws_share), last.sinks[0],
        last.sinks[1]);
    doc["lanes"] = w;
    doc["ceiling_flights"] = {{"ratio", median(flights_ratio)}, {"ratios", flights_ratio}};
    doc["ceiling_with_draws"] = {{"ratio", median(draws_ratio)},
                                 {"ratios", draws_ratio},
                                 {"share_of_flights", median(draws_share)},
                                 {"draw_ns_per_particle", median(draw_ns)},
                                 {"scalar_draw_ns_per_particle", median(scalar_ns)}};
  }

  // checkpoints: every 0.2 s the merged tallies go to disk (atomically, fsync), against none; the
  // default interval is 300 s, so this is the cost of about 1500 default checkpoints per 300 s
  const Scene s = parse_scene("[leak]\nomega = \"2/3\"\n[ensemble]\nparticles = " + n + "\n");
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "bench_scale.checkpoint";
  std::vector<double> overhead;
  int written = 0;
  for (int k = 0; k < rounds; ++k) {
    RunOptions plain_opt;
    plain_opt.threads = threads;
    plain_opt.simd_lanes = lanes;
    const RunResult a = run_ensemble(s, plain_opt);
    RunOptions ck = plain_opt;
    ck.checkpoint_seconds = 0.2;
    ck.checkpoint = [&](const Tally& t, const IntervalSet& done, const std::vector<EscapeRecord>& rec) {
      write_tally_file(file, TallyFile{"bench", s.particles, 0, s.particles, done, t, rec});
      ++written;
    };
    const RunResult b = run_ensemble(s, ck);
    overhead.push_back(b.wall_seconds / a.wall_seconds - 1);
  }
  std::filesystem::remove(file);
  std::printf("\ncheckpoints every 0.2 s on omega = 2/3 (%d written): wall time %+.1f%% (median; rounds:", written,
              100 * median(overhead));
  for (double x : overhead) std::printf(" %+.1f%%", 100 * x);
  std::printf(")\n");
  doc["checkpoint_overhead"] = median(overhead);
  if (!json_path.empty()) write_file_atomic(json_path, doc.dump(2) + "\n");
  return 0;
}
