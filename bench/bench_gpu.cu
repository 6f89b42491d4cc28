// bench_gpu: the GPU engine against a plain one-thread-a-particle CUDA loop of the same scene (bench/plain.hpp, compiled
// for the device as it is), rounds interleaved in one process, and the CPU's engine on all cores; the same particles
// (ids 0 .. N-1, the same initial states) in each. Per scene: collisions a second of each, their ratio, the wall time
// of the particles, and each kernel's registers and blocks resident a multiprocessor; the engine's kernel alone in each
// of its register caps (gpu::Device::set_min_blocks: occupancy against spills); then the card's FP64 peak and
// the collisions a second it would allow at 100 FP64 operations a collision. Both GPU loops are compiled with
// -fmad=false (the engine needs it for its bits; the plain loop takes it for a like-for-like count).
//   bench_gpu [PARTICLES = 10^7] [ROUNDS = 3] [CPU_PARTICLES = PARTICLES / 10]
// Prints a table and, last, one JSON line (docs/performance.md, "The GPU engine", is written from it).
#include <cuda_runtime.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench/plain.hpp"
#include "io/scene_file.hpp"
#include "sim/engine/engine.hpp"
#include "sim/engine/kernel_adapter.hpp"
#include "sim/gpu/gpu_engine.hpp"

using namespace rotleak;

