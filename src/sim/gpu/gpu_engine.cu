// The GPU engine's CUDA backend: one kernel, run_batch, as many threads as the device holds at once, each running
// gpu_step.hpp's run_lane (particle after particle of the batch) on a model copied to the device; and the host code
// that owns the device memory and launches it. Compiled by
// nvcc with -fmad=false (no contraction: the CPU's operations in the CPU's order; src/CMakeLists.txt), no fast math.
#include <cuda_runtime.h>

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "sim/gpu/gpu_backend.hpp"
#include "sim/gpu/gpu_step.hpp"

namespace rotleak::gpu {

namespace {

constexpr int kThreads = 128;  ///< a block's threads
/// The kernel's register cap by default (blocks a multiprocessor; run_batch): not yet measured against the others.
constexpr int kDefaultMinBlocks = 6;

void check(cudaError_t e, const char* what) {
  if (e != cudaSuccess) throw std::runtime_error(std::string("GPU engine: ") + what + ": " + cudaGetErrorString(e));
}

/// The kernel, its registers capped so that MinBlocks blocks fit a multiprocessor (1: the compiler's choice; 6: 80
/// registers; 8: 64, spilling the rest to local memory): occupancy against spills, which bench_gpu measures.
template <class M, bool FC, int MinBlocks>
__global__ void __launch_bounds__(kThreads, MinBlocks) run_batch(const M* __restrict__ model, Batch b, LaunchData d) {
  if constexpr (FC)
    run_lane(*model, b, d, cell_observer(model, d));
  else
    run_lane(*model, b, d, NoCollisionObserver<double>{});
}

template <class T>
void upload(T*& at, std::size_t& capacity, const T* from, std::size_t n, const char* what) {
  if (n > capacity) {
    cudaFree(at);
    at = nullptr, capacity = 0;
    check(cudaMalloc(&at, n * sizeof(T)), what);
    capacity = n;
  }
  if (from) check(cudaMemcpy(at, from, n * sizeof(T), cudaMemcpyHostToDevice), what);
}

template <class M>
class CudaBackend final : public Device::Backend {
 public:
  CudaBackend(const M& m, const Device::Layout& l, const Shape& s) : model_host_(m), layout_(l), dt_(s.dt) {
    static_assert(std::is_trivially_copyable_v<M>, "the model is copied to the device byte for byte");
    const std::string why = cuda_unavailable();
    if (!why.empty()) throw std::runtime_error("--engine gpu: " + why);
    check(cudaMalloc(&model_, sizeof(M)), "cudaMalloc(model)");
    check(cudaMemcpy(model_, &m, sizeof(M), cudaMemcpyHostToDevice), "cudaMemcpy(model)");
    check(cudaMalloc(&next_, sizeof(unsigned long long)), "cudaMalloc(next)");
    if (l.fc && s.density) {
      check(cudaMalloc(&cells_, sizeof(DensityCells)), "cudaMalloc(cells)");
      check(cudaMemcpy(cells_, s.density, sizeof(DensityCells), cudaMemcpyHostToDevice), "cudaMemcpy(cells)");
    }
    check(cudaMalloc(&words_, l.words() * sizeof(unsigned long long)), "cudaMalloc(tallies)");
    check(cudaMemset(words_, 0, l.words() * sizeof(unsigned long long)), "cudaMemset(tallies)");
    if (l.sums() == 0) return;
    const std::size_t bytes = l.sums() * kSumDigits * sizeof(unsigned long long);
    check(cudaMalloc(&digits_, bytes), "cudaMalloc(exact sums)");
    check(cudaMemset(digits_, 0, bytes), "cudaMemset(exact sums)");
  }
  ~CudaBackend() override {
    cudaFree(model_), cudaFree(cells_), cudaFree(words_), cudaFree(digits_), cudaFree(next_);
    cudaFree(draws_), cudaFree(weights_), cudaFree(starts_), cudaFree(ends_), cudaFree(full_);
  }
  CudaBackend(const CudaBackend&) = delete;
  CudaBackend& operator=(const CudaBackend&) = delete;

  void run(const Batch& b, End* ends, ParticleEnd* full) override {
    LaunchData d = launch_data(layout_, words_, digits_, dt_, cells_);
    if (b.draws) upload(draws_, draws_n_, b.draws, b.count, "cudaMemcpy(draws)"), d.draws = draws_;
    if (b.weights) upload(weights_, weights_n_, b.weights, b.count, "cudaMemcpy(weights)"), d.weights = weights_;
    if (b.starts) upload(starts_, starts_n_, b.starts, b.count, "cudaMemcpy(starts)"), d.starts = starts_;
    if (ends) upload<End>(ends_, ends_n_, nullptr, b.count, "cudaMalloc(ends)"), d.ends = ends_;
    if (full) upload<ParticleEnd>(full_, full_n_, nullptr, b.count, "cudaMalloc(ends)"), d.full = full_;
    d.next = next_;
    check(cudaMemset(next_, 0, sizeof(unsigned long long)), "cudaMemset(next)");
    const auto kernel = kernel_of(d.cells != nullptr);
    cudaFuncAttributes attr{};
    check(cudaFuncGetAttributes(&attr, kernel), "cudaFuncGetAttributes");
    registers = attr.numRegs;
    check(cudaOccupancyMaxActiveBlocksPerMultiprocessor(&blocks, kernel, kThreads, 0), "occupancy");
    int device = 0, sms = 0;
    check(cudaGetDevice(&device), "cudaGetDevice");
    check(cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device), "multiprocessors");
    // every thread resident at once, each taking particles until the batch is spent
    const std::uint64_t resident = static_cast<std::uint64_t>(blocks > 0 ? blocks : 1) * static_cast<std::uint64_t>(sms);
    const std::uint64_t grid = std::min<std::uint64_t>(resident, (b.count + kThreads - 1) / kThreads);
    kernel<<<static_cast<unsigned>(grid), kThreads>>>(model_, b, d);
    check(cudaGetLastError(), "launch");
    check(cudaDeviceSynchronize(), "run_batch");
    if (ends) check(cudaMemcpy(ends, ends_, b.count * sizeof(End), cudaMemcpyDeviceToHost), "cudaMemcpy(ends)");
    if (full)
      check(cudaMemcpy(full, full_, b.count * sizeof(ParticleEnd), cudaMemcpyDeviceToHost), "cudaMemcpy(ends)");
  }

