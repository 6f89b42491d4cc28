// The vectorised kernel's adapter: the scene in the kernel's plain structs, the context a block of
// particles (or a split run's members) runs in, and the loop that feeds the kernel its starts and takes
// its ends and f_c counts through plain buffers (simd::Exchange). The f_c observer the scalar engine and
// the kernel's fast-forward hand-off share is in sim/tally/density.hpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "sim/kernel/simd_engine.hpp"
#include "sim/model/particle.hpp"
#include "sim/model/sampling.hpp"
#include "sim/model/scene.hpp"
#include "sim/tally/density.hpp"

namespace rotleak {

/// The initial data of particle i of a run: the scene's draw of id first_id + i (by its sampling
/// scheme), or a given list (weight 1); and its weight.
struct DrawSource {
  const Sampler* sampler;
  std::uint64_t first_id;
  const std::vector<InitialDraw>* draws;
  InitialDraw operator()(std::uint64_t i) const { return draws ? (*draws)[i] : sampler->draw(first_id + i); }
  double weight(const InitialDraw& d) const { return draws ? 1.0 : sampler->weight(d); }
};

/// The vectorised kernel's view of a double model.
simd::KernelScene simd_scene(const Model<double>& m);
/// A table and its leaks in the kernel's plain numbers (every value TableModel<double> holds, copied).
void kernel_table(const TableModel<double>& m, simd::KernelTable& out);
/// The kernel's view of a double table model whose numbers `table` holds (kernel_table; it must outlive the scene).
simd::KernelScene simd_scene(const TableModel<double>& m, const simd::KernelTable& table);

/// The scene's f_c windows and bins in the kernel's scene, and the time cells the kernel counts in, both
/// from the scene's one spec (observe.collision_density): the kernel's plain copy and the cells that
/// fold its counts into windows cannot disagree. Empty cells when the scene observes no f_c.
DensityCells simd_density(simd::KernelScene& s, const Scene& scene);
/// The scene's f_c time cells alone (empty when it observes no f_c): what the GPU engine counts in.
DensityCells scene_density_cells(const Scene& scene);

/// The kernel's f_c time windows [from[w], to[w]] (n of them, at most simd::kMaxDensityWindows): the windows,
/// their span, and the edges a counted collision's time cell depends on (KernelScene::cell_base).
void set_density_windows(simd::KernelScene& s, int n, const double* from, const double* to);

struct SimdContext {
  const Model<double>* model;
  const TableModel<double>* table = nullptr;  ///< a table's run: its model (starts, escapes' s and leak)
  DrawSource draw;
  std::uint64_t next, hi;
  std::function<void(std::uint64_t, const ParticleEnd&)> record;
  std::vector<simd::Start> resume;   ///< back from the fast-forward (Start::id: the particle)
  bool weights = false;              ///< lanes carry their weight (a weighted run: its tallies and f_c)
  std::uint64_t* density = nullptr;  ///< this thread's f_c counts, by time cell
  FixedSum* density_w = nullptr;     ///< and weighted sums
  /// set (an unweighted f_c): the kernel adds its counted collisions to `density` itself (simd::Exchange::counts)
  bool kernel_counts = false;
  DensityObserver<double>* observer = nullptr;  ///< f_c of the fast-forwarded bounces
  const DensityCells* cells = nullptr;          ///< the kernel's time cells
  /// A split run's members: particle i (next .. hi) starts from (*members)[i] instead of a draw
  const std::vector<simd::Start>* members = nullptr;
  /// An escape's boundary coordinate (ParticleEnd::s: an atan2 on an arc) is wanted only for escape
  /// records; without them it is left at 0.
  bool escape_s = true;
  /// The kernel's scene, for its draws: initial states are drawn kStartBatch at a time, vectorised (draw_starts)
  const simd::KernelScene* kernel = nullptr;
};

/// How many particles a SimdContext draws at once.
inline constexpr std::size_t kStartBatch = 64;

/// The starts of particles first .. first + n - 1 of a draw source (their initial states; with their weights
/// when `weights`), made by `kernel`: a uniform Birkhoff source's draws and states together
/// (simd::uniform_starts), any other source's draws one by one and their states vectorised
/// (simd::birkhoff_states, simd::flow_directions). The scalar core's formulas, the same bits as initial_state.
void draw_starts(const DrawSource& draw, const simd::KernelScene& kernel, bool weights, std::uint64_t first,
                 std::size_t n, simd::Start* out);

/// Runs a context's particles [next, hi) through the kernel of `scene` (its state lives for this call): feeds it
/// their starts (the fast-forward's returns first, then its members in a split run, or the draws of its ids),
/// fast-forwards a handed-back lane and queues it again, records an ended one, and adds a weighted f_c's
/// counted collisions to the context's sums.
void simd_run(const simd::KernelScene& scene, SimdContext& ctx);

}  // namespace rotleak
