// Engine throughput: collisions per second of a plain scalar loop (compiled here, the
// baseline), the scalar engine, the vectorised engine and both with fast-forward, on the stationary
// s_L = 0 scene and on omega = 1; particles per second to t_max; and the fast-forward on a run
// dominated by long-lived MUPOs (s_L = 0, t_max = 2e5). Ratios are taken in this one process and
// printed as a Markdown table after Google Benchmark's own report. Reports, never fails.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "bench/plain.hpp"
#include "io/scene_file.hpp"
#include "sim/engine/engine.hpp"
#include "sim/kernel/simd_engine.hpp"
#include "sim/model/particle.hpp"

using namespace rotleak;

namespace {

struct Rate {
  double collisions_per_second = 0, particles_per_second = 0;
};
std::map<std::string, Rate> g_rates;

Scene scene_for(const std::string& omega, std::uint64_t particles, double t_max = 20000) {
  return parse_scene("[leak]\nwidth = \"0.01\"\nstart = \"0\"\nomega = \"" + omega + "\"\n[ensemble]\nparticles = " +
                     std::to_string(particles) + "\n[run]\nt_max = " + std::to_string(t_max) + "\n");
}

void BM_plain(benchmark::State& state, const char* omega) {
  const Scene s = scene_for(omega, 1);
  const Model<double> model = Model<double>::from(s);
  const InitialConditions ic = initial_conditions(s);
  bench::PlainScene plain;
  plain.omega = s.omega.to_double();
  std::uint64_t id = 0, collisions = 0, particles = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (auto _ : state) {
    const ParticleState<double> ps = initial_state(model.stadium, ic.draw(id++));
    collisions += bench::plain_particle(ps.q.x, ps.q.y, ps.v.x, ps.v.y, ps.t, plain);
    ++particles;
  }
  const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  state.counters["collisions/s"] = benchmark::Counter(static_cast<double>(collisions), benchmark::Counter::kIsRate);
  g_rates[std::string("plain scalar loop, omega = ") + omega] = {collisions / sec, particles / sec};
}

void BM_engine(benchmark::State& state, const char* omega, Engine engine, bool ff, int threads) {
  Scene s = scene_for(omega, 200000);
  s.fast_forward = ff;
  RunOptions o;
  o.engine = engine;
  o.threads = threads;
  double collisions = 0, particles = 0, sec = 0;
  for (auto _ : state) {
    const RunResult r = run_ensemble(s, o);
    collisions += static_cast<double>(r.tally.collisions);
    particles += static_cast<double>(s.particles);
    sec += r.wall_seconds;
  }
  state.counters["collisions/s"] = benchmark::Counter(collisions, benchmark::Counter::kIsRate);
  g_rates[to_string(engine) + " engine" + (ff ? " + fast-forward" : "") + ", " + std::to_string(threads) +
          (threads == 1 ? " thread" : " threads") + ", omega = " + omega] = {collisions / sec, particles / sec};
}

// Long-lived particles only: ids still alive at t = 5000 (deep in the algebraic tail, which the
// MUPOs make) among the first 2*10^6, run to t_max = 2e5: a run whose cost is MUPO phases.
void BM_mupo_tail(benchmark::State& state, bool ff) {
  static std::vector<std::uint64_t> ids = [] {
    Scene probe = scene_for("0", 2000000, 5000);
    probe.escape_records = true;
    const RunResult r = run_ensemble(probe, RunOptions{});
    std::vector<std::uint64_t> out;
    for (std::uint64_t i = 0; i < r.records.size(); ++i)
      if (r.records[i].fate != Fate::escaped) out.push_back(i);
    return out;
  }();
  const Scene s = scene_for("0", 1, 200000);
  Model<double> model = Model<double>::from(s);
  model.fast_forward = ff;
  const InitialConditions ic = initial_conditions(s);
  NoCollisionObserver<double> none;
  double collisions = 0, sec = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    for (std::uint64_t id : ids)
      collisions +=
          static_cast<double>(run_particle(model, initial_state(model.stadium, ic.draw(id)), none).collisions);
    sec += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  state.counters["particles"] = static_cast<double>(ids.size());
  g_rates[std::string("MUPO tail (") + std::to_string(ids.size()) + " ids alive at t = 5000, t_max 2e5), scalar" +
          (ff ? " + fast-forward" : ", stepping")] = {collisions / sec,
                                                      static_cast<double>(ids.size()) * state.iterations() / sec};
}

}  // namespace

BENCHMARK_CAPTURE(BM_plain, stationary, "0")->MinTime(1.0);
BENCHMARK_CAPTURE(BM_plain, omega1, "1")->MinTime(1.0);
BENCHMARK_CAPTURE(BM_engine, scalar_1t, "0", Engine::scalar, false, 1)->Iterations(2)->UseRealTime();
BENCHMARK_CAPTURE(BM_engine, simd_1t, "0", Engine::simd, false, 1)->Iterations(2)->UseRealTime();
BENCHMARK_CAPTURE(BM_engine, simd_ff_1t, "0", Engine::simd, true, 1)->Iterations(2)->UseRealTime();
BENCHMARK_CAPTURE(BM_engine, scalar_2t, "0", Engine::scalar, false, 2)->Iterations(2)->UseRealTime();
BENCHMARK_CAPTURE(BM_engine, simd_2t, "0", Engine::simd, false, 2)->Iterations(2)->UseRealTime();
BENCHMARK_CAPTURE(BM_engine, simd_ff_2t, "0", Engine::simd, true, 2)->Iterations(2)->UseRealTime();
BENCHMARK_CAPTURE(BM_engine, omega1_scalar_1t, "1", Engine::scalar, false, 1)->Iterations(2)->UseRealTime();
BENCHMARK_CAPTURE(BM_engine, omega1_simd_1t, "1", Engine::simd, false, 1)->Iterations(2)->UseRealTime();
BENCHMARK_CAPTURE(BM_engine, omega1_simd_ff_1t, "1", Engine::simd, true, 1)->Iterations(2)->UseRealTime();
BENCHMARK_CAPTURE(BM_mupo_tail, stepping, false)->Iterations(1)->UseRealTime();
BENCHMARK_CAPTURE(BM_mupo_tail, fast_forward, true)->Iterations(1)->UseRealTime();

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (!simd::available()) std::fprintf(stderr, "note: no AVX2+FMA here; the simd rows will fail\n");
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  const double base0 = g_rates["plain scalar loop, omega = 0"].collisions_per_second;
  const double base1 = g_rates["plain scalar loop, omega = 1"].collisions_per_second;
  std::printf("\n| run | collisions/s | particles/s | vs plain loop (1 thread, same omega) |\n|---|---|---|---|\n");
  for (const auto& [name, r] : g_rates) {
    const bool w1 = name.find("omega = 1") != std::string::npos;
    const double base = w1 ? base1 : base0;
    std::printf("| %s | %.3g | %.3g | %.2f |\n", name.c_str(), r.collisions_per_second, r.particles_per_second,
                name.find("MUPO") == std::string::npos ? r.collisions_per_second / base : 0.0);
  }
  double step = 0, ff = 0;
  for (const auto& [name, r] : g_rates)
    if (name.find("MUPO") != std::string::npos)
      (name.find("fast-forward") != std::string::npos ? ff : step) = r.particles_per_second;
  if (step > 0)
    std::printf("\nMUPO tail: fast-forward %.1fx faster than stepping (same collisions counted)\n", ff / step);
  return 0;
}
