#include <omp.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "numeric/input.hpp"
#include "sim/engine/engine.hpp"
#include "sim/engine/population.hpp"
#include "sim/gpu/gpu_engine.hpp"
#include "sim/kernel/simd_engine.hpp"

namespace rotleak {

std::string to_string(Engine e) {
  switch (e) {
    case Engine::automatic:
      return "auto";
    case Engine::scalar:
      return "scalar";
    case Engine::simd:
      return "simd";
    case Engine::gpu:
      return "gpu";
  }
  return "?";
}

int default_simd_lanes() {
  const char* forced = std::getenv("ROTLEAK_SIMD_LANES");
  if (!forced || !*forced) return simd::widest_lanes();
  const std::string v = forced;
  const int lanes = v == "4" ? 4 : v == "8" ? 8 : 0;
  if (!simd::lanes_available(lanes))
    throw InputError("ROTLEAK_SIMD_LANES", v,
                     std::string("4 (AVX2) or 8 (AVX-512), a kernel this CPU runs: ") +
                         (simd::widest_lanes() == 8   ? "4 or 8"
                          : simd::widest_lanes() == 4 ? "4 only"
                                                      : "none (unset it: the scalar core runs)"));
  return lanes;
}

Engine resolve_engine(Engine requested, const Scene& scene) {
  // The kernel runs the double tier, with f_c for up to kMaxDensityWindows windows.
  const bool fits = scene.tier == Tier::double_ &&
                    (!scene.collision_density ||
                     scene.collision_density->windows.size() <= static_cast<std::size_t>(simd::kMaxDensityWindows));
  if (requested == Engine::gpu) {  // the scalar core on the device: the double tier
    if (const std::string why = gpu::unavailable(); !why.empty()) throw std::runtime_error(why);
    if (!fits)
      throw std::runtime_error("the GPU engine runs the double tier (with at most " +
                               std::to_string(simd::kMaxDensityWindows) + " collision_density windows)");
    return Engine::gpu;
  }
  if (requested == Engine::simd) {
    if (!simd::available()) throw std::runtime_error("--engine simd: this CPU lacks AVX2 and FMA");
    if (!fits)
      throw std::runtime_error("--engine simd runs the double tier (with at most " +
                               std::to_string(simd::kMaxDensityWindows) + " collision_density windows)");
    return Engine::simd;
  }
  if (requested == Engine::scalar) return Engine::scalar;
  return fits && simd::available() ? Engine::simd : Engine::scalar;
}

Engine parse_engine(const std::string& key, const std::string& name) {
  if (name != "auto" && name != "scalar" && name != "simd" && name != "gpu")
    throw InputError(key, name, "allowed: auto, scalar, simd, gpu");
  return name == "scalar" ? Engine::scalar
         : name == "simd" ? Engine::simd
         : name == "gpu"  ? Engine::gpu
                          : Engine::automatic;
}

void check_engine(const std::string& key, Engine e, const Scene& scene) {
  try {
    resolve_engine(e, scene);
  } catch (const std::runtime_error& err) {
    throw InputError(key, to_string(e), err.what());
  }
}

void check_resources(const Scene& scene, int threads) {
  const int procs = omp_get_num_procs();
  if (threads > kThreadsPerCore * procs)
    throw InputError("--threads", std::to_string(threads),
                     "at most " + std::to_string(kThreadsPerCore) +
                         " per core: <= " + std::to_string(kThreadsPerCore * procs) + " on this machine (" +
                         std::to_string(procs) + " cores; 0: one per core)");
  const double n_threads = threads > 0 ? threads : omp_get_max_threads();
  // a count per bin, and for weighted runs two exact sums (24 bytes each) per survival bin and one per density bin
  const bool weighted = scene.sampling.weighted();
  const double survival = (weighted ? 56.0 : 8.0) * static_cast<double>(scene.survival_bins());
  const double density = scene.collision_density
                             ? (weighted ? 32.0 : 8.0) * static_cast<double>(scene.collision_density->bins) *
                                   static_cast<double>(scene.collision_density->windows.size())
                             : 0.0;
  const double records =
      scene.escape_records ? static_cast<double>(sizeof(EscapeRecord)) * static_cast<double>(scene.particles) : 0.0;
  // split runs: four exact line sums (~64 bytes each) and two counts per grid point, and a block's
  // population of at most kBlockSize x split_cap members (member, its end, its kernel start) per thread
  const double lines = scene.splitting.on ? 300.0 * static_cast<double>(scene.survival_bins()) : 0.0;
  const double population =
      scene.splitting.on ? static_cast<double>(kBlockSize) * static_cast<double>(scene.splitting.cap) *
                               static_cast<double>(2 * sizeof(Member) + sizeof(ParticleEnd) + sizeof(simd::Start))
                         : 0.0;
  const double need = (survival + density + lines) * (n_threads + 1) + population * n_threads +
                      records;  // a tally per thread and the merged one
  double have = static_cast<double>(::sysconf(_SC_PHYS_PAGES)) * static_cast<double>(::sysconf(_SC_PAGE_SIZE));
  struct rlimit as {};
  if (::getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY)
    have = std::min(have, static_cast<double>(as.rlim_cur));
  if (need <= 0.8 * have) return;
  char why[300];
  std::snprintf(why, sizeof why, "the run would need %.3g GB for its tallies (%.0f threads) but may use %.3g GB here",
                need / 1e9, n_threads, 0.8 * have / 1e9);
  if (population * n_threads >= survival * (n_threads + 1) && population >= density)
    throw InputError("run.split_cap", std::to_string(scene.splitting.cap),
                     std::string(why) + "; a block of " + std::to_string(kBlockSize) +
                         " lines may hold split_cap members each: a smaller cap (or fewer --threads)");
  if (records >= survival * (n_threads + 1) && records >= density * (n_threads + 1))
    throw InputError(
        "ensemble.particles", std::to_string(scene.particles),
        std::string(why) + "; observe.escapes keeps 32 bytes per particle: fewer particles, or no escape records");
  if (density > survival)
    throw InputError("observe.collision_density",
                     std::to_string(scene.collision_density->bins) + " bins x " +
                         std::to_string(scene.collision_density->windows.size()) + " windows",
                     std::string(why) + "; fewer bins or windows (or fewer --threads)");
  throw InputError("observe.survival_dt", std::to_string(scene.survival_bins()) + " bins",
                   std::string(why) + "; a coarser survival_dt (or fewer --threads)");
}

namespace {

/// The engine and lanes that run a scene whose tier is known: `asked` resolved (an InputError naming
/// --engine when it cannot run the scene here), the lanes checked against this CPU.
void settle_engine(const Scene& scene, Engine asked, int lanes_asked, Engine& engine, int& lanes) {
  check_engine("--engine", asked, scene);
  engine = resolve_engine(asked, scene);
  lanes = 0;
  if (engine != Engine::simd) return;
  lanes = lanes_asked > 0 ? lanes_asked : default_simd_lanes();
  if (!simd::lanes_available(lanes))
    throw std::invalid_argument("RunOptions::simd_lanes = " + std::to_string(lanes_asked) +
                                ": this CPU runs the vectorised kernel with 4 lanes (AVX2)" +
                                (simd::lanes_available(8) ? " or 8 (AVX-512)" : ""));
}

/// A split run runs the double tier (or auto, until settled) from the scene's own draws, without records.
void check_split_needs(const Scene& scene, bool outside_draws) {
  if (scene.splitting.on &&
      (!(scene.tier.automatic() || scene.tier == Tier::double_) || outside_draws || scene.escape_records))
    throw std::invalid_argument("a split run runs the double tier from the scene's own draws, without escape records");
}

}  // namespace

RunPlan plan_run(Scene scene, const RunOptions& options) {
  check_resources(scene, options.threads);
  if (!scene.tier.automatic() && !scene.tier.ensemble())
    throw std::invalid_argument("the ensemble engine runs float, double or long_double, not " + scene.tier.name());
  if (options.draws && options.draws->size() != scene.particles)
    throw std::invalid_argument("RunOptions::draws holds " + std::to_string(options.draws->size()) + " draws for " +
                                std::to_string(scene.particles) + " particles");
  check_split_needs(scene, options.draws != nullptr);
  RunPlan plan;
  plan.stadium_ = std::make_shared<const Stadium<double>>(scene.d, scene.r);
  plan.scene_ = std::move(scene);
  plan.asked_ = options.engine;
  plan.lanes_asked_ = options.simd_lanes;
  plan.threads_ = options.threads;
  if (!plan.scene_.tier.automatic())
    settle_engine(plan.scene_, plan.asked_, plan.lanes_asked_, plan.engine_, plan.lanes_);
  return plan;
}

RunPlan RunPlan::with_particles(std::uint64_t particles) const {
  RunPlan p = *this;
  p.scene_.particles = particles;
  return p;
}

RunPlan RunPlan::with_tier(Tier tier) const {
  if (!scene_.tier.automatic()) return *this;
  RunPlan p = *this;
  p.scene_.tier = tier;
  check_split_needs(p.scene_, false);  // the draws were checked by plan_run
  settle_engine(p.scene_, p.asked_, p.lanes_asked_, p.engine_, p.lanes_);
  return p;
}

}  // namespace rotleak
