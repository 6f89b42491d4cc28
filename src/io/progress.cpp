#include "io/progress.hpp"

#include <cstdio>

namespace rotleak {

ProgressLine::ProgressLine(bool enabled, std::uint64_t total)
    : enabled_(enabled), total_(total), start_(std::chrono::steady_clock::now()), last_(start_) {}

void ProgressLine::update(std::uint64_t done, std::uint64_t collisions) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_ < std::chrono::milliseconds(500)) return;
  last_ = now;
  draw(done, collisions, false);
}

void ProgressLine::finish(std::uint64_t done, std::uint64_t collisions) {
  if (enabled_) draw(done, collisions, true);
}

void ProgressLine::draw(std::uint64_t done, std::uint64_t collisions, bool final) {
  const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double frac = total_ ? static_cast<double>(done) / static_cast<double>(total_) : 1.0;
  const double rate = el > 0 ? static_cast<double>(collisions) / el : 0.0;
  const double eta = frac > 0 ? el * (1 - frac) / frac : 0.0;
  std::fprintf(stderr, "\r[rotleak] %5.1f%%  %llu/%llu particles  %.3g collisions/s  %s %.0f s   %s",
               100 * frac, static_cast<unsigned long long>(done), static_cast<unsigned long long>(total_), rate,
               final ? "took" : "ETA", final ? el : eta, final ? "\n" : "");
  std::fflush(stderr);
}

}  // namespace rotleak
