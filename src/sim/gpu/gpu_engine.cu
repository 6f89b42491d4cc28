// The GPU engine's CUDA backend: one kernel, run_batch, whose thread i runs gpu_step.hpp's run_one for particle i of a
// batch on a model copied to the device, and the host code that owns the device memory and launches it. Compiled by
// nvcc with -fmad=false (no contraction: the CPU's operations in the CPU's order; src/CMakeLists.txt), no fast math.
#include <cuda_runtime.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "sim/gpu/gpu_backend.hpp"
#include "sim/gpu/gpu_step.hpp"

namespace rotleak::gpu {

namespace {

constexpr int kThreads = 128;  ///< a block's threads

void check(cudaError_t e, const char* what) {
  if (e != cudaSuccess) throw std::runtime_error(std::string("GPU engine: ") + what + ": " + cudaGetErrorString(e));
}

template <class M>
__global__ void __launch_bounds__(kThreads) run_batch(const M* __restrict__ model, Batch b, LaunchData d) {
  const std::uint64_t i = static_cast<std::uint64_t>(blockIdx.x) * kThreads + threadIdx.x;
  if (i < b.count) run_one(*model, b, d, i);
}

template <class M>
class CudaBackend final : public Device::Backend {
 public:
  CudaBackend(const M& m, const DensityCells* d, bool weighted) {
    static_assert(std::is_trivially_copyable_v<M>, "the model is copied to the device byte for byte");
    const std::string why = cuda_unavailable();
    if (!why.empty()) throw std::runtime_error("--engine gpu: " + why);
    check(cudaMalloc(&model_, sizeof(M)), "cudaMalloc(model)");
    check(cudaMemcpy(model_, &m, sizeof(M), cudaMemcpyHostToDevice), "cudaMemcpy(model)");
    if (!d) return;
    check(cudaMalloc(&cells_, sizeof(DensityCells)), "cudaMalloc(cells)");
    check(cudaMemcpy(cells_, d, sizeof(DensityCells), cudaMemcpyHostToDevice), "cudaMemcpy(cells)");
    n_ = static_cast<std::size_t>(d->cells()) * static_cast<std::size_t>(d->bins);
    check(cudaMalloc(&counts_, n_ * sizeof(unsigned long long)), "cudaMalloc(f_c)");
    check(cudaMemset(counts_, 0, n_ * sizeof(unsigned long long)), "cudaMemset(f_c)");
    if (!weighted) return;
    check(cudaMalloc(&sums_, n_ * kSumDigits * sizeof(unsigned long long)), "cudaMalloc(weighted f_c)");
    check(cudaMemset(sums_, 0, n_ * kSumDigits * sizeof(unsigned long long)), "cudaMemset(weighted f_c)");
  }
  ~CudaBackend() override {
    cudaFree(model_), cudaFree(cells_), cudaFree(counts_), cudaFree(sums_);
    cudaFree(draws_), cudaFree(weights_), cudaFree(ends_);
  }
  CudaBackend(const CudaBackend&) = delete;
  CudaBackend& operator=(const CudaBackend&) = delete;

  void run(const Batch& b, End* ends) override {
    reserve(b.count);
    if (b.draws)
      check(cudaMemcpy(draws_, b.draws, b.count * sizeof(InitialDraw), cudaMemcpyHostToDevice), "cudaMemcpy(draws)");
    if (b.weights)
      check(cudaMemcpy(weights_, b.weights, b.count * sizeof(double), cudaMemcpyHostToDevice), "cudaMemcpy(weights)");
    const LaunchData d{b.draws ? draws_ : nullptr, b.weights ? weights_ : nullptr, ends_, cells_, counts_, sums_};
    const auto kernel = run_batch<M>;
    cudaFuncAttributes attr{};
    check(cudaFuncGetAttributes(&attr, kernel), "cudaFuncGetAttributes");
    registers = attr.numRegs;
    check(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&blocks, kernel, kThreads, 0), "occupancy");
    const std::uint64_t grid = (b.count + kThreads - 1) / kThreads;
    kernel<<<static_cast<unsigned>(grid), kThreads>>>(model_, b, d);
    check(cudaGetLastError(), "launch");
    check(cudaDeviceSynchronize(), "run_batch");
    check(cudaMemcpy(ends, ends_, b.count * sizeof(End), cudaMemcpyDeviceToHost), "cudaMemcpy(ends)");
  }

