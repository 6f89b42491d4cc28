#include "sim/engine/engine.hpp"

#include <omp.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <stdexcept>
#include <type_traits>

#include "numeric/input.hpp"
#include "numeric/tier_dispatch.hpp"
#include "sim/engine/kernel_adapter.hpp"
#include "sim/engine/population.hpp"
#include "sim/kernel/simd_engine.hpp"
#include "sim/model/particle.hpp"
#include "sim/model/sampling.hpp"

namespace rotleak {

namespace {

/// When an epoch that starts now ends: after checkpoint_seconds (0: never).
std::chrono::steady_clock::time_point epoch_deadline(double checkpoint_seconds) {
  if (!(checkpoint_seconds > 0)) return std::chrono::steady_clock::time_point::max();
  return std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                std::chrono::duration<double>(checkpoint_seconds));
}

/// What every thread of a run shares: the model in tier R, the draws, the split rule, the engine that
/// runs and the kernel's set-up; checks the options against the scene.
template <class R>
struct RunSetup {
  const Scene& scene;
  const RunOptions& opt;
  Model<R> model;
  std::unique_ptr<Sampler> sampler;
  DrawSource source;
  std::unique_ptr<SplitRule> scene_rule;
  const SplitRule* split_rule = nullptr;
  Engine engine;
  simd::KernelScene kernel{};  ///< the vectorised kernel's scene (engine simd)
  DensityCells cells;          ///< and its f_c time cells

  RunSetup(const Scene& s, const RunOptions& o)
      : scene(s),
        opt(o),
        model(Model<R>::from(s)),
        sampler(make_sampler(s)),
        source{sampler.get(), o.first_id, o.draws} {
    if (opt.draws && opt.draws->size() != scene.particles)
      throw std::invalid_argument("RunOptions::draws holds " + std::to_string(opt.draws->size()) + " draws for " +
                                  std::to_string(scene.particles) + " particles");
    if (scene.splitting.on && (!std::is_same_v<R, double> || opt.draws || scene.escape_records))
      throw std::invalid_argument(
          "a split run runs the double tier from the scene's own draws, without escape records");
    if (scene.splitting.on && !opt.split_rule) scene_rule = make_split_rule(scene);
    if (scene.splitting.on) split_rule = opt.split_rule ? opt.split_rule : scene_rule.get();
    engine = resolve_engine(opt.engine, scene);
    if constexpr (std::is_same_v<R, double>)
      if (engine == Engine::simd) {
        kernel = simd_scene(model);
        simd_density(kernel, scene);
        cells = DensityCells::of(kernel.bins, kernel.density_windows, kernel.win_from, kernel.win_to);
        kernel.lanes = opt.simd_lanes > 0 ? opt.simd_lanes : default_simd_lanes();
        if (!simd::lanes_available(kernel.lanes))
          throw std::invalid_argument("RunOptions::simd_lanes = " + std::to_string(opt.simd_lanes) +
                                      ": this CPU runs the vectorised kernel with 4 lanes (AVX2)" +
                                      (simd::lanes_available(8) ? " or 8 (AVX-512)" : ""));
      }
  }

  /// The result before any block runs: the start tallies, the blocks they hold, the engine that runs.
  RunResult start() const {
    RunResult r;
    r.tally.resize(scene);
    if (scene.escape_records) r.records.resize(scene.particles);
    r.engine = engine;
    r.simd_lanes = engine == Engine::simd ? kernel.lanes : 0;
    r.first_id = opt.first_id;
    const std::uint64_t blocks = block_count(scene.particles);
    if (opt.start_done) r.done = *opt.start_done;
    if (!r.done.empty() && r.done.intervals().back().second > blocks)
      throw std::invalid_argument("RunOptions::start_done names blocks beyond the run's " + std::to_string(blocks));
    if (opt.start) r.tally.merge(*opt.start);
    if (opt.start_records && scene.escape_records) r.records = *opt.start_records;
    return r;
  }

  /// The blocks to run: opt.blocks, or all of them.
  IntervalSet todo() const {
    const std::uint64_t blocks = block_count(scene.particles);
    const IntervalSet t = opt.blocks ? *opt.blocks : IntervalSet::range(0, blocks);
    if (!t.empty() && t.intervals().back().second > blocks)
      throw std::invalid_argument("RunOptions::blocks names block " + std::to_string(t.intervals().back().second - 1) +
                                  " of a run of " + std::to_string(blocks));
    return t;
  }
};

/// One thread's share of a run: its tallies and observers, and the engine that runs a block of ids
/// (the scalar core particle by particle, or the vectorised kernel), or a split run's lines.
template <class R>
class Worker {
 public:
  Tally local;

