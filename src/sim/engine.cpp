#include "sim/engine.hpp"

#include <omp.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <stdexcept>
#include <type_traits>

#include "numeric/tier_dispatch.hpp"
#include "sim/kernel_adapter.hpp"
#include "sim/particle.hpp"
#include "sim/population.hpp"
#include "sim/sampling.hpp"
#include "sim/simd_engine.hpp"

namespace rotleak {

namespace {

/// Runs particles [lo, hi) one after the other. (Interleaving several flights per thread was
/// measured slower here: the loop is bound by branch mispredictions, not by its dependency chain.)
template <class R, class Observer, class Record>
void run_block(const Model<R>& model, const DrawSource& draw, std::uint64_t lo, std::uint64_t hi, Observer& observe,
               Record& record) {
  for (std::uint64_t i = lo; i < hi; ++i) {
    const InitialDraw d = draw(i);
    if constexpr (Observer::active) observe.weight = draw.weight(d);
    record(i, run_particle(model, initial_state(model.stadium, d), observe));
  }
}

template <class R>
RunResult run_tier(const Scene& scene, const RunOptions& opt) {
  const Model<R> model = Model<R>::from(scene);
  const std::unique_ptr<Sampler> sampler = make_sampler(scene);
  if (opt.draws && opt.draws->size() != scene.particles)
    throw std::invalid_argument("RunOptions::draws holds " + std::to_string(opt.draws->size()) + " draws for " +
                                std::to_string(scene.particles) + " particles");
  const DrawSource source{sampler.get(), opt.first_id, opt.draws};
  const std::unique_ptr<SplitRule> scene_rule =
      scene.splitting.on && !opt.split_rule ? make_split_rule(scene) : nullptr;
  const SplitRule* split_rule = scene.splitting.on ? (opt.split_rule ? opt.split_rule : scene_rule.get()) : nullptr;
  if (scene.splitting.on && (!std::is_same_v<R, double> || opt.draws || scene.escape_records))
    throw std::invalid_argument("a split run runs the double tier from the scene's own draws, without escape records");
  RunResult result;
  result.tally.resize(scene);
  if (scene.escape_records) result.records.resize(scene.particles);

  result.engine = resolve_engine(opt.engine, scene);
  result.first_id = opt.first_id;
  const bool use_simd = result.engine == Engine::simd;
  simd::Scene kernel_scene{};
  DensityCells cells;
  if constexpr (std::is_same_v<R, double>)
    if (use_simd) {
      kernel_scene = simd_scene(model);
      simd_density(kernel_scene, scene);
      cells.bins = kernel_scene.bins;
      density_cells(kernel_scene.density_windows, kernel_scene.win_from, kernel_scene.win_to, cells.windows);
      kernel_scene.lanes = opt.simd_lanes > 0 ? opt.simd_lanes : simd::widest_lanes();
      if (!simd::lanes_available(kernel_scene.lanes))
        throw std::invalid_argument("RunOptions::simd_lanes = " + std::to_string(opt.simd_lanes) +
                                    ": this CPU runs the vectorised kernel with 4 lanes (AVX2)" +
                                    (simd::lanes_available(8) ? " or 8 (AVX-512)" : ""));
      result.simd_lanes = kernel_scene.lanes;
    }
  const std::uint64_t n = scene.particles;
  const std::uint64_t blocks = block_count(n);
  const IntervalSet todo = opt.blocks ? *opt.blocks : IntervalSet::range(0, blocks);
  if (!todo.empty() && todo.intervals().back().second > blocks)
    throw std::invalid_argument("RunOptions::blocks names block " + std::to_string(todo.intervals().back().second - 1) +
                                " of a run of " + std::to_string(blocks));
  if (opt.start_done) result.done = *opt.start_done;
  if (!result.done.empty() && result.done.intervals().back().second > blocks)
    throw std::invalid_argument("RunOptions::start_done names blocks beyond the run's " + std::to_string(blocks));
  const std::uint64_t already = particles_in(result.done, n), goal = already + particles_in(todo, n);
  if (opt.start) result.tally.merge(*opt.start);
  if (opt.start_records && scene.escape_records) result.records = *opt.start_records;
  const double dt = scene.survival_dt;
  const std::size_t nbins = result.tally.escapes_per_bin.size();
  std::atomic<std::uint64_t> done{already}, collisions_done{result.tally.collisions};
  const auto t0 = std::chrono::steady_clock::now();

  const int threads = opt.threads > 0 ? opt.threads : omp_get_max_threads();
  const std::uint64_t total = todo.size();
  std::uint64_t at = 0;  // the blocks todo.nth(0 .. at) are done
  // Epochs: threads take blocks in todo order from a shared counter until all are taken, a stop is
  // asked for, or the checkpoint time has come; then the tallies are merged and checkpointed.
  while (true) {
    const auto deadline =
        opt.checkpoint_seconds > 0
            ? std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                     std::chrono::duration<double>(opt.checkpoint_seconds))
            : std::chrono::steady_clock::time_point::max();
    std::atomic<std::uint64_t> next{at};
    std::atomic<bool> halt{false};
#pragma omp parallel num_threads(threads)
    {
#pragma omp single
      result.threads = omp_get_num_threads();
      Tally local;
      local.resize(scene);
      DensityObserver<R> density{&model.stadium, scene.collision_density ? &scene.collision_density->windows : nullptr,
                                 scene.collision_density ? scene.collision_density->bins : 0,
                                 local.collision_density.data(),
                                 local.weighted ? local.collision_density_w.data() : nullptr};
      NoCollisionObserver<R> none;
      const std::size_t n_cells = 2 * static_cast<std::size_t>(kernel_scene.density_windows) + 1;
      std::vector<std::uint64_t> cell_counts;  // the kernel's unweighted f_c, by time cell
      if (use_simd && scene.collision_density && !local.weighted)
        cell_counts.assign(n_cells * static_cast<std::size_t>(cells.bins), 0);
      auto record = [&](std::uint64_t i, const ParticleEnd& end) {
        double w = 1;
        if (local.weighted) {  // the weight is a function of (seed, id): rebuilt here, not carried by lanes
          w = source.weight(source(i));
          local.total_w.add(w);
          local.total_w2.add(w * w);
        }
        switch (end.fate) {
          case Fate::escaped: {
            std::size_t b = static_cast<std::size_t>(end.t / dt);
            if (b >= nbins) b = nbins - 1;
            ++local.escapes_per_bin[b];
            ++local.escaped;
            if (local.weighted) {
              local.escaped_w[b].add(w);
              local.escaped_w2[b].add(w * w);
            }
            break;
          }
          case Fate::survived:
            ++local.survived;
            break;
          case Fate::stuck:
            ++local.stuck;
            break;
        }
        local.collisions += end.collisions;
        if (scene.escape_records) result.records[i] = {end.t, end.s, end.collisions, end.fate};
      };
      // A split run's members, advanced to `stop` by the engine that runs the scene (its ends by position).
      std::vector<simd::Start> starts;
      const AdvanceMembers advance_members = [&](const std::vector<Member>& members, const std::vector<double>& weights,
                                                 double stop, std::vector<ParticleEnd>& ends) {
        if constexpr (std::is_same_v<R, double>) {
          Model<double> epoch = model;
          epoch.t_max = stop;
          auto put = [&](std::uint64_t i, const ParticleEnd& e) { ends[i] = e; };
          if (use_simd) {
            simd::Scene ks = kernel_scene;
            ks.t_max = stop;
            ks.keep_last = true;
            starts.resize(members.size());
            for (std::size_t i = 0; i < members.size(); ++i) {
              const ParticleState<double>& ps = members[i].ps;
              starts[i] = {ps.q.x,    ps.q.y, ps.v.x, ps.v.y, ps.t, static_cast<double>(members[i].collisions),
                           weights[i]};
            }
            SimdContext ctx{&epoch, source, 0, members.size(), put, {}};
            ctx.members = &starts;
            if (scene.collision_density) {
              ctx.weights = true;
              ctx.density = local.collision_density.data();
              ctx.density_w = local.collision_density_w.data();
              ctx.observer = &density;
              ctx.cells = &cells;
            }
            simd::run(ks, &ctx, simd_next, simd_finish, kSimdExact);
          } else {
            for (std::size_t i = 0; i < members.size(); ++i) {
              Flight<double> f{members[i].ps, {}, 0};
              f.end.collisions = members[i].collisions;
              density.weight = weights[i];
              if (scene.collision_density)
                while (advance(epoch, f, density)) {
                }
              else
                while (advance(epoch, f, none)) {
                }
              ends[i] = f.end;
            }
          }
        }
      };
      while (true) {
        // the halt check comes before taking a block: every block taken is run
        if (halt.load(std::memory_order_relaxed) || (opt.stop && opt.stop->load(std::memory_order_relaxed))) break;
        const std::uint64_t k = next.fetch_add(1);
        if (k >= total) break;
        const std::uint64_t blk = todo.nth(k);
        const std::uint64_t lo = blk * kBlockSize, hi = std::min(n, lo + kBlockSize);
        const std::uint64_t before = local.collisions;
        if (split_rule) {
          if constexpr (std::is_same_v<R, double>)
            run_lines(scene, *sampler, *split_rule, opt.first_id + lo, opt.first_id + hi, advance_members, local);
        } else if (use_simd) {
          if constexpr (std::is_same_v<R, double>) {
            SimdContext ctx{&model, source, lo, hi, record, {}};
            if (scene.collision_density) {
              ctx.weights = local.weighted;
              ctx.density = local.collision_density.data();
              ctx.density_w = local.weighted ? local.collision_density_w.data() : nullptr;
              ctx.observer = &density;
              ctx.cells = &cells;
            }
            simd::Exact exact = kSimdExact;
            if (!cell_counts.empty()) exact.counts = cell_counts.data();
            simd::run(kernel_scene, &ctx, simd_next, simd_finish, exact);
            if (!cell_counts.empty()) cells.fold(cell_counts.data(), local.collision_density.data(), n_cells);
          }
        } else if (scene.collision_density) {
          run_block(model, source, lo, hi, density, record);
        } else {
          run_block(model, source, lo, hi, none, record);
        }
        const std::uint64_t d = done.fetch_add(hi - lo) + (hi - lo);
        const std::uint64_t c = collisions_done.fetch_add(local.collisions - before) + (local.collisions - before);
        if (opt.progress && omp_get_thread_num() == 0) opt.progress(d, goal, c, false);
        if (std::chrono::steady_clock::now() >= deadline) halt.store(true, std::memory_order_relaxed);
      }
#pragma omp critical
      result.tally.merge(local);
    }
    const std::uint64_t end = std::min(next.load(), total);
    result.done.insert(todo.slice(at, end));  // the todo positions [at, end) are done
    at = end;
    if (at >= total) break;
    if (opt.checkpoint) opt.checkpoint(result.tally, result.done, result.records);
    if (opt.stop && opt.stop->load()) {
      result.complete = false;
      break;
    }
  }
  check_conservation(result.tally, result.done, n);
  result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (opt.progress && result.complete) opt.progress(goal, goal, result.tally.collisions, true);
  return result;
}

}  // namespace