  void take(unsigned long long* counts, unsigned long long* digits) override {
    if (n_ == 0) return;
    check(cudaMemcpy(counts, counts_, n_ * sizeof(unsigned long long), cudaMemcpyDeviceToHost), "cudaMemcpy(f_c)");
    check(cudaMemset(counts_, 0, n_ * sizeof(unsigned long long)), "cudaMemset(f_c)");
    if (!digits || !sums_) return;
    const std::size_t bytes = n_ * kSumDigits * sizeof(unsigned long long);
    check(cudaMemcpy(digits, sums_, bytes, cudaMemcpyDeviceToHost), "cudaMemcpy(weighted f_c)");
    check(cudaMemset(sums_, 0, bytes), "cudaMemset(weighted f_c)");
  }

 private:
  void reserve(std::uint64_t n) {
    if (n <= capacity_) return;
    cudaFree(draws_), cudaFree(weights_), cudaFree(ends_);
    draws_ = nullptr, weights_ = nullptr, ends_ = nullptr, capacity_ = 0;
    check(cudaMalloc(&draws_, n * sizeof(InitialDraw)), "cudaMalloc(draws)");
    check(cudaMalloc(&weights_, n * sizeof(double)), "cudaMalloc(weights)");
    check(cudaMalloc(&ends_, n * sizeof(End)), "cudaMalloc(ends)");
    capacity_ = n;
  }

  M* model_ = nullptr;
  DensityCells* cells_ = nullptr;
  unsigned long long* counts_ = nullptr;
  unsigned long long* sums_ = nullptr;  ///< weighted f_c: kSumDigits a (cell, bin)
  std::size_t n_ = 0;                   ///< cells x bins
  InitialDraw* draws_ = nullptr;
  double* weights_ = nullptr;
  End* ends_ = nullptr;
  std::uint64_t capacity_ = 0;
};

}  // namespace

std::string cuda_unavailable() {
  int n = 0;
  const cudaError_t e = cudaGetDeviceCount(&n);
  if (e != cudaSuccess) return std::string("no CUDA device is visible (") + cudaGetErrorString(e) + ")";
  if (n == 0) return "no CUDA device is visible";
  cudaDeviceProp p{};
  if (cudaGetDeviceProperties(&p, 0) != cudaSuccess) return "the CUDA device's properties cannot be read";
  if (p.major < 9)
    return "the CUDA device " + std::string(p.name) + " has compute capability " + std::to_string(p.major) + "." +
           std::to_string(p.minor) + "; this build carries code for 9.0 and later";
  return "";
}

std::string cuda_device_name() {
  const std::string why = cuda_unavailable();
  if (!why.empty()) return why;
  cudaDeviceProp p{};
  check(cudaGetDeviceProperties(&p, 0), "cudaGetDeviceProperties");
  return std::string(p.name) + ", " + std::to_string(p.multiProcessorCount) + " multiprocessors, " +
         std::to_string(p.totalGlobalMem >> 30) + " GiB";
}

std::unique_ptr<Device::Backend> cuda_backend(const Model<double>& m, const DensityCells* d, bool weighted) {
  return std::make_unique<CudaBackend<Model<double>>>(m, d, weighted);
}
std::unique_ptr<Device::Backend> cuda_backend(const TableModel<double>& m, const DensityCells* d, bool weighted) {
  return std::make_unique<CudaBackend<TableModel<double>>>(m, d, weighted);
}

}  // namespace rotleak::gpu