namespace {

constexpr int kThreads = 128;

void check(cudaError_t e, const char* what) {
  if (e != cudaSuccess) {
    std::fprintf(stderr, "bench_gpu: %s: %s\n", what, cudaGetErrorString(e));
    std::exit(1);
  }
}

/// The plain loop: particle id from the scene's own draw and initial state, then bench::plain_particle.
__global__ void __launch_bounds__(kThreads)
    plain_batch(Stadium<double> st, std::uint64_t n, std::uint64_t seed, double window, bench::PlainScene p,
                unsigned long long* collisions) {
  const std::uint64_t id = static_cast<std::uint64_t>(blockIdx.x) * kThreads + threadIdx.x;
  if (id >= n) return;
  const ParticleState<double> ps = initial_state(st, InitialConditions::birkhoff_draw(seed, window, id));
  const std::uint64_t c = bench::plain_particle(ps.q.x, ps.q.y, ps.v.x, ps.v.y, ps.t, p);
  atomicAdd(collisions, static_cast<unsigned long long>(c));
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct Rate {
  double rate = 0, seconds = 0;
  std::uint64_t collisions = 0;
};

Rate plain_run(const Scene& s) {
  const Stadium<double> st(s.d, s.r);
  bench::PlainScene p;
  p.omega = s.omega.to_double(), p.start = s.start.to_double(), p.width = s.width.to_double(), p.t_max = s.t_max;
  unsigned long long* counts = nullptr;
  unsigned long long* total = nullptr;
  check(cudaMalloc(&total, sizeof *total), "cudaMalloc");
  check(cudaMemset(total, 0, sizeof *total), "cudaMemset");
  if (s.collision_density) {
    p.bins = s.collision_density->bins;
    for (const auto& w : s.collision_density->windows) p.add_window(w.from, w.to);
    const std::size_t n = static_cast<std::size_t>(p.bins) * static_cast<std::size_t>(p.n_windows);
    check(cudaMalloc(&counts, n * sizeof *counts), "cudaMalloc");
    check(cudaMemset(counts, 0, n * sizeof *counts), "cudaMemset");
    p.density = reinterpret_cast<std::uint64_t*>(counts);
  }
  const auto t0 = std::chrono::steady_clock::now();
  const auto blocks = static_cast<unsigned>((s.particles + kThreads - 1) / kThreads);
  plain_batch<<<blocks, kThreads>>>(st, s.particles, s.seed, s.creation_window, p, total);
  check(cudaGetLastError(), "launch");
  check(cudaDeviceSynchronize(), "plain_batch");
  Rate r;
  r.seconds = seconds_since(t0);
  unsigned long long c = 0;
  check(cudaMemcpy(&c, total, sizeof c, cudaMemcpyDeviceToHost), "cudaMemcpy");
  r.collisions = c;
  r.rate = static_cast<double>(c) / r.seconds;
  cudaFree(total), cudaFree(counts);
  return r;
}

Rate engine_run(const Scene& s, Engine e, int threads) {
  RunOptions opt;
  opt.engine = e;
  opt.threads = threads;
  const RunResult res = run_ensemble(s, opt);
  return {static_cast<double>(res.tally.collisions) / res.wall_seconds, res.wall_seconds, res.tally.collisions};
}

/// The engine's kernel alone, capped for min_blocks blocks a multiprocessor: one launch of the scene's particles (the
/// device's own draws, the tallies on the device, nothing back but the counts), timed from launch to its counts.
struct KernelRate {
  double rate = 0;
  int registers = 0, blocks = 0;
};
KernelRate kernel_run(const Scene& s, int min_blocks) {
  const Model<double> model = Model<double>::from(s);
  const DensityCells cells = scene_density_cells(s);
  Tally t;
  t.resize(s);
  gpu::Device device(model, gpu::Shape::of(t, s.survival_dt, s.collision_density ? &cells : nullptr));
  device.set_min_blocks(min_blocks);
  const gpu::Batch batch{0, s.particles, nullptr, nullptr, s.seed, s.creation_window, nullptr};
  const auto t0 = std::chrono::steady_clock::now();
  device.run(batch);
  const double seconds = seconds_since(t0);
  KernelRate k;
  k.rate = static_cast<double>(device.collisions()) / seconds;
  k.registers = device.registers(), k.blocks = device.blocks_per_multiprocessor();
  return k;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const std::uint64_t particles = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 10000000;
  const int rounds = argc > 2 ? std::atoi(argv[2]) : 3;
  const std::uint64_t cpu_particles = argc > 3 ? std::strtoull(argv[3], nullptr, 10) : particles / 10;
  if (const std::string why = gpu::unavailable(); !why.empty()) {
    std::printf("bench_gpu: %s\n", why.c_str());
    return 0;
  }
  cudaDeviceProp prop{};
  check(cudaGetDeviceProperties(&prop, 0), "cudaGetDeviceProperties");
  int clock_khz = 0;
  check(cudaDeviceGetAttribute(&clock_khz, cudaDevAttrClockRate, 0), "cudaDeviceGetAttribute");
  cudaFuncAttributes plain_attr{};
  check(cudaFuncGetAttributes(&plain_attr, plain_batch), "cudaFuncGetAttributes");
  int plain_blocks = 0;
  check(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&plain_blocks, plain_batch, kThreads, 0), "occupancy");
  std::printf("bench_gpu: %s; %llu particles a scene, %d interleaved rounds; the CPU engine on %d threads, %llu particles\n\n",
              gpu::device_name().c_str(), static_cast<unsigned long long>(particles), rounds, omp_get_max_threads(),
              static_cast<unsigned long long>(cpu_particles));
  struct Case {
    const char* name;
    std::vector<std::string> set;
  };
  const std::vector<Case> cases = {
      {"s_L = 0", {"leak.start=0", "leak.omega=0"}},
      {"omega = 2/3", {"leak.omega=2/3"}},
      {"quick-start with f_c",
       {"observe.collision_density={ bins = 1000, windows = [[0, 20000], [2000, 20000]] }"}}};
  std::printf("| scene | engine coll/s | plain coll/s | engine / plain | engine s | plain s | CPU coll/s (%d threads) "
              "| engine / CPU | engine regs, blocks/SM | plain regs, blocks/SM |\n|---|---|---|---|---|---|---|---|---|---|\n",
              omp_get_max_threads());
  std::string json = "{\"device\": \"" + std::string(prop.name) + "\", \"particles\": " + std::to_string(particles) +
                     ", \"rounds\": " + std::to_string(rounds) + ", \"scenes\": [";
  std::string caps_table =
      "\nThe engine's kernel alone (one launch of the same particles, tallies on the device), by register cap:\n\n"
      "| scene | blocks/SM asked | collisions/s | registers | blocks/SM |\n|---|---|---|---|---|\n";
  for (std::size_t k = 0; k < cases.size(); ++k) {
    std::vector<std::string> set = cases[k].set;
    set.push_back("ensemble.particles=" + std::to_string(particles));
    const Scene s = parse_scene("", set);
    std::vector<double> engine, plain, engine_s, plain_s;
    std::uint64_t engine_c = 0, plain_c = 0;
    for (int r = 0; r < rounds; ++r) {
      const Rate p = plain_run(s), e = engine_run(s, Engine::gpu, 0);
      plain.push_back(p.rate), plain_s.push_back(p.seconds), plain_c = p.collisions;
      engine.push_back(e.rate), engine_s.push_back(e.seconds), engine_c = e.collisions;
    }
    std::vector<std::string> cpu_set = set;
    cpu_set.back() = "ensemble.particles=" + std::to_string(cpu_particles);
    const Rate cpu = engine_run(parse_scene("", cpu_set), Engine::automatic, 0);
    // the engine's kernel alone in each of its register caps, interleaved too
    constexpr int kCaps[] = {1, 6, 8};
    std::vector<std::vector<double>> caps(3);
    KernelRate cap_info[3];
    for (int r = 0; r < rounds; ++r)
      for (int c = 0; c < 3; ++c) {
        cap_info[c] = kernel_run(s, kCaps[c]);
        caps[static_cast<std::size_t>(c)].push_back(cap_info[c].rate);
      }
    gpu::Shape shape;
    const DensityCells cells = scene_density_cells(s);
    shape.density = s.collision_density ? &cells : nullptr;
    const Model<double> model = Model<double>::from(s);
    gpu::Device device(model, shape);  // the default cap's registers and occupancy, from one particle
    const gpu::Batch one{0, 1, nullptr, nullptr, s.seed, s.creation_window, nullptr};
    device.run(one);
    const double ratio = median(engine) / median(plain);
    std::printf("| %s | %.3g | %.3g | %.2f | %.2f | %.2f | %.3g | %.1f | %d, %d | %d, %d |\n", cases[k].name,
                median(engine), median(plain), ratio, median(engine_s), median(plain_s), cpu.rate,
                median(engine) / cpu.rate, device.registers(), device.blocks_per_multiprocessor(), plain_attr.numRegs,
                plain_blocks);
    char row[800];
    std::snprintf(row, sizeof row,
                  "%s{\"scene\": \"%s\", \"engine_rate\": %.6g, \"plain_rate\": %.6g, \"ratio\": %.4f, "
                  "\"engine_seconds\": %.4f, \"plain_seconds\": %.4f, \"engine_collisions\": %llu, "
                  "\"plain_collisions\": %llu, \"cpu_rate\": %.6g, \"engine_registers\": %d, \"engine_blocks\": %d, "
                  "\"plain_registers\": %d, \"plain_blocks\": %d",
                  k ? ", " : "", cases[k].name, median(engine), median(plain), ratio, median(engine_s),
                  median(plain_s), static_cast<unsigned long long>(engine_c), static_cast<unsigned long long>(plain_c),
                  cpu.rate, device.registers(), device.blocks_per_multiprocessor(), plain_attr.numRegs, plain_blocks);
    json += row;
    json += ", \"kernel_caps\": [";
    for (int c = 0; c < 3; ++c) {
      const double rate = median(caps[static_cast<std::size_t>(c)]);
      std::snprintf(row, sizeof row, "| %s | %d | %.3g | %d | %d |\n", cases[k].name, kCaps[c], rate,
                    cap_info[c].registers, cap_info[c].blocks);
      caps_table += row;
      std::snprintf(row, sizeof row, "%s{\"min_blocks\": %d, \"rate\": %.6g, \"registers\": %d, \"blocks\": %d}",
                    c ? ", " : "", kCaps[c], rate, cap_info[c].registers, cap_info[c].blocks);
      json += row;
    }
    json += "]}";
  }
  std::printf("%s", caps_table.c_str());
  // FP64: 64 FMA units a multiprocessor on Hopper, 2 operations an FMA
  const double peak = static_cast<double>(prop.multiProcessorCount) * clock_khz * 1e3 * 64 * 2;
  std::printf("\nFP64 peak: %d multiprocessors x %.2f GHz x 128 = %.3g FLOP/s; at 100 FP64 operations a collision: "
              "%.3g collisions/s\n",
              prop.multiProcessorCount, clock_khz * 1e-6, peak, peak / 100);
  char tail[200];
  std::snprintf(tail, sizeof tail, "], \"fp64_peak\": %.6g, \"limit_at_100_flops\": %.6g}", peak, peak / 100);
  json += tail;
  std::printf("%s\n", json.c_str());
  return 0;
}
