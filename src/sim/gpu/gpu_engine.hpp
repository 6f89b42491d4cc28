// The GPU engine (docs/model.md, "The GPU engine"): the double tier's collision step, sim/model/particle.hpp's
// advance on Model<double> or TableModel<double>, compiled by nvcc for the device from the same source (ROTLEAK_HD)
// with -fmad=false, each device thread running particle after particle. Its draws are the CPU's (the uniform Birkhoff
// draw made on the device by the same Philox, any other sampler's draws made on the host), and what it counts --
// the particles' ends, f_c -- it counts on the device in integers and exact fixed-point sums, added in any order:
// the run's files are the CPU engines' bytes. Only escape records and a split run's members come back one by one.
// This header holds no CUDA type: the engine (sim/engine) calls it in every build; a build without a CUDA
// compiler has gpu_none.cpp behind it, which says why at the first question.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sim/model/initial.hpp"
#include "sim/model/particle.hpp"
#include "sim/tally/density.hpp"
#include "sim/tally/tally.hpp"

namespace rotleak::gpu {

/// One particle's end as the device returns it when escape records are kept: ParticleEnd's fate, time, s,
/// collisions and leak.
struct End {
  double t = 0, s = 0;
  std::uint64_t collisions = 0;
  std::int32_t fate = 0, leak = 0;
};

/// A split run's member as an epoch's launch takes it: its state and its collisions so far.
struct Start {
  ParticleState<double> ps;
  std::uint64_t collisions = 0;
};

/// Exact sums on the device: each an exact fixed-point sum of doubles, as kSumDigits digits of kDigitBits bits
/// (digit j weighs 2^(kLowestBit + kDigitBits j)) held in 64-bit words that integer atomics add to in any order; the
/// 40 bits above a digit take the carries of 2^40 additions, and the device's words are drained into FixedSums on the
/// host before 2^39 (Device::run). Addends lie in [0, 2^128): weights below 2^64 and their squares.
inline constexpr int kDigitBits = 24;
inline constexpr int kLowestBit = -1080;  ///< at or below the smallest subnormal's bit, 2^-1074
inline constexpr int kSumDigits = (128 + 53 - kLowestBit) / kDigitBits + 2;

/// What the device counts of a run's particles, as Tally counts them: their ends (Tally::add_end: the fates, the
/// escapes by bin and by leak, the collisions, and for weighted particles the weighted estimator's sums of w and
/// w^2), and f_c in the time cells of `density` (a collision at t once, in bin b of cell formula::time_cell(t), when a
/// window holds that cell; with its weight too when weighted; DensityCells::fold gives the windows' counts).
struct Shape {
  const DensityCells* density = nullptr;  ///< null: no f_c
  bool weighted = false;                  ///< the particles carry weights (a sampling scheme's, or a split member's)
  std::size_t bins = 0;   ///< escape bins (Tally::escapes_per_bin); 0: the ends are the host's to book (split epochs)
  std::size_t leaks = 0;  ///< Tally::escapes_by_leak's leaks, 0 when it is not kept (one leak)
  double dt = 1;          ///< the escape bins' width (Scene::survival_dt)
  /// The Shape of a run's tally: its bins, leaks and estimator (counting or weighted; a split run's lines estimator
  /// books its ends on the host, so bins = 0 there).
  static Shape of(const Tally& t, double dt, const DensityCells* density);
};

/// A launch: particles [0, count). Each starts from starts[i] when `starts` is set (an epoch of a split run), else
/// from draws[i] when `draws` is set, else from InitialConditions::birkhoff_draw(seed, creation_window, first + i);
/// its weight is weights[i] when `weights` is set, else 1. Host memory.
struct Batch {
  std::uint64_t first = 0, count = 0;
  const InitialDraw* draws = nullptr;
  const double* weights = nullptr;
  std::uint64_t seed = 0;
  double creation_window = 0;
  const Start* starts = nullptr;
};

/// Whether ROTLEAK_GPU_EMULATE is set (to 1): the engine's launches then run their kernel's code on this machine's
/// cores (OpenMP threads as the device's threads), the same step, draws, ends and tallies: how the engine's host
/// side (batches, tallies, checkpoints, split epochs) is tested where no device is. Slow; never chosen by itself.
/// Any other value than 0 or 1 is an InputError naming ROTLEAK_GPU_EMULATE.
bool emulated();
/// "" when the GPU engine can run here (this build has it and a CUDA device is visible, or it is emulated); else
/// one line that says why not.
std::string unavailable();
/// The device this process runs on, in words (its name, multiprocessors, memory), or unavailable()'s line.
std::string device_name();
/// The CUDA devices this process sees (0 emulated or without CUDA).
int device_count();
/// Which of them this process's Devices run on from now (an MPI rank takes its node rank modulo device_count()).
void select_device(int index);

/// One model on the device, with its tallies: batches run on it one after another. Each device thread takes the
/// batch's next particle when its own ends (an atomic counter), so a warp's threads stay busy until the batch runs
/// out; which thread runs a particle changes nothing in its trajectory, and the tallies are integers and exact sums.
class Device {
 public:
  Device(const Model<double>& model, const Shape& shape);
  Device(const TableModel<double>& model, const Shape& shape);
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  /// Runs the batch's particles, blocking until done; their ends tallied on the device (Shape), and also written to
  /// ends[0 .. count) when `ends` is set (escape records; host memory), and whole, last state included, to
  /// full[0 .. count) when `full` is set (an epoch's members). Weights must lie in [0, 2^64).
  void run(const Batch& batch, End* ends = nullptr, ParticleEnd* full = nullptr);
  /// The particles' t_max from now (a split run's epochs end at each split time).
  void set_t_max(double t_max);
  /// The kernel whose registers are capped so that n blocks share a multiprocessor: 1 (the compiler's choice), 6 or
  /// 8; 0 the default. The bits are the same in each (bench_gpu times them); no effect emulated.
  void set_min_blocks(int n);
  /// Adds what the launches counted since the last take into t (collisions, fates, escapes by bin and leak, the
  /// weighted estimator's sums; none of it when Shape::bins is 0: the host books those ends) and f_c's counts by time
  /// cell into cell_counts (cells x bins), their weights' exact sums into cell_sums (weighted); zeroes them here.
  void take(Tally& t, std::uint64_t* cell_counts, FixedSum* cell_sums);
  /// Collisions the launches made since the last take.
  std::uint64_t collisions() const { return words_[Layout::kCollisions]; }
  /// Registers a thread of the last launch's kernel used, and its blocks resident on a multiprocessor (0 emulated).
  int registers() const;
  int blocks_per_multiprocessor() const;

