// The vectorised double engine: four (AVX2) or eight (AVX-512) particles per register, branch-free
// piece selection, lanes refilled from the id stream as particles end. Its translation units alone
// are compiled for those instruction sets and selected at run time; they see only the plain structs
// below (no shared inline code gets vector instructions) and talk to the caller through plain buffers
// (Exchange: the particles to start, the ended ones, f_c's counted collisions), never a callback: run() returns
// when a buffer needs the caller, and goes on where it stopped (KernelState).
#pragma once

#include <cstddef>
#include <cstdint>

#include "geometry/table_piece.hpp"
#include "leak/leak_window.hpp"
#include "sim/model/fate.hpp"

namespace rotleak::simd {

/// Time windows of the f_c observer the kernel takes (more: the scalar engine runs).
inline constexpr int kMaxDensityWindows = 8;

/// Pieces, loops and leaks a table the kernel runs may have (Table's and LeakList's own limits).
inline constexpr int kKernelPieces = kMaxTablePieces, kKernelLoops = kMaxTableLoops, kKernelLeaks = kMaxLeaks;

/// One leak of a table: LeakList<double>'s own plain numbers (leak/leak_window.hpp); the stadium's, Leak<double>'s.
using KernelLeak = LeakView<double>;
using StadiumLeak = LeakView<double, 4>;

/// A table and its leaks (Table<double>, LeakList<double>) in plain numbers: what the kernel's table step reads.
struct KernelTable {
  int pieces, loops, leaks;
  /// the pieces as Table<double> holds them (geometry/table_piece.hpp: plain numbers; the kernel calls only the
  /// header's templates on its own packs, never a member function)
  TablePiece<double> piece[kKernelPieces];
  int loop_first[kKernelLoops], loop_count[kKernelLoops];  ///< each loop's pieces
  double inv_length[kKernelLoops], loop_length[kKernelLoops], loop_offset[kKernelLoops];
  double perimeter, slack, two_pi;
  KernelLeak leak[kKernelLeaks];
};

/// Everything the kernel needs, in doubles, from a Model<double> (or a TableModel<double>: `table`).
struct KernelScene {
  double r, half_d, t_max;
  double L, inv_L, r_over_L, L_over_r, pi;
  double junction[4];
  /// The leak as the scalar core's Leak<double> holds it (leak/leak_window.hpp: its windows when stationary, its
  /// schedule, half width, each piece's mid and reach) and the four pieces (0 top, 1 right arc, 2 bottom, 3 left
  /// arc) as the leak test, leak_takes, reads them: the kernel's leak test is that template on its packs.
  StadiumLeak leak;
  TablePiece<double> leak_piece[4];
  /// false: the leak's centre never comes within reach of an arc for t in [0, t_max] (a slow leak on a straight
  /// edge), so the first look takes no arc lane's angle
  bool arcs_reachable;
  /// > 0: the moving leak's first look takes formula::rough_leak_phase, whose offsets lie within this bound of
  /// the exact phase's for t <= t_max (formula::rough_phase_bound), and the exact phase only for lanes within
  /// it of a decision's edge; 0: the exact phase at every hit (a bound too wide to be of use)
  double phase_bound;
  /// a vector atan2 (SLEEF, 3.5 ulp) may decide differently from libm's only this close to a leak
  /// end or a bin edge (in s); such lanes take the core's s (libm's atan2, lane by lane)
  double margin;
  // f_c: collisions with t in any window [win_from, win_to] counted in `bins` bins of s
  int density_windows;
  int bins;
  double win_from[kMaxDensityWindows], win_to[kMaxDensityWindows];
  double win_span_from, win_span_to;  ///< the least from and the greatest to
  /// The time cell of a counted collision (t in [win_span_from, win_span_to]): cell_base plus the cell_from
  /// edges with t >= edge and the cell_to edges with t > edge. It is formula::time_cell's count without the
  /// edges whose answer the span fixes (a from at the span's start is always passed, a to at its end never).
  /// set_density_windows (sim/engine/kernel_adapter.hpp) fills these from the windows.
  double cell_base;
  int n_cell_from, n_cell_to;
  double cell_from[kMaxDensityWindows], cell_to[kMaxDensityWindows];
  /// > 0: a lane whose straight-edge hit starts at least this many bounces between the straight
  /// edges is handed back (LaneEnd::handed_back) for the scalar fast-forward; 0: never.
  double handoff_bounces;
  /// true (a split run's epoch): a lane that passes t_max reports (End) the state of its last collision
  /// before it, where the member goes on; false: its state is not used
  bool keep_last = false;
  /// the kernel: 4 (AVX2) or 8 (AVX-512) lanes a register; lanes_available(lanes) must hold
  int lanes = 4;
  /// Any other table, or several leaks: the table and leaks every lane runs (the stadium's fields above but t_max,
  /// the f_c windows, bins and keep_last are then unused); null: the stadium.
  const KernelTable* table = nullptr;
};

struct Start {
  double qx, qy, vx, vy, t;
  std::uint64_t collisions = 0;  ///< already made (a particle coming back from the fast-forward)
  double weight = 1;             ///< the particle's sampling weight (for the weighted f_c)
  std::uint64_t id = 0;          ///< the caller's name for the particle, given back in End::id
};

/// One counted collision of the weighted f_c observer: its time cell, its bin and its weight. The time
/// cell of t is the number of window edges it has passed, counting from_w when t >= from_w and to_w
/// when t > to_w: 0 .. 2 density_windows (formula::time_cell); it fixes the set of windows that hold t
/// (density_cells), so the kernel counts each collision once and the caller adds the cell to each of
/// its windows (DensityCells::fold).
struct DensityHit {
  std::uint32_t cell, bin;
  double weight;
};

struct End {
  LaneEnd fate;  ///< a Fate, or handed back mid-flight (the state below)
  /// the lane's state: where it ended (escaped, stuck, handed back); survived with KernelScene::keep_last,
  /// at its last collision before t_max, from which the flight that passes t_max starts
  double t, qx, qy, vx, vy;
  double weight;  ///< Start::weight, travelling with the lane
  int piece;
  int leak = 0;  ///< the leak it escaped through (a table's list; 0 on the stadium)
  std::uint64_t collisions;
  std::uint64_t id;  ///< Start::id
};

/// What the caller and the kernel exchange in one call of run(): plain buffers the caller owns. The kernel takes
/// starts in order (from `taken` on), appends the ended lanes to `ends` and, in a weighted f_c, the counted
/// collisions to `hits`; with `counts` (an unweighted f_c: the thread's counts by time cell, indexed
/// cell * bins + bin) it increments the counts itself. A call returns before a buffer could overflow: a step
/// ends at most one particle and counts at most one collision a lane, so `ends` and `hits` hold at least
/// kMaxPackLanes.
struct Exchange {
  const Start* starts = nullptr;
  std::size_t n_starts = 0, taken = 0;
  /// no particle will follow these but what the caller makes of the ends (a hand-back's return): a lane without a
  /// start is parked, not waited for
  bool last = false;
  End* ends = nullptr;
  std::size_t end_capacity = 0, n_ends = 0;
  DensityHit* hits = nullptr;
  std::size_t hit_capacity = 0, n_hits = 0;
  std::uint64_t* counts = nullptr;
};

/// Why run() returned: a lane wants a start (and `last` is not set), `ends` or `hits` is nearly full, or every
/// lane is idle (no particle left in the kernel).
enum class Pause { starts, ends, hits, idle };

/// The most lanes a pack of any kernel holds.
inline constexpr int kMaxPackLanes = 64;
/// The lanes between calls of run(): the pack of the kernel that ran them, as that kernel lays it out. One state
/// serves one scene and one kernel width from its first call to its last (Pause::idle with nothing left to start).
struct KernelState {
  alignas(64) unsigned char pack[16384];
  bool started = false;
};

/// True when this CPU has AVX2 and FMA.
bool available();

/// The widest kernel this CPU runs: 8 (AVX-512F/DQ), 4 (AVX2+FMA) or 0 (none).
int widest_lanes();

/// True when this CPU runs the kernel of `lanes` (4 or 8) lanes a register.
bool lanes_available(int lanes);

/// The kernel's rough s of an arc point (the first look of the moving leak and of f_c), for its test: out[i] for
/// (ay[i], ax[i]) at distance r from the arc's centre (formula::arc_angle_y, arc_angle_x) on an arc that starts
/// at s = 0, with r / L = r_over_L (1: the angle itself), any n, by the kernel of `lanes` lanes; requires
/// lanes_available(lanes).
void rough_arc_s(int lanes, double r, double r_over_L, const double* ay, const double* ax, double* out, std::size_t n);

/// The kernel's f_c time cell (DensityHit) of each t[i] in [S.win_span_from, S.win_span_to] (a counted
/// collision's), for its test: out[i], by the kernel of S.lanes lanes over S's density windows; requires
/// lanes_available(S.lanes).
void time_cells(const KernelScene& S, const double* t, double* out, std::size_t n);

/// A boundary point for probe(): on piece `piece` (0 top, 1 right arc, 2 bottom, 3 left arc) at (x, y), at time t.
struct Probe {
  int piece;
  double x, y, t;
};
struct ProbeResult {
  double bin;    ///< f_c's bin floor(s S.bins), from the kernel's s
  bool in_leak;  ///< the kernel's leak test (the moving one when S.leak.by_s)
};
/// The kernel's own decisions at given collision points, for the ulp-edge probe test: each point's f_c bin and
/// whether it is in the leak, by the kernel of S.lanes lanes, computed as run() computes them (the same
/// functions); requires lanes_available(S.lanes).
void probe(const KernelScene& S, const Probe* points, ProbeResult* out, std::size_t n);

/// Initial states from their draws, vectorised, by the kernel of S.lanes lanes (requires lanes_available):
/// - birkhoff_states: out[i]'s position and velocity of Birkhoff (s[i], p[i]), Stadium<double>::at and velocity;
/// - flow_directions: a flow start's direction (cos 2 pi u[i], sin 2 pi u[i]) in vx[i], vy[i].
/// The same formulas as the scalar core's (geometry/formulas.hpp; an angle's sine and cosine by
/// numeric/sin_cos.hpp), so the same bits.
void birkhoff_states(const KernelScene& S, const double* s, const double* p, Start* out, std::size_t n);
void flow_directions(const KernelScene& S, const double* u, double* vx, double* vy, std::size_t n);
/// The uniform Birkhoff starts of particles first .. first + n - 1 of a scene with this seed and creation window,
/// draws and states together (InitialConditions::draw's Philox4x64-10 words, then birkhoff_states), vectorised:
/// out[i]'s position, velocity and creation time, the scalar core's bits.
void uniform_starts(const KernelScene& S, std::uint64_t seed, double window, std::uint64_t first, std::size_t n,
                    Start* out);

/// Runs the particles of `x` (and those `state` still holds) by the kernel of scene.lanes until a buffer needs the
/// caller (Pause); the next call with the same state goes on where this one stopped. Requires
/// lanes_available(scene.lanes).
Pause run(const KernelScene& scene, KernelState& state, Exchange& x);

/// The ceiling of the kernel's physics, for bench_scale: one pack of S.lanes-wide registers flying
/// `steps` collisions from `starts` (a pack's worth, KernelScene::lanes times the kernel's registers per
/// pack, see pack_lanes) through the same next hit and reflection as run(), with no clock, leak, fate
/// or refill. Returns the sum of the flight times (so that nothing is left out).
double flights_only(const KernelScene& S, const Start* starts, std::uint64_t steps);
/// Lanes of one pack of the kernel of `lanes` lanes a register.
int pack_lanes(int lanes);

}  // namespace rotleak::simd
