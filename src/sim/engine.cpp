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
#include "sim/particle.hpp"
#include "sim/population.hpp"
#include "sim/sampling.hpp"
#include "sim/simd_engine.hpp"

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
    levels = std::max(levels, o.levels);
    max_population = std::max(max_population, o.max_population);
    max_line = std::max(max_line, o.max_line);
  }
}

namespace {

/// f_c(s): counts collision positions in each requested time window.
template <class R>
struct DensityObserver {
  static constexpr bool active = true;
  const Stadium<R>* stadium;
  const std::vector<TimeWindow>* windows;
  int bins;
  std::uint64_t* counts;
  FixedSum* weighted_counts = nullptr;  ///< weighted runs: sums of the particle's weight
  double weight = 1;                    ///< of the particle in flight

  void operator()(Piece p, const Vec2<R>& q, const R& t) {
    const double tt = num_traits<R>::to_double(t);
    bool any = false;
    for (const auto& w : *windows) any |= (tt >= w.from && tt <= w.to);
    if (!any) return;
    const double s = num_traits<R>::to_double(stadium->s_of(p, q));
    int b = static_cast<int>(s * bins);
    if (b >= bins) b = bins - 1;
    if (b < 0) b = 0;
    for (std::size_t i = 0; i < windows->size(); ++i)
      if (tt >= (*windows)[i].from && tt <= (*windows)[i].to) {
        ++counts[i * static_cast<std::size_t>(bins) + b];
        if (weighted_counts) weighted_counts[i * static_cast<std::size_t>(bins) + b].add(weight);
      }
  }
};

/// The initial data of particle i of a run: the scene's draw of id first_id + i (by its sampling
/// scheme), or a given list (weight 1); and its weight.
struct DrawSource {
  const Sampler* sampler;
  std::uint64_t first_id;
  const std::vector<InitialDraw>* draws;
  InitialDraw operator()(std::uint64_t i) const { return draws ? (*draws)[i] : sampler->draw(first_id + i); }
  double weight(const InitialDraw& d) const { return draws ? 1.0 : sampler->weight(d); }
};

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

/// The vectorised kernel's view of a double model.
simd::Scene simd_scene(const Model<double>& m) {
  simd::Scene s{};
  const Stadium<double>& st = m.stadium;
  s.r = st.r();
  s.half_d = st.half_d();
  s.t_max = m.t_max;
  s.L = st.perimeter();
  s.inv_L = 1 / st.perimeter();
  s.r_over_L = st.r() / st.perimeter();
  s.pi = st.pi();
  for (int k = 0; k < 4; ++k) s.junction[k] = st.junction(k);
  s.rotating = m.leak.schedule().rotating();
  for (int p = 0; p < 4; ++p) {
    const auto& pw = m.leak.windows(static_cast<Piece>(p));
    s.n_windows[p] = pw.n;
    for (int w = 0; w < pw.n; ++w) {
      s.lo[p][w] = pw.w[w].lo;
      s.hi[p][w] = pw.w[w].hi;
      s.from_x[p][w] = pw.w[w].from.x;
      s.from_y[p][w] = pw.w[w].from.y;
      s.to_x[p][w] = pw.w[w].to.x;
      s.to_y[p][w] = pw.w[w].to.y;
    }
  }
  s.omega_hi = m.leak.schedule().omega_split().hi;
  s.omega_lo = m.leak.schedule().omega_split().lo;
  s.start = m.leak.schedule().start();
  s.half_width = m.leak.half_width();
  for (int k = 0; k < 4; ++k) {
    s.arc_mid[k] = m.leak.piece_mid(k);
    s.arc_reach[k] = m.leak.reach(k);
  }
  s.margin = 1e-12;
  s.density_windows = 0;
  s.bins = 1;
  // a jump costs a few hundred ns, about 40 vectorised bounces: hand over only long phases
  s.handoff_bounces = m.fast_forward ? 128 : 0;
  return s;
}

/// The f_c observer's windows and bins for the kernel.
void simd_density(simd::Scene& s, const Scene& scene) {
  if (!scene.collision_density) return;
  s.density_windows = static_cast<int>(scene.collision_density->windows.size());
  s.bins = scene.collision_density->bins;
  for (int w = 0; w < s.density_windows; ++w) {
    s.win_from[w] = scene.collision_density->windows[static_cast<std::size_t>(w)].from;
    s.win_to[w] = scene.collision_density->windows[static_cast<std::size_t>(w)].to;
    s.win_span_from = w == 0 ? s.win_from[w] : std::min(s.win_span_from, s.win_from[w]);
    s.win_span_to = w == 0 ? s.win_to[w] : std::max(s.win_span_to, s.win_to[w]);
  }
}

/// The kernel's f_c counts by time cell (simd::DensityHit), folded into the windows' counts.
struct DensityCells {
  int bins = 0;
  unsigned windows[2 * simd::kMaxDensityWindows + 1] = {};  ///< bit w: window w holds the cell's times

