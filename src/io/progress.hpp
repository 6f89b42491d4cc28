// A progress line on stderr (rate, ETA), redrawn at most twice a second; silent when disabled.
#pragma once

#include <chrono>
#include <cstdint>

namespace rotleak {

class ProgressLine {
 public:
  ProgressLine(bool enabled, std::uint64_t total);
  /// Call from one thread only.
  void update(std::uint64_t done, std::uint64_t collisions);
  void finish(std::uint64_t done, std::uint64_t collisions);

 private:
  void draw(std::uint64_t done, std::uint64_t collisions, bool final);
  bool enabled_;
  std::uint64_t total_;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace rotleak
