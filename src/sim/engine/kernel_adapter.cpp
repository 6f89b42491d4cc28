#include "sim/engine/kernel_adapter.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include "leak/leak_formulas.hpp"

namespace rotleak {

namespace {

/// Can the moving leak touch an arc for some t in [0, t_max]? Its centre start + omega t sweeps an interval of
/// half length |omega| t_max / 2 about start + omega t_max / 2, and touches arc k within the leak's reach[k] of the
/// arc's middle mid[k]; 1e-9 covers this double arithmetic's roundings and the rough phase's bound many times over.
bool arcs_reachable(const simd::KernelScene& s) {
  const simd::StadiumLeak& l = s.leak;
  if (!l.by_s) return false;
  const double sweep = (std::abs(l.omega_hi) + std::abs(l.omega_lo)) * s.t_max / 2;
  if (!(sweep < 0.5)) return true;
  const double centre = l.start + l.omega_hi * s.t_max / 2;
  for (int k = 1; k <= 3; k += 2)
    if (std::abs(formula::circular_offset(l.mid[k], centre)) <= l.reach[k] + sweep + 1e-9) return true;
  return false;
}

}  // namespace

/// The vectorised kernel's view of a double model.
simd::KernelScene simd_scene(const Model<double>& m) {
  simd::KernelScene s{};
  const Stadium<double>& st = m.stadium;
  s.r = st.r();
  s.half_d = st.half_d();
  s.t_max = m.t_max;
  s.L = st.perimeter();
  s.inv_L = st.inv_perimeter();  // the core's own, rounded once from 1 / L (1 / fl(L) differs by an ulp for d = 1)
  s.r_over_L = st.r_over_perimeter();
  s.L_over_r = st.L_over_r();
  s.pi = st.pi();
  for (int k = 0; k < 4; ++k) s.junction[k] = st.junction(k);
  s.leak = m.leak.view();
  for (int k = 0; k < 4; ++k) s.leak_piece[k] = m.leak.pieces()[k];
  s.arcs_reachable = arcs_reachable(s);
  s.margin = 1e-12;
  // the rough phase pays only where its bound leaves few lanes to the exact one (and far from s's wrap at 1/2)
  const double bound = formula::rough_phase_bound(s.leak.omega_hi, s.leak.omega_lo, s.t_max);
  const double hw = s.leak.half_width;
  s.phase_bound = s.leak.by_s && hw <= 0.25 && bound <= hw / 64 ? bound : 0;
  s.density_windows = 0;
  s.bins = 1;
  // a jump costs a few hundred ns, about 40 vectorised bounces: hand over only long phases
  s.handoff_bounces = m.fast_forward ? 128 : 0;
  return s;
}

void kernel_table(const TableModel<double>& m, simd::KernelTable& out) {
  const Table<double>& t = m.table;
  out = {};
  out.pieces = t.pieces(), out.loops = t.loops(), out.leaks = m.leaks.size();
  for (int k = 0; k < t.pieces(); ++k) out.piece[k] = t.piece(k);
  for (int l = 0; l < t.loops(); ++l) {
    out.loop_first[l] = t.loop_first(l), out.loop_count[l] = t.loop_count(l);
    out.inv_length[l] = t.inv_loop_length(l), out.loop_length[l] = t.loop_length(l);
    out.loop_offset[l] = t.loop_offset(l);
  }
  out.perimeter = t.perimeter(), out.slack = t.slack(), out.two_pi = t.two_pi();
  for (int j = 0; j < m.leaks.size(); ++j) out.leak[j] = m.leaks[j];
}

simd::KernelScene simd_scene(const TableModel<double>& m, const simd::KernelTable& table) {
  simd::KernelScene s{};
  s.t_max = m.t_max;
  s.table = &table;
  s.density_windows = 0;
  s.bins = 1;
  return s;
}

DensityCells scene_density_cells(const Scene& scene) {
  if (!scene.collision_density) return {};
  const auto& windows = scene.collision_density->windows;
  double from[simd::kMaxDensityWindows], to[simd::kMaxDensityWindows];
  const int n = static_cast<int>(windows.size());
  for (int w = 0; w < n; ++w)
    from[w] = windows[static_cast<std::size_t>(w)].from, to[w] = windows[static_cast<std::size_t>(w)].to;
  return DensityCells::of(scene.collision_density->bins, n, from, to);
}

DensityCells simd_density(simd::KernelScene& s, const Scene& scene) {
  if (!scene.collision_density) return {};
  const DensityCells cells = scene_density_cells(scene);
  set_density_windows(s, cells.n_windows, cells.from, cells.to);
  s.bins = cells.bins;
  return cells;
}

void set_density_windows(simd::KernelScene& s, int n, const double* from, const double* to) {
  s.density_windows = n;
  s.n_cell_from = s.n_cell_to = 0;
  s.cell_base = 0;
  for (int w = 0; w < n; ++w) {
    s.win_from[w] = from[w], s.win_to[w] = to[w];
    s.win_span_from = w == 0 ? from[w] : std::min(s.win_span_from, from[w]);
    s.win_span_to = w == 0 ? to[w] : std::max(s.win_span_to, to[w]);
  }
  // formula::time_cell counts from[w] when t >= from[w] and to[w] when t > to[w]; for t in the span a from
  // at its start always counts and a to at its end never does (no to lies before the span's start)
  for (int w = 0; w < n; ++w) {
    if (from[w] <= s.win_span_from)
      s.cell_base += 1;
    else
      s.cell_from[s.n_cell_from++] = from[w];
    if (to[w] < s.win_span_to) s.cell_to[s.n_cell_to++] = to[w];
  }
}

namespace {

/// f_c's counted collisions of a weighted run (or a split run's epoch) into the context's counts and sums.
void density_hits(SimdContext& ctx, const simd::DensityHit* hits, std::size_t n) {
  const std::uint32_t bins = static_cast<std::uint32_t>(ctx.cells->bins);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t cell = hits[i].cell;
    if (!ctx.cells->windows[cell]) continue;  // a gap between windows
    const std::uint32_t k = cell * bins + hits[i].bin;
    ++ctx.density[k];
    if (ctx.density_w) ctx.density_w[k].add(hits[i].weight);
  }
}

/// The next starts into `starts`: the fast-forward's returns first, then (while fewer than kStartBatch wait) the
/// next kStartBatch of the context's members or draws. Start::id is the particle's index in [0, hi).
void more_starts(SimdContext& ctx, std::vector<simd::Start>& starts) {
  starts.insert(starts.end(), ctx.resume.rbegin(), ctx.resume.rend());
  ctx.resume.clear();
  if (starts.size() >= kStartBatch || ctx.next >= ctx.hi) return;
  const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(kStartBatch, ctx.hi - ctx.next));
  const std::size_t at = starts.size();
  starts.resize(at + n);
  simd::Start* out = starts.data() + at;
  if (ctx.members) {
    std::copy_n(ctx.members->begin() + static_cast<std::ptrdiff_t>(ctx.next), n, out);
  } else if (ctx.table) {  // a table's starts: the scalar core's initial_state, one by one
    for (std::size_t i = 0; i < n; ++i) {
      const InitialDraw d = ctx.draw(ctx.next + i);
      const ParticleState<double> ps = initial_state(ctx.table->table, d);
      out[i] = {ps.q.x, ps.q.y, ps.v.x, ps.v.y, ps.t, 0, ctx.weights ? ctx.draw.weight(d) : 1.0};
    }
  } else {
    draw_starts(ctx.draw, *ctx.kernel, ctx.weights, ctx.next, n, out);
  }
  for (std::size_t i = 0; i < n; ++i) out[i].id = ctx.next + i;
  ctx.next += n;
}

