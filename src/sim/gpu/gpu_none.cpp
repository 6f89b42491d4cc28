// The GPU engine in a build without a CUDA compiler: no device backend, and the one line that says why (the
// emulation on the host, gpu_host.cpp, is still there for the tests).
#include <stdexcept>
#include <string>

#include "sim/gpu/gpu_backend.hpp"

namespace rotleak::gpu {

std::string cuda_unavailable() {
  return "this build has no GPU engine: CMake found no CUDA compiler (nvcc) when it was configured "
         "(ROTLEAK_GPU=OFF, or no CUDA toolkit)";
}
std::string cuda_device_name() { return cuda_unavailable(); }

int cuda_device_count() { return 0; }
void cuda_select_device(int) {}

std::unique_ptr<Device::Backend> cuda_backend(const Model<double>&, const Device::Layout&, const Shape&) {
  throw std::runtime_error("--engine gpu: " + cuda_unavailable());
}
std::unique_ptr<Device::Backend> cuda_backend(const TableModel<double>&, const Device::Layout&, const Shape&) {
  throw std::runtime_error("--engine gpu: " + cuda_unavailable());
}

}  // namespace rotleak::gpu
