// The text checkpoints of the verify commands (verify/orbit_checkpoint.hpp, verify/certify_checkpoint.hpp):
// line 1 a format line, line 2 `inputs ...`, then one record a line, words separated by blanks. One reader of
// that frame, so each checkpoint's parser reads only its own records; every failure names the file and line.
#pragma once

#include <cstddef>
#include <istream>
#include <sstream>
#include <string>
#include <vector>

namespace rotleak {

class CheckpointReader {
 public:
  /// Reads lines 1 and 2 (std::runtime_error if line 1 is not `magic` or line 2 no inputs line).
  CheckpointReader(const std::string& text, const std::string& magic, const std::string& where);
  const std::string& inputs() const { return inputs_; }
  /// The next record's words; false after the last.
  bool next(std::vector<std::string>& words);
  /// std::runtime_error "WHERE:LINE: why".
  [[noreturn]] void fail(const std::string& why) const;
  /// A word that must be a non-negative integer.
  std::size_t count(const std::string& word) const;
  /// A word that must be a finite number >= 0 (decimal or C's hexadecimal %a, read exactly).
  double time(const std::string& word) const;

 private:
  std::istringstream in_;
  std::string where_, inputs_;
  std::size_t line_ = 0;
};

}  // namespace rotleak