/// A lane's end: a handed-back lane is fast-forwarded and queued again (or recorded, if it ended in the jump), an
/// ended one recorded.
void finish(SimdContext& ctx, const simd::End& e) {
  if (e.fate == LaneEnd::handed_back) {  // handed back at the start of a bouncing-ball phase: jump it exactly
    Flight<double> f{{{e.qx, e.qy}, {e.vx, e.vy}, e.t}, {}, 0};
    f.end.collisions = e.collisions;
    const double weight = e.weight;
    f.end.weight = weight;
    if (ctx.observer) ctx.observer->weight = weight;
    if (fast_forward(*ctx.model, f, ctx.observer)) {  // a null observer sees nothing
      ctx.resume.push_back({f.ps.q.x, f.ps.q.y, f.ps.v.x, f.ps.v.y, f.ps.t, f.end.collisions, weight, e.id});
    } else {
      ctx.record(e.id, f.end);
    }
    return;
  }
  ParticleEnd end;
  end.weight = e.weight;
  end.fate = static_cast<Fate>(e.fate);
  end.t = e.t;
  end.collisions = e.collisions;
  if (end.fate == Fate::survived) {
    end.t = ctx.table ? ctx.table->t_max : ctx.model->t_max;
    end.last = {{e.qx, e.qy}, {e.vx, e.vy}, e.t};
  }
  if (end.fate == Fate::escaped) {
    end.leak = e.leak;
    if (ctx.escape_s)
      end.s = ctx.table ? ctx.table->table.s_of(e.piece, {e.qx, e.qy})
                        : ctx.model->stadium.s_of(static_cast<Piece>(e.piece), {e.qx, e.qy});
  }
  ctx.record(e.id, end);
}

