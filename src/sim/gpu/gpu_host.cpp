// The GPU engine's launches emulated on this machine's cores (ROTLEAK_GPU_EMULATE): each OpenMP thread a device
// thread running gpu_step.hpp's run_lane, taking the batch's particles from the same atomic counter, its ends and
// tallies added by atomics as on a device.
#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "sim/gpu/gpu_backend.hpp"
#include "sim/gpu/gpu_step.hpp"

namespace rotleak::gpu {

namespace {

template <class M>
class HostBackend final : public Device::Backend {
 public:
  HostBackend(const M& m, const Device::Layout& l, const Shape& s)
      : model_(m), layout_(l), dt_(s.dt), words_(l.words(), 0), digits_(l.sums() * kSumDigits, 0) {
    if (s.density) cells_ = *s.density;
  }

  void run(const Batch& b, End* ends, ParticleEnd* full) override {
    LaunchData d = launch_data(layout_, words_.data(), digits_.data(), dt_, &cells_);
    d.draws = b.draws, d.weights = b.weights, d.starts = b.starts, d.ends = ends, d.full = full;
    unsigned long long next = 0;
    d.next = &next;
#pragma omp parallel
    {
      if (d.cells)
        run_lane(model_, b, d, cell_observer(&model_, d));
      else
        run_lane(model_, b, d, NoCollisionObserver<double>{});
    }
  }

  std::uint64_t take_collisions() override { return std::exchange(words_[Device::Layout::kCollisions], 0ULL); }

  void take(unsigned long long* words, unsigned long long* digits) override {
    std::copy(words_.begin(), words_.end(), words);
    std::fill(words_.begin(), words_.end(), 0);
    std::copy(digits_.begin(), digits_.end(), digits);
    std::fill(digits_.begin(), digits_.end(), 0);
  }

  void set_t_max(double t_max) override { model_.t_max = t_max; }

 private:
  M model_;
  Device::Layout layout_;
  double dt_;
  DensityCells cells_{};
  std::vector<unsigned long long> words_, digits_;
};

}  // namespace

std::unique_ptr<Device::Backend> host_backend(const Model<double>& m, const Device::Layout& l, const Shape& s) {
  return std::make_unique<HostBackend<Model<double>>>(m, l, s);
}
std::unique_ptr<Device::Backend> host_backend(const TableModel<double>& m, const Device::Layout& l, const Shape& s) {
  return std::make_unique<HostBackend<TableModel<double>>>(m, l, s);
}

}  // namespace rotleak::gpu