  Worker(const RunSetup<R>& s, std::vector<EscapeRecord>& records) : s_(s), records_(records) {
    local.resize(s.scene);
    const Scene& sc = s.scene;
    density_ = {&s.model.stadium, sc.collision_density ? &sc.collision_density->windows : nullptr,
                sc.collision_density ? sc.collision_density->bins : 0, local.collision_density.data(),
                local.weighted() ? local.collision_density_w.data() : nullptr};
    if (s.engine == Engine::simd && sc.collision_density) {  // f_c by time cell (DensityCells), folded in flush()
      const auto n = static_cast<std::size_t>(s.cells.cells()) * static_cast<std::size_t>(s.cells.bins);
      cell_counts_.assign(n, 0);
      if (local.weighted()) cell_sums_.assign(n, FixedSum{});
      density_.counts = cell_counts_.data();
      density_.weighted_counts = local.weighted() ? cell_sums_.data() : nullptr;
      density_.cells = &s.cells;
    }
  }

  /// Completes `local`: the f_c counted by time cell into its windows. Before `local` is read.
  void flush() {
    if (!cell_counts_.empty())
      s_.cells.fold(cell_counts_.data(), cell_sums_.empty() ? nullptr : cell_sums_.data(),
                    local.collision_density.data(), local.weighted() ? local.collision_density_w.data() : nullptr);
  }

  /// Particles (ids first_id + [lo, hi)), or the lines they start.
  void run_block(std::uint64_t lo, std::uint64_t hi) {
    if (s_.split_rule) {
      if constexpr (std::is_same_v<R, double>)
        run_lines(
            s_.scene, *s_.sampler, *s_.split_rule, s_.opt.first_id + lo, s_.opt.first_id + hi,
            [this](const std::vector<Member>& m, const std::vector<double>& w, double stop,
                   std::vector<ParticleEnd>& ends) { advance_members(m, w, stop, ends); },
            local);
    } else if (s_.engine == Engine::simd) {
      if constexpr (std::is_same_v<R, double>) {
        SimdContext ctx = context(s_.model, lo, hi, local.weighted(),
                                  [this](std::uint64_t i, const ParticleEnd& e) { record(i, e); });
        simd::Exact exact = kSimdExact;
        if (!cell_counts_.empty() && !local.weighted()) exact.counts = cell_counts_.data();
        simd::run(s_.kernel, &ctx, simd_next, simd_finish, exact);
      }
    } else {
      auto rec = [this](std::uint64_t i, const ParticleEnd& e) { record(i, e); };
      if (s_.scene.collision_density)
        run_particles(lo, hi, density_, rec);
      else
        run_particles(lo, hi, none_, rec);
    }
  }

 private:
  /// Runs particles [lo, hi) one after the other. (Interleaving several flights per thread was
  /// measured slower here: the loop is bound by branch mispredictions, not by its dependency chain.)
  template <class Observer, class Record>
  void run_particles(std::uint64_t lo, std::uint64_t hi, Observer& observe, Record& rec) {
    for (std::uint64_t i = lo; i < hi; ++i) {
      const InitialDraw d = s_.source(i);
      if constexpr (Observer::active) observe.weight = s_.source.weight(d);
      rec(i, run_particle(s_.model, initial_state(s_.model.stadium, d), observe));
    }
  }

  /// A particle's end into the thread's tallies (and its escape record).
  void record(std::uint64_t i, const ParticleEnd& end) {
    // the weight is a function of (seed, id): rebuilt here, not carried by lanes
    const double w = local.weighted() ? s_.source.weight(s_.source(i)) : 1.0;
    local.add_end(end.fate, end.t, end.collisions, w, s_.scene.survival_dt);
    if (s_.scene.escape_records) records_[i] = {end.t, end.s, end.collisions, end.fate};
  }

  /// The kernel's context for particles [lo, hi) of `model`, f_c wired to the thread's tallies.
  template <class Put>
  SimdContext context(const Model<double>& model, std::uint64_t lo, std::uint64_t hi, bool weights, Put put) {
    SimdContext ctx{&model, s_.source, lo, hi, put, {}};
    if (s_.scene.collision_density) {
      ctx.weights = weights;
      ctx.density = cell_counts_.data();
      ctx.density_w = local.weighted() ? cell_sums_.data() : nullptr;
      if constexpr (std::is_same_v<R, double>) ctx.observer = &density_;
      ctx.cells = &s_.cells;
    }
    return ctx;
  }