  std::uint64_t take_collisions() override {
    unsigned long long c = 0;
    unsigned long long* at = words_ + Device::Layout::kCollisions;
    check(cudaMemcpy(&c, at, sizeof c, cudaMemcpyDeviceToHost), "cudaMemcpy(collisions)");
    check(cudaMemset(at, 0, sizeof c), "cudaMemset(collisions)");
    return c;
  }

  void take(unsigned long long* words, unsigned long long* digits) override {
    const std::size_t n = layout_.words() * sizeof(unsigned long long);
    check(cudaMemcpy(words, words_, n, cudaMemcpyDeviceToHost), "cudaMemcpy(tallies)");
    check(cudaMemset(words_, 0, n), "cudaMemset(tallies)");
    if (!digits_) return;
    const std::size_t bytes = layout_.sums() * kSumDigits * sizeof(unsigned long long);
    check(cudaMemcpy(digits, digits_, bytes, cudaMemcpyDeviceToHost), "cudaMemcpy(exact sums)");
    check(cudaMemset(digits_, 0, bytes), "cudaMemset(exact sums)");
  }

  void set_min_blocks(int n) override {
    if (n != 0 && n != 1 && n != 6 && n != 8)
      throw std::invalid_argument("GPU engine: a kernel for " + std::to_string(n) +
                                  " blocks a multiprocessor; this build has 1, 6 and 8");
    min_blocks_ = n == 0 ? kDefaultMinBlocks : n;
  }

  void set_t_max(double t_max) override {
    model_host_.t_max = t_max;
    check(cudaMemcpy(model_, &model_host_, sizeof(M), cudaMemcpyHostToDevice), "cudaMemcpy(model)");
  }

 private:
  using Kernel = void (*)(const M*, Batch, LaunchData);
  Kernel kernel_of(bool fc) const {
    if (min_blocks_ == 8) return fc ? run_batch<M, true, 8> : run_batch<M, false, 8>;
    if (min_blocks_ == 6) return fc ? run_batch<M, true, 6> : run_batch<M, false, 6>;
    return fc ? run_batch<M, true, 1> : run_batch<M, false, 1>;
  }

  int min_blocks_ = kDefaultMinBlocks;
  M model_host_;
  Device::Layout layout_;
  double dt_;
  M* model_ = nullptr;
  DensityCells* cells_ = nullptr;
  unsigned long long* words_ = nullptr;
  unsigned long long* digits_ = nullptr;
  unsigned long long* next_ = nullptr;
  InitialDraw* draws_ = nullptr;
  double* weights_ = nullptr;
  Start* starts_ = nullptr;
  End* ends_ = nullptr;
  ParticleEnd* full_ = nullptr;
  std::size_t draws_n_ = 0, weights_n_ = 0, starts_n_ = 0, ends_n_ = 0, full_n_ = 0;
};

}  // namespace

std::string cuda_unavailable() {
  int n = 0;
  const cudaError_t e = cudaGetDeviceCount(&n);
  if (e != cudaSuccess) return std::string("no CUDA device is visible (") + cudaGetErrorString(e) + ")";
  if (n == 0) return "no CUDA device is visible";
  int device = 0;
  cudaDeviceProp p{};
  if (cudaGetDevice(&device) != cudaSuccess || cudaGetDeviceProperties(&p, device) != cudaSuccess)
    return "the CUDA device's properties cannot be read";
  if (p.major < 9)
    return "the CUDA device " + std::string(p.name) + " has compute capability " + std::to_string(p.major) + "." +
           std::to_string(p.minor) + "; this build carries code for 9.0 and later";
  return "";
}

std::string cuda_device_name() {
  const std::string why = cuda_unavailable();
  if (!why.empty()) return why;
  int device = 0;
  check(cudaGetDevice(&device), "cudaGetDevice");
  cudaDeviceProp p{};
  check(cudaGetDeviceProperties(&p, device), "cudaGetDeviceProperties");
  return "device " + std::to_string(device) + ": " + std::string(p.name) + ", " + std::to_string(p.multiProcessorCount) + " multiprocessors, " +
         std::to_string(p.totalGlobalMem >> 30) + " GiB";
}

int cuda_device_count() {
  int n = 0;
  return cudaGetDeviceCount(&n) == cudaSuccess ? n : 0;
}

void cuda_select_device(int index) { check(cudaSetDevice(index), "cudaSetDevice"); }

std::unique_ptr<Device::Backend> cuda_backend(const Model<double>& m, const Device::Layout& l, const Shape& s) {
  return std::make_unique<CudaBackend<Model<double>>>(m, l, s);
}
std::unique_ptr<Device::Backend> cuda_backend(const TableModel<double>& m, const Device::Layout& l, const Shape& s) {
  return std::make_unique<CudaBackend<TableModel<double>>>(m, l, s);
}

}  // namespace rotleak::gpu
