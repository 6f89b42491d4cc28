// Where a GPU launch runs: a CUDA device (gpu_engine.cu; gpu_none.cpp in a build without nvcc) or this machine's
// cores (gpu_host.cpp, ROTLEAK_GPU_EMULATE). Both run gpu_step.hpp's run_lane on each of their threads; Device
// (gpu_device.cpp) holds one and does what they share (checks, the words and digits drained into exact tallies).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "sim/gpu/gpu_engine.hpp"

namespace rotleak::gpu {

struct Device::Backend {
  virtual ~Backend() = default;
  /// The batch's particles run; their ends into `ends` and `full` when set (host memory).
  virtual void run(const Batch& b, End* ends, ParticleEnd* full) = 0;
  /// The collisions the launches made since the last call (Layout::kCollisions), zeroed where it is kept.
  virtual std::uint64_t take_collisions() = 0;
  /// Layout's words (kCollisions' is 0 after take_collisions) and digits (kSumDigits a sum) made since the
  /// last call, into words and digits (sized by the caller); zeroed where they are kept.
  virtual void take(unsigned long long* words, unsigned long long* digits) = 0;
  virtual void set_t_max(double t_max) = 0;
  /// The kernel whose registers let n blocks share a multiprocessor (0: the default); a device only.
  virtual void set_min_blocks(int /*n*/) {}
  int registers = 0, blocks = 0;  ///< of the last launch's kernel (a device only)
};

/// "" when a CUDA device is visible to this build, else why not.
std::string cuda_unavailable();
/// The CUDA device's name and size, or why none is visible.
std::string cuda_device_name();
int cuda_device_count();
void cuda_select_device(int index);
std::unique_ptr<Device::Backend> cuda_backend(const Model<double>& m, const Device::Layout& l, const Shape& s);
std::unique_ptr<Device::Backend> cuda_backend(const TableModel<double>& m, const Device::Layout& l, const Shape& s);
std::unique_ptr<Device::Backend> host_backend(const Model<double>& m, const Device::Layout& l, const Shape& s);
std::unique_ptr<Device::Backend> host_backend(const TableModel<double>& m, const Device::Layout& l, const Shape& s);

}  // namespace rotleak::gpu