  struct Backend;
  /// Where the words and sums lie in the device's buffers (gpu_step.hpp's LaunchData).
  /// Words: the collisions made, the stuck particles, the escapes by bin, by leak and bin, f_c's counts (the escaped
  /// are the bins' sum, the survivors the rest of the particles launched). Sums: w and w^2 of every end, of the
  /// escapes by bin (w, then w^2), f_c's weights.
  struct Layout {
    static constexpr std::size_t kCollisions = 0, kStuck = 1;
    std::size_t bins = 0, leaks = 0, fc = 0;  ///< escape bins, kept leaks, f_c's cells x bins
    bool weighted_ends = false, weighted_fc = false;
    std::size_t by_bin() const { return 2; }
    std::size_t by_leak() const { return by_bin() + bins; }
    std::size_t fc_word() const { return by_leak() + leaks * bins; }
    std::size_t words() const { return fc_word() + fc; }
    std::size_t fc_sum() const { return weighted_ends ? 2 + 2 * bins : 0; }
    std::size_t sums() const { return fc_sum() + (weighted_fc ? fc : 0); }
  };

 private:
  void drain();
  Layout layout_;
  std::unique_ptr<Backend> impl_;
  std::uint64_t pending_ = 0;         ///< additions the device's words took since they were last drained
  std::uint64_t particles_ = 0;       ///< launched since the last take
  std::vector<std::uint64_t> words_;  ///< drained, not yet taken: Layout's words
  std::vector<FixedSum> sums_;        ///< and sums
};

}  // namespace rotleak::gpu