/// How many ends and counted collisions the kernel may leave between two looks.
constexpr std::size_t kEndBuffer = 256, kHitBuffer = 4096;
static_assert(kEndBuffer >= simd::kMaxPackLanes && kHitBuffer >= simd::kMaxPackLanes);

}  // namespace

void simd_run(const simd::KernelScene& scene, SimdContext& ctx) {
  auto state = std::make_unique<simd::KernelState>();
  std::vector<simd::Start> starts;
  std::vector<simd::End> ends(kEndBuffer);
  std::vector<simd::DensityHit> hits(ctx.cells && !ctx.kernel_counts ? kHitBuffer : 0);
  simd::Exchange x;
  x.ends = ends.data(), x.end_capacity = ends.size();
  x.hits = hits.empty() ? nullptr : hits.data(), x.hit_capacity = hits.size();
  x.counts = ctx.kernel_counts ? ctx.density : nullptr;
  for (;;) {
    more_starts(ctx, starts);
    x.starts = starts.data(), x.n_starts = starts.size(), x.taken = 0, x.n_ends = 0, x.n_hits = 0;
    x.last = ctx.next >= ctx.hi;
    const simd::Pause why = simd::run(scene, *state, x);
    starts.erase(starts.begin(), starts.begin() + static_cast<std::ptrdiff_t>(x.taken));
    for (std::size_t i = 0; i < x.n_ends; ++i) finish(ctx, ends[i]);
    if (x.n_hits) density_hits(ctx, hits.data(), x.n_hits);
    if (why == simd::Pause::idle && starts.empty() && ctx.resume.empty() && ctx.next >= ctx.hi) return;
  }
}

void draw_starts(const DrawSource& draw, const simd::KernelScene& kernel, bool weights, std::uint64_t first,
                 std::size_t n, simd::Start* out) {
  if (const InitialConditions* ic = draw.draws ? nullptr : draw.sampler->uniform_birkhoff()) {
    simd::uniform_starts(kernel, ic->seed(), ic->creation_window(), draw.first_id + first, n, out);
    return;
  }
  // the draws (Philox, the sampler), then every Birkhoff start's state and every flow start's direction in
  // one vectorised call each
  double s[kStartBatch], p[kStartBatch], u[kStartBatch], vx[kStartBatch], vy[kStartBatch];
  std::size_t at[kStartBatch], flow[kStartBatch];
  simd::Start states[kStartBatch];
  for (std::size_t lo = 0; lo < n; lo += kStartBatch) {
    const std::size_t k = std::min(kStartBatch, n - lo);
    std::size_t nb = 0, nf = 0;
    for (std::size_t i = 0; i < k; ++i) {
      const InitialDraw d = draw(first + lo + i);
      simd::Start& o = out[lo + i];
      o = {d.x, d.y, 0, 0, d.tau, 0, weights ? draw.weight(d) : 1.0};
      if (d.flow) {
        u[nf] = d.u, flow[nf++] = lo + i;
      } else {
        s[nb] = d.s, p[nb] = d.p, at[nb++] = lo + i;
      }
    }
    if (nb) simd::birkhoff_states(kernel, s, p, states, nb);
    for (std::size_t j = 0; j < nb; ++j) {
      simd::Start& o = out[at[j]];
      o.qx = states[j].qx, o.qy = states[j].qy, o.vx = states[j].vx, o.vy = states[j].vy;
    }
    if (nf) simd::flow_directions(kernel, u, vx, vy, nf);
    for (std::size_t j = 0; j < nf; ++j) out[flow[j]].vx = vx[j], out[flow[j]].vy = vy[j];
  }
}

}  // namespace rotleak
