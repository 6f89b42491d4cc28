// Device: a backend (a CUDA device, or the host's emulation of one) and what both share -- the checks on a batch,
// and the weighted f_c's digits added into exact sums.
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "numeric/input.hpp"
#include "sim/gpu/gpu_backend.hpp"

namespace rotleak::gpu {

bool emulated() {
  const char* v = std::getenv("ROTLEAK_GPU_EMULATE");
  if (!v || !*v || std::string(v) == "0") return false;
  if (std::string(v) != "1")
    throw InputError("ROTLEAK_GPU_EMULATE", v, "1 (the GPU engine's kernel on this machine's cores), or 0 / unset");
  return true;
}

std::string unavailable() { return emulated() ? "" : cuda_unavailable(); }
std::string device_name() { return emulated() ? "the host's cores (ROTLEAK_GPU_EMULATE)" : cuda_device_name(); }

Device::Device(const Model<double>& model, const DensityCells* density, bool weighted)
    : impl_(emulated() ? host_backend(model, density, weighted) : cuda_backend(model, density, weighted)),
      weighted_(weighted && density),
      density_size_(density ? static_cast<std::size_t>(density->cells()) * static_cast<std::size_t>(density->bins)
                            : 0) {}
Device::Device(const TableModel<double>& model, const DensityCells* density, bool weighted)
    : impl_(emulated() ? host_backend(model, density, weighted) : cuda_backend(model, density, weighted)),
      weighted_(weighted && density),
      density_size_(density ? static_cast<std::size_t>(density->cells()) * static_cast<std::size_t>(density->bins)
                            : 0) {}
Device::~Device() = default;

void Device::run(const Batch& b, End* ends) {
  if (b.count == 0) return;
  if (b.weights)
    for (std::uint64_t i = 0; i < b.count; ++i)
      if (!(b.weights[i] >= 0 && b.weights[i] < 0x1p64))
        throw std::runtime_error("GPU engine: a particle's weight " + std::to_string(b.weights[i]) +
                                 " lies outside [0, 2^64), the weighted f_c's range on the device");
  impl_->run(b, ends);
  if (weighted_) {  // each digit word takes at most 2^40 additions below 2^24 (gpu_engine.hpp)
    std::uint64_t collisions = 0;
    for (std::uint64_t i = 0; i < b.count; ++i) collisions += ends[i].collisions;
    if (collisions >= (1ULL << 40))
      throw std::runtime_error("GPU engine: a launch of " + std::to_string(collisions) +
                               " collisions overflows the weighted f_c's digits (at most 2^40)");
  }
}

void Device::take_density(std::uint64_t* counts, FixedSum* sums) {
  if (density_size_ == 0) return;
  std::vector<unsigned long long> got(density_size_), digits(weighted_ ? density_size_ * kSumDigits : 0);
  impl_->take(got.data(), weighted_ ? digits.data() : nullptr);
  for (std::size_t k = 0; k < density_size_; ++k) counts[k] += got[k];
  if (!weighted_ || !sums) return;
  for (std::size_t k = 0; k < density_size_; ++k)
    for (int j = 0; j < kSumDigits; ++j)
      if (const unsigned long long v = digits[k * kSumDigits + static_cast<std::size_t>(j)])
        sums[k].add_bits(v, kLowestBit + static_cast<long>(kDigitBits) * j);
}

int Device::registers() const { return impl_->registers; }
int Device::blocks_per_multiprocessor() const { return impl_->blocks; }

}  // namespace rotleak::gpu
