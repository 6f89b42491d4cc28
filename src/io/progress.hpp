// A progress line on stderr (rate, ETA), redrawn at most twice a second; silent when disabled.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <string>

namespace rotleak {

class ProgressLine {
 public:
  /// `label` opens the line ("[rotleak]", "[rotleak audit] float ensemble").
  explicit ProgressLine(bool enabled, std::string label = "[rotleak]");
  /// Call from one thread at a time; `final` draws the closing line.
  void update(std::uint64_t done, std::uint64_t total, std::uint64_t collisions, bool final);

 private:
  bool enabled_;
  std::string label_;
  std::chrono::steady_clock::time_point start_, last_;
};

/// A RunOptions::progress callback drawing a ProgressLine (empty when disabled).
std::function<void(std::uint64_t, std::uint64_t, std::uint64_t, bool)> progress_on_stderr(
    bool enabled, const std::string& label = "[rotleak]");

}  // namespace rotleak
