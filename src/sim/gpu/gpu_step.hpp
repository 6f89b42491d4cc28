// One particle of a GPU launch, written once for the device's kernel (gpu_engine.cu) and for the host's emulation
// of it (gpu_host.cpp, ROTLEAK_GPU_EMULATE: the engine's host side tested where no device is): its draw, its life
// (sim/model/particle.hpp's run_particle), its end, and its f_c -- integer counts and the weights' exact digits,
// added by atomics whose order cannot matter.
#pragma once

#include <atomic>
#include <bit>
#include <cstddef>
#include <cstdint>

#include "geometry/formulas.hpp"
#include "numeric/device.hpp"
#include "sim/gpu/gpu_engine.hpp"
#include "sim/tally/density_bin.hpp"

namespace rotleak::gpu {

/// *at += v, atomically (a device's atomicAdd, the host's atomic_ref).
ROTLEAK_HD inline void add_count(unsigned long long* at, unsigned long long v) {
#ifdef __CUDA_ARCH__
  atomicAdd(at, v);
#else
  std::atomic_ref<unsigned long long>(*at).fetch_add(v, std::memory_order_relaxed);
#endif
}

/// w (in [2^-1074, 2^64)) added exactly to the digits of one weighted f_c sum (kDigitBits each, gpu_engine.hpp):
/// w = m 2^q with m an integer below 2^53; m shifted to its place spans four digits at most.
ROTLEAK_HD inline void add_weight(unsigned long long* digits, double w) {
  const auto bits = std::bit_cast<unsigned long long>(w);
  const int biased = static_cast<int>((bits >> 52) & 0x7ff);
  const unsigned long long m = (bits & ((1ULL << 52) - 1)) | (biased != 0 ? 1ULL << 52 : 0);
  const int q = (biased != 0 ? biased : 1) - 1075 - kLowestBit;  // m's lowest bit, counted from kLowestBit
  const int j = q / kDigitBits, shift = q % kDigitBits;
  const unsigned __int128 v = static_cast<unsigned __int128>(m) << shift;
  constexpr unsigned long long mask = (1ULL << kDigitBits) - 1;
  for (int d = 0; d < 4; ++d) {
    const auto part = static_cast<unsigned long long>(v >> (d * kDigitBits)) & mask;
    if (part != 0) add_count(digits + j + d, part);
  }
}

ROTLEAK_HD inline int bin_of(const Model<double>& m, Piece p, const Vec2<double>& q, int bins) {
  return density_bin_of(m.stadium, p, q, bins);
}
ROTLEAK_HD inline int bin_of(const TableModel<double>& m, int k, const Vec2<double>& q, int bins) {
  return density_bin_of(m.table, k, q, bins);
}

/// f_c in a launch: a collision counted once, in its time cell, when a window holds that cell (DensityCells);
/// with the particle's weight added too when `sums` is set.
template <class M>
struct CellObserver {
  static constexpr bool active = true;
  const M* model;
  const DensityCells* cells;
  unsigned long long* counts;
  unsigned long long* sums;  ///< kSumDigits a (cell, bin), or null
  double weight = 1;

  template <class P>
  ROTLEAK_HD void operator()(P piece, const Vec2<double>& q, const double& t) {
    const int c = static_cast<int>(formula::time_cell(t, cells->from, cells->to, cells->n_windows));
    if (cells->windows[c] == 0) return;
    const int b = bin_of(*model, piece, q, cells->bins);
    const std::size_t k =
        static_cast<std::size_t>(c) * static_cast<std::size_t>(cells->bins) + static_cast<std::size_t>(b);
    add_count(counts + k, 1ULL);
    if (sums) add_weight(sums + k * kSumDigits, weight);
  }
};

/// Where a launch's particles come from and where their ends and f_c go (device memory on a device).
struct LaunchData {
  const InitialDraw* draws;  ///< null: the uniform Birkhoff draws of Batch's seed and creation window
  const double* weights;     ///< null: weight 1
  End* ends;
  const DensityCells* cells;   ///< null: no f_c
  unsigned long long* counts;  ///< cells x bins
  unsigned long long* sums;    ///< weighted f_c: kSumDigits a (cell, bin), or null
};

/// Particle i of the batch: its draw, its life, its end into ends[i], its collisions into f_c.
template <class M>
ROTLEAK_HD void run_one(const M& model, const Batch& b, const LaunchData& d, std::uint64_t i) {
  const InitialDraw draw =
      d.draws ? d.draws[i] : InitialConditions::birkhoff_draw(b.seed, b.creation_window, b.first + i);
  ParticleEnd e;
  if (d.cells) {
    CellObserver<M> observe{&model, d.cells, d.counts, d.sums, d.weights ? d.weights[i] : 1.0};
    e = run_particle(model, initial_state(model, draw), observe);
  } else {
    NoCollisionObserver<double> observe;
    e = run_particle(model, initial_state(model, draw), observe);
  }
  d.ends[i] = End{e.t, e.s, e.collisions, static_cast<std::int32_t>(e.fate), static_cast<std::int32_t>(e.leak)};
}

}  // namespace rotleak::gpu