  /// counts[c bins + b] into density[w bins + b] for each window w of cell c; counts zeroed
  void fold(std::uint64_t* counts, std::uint64_t* density, std::size_t cells) const {
    const auto nb = static_cast<std::size_t>(bins);
    for (std::size_t c = 0; c < cells; ++c)
      for (unsigned m = windows[c]; m; m &= m - 1) {
        const auto w = static_cast<std::size_t>(__builtin_ctz(m));
        for (std::size_t b = 0; b < nb; ++b) density[w * nb + b] += counts[c * nb + b];
      }
    std::fill(counts, counts + cells * nb, 0);
  }
};

struct SimdContext {
  const Model<double>* model;
  DrawSource draw;
  std::uint64_t next, hi;
  std::function<void(std::uint64_t, const ParticleEnd&)> record;
  std::vector<std::pair<std::uint64_t, simd::Start>> resume;  ///< back from the fast-forward
  bool weights = false;                                       ///< lanes carry their weight (weighted f_c)
  std::uint64_t* density = nullptr;                           ///< this thread's f_c counts
  FixedSum* density_w = nullptr;                              ///< and weighted sums
  DensityObserver<double>* observer = nullptr;                ///< f_c of the fast-forwarded bounces
  const DensityCells* cells = nullptr;                        ///< the kernel's time cells
  /// A split run's members: particle i (next .. hi) starts from (*members)[i] instead of a draw
  const std::vector<simd::Start>* members = nullptr;
};

bool simd_escape(void* c, int piece, double x, double y, double t) {
  return static_cast<SimdContext*>(c)->model->leak.hit(static_cast<Piece>(piece), {x, y}, t);
}

double simd_s_of(void* c, int piece, double x, double y) {
  return static_cast<SimdContext*>(c)->model->stadium.s_of(static_cast<Piece>(piece), {x, y});
}

void simd_density_hits(void* c, const simd::DensityHit* hits, int n) {
  auto* ctx = static_cast<SimdContext*>(c);
  const std::uint32_t bins = static_cast<std::uint32_t>(ctx->cells->bins);
  for (int i = 0; i < n; ++i) {
    const std::uint32_t cell = hits[i].index / bins, b = hits[i].index % bins;
    for (unsigned m = ctx->cells->windows[cell]; m; m &= m - 1) {
      const std::uint32_t k = static_cast<std::uint32_t>(__builtin_ctz(m)) * bins + b;
      ++ctx->density[k];
      if (ctx->density_w) ctx->density_w[k].add(hits[i].weight);
    }
  }
}

constexpr simd::Exact kSimdExact{simd_escape, simd_s_of, simd_density_hits};

bool simd_next(void* c, simd::Start* start, std::uint64_t* id) {
  auto* ctx = static_cast<SimdContext*>(c);
  if (!ctx->resume.empty()) {
    *id = ctx->resume.back().first;
    *start = ctx->resume.back().second;
    ctx->resume.pop_back();
    return true;
  }
  if (ctx->next >= ctx->hi) return false;
  *id = ctx->next++;
  if (ctx->members) {
    *start = (*ctx->members)[*id];
    return true;
  }
  const InitialDraw d = ctx->draw(*id);
  const ParticleState<double> ps = initial_state(ctx->model->stadium, d);
  *start = {ps.q.x, ps.q.y, ps.v.x, ps.v.y, ps.t, 0, ctx->weights ? ctx->draw.weight(d) : 1.0};
  return true;
}

void simd_finish(void* c, std::uint64_t id, const simd::End& e) {
  auto* ctx = static_cast<SimdContext*>(c);
  if (e.fate == LaneEnd::handed_back) {  // handed back at the start of a bouncing-ball phase: jump it exactly, then
                                         // give it back to a lane (or record it, if it ended in the jump)
    Flight<double> f{{{e.qx, e.qy}, {e.vx, e.vy}, e.t}, {}, 0};
    f.end.collisions = e.collisions;
    const double weight = e.weight;
    if (ctx->observer) ctx->observer->weight = weight;
    if (fast_forward(*ctx->model, f, ctx->observer)) {  // a null observer sees nothing
      ctx->resume.push_back(
          {id, {f.ps.q.x, f.ps.q.y, f.ps.v.x, f.ps.v.y, f.ps.t, static_cast<double>(f.end.collisions), weight}});
    } else {
      ctx->record(id, f.end);
    }
    return;
  }
  ParticleEnd end;
  end.fate = static_cast<Fate>(e.fate);
  end.t = e.t;
  end.collisions = e.collisions;
  if (end.fate == Fate::survived) {
    end.t = ctx->model->t_max;
    end.last = {{e.qx, e.qy}, {e.vx, e.vy}, e.t};
  }
  if (end.fate == Fate::escaped) end.s = ctx->model->stadium.s_of(static_cast<Piece>(e.piece), {e.qx, e.qy});
  ctx->record(id, end);
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

// With c(x) the cell of time x (non-decreasing in x), t >= from_w exactly when c(t) >= c(from_w)
// (below from_w, from_w's own edge is not passed), and t <= to_w exactly when c(t) <= c(to_w).
void density_cells(int windows, const double* from, const double* to, unsigned* cells) {
  const auto cell_of = [&](double x) {
    int c = 0;
    for (int v = 0; v < windows; ++v) c += (x >= from[v]) + (x > to[v]);
    return c;
  };
  for (int c = 0; c <= 2 * windows; ++c) {
    cells[c] = 0;
    for (int w = 0; w < windows; ++w)
      if (cell_of(from[w]) <= c && c <= cell_of(to[w])) cells[c] |= 1u << w;
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