  /// A split run's members, advanced to `stop` by the engine that runs the scene (ends by position).
  void advance_members(const std::vector<Member>& members, const std::vector<double>& weights, double stop,
                       std::vector<ParticleEnd>& ends) {
    if constexpr (std::is_same_v<R, double>) {
      Model<double> epoch = s_.model;
      epoch.t_max = stop;
      if (s_.engine == Engine::simd) {
        simd::KernelScene ks = s_.kernel;
        ks.t_max = stop;
        ks.keep_last = true;
        starts_.resize(members.size());
        for (std::size_t i = 0; i < members.size(); ++i) {
          const ParticleState<double>& ps = members[i].ps;
          starts_[i] = {ps.q.x, ps.q.y, ps.v.x, ps.v.y, ps.t, members[i].collisions, weights[i]};
        }
        SimdContext ctx =
            context(epoch, 0, members.size(), true, [&ends](std::uint64_t i, const ParticleEnd& e) { ends[i] = e; });
        ctx.members = &starts_;
        simd::run(ks, &ctx, simd_next, simd_finish, kSimdExact);
      } else {
        for (std::size_t i = 0; i < members.size(); ++i) {
          Flight<double> f{members[i].ps, {}, 0};
          f.end.collisions = members[i].collisions;
          density_.weight = weights[i];
          if (s_.scene.collision_density)
            while (advance(epoch, f, density_)) {
            }
          else
            while (advance(epoch, f, none_)) {
            }
          ends[i] = f.end;
        }
      }
    }
  }

  const RunSetup<R>& s_;
  std::vector<EscapeRecord>& records_;
  DensityObserver<R> density_{};
  NoCollisionObserver<R> none_;
  std::vector<std::uint64_t> cell_counts_;  ///< the vectorised engine's f_c, by time cell (DensityCells)
  std::vector<FixedSum> cell_sums_;         ///< and its weighted sums
  std::vector<simd::Start> starts_;         ///< a split run's members, as the kernel takes them
};

/// The batch lifecycle: set up, run epochs of blocks on all threads (each block taken once, in todo
/// order), merge the threads' exact tallies, checkpoint between epochs, check conservation.
template <class R>
RunResult run_tier(const Scene& scene, const RunOptions& opt) {
  const RunSetup<R> setup(scene, opt);
  RunResult result = setup.start();
  const IntervalSet todo = setup.todo();
  const std::uint64_t n = scene.particles, total = todo.size();
  const std::uint64_t goal = particles_in(result.done, n) + particles_in(todo, n);
  std::atomic<std::uint64_t> done{particles_in(result.done, n)}, collisions_done{result.tally.collisions};
  const int threads = opt.threads > 0 ? opt.threads : omp_get_max_threads();
  const auto t0 = std::chrono::steady_clock::now();
  // Epochs: threads take blocks in todo order from a shared counter until all are taken, a stop is
  // asked for, or the checkpoint time has come; then the tallies are merged and checkpointed.
  for (std::uint64_t at = 0;;) {  // the blocks todo.nth(0 .. at) are done
    const auto deadline = epoch_deadline(opt.checkpoint_seconds);
    std::atomic<std::uint64_t> next{at};
    std::atomic<bool> halt{false};
#pragma omp parallel num_threads(threads)
    {
#pragma omp single
      result.threads = omp_get_num_threads();
      Worker<R> worker(setup, result.records);
      // the halt check comes before taking a block: every block taken is run
      while (!halt.load(std::memory_order_relaxed) && !(opt.stop && opt.stop->load(std::memory_order_relaxed))) {
        const std::uint64_t k = next.fetch_add(1);
        if (k >= total) break;
        const std::uint64_t lo = todo.nth(k) * kBlockSize, hi = std::min(n, lo + kBlockSize);
        const std::uint64_t before = worker.local.collisions;
        worker.run_block(lo, hi);
        const std::uint64_t d = done.fetch_add(hi - lo) + (hi - lo);
        const std::uint64_t c =
            collisions_done.fetch_add(worker.local.collisions - before) + (worker.local.collisions - before);
        if (opt.progress && omp_get_thread_num() == 0) opt.progress(d, goal, c, false);
        if (std::chrono::steady_clock::now() >= deadline) halt.store(true, std::memory_order_relaxed);
      }
      worker.flush();
#pragma omp critical
      result.tally.merge(worker.local);
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
