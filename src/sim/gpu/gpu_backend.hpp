// Where a GPU launch runs: a CUDA device (gpu_engine.cu; gpu_none.cpp in a build without nvcc) or this machine's
// cores (gpu_host.cpp, ROTLEAK_GPU_EMULATE). Both run gpu_step.hpp's run_one for each particle; Device
// (gpu_device.cpp) holds one and does what they share (checks, f_c's digits into exact sums).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "sim/gpu/gpu_engine.hpp"

namespace rotleak::gpu {

struct Device::Backend {
  virtual ~Backend() = default;
  /// The batch's particles run; their ends into `ends` (host memory).
  virtual void run(const Batch& b, End* ends) = 0;
  /// The f_c counts (cells x bins) and, weighted, the digits (kSumDigits a count) made since the last call, into
  /// counts and digits (sized by the caller); zeroed where they are kept.
  virtual void take(unsigned long long* counts, unsigned long long* digits) = 0;
  int registers = 0, blocks = 0;  ///< of the last launch's kernel (a device only)
};

/// "" when a CUDA device is visible to this build, else why not.
std::string cuda_unavailable();
/// The CUDA device's name and size, or why none is visible.
std::string cuda_device_name();
std::unique_ptr<Device::Backend> cuda_backend(const Model<double>& m, const DensityCells* d, bool weighted);
std::unique_ptr<Device::Backend> cuda_backend(const TableModel<double>& m, const DensityCells* d, bool weighted);
std::unique_ptr<Device::Backend> host_backend(const Model<double>& m, const DensityCells* d, bool weighted);
std::unique_ptr<Device::Backend> host_backend(const TableModel<double>& m, const DensityCells* d, bool weighted);

}  // namespace rotleak::gpu
