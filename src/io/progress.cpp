#include "io/progress.hpp"

#include <cstdio>
#include <memory>
#include <utility>

namespace rotleak {

ProgressLine::ProgressLine(bool enabled, std::string label)
    : enabled_(enabled), label_(std::move(label)), start_(std::chrono::steady_clock::now()), last_(start_) {}

void ProgressLine::update(std::uint64_t done, std::uint64_t total, std::uint64_t collisions, bool final) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (!final && now - last_ < std::chrono::milliseconds(500)) return;
  last_ = now;
  const double el = std::chrono::duration<double>(now - start_).count();
  const double frac = total ? static_cast<double>(done) / static_cast<double>(total) : 1.0;
  const double rate = el > 0 ? static_cast<double>(collisions) / el : 0.0;
  const double eta = frac > 0 ? el * (1 - frac) / frac : 0.0;
  std::fprintf(stderr, "\r%s %5.1f%%  %llu/%llu particles  %.3g collisions/s  %s %.0f s   %s", label_.c_str(),
               100 * frac, static_cast<unsigned long long>(done), static_cast<unsigned long long>(total), rate,
               final ? "took" : "ETA", final ? el : eta, final ? "\n" : "");
  std::fflush(stderr);
}

std::function<void(std::uint64_t, std::uint64_t, std::uint64_t, bool)> progress_on_stderr(bool enabled,
                                                                                          const std::string& label) {
  if (!enabled) return {};
  auto line = std::make_shared<ProgressLine>(true, label);
  return [line](std::uint64_t done, std::uint64_t total, std::uint64_t collisions, bool final) {
    line->update(done, total, collisions, final);
  };
}

}  // namespace rotleak
