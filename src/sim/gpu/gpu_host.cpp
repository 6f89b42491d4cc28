// The GPU engine's launches emulated on this machine's cores (ROTLEAK_GPU_EMULATE): gpu_step.hpp's run_one for each
// particle of a batch, OpenMP over them, the f_c counts and digits added by atomics as on a device.
#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

#include "sim/gpu/gpu_backend.hpp"
#include "sim/gpu/gpu_step.hpp"

namespace rotleak::gpu {

namespace {

template <class M>
class HostBackend final : public Device::Backend {
 public:
  HostBackend(const M& m, const DensityCells* d, bool weighted) : model_(m) {
    if (!d) return;
    cells_ = *d;
    density_ = true;
    const std::size_t n = static_cast<std::size_t>(cells_.cells()) * static_cast<std::size_t>(cells_.bins);
    counts_.assign(n, 0);
    if (weighted) sums_.assign(n * kSumDigits, 0);
  }

  void run(const Batch& b, End* ends) override {
    const LaunchData data{
        b.draws, b.weights, ends, density_ ? &cells_ : nullptr, counts_.data(), sums_.empty() ? nullptr : sums_.data()};
    const auto n = static_cast<std::int64_t>(b.count);
#pragma omp parallel for schedule(dynamic, 256)
    for (std::int64_t i = 0; i < n; ++i) run_one(model_, b, data, static_cast<std::uint64_t>(i));
  }

  void take(unsigned long long* counts, unsigned long long* digits) override {
    std::copy(counts_.begin(), counts_.end(), counts);
    std::fill(counts_.begin(), counts_.end(), 0);
    if (!digits || sums_.empty()) return;
    std::copy(sums_.begin(), sums_.end(), digits);
    std::fill(sums_.begin(), sums_.end(), 0);
  }

 private:
  M model_;
  DensityCells cells_{};
  bool density_ = false;
  std::vector<unsigned long long> counts_, sums_;
};

}  // namespace

std::unique_ptr<Device::Backend> host_backend(const Model<double>& m, const DensityCells* d, bool weighted) {
  return std::make_unique<HostBackend<Model<double>>>(m, d, weighted);
}
std::unique_ptr<Device::Backend> host_backend(const TableModel<double>& m, const DensityCells* d, bool weighted) {
  return std::make_unique<HostBackend<TableModel<double>>>(m, d, weighted);
}

}  // namespace rotleak::gpu
