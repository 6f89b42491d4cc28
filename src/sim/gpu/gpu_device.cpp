// Device: a backend (a CUDA device, or the host's emulation of one) and what both share -- the checks on a batch,
// and the device's words and digits drained into integer counts and exact sums, then into a Tally.
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <utility>
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

int device_count() { return emulated() ? 0 : cuda_device_count(); }
void select_device(int index) {
  if (!emulated()) cuda_select_device(index);
}

Shape Shape::of(const Tally& t, double dt, const DensityCells* density) {
  Shape s;
  s.density = density;
  s.weighted = t.weighted();
  s.dt = dt;
  if (t.get_if<LinesEstimator>()) return s;  // a split run books its members' ends on the host
  s.bins = t.escapes_per_bin.size();
  s.leaks = s.bins ? t.escapes_by_leak.size() / s.bins : 0;
  return s;
}

namespace {

Device::Layout layout_of(const Shape& s) {
  Device::Layout l;
  l.bins = s.bins;
  l.leaks = s.leaks;
  l.fc = s.density ? static_cast<std::size_t>(s.density->cells()) * static_cast<std::size_t>(s.density->bins) : 0;
  l.weighted_ends = s.weighted && s.bins > 0;
  l.weighted_fc = s.weighted && l.fc > 0;
  return l;
}

/// Each of the device's words takes at most this many additions between drains: far below the 2^40 that a digit's
/// 40 spare bits carry.
constexpr std::uint64_t kDrainAt = 1ULL << 39;

}  // namespace

Device::Device(const Model<double>& model, const Shape& shape)
    : layout_(layout_of(shape)),
      impl_(emulated() ? host_backend(model, layout_, shape) : cuda_backend(model, layout_, shape)),
      words_(layout_.words(), 0),
      sums_(layout_.sums()) {}
Device::Device(const TableModel<double>& model, const Shape& shape)
    : layout_(layout_of(shape)),
      impl_(emulated() ? host_backend(model, layout_, shape) : cuda_backend(model, layout_, shape)),
      words_(layout_.words(), 0),
      sums_(layout_.sums()) {}
Device::~Device() = default;

void Device::run(const Batch& b, End* ends, ParticleEnd* full) {
  if (b.count == 0) return;
  if (b.weights)
    for (std::uint64_t i = 0; i < b.count; ++i)
      if (!(b.weights[i] >= 0 && b.weights[i] < 0x1p64))
        throw std::runtime_error("GPU engine: a particle's weight " + std::to_string(b.weights[i]) +
                                 " lies outside [0, 2^64), the range of the device's exact sums");
  impl_->run(b, ends, full);
  particles_ += b.count;
  const std::uint64_t made = impl_->take_collisions();
  words_[Layout::kCollisions] += made;
  // a digit word takes one addition a collision (f_c) and a few an end; integer counts need no such bound
  const std::uint64_t added = made + 4 * b.count;
  if (layout_.sums() > 0 && added >= kDrainAt)
    throw std::runtime_error("GPU engine: a launch of " + std::to_string(made) +
                             " collisions overflows the device's exact sums (at most 2^39 a launch)");
  pending_ += added;
  if (pending_ >= kDrainAt) drain();
}

void Device::drain() {
  pending_ = 0;
  std::vector<unsigned long long> got(layout_.words()), digits(layout_.sums() * kSumDigits);
  impl_->take(got.data(), digits.data());
  for (std::size_t k = 0; k < got.size(); ++k)  // the collisions' word is taken after each launch: 0 here
    words_[k] += got[k];
  for (std::size_t k = 0; k < sums_.size(); ++k)
    for (int j = 0; j < kSumDigits; ++j)
      if (const unsigned long long v = digits[k * kSumDigits + static_cast<std::size_t>(j)])
        sums_[k].add_bits(v, kLowestBit + static_cast<long>(kDigitBits) * j);
}

void Device::set_t_max(double t_max) { impl_->set_t_max(t_max); }
void Device::set_min_blocks(int n) { impl_->set_min_blocks(n); }

void Device::take(Tally& t, std::uint64_t* cell_counts, FixedSum* cell_sums) {
  drain();
  const Layout& l = layout_;
  if (l.bins) {  // else the host books the ends, their collisions included (a split run's epochs)
    t.collisions += words_[Layout::kCollisions];
    std::uint64_t escaped = 0;
    for (std::size_t b = 0; b < l.bins; ++b)
      t.escapes_per_bin[b] += words_[l.by_bin() + b], escaped += words_[l.by_bin() + b];
    const std::uint64_t stuck = words_[Layout::kStuck];
    t.escaped += escaped, t.stuck += stuck;
    t.survived += particles_ - escaped - stuck;
    for (std::size_t k = 0; k < l.leaks * l.bins; ++k) t.escapes_by_leak[k] += words_[l.by_leak() + k];
  }
  if (l.weighted_ends) {
    auto& e = t.as<WeightedEstimator>();
    e.total_w.merge(sums_[0]);
    e.total_w2.merge(sums_[1]);
    for (std::size_t b = 0; b < l.bins; ++b) {
      e.escaped_w[b].merge(sums_[2 + b]);
      e.escaped_w2[b].merge(sums_[2 + l.bins + b]);
    }
  }
  if (cell_counts)
    for (std::size_t k = 0; k < l.fc; ++k) cell_counts[k] += words_[l.fc_word() + k];
  if (cell_sums && l.weighted_fc)
    for (std::size_t k = 0; k < l.fc; ++k) cell_sums[k].merge(sums_[l.fc_sum() + k]);
  words_.assign(l.words(), 0);
  sums_.assign(l.sums(), FixedSum{});
  particles_ = 0;
}

int Device::registers() const { return impl_->registers; }
int Device::blocks_per_multiprocessor() const { return impl_->blocks; }

}  // namespace rotleak::gpu