std::string to_string(Engine e) {
  switch (e) {
    case Engine::automatic:
      return "auto";
    case Engine::scalar:
      return "scalar";
    case Engine::simd:
      return "simd";
  }
  return "?";
}

Engine resolve_engine(Engine requested, const Scene& scene) {
  // The kernel runs the double tier, with f_c for up to kMaxDensityWindows windows.
  const bool fits = scene.tier == Tier::double_ &&
                    (!scene.collision_density ||
                     scene.collision_density->windows.size() <= static_cast<std::size_t>(simd::kMaxDensityWindows));
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
  if (name != "auto" && name != "scalar" && name != "simd") throw InputError(key, name, "allowed: auto, scalar, simd");
  return name == "scalar" ? Engine::scalar : name == "simd" ? Engine::simd : Engine::automatic;
}

void check_engine(const std::string& key, Engine e, const Scene& scene) {
  try {
    resolve_engine(e, scene);
  } catch (const std::runtime_error& err) {
    throw InputError(key, to_string(e), err.what());
  }
}

Engine engine_from_name(const std::string& key, const std::string& name, const Scene& scene) {
  const Engine e = parse_engine(key, name);
  check_engine(key, e, scene);
  return e;
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

RunResult run_ensemble(const Scene& scene, const RunOptions& options) {
  check_resources(scene, options.threads);
  if (!scene.tier.automatic() && !scene.tier.ensemble())
    throw std::invalid_argument("the ensemble engine runs float, double or long_double, not " + scene.tier.name());
  return with_tier(scene.tier, [&](auto type) -> RunResult {
    using R = typename decltype(type)::type;
    if constexpr (std::is_floating_point_v<R>)
      return run_tier<R>(scene, options);
    else
      throw std::logic_error("unreachable: not an ensemble tier");
  });
}

}  // namespace rotleak
