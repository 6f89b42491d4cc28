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
#include <memory>
#include <optional>
#include <stdexcept>
#include <type_traits>

#include "numeric/input.hpp"
#include "numeric/tier_dispatch.hpp"
#include "sim/engine/kernel_adapter.hpp"
#include "sim/engine/population.hpp"
#include "sim/gpu/gpu_engine.hpp"
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

/// What every thread of a run shares: the plan, the model in tier R (in double: the plan's stadium), the
/// draws, the split rule and the kernel's set-up.
template <class R>
struct RunSetup {
  const RunPlan& plan;
  const Scene& scene;
  const RunOptions& opt;
  Model<R> model;
  /// Any other table, or several leaks: the model every particle runs (the stadium's model is then unused).
  std::optional<TableModel<R>> table;
  std::unique_ptr<Sampler> sampler;
  DrawSource source;
  std::unique_ptr<SplitRule> scene_rule;
  const SplitRule* split_rule = nullptr;
  Engine engine;
  simd::KernelScene kernel{};                         ///< the vectorised kernel's scene (engine simd)
  std::unique_ptr<simd::KernelTable> kernel_numbers;  ///< and a table's numbers, which it points to
  DensityCells cells;                                 ///< and its f_c time cells

  RunSetup(const RunPlan& p, const RunOptions& o)
      : plan(p),
        scene(p.scene()),
        opt(o),
        model(model_of(p)),
        sampler(make_sampler(scene, p.stadium())),
        source{sampler.get(), o.first_id, o.draws},
        engine(p.engine()) {
    if (scene.on_table()) table.emplace(table_spec(scene), leak_specs(scene), scene.t_max);
    if (scene.splitting.on && !opt.split_rule) scene_rule = make_split_rule(scene, p.stadium());
    if (scene.splitting.on) split_rule = opt.split_rule ? opt.split_rule : scene_rule.get();
    if constexpr (std::is_same_v<R, double>)
      if (engine == Engine::simd) {
        if (table) {
          kernel_numbers = std::make_unique<simd::KernelTable>();
          kernel_table(*table, *kernel_numbers);
          kernel = simd_scene(*table, *kernel_numbers);
        } else {
          kernel = simd_scene(model);
        }
        cells = simd_density(kernel, scene);
        kernel.lanes = p.simd_lanes();
      }
    if (engine == Engine::gpu) cells = scene_density_cells(scene);
  }

