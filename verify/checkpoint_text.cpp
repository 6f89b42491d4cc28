#include "verify/checkpoint_text.hpp"

#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace rotleak {

CheckpointReader::CheckpointReader(const std::string& text, const std::string& magic, const std::string& where)
    : in_(text), where_(where) {
  std::string line;
  if (!std::getline(in_, line) || line != magic) {
    line_ = 1;
    fail("not a " + magic.substr(0, magic.rfind(' ')) + " file");
  }
  line_ = 2;
  if (!std::getline(in_, line)) fail("truncated: no inputs line");
  if (line.rfind("inputs ", 0) != 0) fail("no inputs line");
  inputs_ = line.substr(7);
}

bool CheckpointReader::next(std::vector<std::string>& words) {
  std::string line;
  if (!std::getline(in_, line)) return false;
  ++line_;
  words.clear();
  std::istringstream w(line);
  for (std::string x; w >> x;) words.push_back(x);
  return true;
}

void CheckpointReader::fail(const std::string& why) const {
  throw std::runtime_error(where_ + ":" + std::to_string(line_) + ": " + why);
}

std::size_t CheckpointReader::count(const std::string& word) const {
  std::size_t at = 0;
  unsigned long long v = 0;
  try {
    v = std::stoull(word, &at);
  } catch (const std::exception&) {
    at = 0;
  }
  if (word.empty() || word[0] == '-' || at != word.size()) fail("not a count: \"" + word + "\"");
  return static_cast<std::size_t>(v);
}

double CheckpointReader::time(const std::string& word) const {
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  if (word.empty() || end != word.c_str() + word.size() || !std::isfinite(v) || v < 0)
    fail("not a time: \"" + word + "\"");
  return v;
}

}  // namespace rotleak
