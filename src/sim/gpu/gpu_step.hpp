// A GPU launch's thread, written once for the device's kernel (gpu_engine.cu) and for the host's emulation of it
// (gpu_host.cpp, ROTLEAK_GPU_EMULATE: the engine's host side tested where no device is): it takes the batch's next
// particle (an atomic counter) whenever its own has ended, so the threads of a warp keep stepping until the batch
// runs out; each step is sim/model/particle.hpp's advance. A particle's end is counted where it ends -- fates,
// escapes by bin and leak, the weighted estimator's sums -- and its collisions into f_c, by integer atomics and exact
// fixed-point digits whose order cannot matter; the thread's own totals once, when it leaves.
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

/// *at += v, atomically (a device's atomicAdd, the host's atomic_ref); returns the value before.
ROTLEAK_HD inline unsigned long long add_count(unsigned long long* at, unsigned long long v) {
#ifdef __CUDA_ARCH__
  return atomicAdd(at, v);
#else
  return std::atomic_ref<unsigned long long>(*at).fetch_add(v, std::memory_order_relaxed);
#endif
}

/// w (0, or in [2^-1074, 2^128)) added exactly to the digits of one exact sum (kDigitBits each, gpu_engine.hpp):
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

/// Where a launch's particles come from and where their ends and tallies go (device memory on a device; Device::Layout
/// says where each part of the words and digits lies).
struct LaunchData {
  const InitialDraw* draws;        ///< null: the uniform Birkhoff draws of Batch's seed and creation window
  const double* weights;           ///< null: weight 1
  const Start* starts;             ///< an epoch's members, or null
  End* ends;                       ///< each particle's end (escape records), or null
  ParticleEnd* full;               ///< each member's whole end (an epoch), or null
  unsigned long long* next;        ///< the batch's next particle to take
  unsigned long long* collisions;  ///< collisions made
  unsigned long long* stuck;       ///< particles stuck (escaped and survived: Device::take)
  unsigned long long* by_bin;      ///< escapes by bin, or null: the ends are the host's to book (an epoch)
  unsigned long long* by_leak;     ///< escapes by leak and bin (leaks x bins), or null
  unsigned long long* end_sums;    ///< weighted: sums of w, w^2, escaped w by bin, escaped w^2 by bin; or null
  std::uint64_t bins;
  double dt;
  const DensityCells* cells;      ///< null: no f_c
  unsigned long long* fc_counts;  ///< cells x bins
  unsigned long long* fc_sums;    ///< weighted f_c: kSumDigits a (cell, bin), or null
};

/// The LaunchData of a layout over `words` and `digits` (where they lie), with `cells` (f_c's, or null).
inline LaunchData launch_data(const Device::Layout& l, unsigned long long* words, unsigned long long* digits, double dt,
                              const DensityCells* cells) {
  const auto sums = [&](std::size_t k) { return digits + k * static_cast<std::size_t>(kSumDigits); };
  LaunchData d{};
  d.collisions = words + Device::Layout::kCollisions;
  d.stuck = words + Device::Layout::kStuck;
  d.by_bin = l.bins ? words + l.by_bin() : nullptr;
  d.by_leak = l.bins && l.leaks ? words + l.by_leak() : nullptr;
  d.end_sums = l.weighted_ends ? sums(0) : nullptr;
  d.bins = l.bins;
  d.dt = dt;
  d.cells = l.fc ? cells : nullptr;
  d.fc_counts = words + l.fc_word();
  d.fc_sums = l.weighted_fc ? sums(l.fc_sum()) : nullptr;
  return d;
}

/// A thread's particle: its flight, its place in the batch, its collisions before the launch, its weight.
struct Lane {
  Flight<double> f;
  std::uint64_t i = 0, before = 0;
  double w = 1;
};

/// A thread's collisions, added to the launch's once when it leaves (an atomic add a particle to one word would
/// queue every thread on it). The fates need no such count: the escapes are the escape bins' sum, the stuck (rare)
/// are added where they happen, and the survivors are the rest of the particles launched (Device::take).
struct LaneCounts {
  unsigned long long collisions = 0;
};

/// The batch's next particle into `lane` (its start, weight, and the observer's weight); false when none is left.
template <class M, class Observer>
ROTLEAK_HD bool take_particle(const M& model, const Batch& b, const LaunchData& d, Lane& lane, Observer& observe) {
  const std::uint64_t i = add_count(d.next, 1ULL);
  if (i >= b.count) return false;
  lane.i = i;
  lane.f = Flight<double>{};
  lane.before = 0;
  if (d.starts) {
    lane.f.ps = d.starts[i].ps;
    lane.before = lane.f.end.collisions = d.starts[i].collisions;
  } else {
    lane.f.ps = initial_state(
        model, d.draws ? d.draws[i] : InitialConditions::birkhoff_draw(b.seed, b.creation_window, b.first + i));
  }
  lane.w = d.weights ? d.weights[i] : 1.0;
  if constexpr (Observer::active) observe.weight = lane.w;
  return true;
}

/// The lane's particle has ended: its end where it is kept, and counted as Tally::add_end counts it.
ROTLEAK_HD inline void finish(const LaunchData& d, const Lane& lane, LaneCounts& c) {
  const ParticleEnd& e = lane.f.end;
  c.collisions += e.collisions - lane.before;
  if (d.ends) d.ends[lane.i] = End{e.t, e.s, e.collisions, static_cast<std::int32_t>(e.fate), e.leak};
  if (d.full) d.full[lane.i] = e;
  if (!d.by_bin) return;
  std::size_t b = 0;
  if (e.fate == Fate::escaped) {
    b = static_cast<std::size_t>(e.t / d.dt);
    if (b > d.bins - 1) b = d.bins - 1;
    add_count(d.by_bin + b, 1ULL);
    if (d.by_leak) add_count(d.by_leak + static_cast<std::size_t>(e.leak) * d.bins + b, 1ULL);
  } else if (e.fate == Fate::stuck) {
    add_count(d.stuck, 1ULL);
  }
  if (!d.end_sums) return;
  constexpr std::size_t K = kSumDigits;
  const double w2 = lane.w * lane.w;
  add_weight(d.end_sums, lane.w);
  add_weight(d.end_sums + K, w2);
  if (e.fate != Fate::escaped) return;
  add_weight(d.end_sums + (2 + b) * K, lane.w);
  add_weight(d.end_sums + (2 + d.bins + b) * K, w2);
}

/// One thread of a launch: particle after particle of the batch until none is left, then its counts.
template <class M, class Observer>
ROTLEAK_HD void run_lane(const M& model, const Batch& b, const LaunchData& d, Observer observe) {
  Lane lane;
  LaneCounts c;
  for (bool live = take_particle(model, b, d, lane, observe); live;) {
    if (advance(model, lane.f, observe)) continue;
    finish(d, lane, c);
    live = take_particle(model, b, d, lane, observe);
  }
  if (c.collisions != 0) add_count(d.collisions, c.collisions);
}

/// f_c's observer of a launch (null cells: none).
template <class M>
ROTLEAK_HD CellObserver<M> cell_observer(const M* model, const LaunchData& d) {
  return CellObserver<M>{model, d.cells, d.fc_counts, d.fc_sums};
}

}  // namespace rotleak::gpu
