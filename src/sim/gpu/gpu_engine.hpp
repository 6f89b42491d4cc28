// The GPU engine (docs/model.md, "The GPU engine"): the double tier's collision step, sim/model/particle.hpp's
// run_particle on Model<double> or TableModel<double>, compiled by nvcc for the device from the same source
// (ROTLEAK_HD) with -fmad=false, one particle a thread. Its draws are the CPU's (the uniform Birkhoff draw made on
// the device by the same Philox, any other sampler's draws made on the host), its f_c counts are integers added
// in any order, and the host records the ends in id order: the run's files are the CPU engines' bytes.
// This header holds no CUDA type: the engine (sim/engine) calls it in every build; a build without a CUDA
// compiler has gpu_none.cpp behind it, which says why at the first question.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "sim/model/initial.hpp"
#include "sim/model/particle.hpp"
#include "sim/tally/density.hpp"

namespace rotleak::gpu {

/// One particle's end as the device returns it: ParticleEnd's fate, time, s, collisions and leak.
struct End {
  double t = 0, s = 0;
  std::uint64_t collisions = 0;
  std::int32_t fate = 0, leak = 0;
};

/// A weighted f_c on the device: each (cell, bin) an exact fixed-point sum of the weights counted there, as
/// kSumDigits digits of kDigitBits bits (digit j weighs 2^(kLowestBit + kDigitBits j)) held in 64-bit words that
/// integer atomics add to in any order; the 40 bits above a digit take the carries of 2^40 additions, far more
/// than a launch makes (Device::run refuses a launch of more collisions). Weights lie in [2^-1074, 2^64).
inline constexpr int kDigitBits = 24;
inline constexpr int kLowestBit = -1080;  ///< at or below the smallest subnormal's bit, 2^-1074
inline constexpr int kSumDigits = (64 + 53 - kLowestBit) / kDigitBits + 2;

/// A launch: particles [0, count) of ids first + i. Their draws come from `draws` (host memory, count of them)
/// when it is not null, else each is InitialConditions::birkhoff_draw(seed, creation_window, first + i); their
/// weights (what a weighted f_c adds) from `weights` (host memory) when not null, else 1.
struct Batch {
  std::uint64_t first = 0, count = 0;
  const InitialDraw* draws = nullptr;
  const double* weights = nullptr;
  std::uint64_t seed = 0;
  double creation_window = 0;
};

/// Whether ROTLEAK_GPU_EMULATE is set (to 1): the engine's launches then run their kernel's code on this machine's
/// cores (OpenMP), the same step, draws, ends and f_c digits: how the engine's host side (batches, records, f_c,
/// checkpoints) is tested where no device is. Slow; never chosen by itself. Any other value than 0 or 1 is an
/// InputError naming ROTLEAK_GPU_EMULATE.
bool emulated();
/// "" when the GPU engine can run here (this build has it and a CUDA device is visible, or it is emulated); else
/// one line that says why not.
std::string unavailable();
/// The device this process runs on, in words (its name, multiprocessors, memory), or unavailable()'s line.
std::string device_name();

/// One model on the device, with its buffers: batches run on it one after another.
class Device {
 public:
  /// The stadium's model or a table's, copied to the device; f_c counted in the time cells of `density` when it
  /// is not null: a collision at t once, in bin b of cell c = formula::time_cell(t), when a window holds that cell
  /// (density->windows[c] != 0), with the particle's weight too when `weighted`. DensityCells::fold then gives the
  /// windows' counts.
  Device(const Model<double>& model, const DensityCells* density, bool weighted);
  Device(const TableModel<double>& model, const DensityCells* density, bool weighted);
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  /// Runs the batch's particles; their ends into ends[0 .. count) (host memory). Blocks until done. Weights must
  /// lie in [0, 2^64) (the weighted f_c's digits) and a launch of a weighted f_c make fewer than 2^40 collisions.
  void run(const Batch& batch, End* ends);
  /// Adds the f_c counts made since the last call (cells x bins, DensityCells' order) into counts, and when weighted
  /// their weights' exact sums into sums; zeroes them on the device.
  void take_density(std::uint64_t* counts, FixedSum* sums);
  /// Registers a thread of the last launch's kernel used, and its blocks resident on a multiprocessor (0 emulated).
  int registers() const;
  int blocks_per_multiprocessor() const;

  struct Backend;

 private:
  std::unique_ptr<Backend> impl_;
  bool weighted_ = false;
  std::size_t density_size_ = 0;  ///< cells x bins
};

}  // namespace rotleak::gpu