  static Model<R> model_of(const RunPlan& p) {
    if constexpr (std::is_same_v<R, double>)
      return Model<double>::from(p.scene(), p.stadium());
    else
      return Model<R>::from(p.scene());
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
    if (s.table)
      table_density_ = {&s.table->table, sc.collision_density ? &sc.collision_density->windows : nullptr,
                        sc.collision_density ? sc.collision_density->bins : 0, local.collision_density.data(),
                        local.weighted() ? local.collision_density_w.data() : nullptr};
    if ((s.engine == Engine::simd || s.engine == Engine::gpu) && sc.collision_density) {
      // f_c by time cell (DensityCells), folded in flush()
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

  /// The GPU engine's escape records of particles [lo, lo + n) (their tallies it counts on the device).
  void record_ends(std::uint64_t lo, std::uint64_t n, const gpu::End* ends) {
    for (std::uint64_t i = 0; i < n; ++i)
      records_[lo + i] = {ends[i].t, ends[i].s, ends[i].collisions, static_cast<Fate>(ends[i].fate), ends[i].leak};
  }
  /// A split run's lines of ids first_id + [lo, hi) for each range, their members advanced on the GPU engine's
  /// device level by level (all ranges' members in one launch), booked into the thread's tallies as run_block books
  /// them.
  void run_device_lines(gpu::Device& device, const std::vector<std::pair<std::uint64_t, std::uint64_t>>& ranges) {
    std::vector<std::pair<std::uint64_t, std::uint64_t>> ids;
    for (const auto& [lo, hi] : ranges) ids.emplace_back(s_.opt.first_id + lo, s_.opt.first_id + hi);
    std::vector<gpu::Start> starts;
    const auto advance = [&](const std::vector<Member>& m, const std::vector<double>& w, double stop,
                             std::vector<ParticleEnd>& ends) {
      starts.resize(m.size());
      for (std::size_t i = 0; i < m.size(); ++i) starts[i] = {m[i].ps, m[i].collisions};
      device.set_t_max(stop);
      gpu::Batch b;
      b.count = m.size(), b.weights = w.data(), b.starts = starts.data();
      device.run(b, nullptr, ends.data());
    };
    run_lines_together(s_.plan, *s_.sampler, *s_.split_rule, ids, advance, local, s_.table ? &*s_.table : nullptr);
  }
  /// f_c's counts by time cell (cells x bins), where the GPU engine adds its own; null without f_c.
  std::uint64_t* cell_counts() { return cell_counts_.empty() ? nullptr : cell_counts_.data(); }
  /// and their weights' exact sums (weighted runs), or null
  FixedSum* cell_sums() { return cell_sums_.empty() ? nullptr : cell_sums_.data(); }

  /// Particles (ids first_id + [lo, hi)), or the lines they start.
  void run_block(std::uint64_t lo, std::uint64_t hi) {
    if (s_.split_rule) {
      if constexpr (std::is_same_v<R, double>)
        run_lines(
            s_.plan, *s_.sampler, *s_.split_rule, s_.opt.first_id + lo, s_.opt.first_id + hi,
            [this](const std::vector<Member>& m, const std::vector<double>& w, double stop,
                   std::vector<ParticleEnd>& ends) { advance_members(m, w, stop, ends); },
            local, s_.table ? &*s_.table : nullptr);
    } else if (s_.engine == Engine::simd) {
      if constexpr (std::is_same_v<R, double>) {
        SimdContext ctx = context(s_.model, lo, hi, local.weighted(),
                                  [this](std::uint64_t i, const ParticleEnd& e) { record(i, e); });
        ctx.kernel_counts = !cell_counts_.empty() && !local.weighted();
        simd_run(s_.kernel, ctx);
      }
    } else if (s_.table) {
      auto rec = [this](std::uint64_t i, const ParticleEnd& e) { record(i, e); };
      if (s_.scene.collision_density)
        run_particles(*s_.table, lo, hi, table_density_, rec);
      else
        run_particles(*s_.table, lo, hi, none_, rec);
    } else {
      auto rec = [this](std::uint64_t i, const ParticleEnd& e) { record(i, e); };
      if (s_.scene.collision_density)
        run_particles(s_.model, lo, hi, density_, rec);
      else
        run_particles(s_.model, lo, hi, none_, rec);
    }
  }

 private:
  /// Runs particles [lo, hi) one after the other. (Interleaving several flights per thread was
  /// measured slower here: the loop is bound by branch mispredictions, not by its dependency chain.)
  template <class M, class Observer, class Record>
  void run_particles(const M& model, std::uint64_t lo, std::uint64_t hi, Observer& observe, Record& rec) {
    for (std::uint64_t i = lo; i < hi; ++i) {
      const InitialDraw d = s_.source(i);
      const double w = local.weighted() ? s_.source.weight(d) : 1.0;
      if constexpr (Observer::active) observe.weight = w;
      ParticleEnd end = run_particle(model, initial_state(model, d), observe);
      end.weight = w;
      rec(i, end);
    }
  }

  /// A particle's end into the thread's tallies (and its escape record); its weight came with it from its start.
  void record(std::uint64_t i, const ParticleEnd& end) {
    local.add_end(end.fate, end.t, end.collisions, end.weight, s_.scene.survival_dt, end.leak);
    if (s_.scene.escape_records) records_[i] = {end.t, end.s, end.collisions, end.fate, end.leak};
  }

  /// The kernel's context for particles [lo, hi) of `model`, f_c wired to the thread's tallies.
  template <class Put>
  SimdContext context(const Model<double>& model, std::uint64_t lo, std::uint64_t hi, bool weights, Put put) {
    SimdContext ctx{};
    ctx.model = &model;
    if (s_.table) ctx.table = &*s_.table;
    ctx.draw = s_.source;
    ctx.next = lo;
    ctx.hi = hi;
    ctx.record = put;
    ctx.escape_s = s_.scene.escape_records;
    ctx.kernel = &s_.kernel;
    ctx.weights = weights;  // lanes carry their weight to the tallies (and to a weighted f_c)
    if (s_.scene.collision_density) {
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
      std::optional<TableModel<double>> epoch_table;
      if (s_.table) epoch_table.emplace(*s_.table), epoch_table->t_max = stop;
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
        if (epoch_table) ctx.table = &*epoch_table;
        ctx.members = &starts_;
        simd_run(ks, ctx);
      } else if (epoch_table) {
        advance_each(*epoch_table, table_density_, members, weights, ends);
      } else {
        advance_each(epoch, density_, members, weights, ends);
      }
    }
  }

  /// The members one after the other on the scalar core, with f_c's observer (when the scene asks for f_c).
  template <class M, class Density>
  void advance_each(const M& epoch, Density& density, const std::vector<Member>& members,
                    const std::vector<double>& weights, std::vector<ParticleEnd>& ends) {
    for (std::size_t i = 0; i < members.size(); ++i) {
      Flight<double> f{members[i].ps, {}, 0};
      f.end.collisions = members[i].collisions;
      density.weight = weights[i];
      if (s_.scene.collision_density)
        while (advance(epoch, f, density)) {
        }
      else
        while (advance(epoch, f, none_)) {
        }
      ends[i] = f.end;
    }
  }

  const RunSetup<R>& s_;
  std::vector<EscapeRecord>& records_;
  DensityObserver<R> density_{};
  TableDensityObserver<R> table_density_{};
  NoCollisionObserver<R> none_;
  std::vector<std::uint64_t> cell_counts_;  ///< the vectorised engine's f_c, by time cell (DensityCells)
  std::vector<FixedSum> cell_sums_;         ///< and its weighted sums
  std::vector<simd::Start> starts_;         ///< a split run's members, as the kernel takes them
};

/// Blocks a GPU launch takes at most. A launch ends when its last particles have: those taken last run their whole
/// lives after the others are done (up to t_max), so a launch must hold many lives a device thread for that tail to
/// be a small part of it (docs/model.md, "The GPU engine"). The device's own draws with no escape records cost no
/// memory a particle: 2^16 blocks (2^28 particles, 10^3 lives a thread of an H100's 2.6*10^5). Draws made here, or
/// escape records, cost about 40 bytes a particle each way: 2048 blocks (2^23 particles). A split run's launches
/// take the members of 64 blocks' lines (2^18 lines) at a split time.
constexpr std::uint64_t kGpuLaunchBlocks = 65536;
constexpr std::uint64_t kGpuBatchBlocks = 2048;
constexpr std::uint64_t kGpuSplitBlocks = 64;

/// A GPU launch's draws, weights and escape records, kept from one launch to the next.
struct GpuBuffers {
  std::vector<InitialDraw> draws;
  std::vector<double> weights;
  std::vector<gpu::End> ends;
};

/// One launch of particles [lo, lo + count): the draws made here unless the device makes them (the uniform Birkhoff
/// scheme), on all threads, each by its id; the escape records, when kept, written in id order.
void launch_particles(const RunSetup<double>& setup, gpu::Device& device, Worker<double>& worker, std::uint64_t lo,
                      std::uint64_t count, GpuBuffers& buf) {
  const RunOptions& opt = setup.opt;
  const bool weighted = worker.local.weighted();
  gpu::Batch batch{opt.first_id + lo, count, nullptr, nullptr, 0, 0, nullptr};
  if (const InitialConditions* uniform = opt.draws ? nullptr : setup.sampler->uniform_birkhoff()) {
    batch.seed = uniform->seed(), batch.creation_window = uniform->creation_window();
  } else {
    buf.draws.resize(count);
    buf.weights.resize(weighted ? count : 0);
    const auto m = static_cast<std::int64_t>(count);
#pragma omp parallel for schedule(static)
    for (std::int64_t i = 0; i < m; ++i) {
      const auto k = static_cast<std::size_t>(i);
      buf.draws[k] = setup.source(lo + k);
      if (weighted) buf.weights[k] = setup.source.weight(buf.draws[k]);
    }
    batch.draws = buf.draws.data();
    if (weighted) batch.weights = buf.weights.data();
  }
  buf.ends.resize(setup.scene.escape_records ? count : 0);
  device.run(batch, buf.ends.empty() ? nullptr : buf.ends.data());
  if (!buf.ends.empty()) worker.record_ends(lo, count, buf.ends.data());
}

/// The GPU engine's lifecycle: the todo blocks in order, one launch for each run of consecutive blocks (at most
/// kGpuLaunchBlocks or kGpuBatchBlocks; for a split run, its lines' epochs for kGpuSplitBlocks), the tallies counted on
/// the device and taken into one Worker's at each merge, escape records written here in id order; progress after each
/// launch, a checkpoint every checkpoint_seconds, a stop between launches. The draws are the device's own for the
/// uniform Birkhoff scheme, else the sampler's, made here on all threads (each by its id: no order to keep).
void run_gpu(const RunSetup<double>& setup, RunResult& result, const IntervalSet& todo, std::uint64_t goal) {
  const RunOptions& opt = setup.opt;
  const std::uint64_t n = setup.scene.particles, total = todo.size();
  const DensityCells* cells = setup.scene.collision_density ? &setup.cells : nullptr;
  const bool split = setup.split_rule != nullptr;
  const gpu::Shape shape = gpu::Shape::of(result.tally, setup.scene.survival_dt, cells);
  gpu::Device device = setup.table ? gpu::Device(*setup.table, shape) : gpu::Device(setup.model, shape);
  GpuBuffers buffers;
  std::optional<Worker<double>> worker(std::in_place, setup, result.records);
  const auto merge = [&] {
    device.take(worker->local, worker->cell_counts(), worker->cell_sums());
    worker->flush();
    result.tally.merge(worker->local);
    worker.emplace(setup, result.records);
  };
  result.threads = 1;
  std::uint64_t done = particles_in(result.done, n);
  const bool device_draws = !opt.draws && setup.sampler->uniform_birkhoff() && !setup.scene.escape_records;
  const std::uint64_t most = opt.gpu_launch_blocks ? opt.gpu_launch_blocks
                             : split               ? kGpuSplitBlocks
                             : device_draws        ? kGpuLaunchBlocks
                                                   : kGpuBatchBlocks;
  auto deadline = epoch_deadline(opt.checkpoint_seconds);
  for (std::uint64_t at = 0; at < total;) {
    std::uint64_t end = at + 1;  // todo positions [at, end): consecutive blocks
    while (end < total && end - at < most && todo.nth(end) == todo.nth(end - 1) + 1) ++end;
    const std::uint64_t lo = todo.nth(at) * kBlockSize, hi = std::min(n, (todo.nth(end - 1) + 1) * kBlockSize);
    const std::uint64_t count = hi - lo;
    if (split) {
      std::vector<std::pair<std::uint64_t, std::uint64_t>> ranges;
      for (std::uint64_t b = lo; b < hi; b += kBlockSize) ranges.emplace_back(b, std::min(hi, b + kBlockSize));
      worker->run_device_lines(device, ranges);
    } else {
      launch_particles(setup, device, *worker, lo, count, buffers);
    }
    result.done.insert(todo.slice(at, end));
    at = end, done += count;
    if (opt.progress)
      opt.progress(done, goal, result.tally.collisions + worker->local.collisions + (split ? 0 : device.collisions()),
                   false);
    if (at < total && ((opt.stop && opt.stop->load()) || std::chrono::steady_clock::now() >= deadline)) {
      merge();
      if (opt.checkpoint) opt.checkpoint(result.tally, result.done, result.records);
      if (opt.stop && opt.stop->load()) {  // read after the checkpoint, which may ask for the stop (as the CPU's)
        result.complete = false;
        return;
      }
      deadline = epoch_deadline(opt.checkpoint_seconds);
    }
  }
  merge();
}

/// The batch lifecycle: set up, run epochs of blocks on all threads (each block taken once, in todo
/// order), merge the threads' exact tallies, checkpoint between epochs, check conservation.
template <class R>
RunResult run_tier(const RunPlan& plan, const RunOptions& opt) {
  const RunSetup<R> setup(plan, opt);
  const Scene& scene = plan.scene();
  RunResult result = setup.start();
  const IntervalSet todo = setup.todo();
  const std::uint64_t n = scene.particles, total = todo.size();
  const std::uint64_t goal = particles_in(result.done, n) + particles_in(todo, n);
  std::atomic<std::uint64_t> done{particles_in(result.done, n)}, collisions_done{result.tally.collisions};
  const int threads = plan.threads() > 0 ? plan.threads() : omp_get_max_threads();
  const auto t0 = std::chrono::steady_clock::now();
  if constexpr (std::is_same_v<R, double>)
    if (setup.engine == Engine::gpu) run_gpu(setup, result, todo, goal);
  // Epochs: threads take blocks in todo order from a shared counter until all are taken, a stop is
  // asked for, or the checkpoint time has come; then the tallies are merged and checkpointed.
  for (std::uint64_t at = 0; setup.engine != Engine::gpu;) {  // the blocks todo.nth(0 .. at) are done
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

RunResult run_ensemble(const RunPlan& plan, const RunOptions& options) {
  if (plan.scene().tier.automatic()) throw std::logic_error("run_ensemble: a tier of auto must be chosen first");
  return with_tier(plan.scene().tier, [&](auto type) -> RunResult {
    using R = typename decltype(type)::type;
    if constexpr (std::is_floating_point_v<R>)
      return run_tier<R>(plan, options);
    else
      throw std::logic_error("unreachable: not an ensemble tier");
  });
}

RunResult run_ensemble(const Scene& scene, const RunOptions& options) {
  return run_ensemble(plan_run(scene, options), options);
}

}  // namespace rotleak
