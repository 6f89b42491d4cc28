// Bad input, named: every layer that reads user text throws this, and the command line prints it as
// one line and exits 2.
#pragma once

#include <stdexcept>
#include <string>

#include "numeric/exact.hpp"

namespace rotleak {

/// Bad input. what() is one line: "<key> = <value>: <what is allowed>".
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& key, const std::string& value, const std::string& allowed)
      : std::runtime_error(key + " = " + value + ": " + allowed), key_(key) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

/// An exact value read from user text; bad text is an InputError naming `key`.
inline ExactReal parse_exact_input(const std::string& key, const std::string& text) {
  try {
    return ExactReal::parse(text);
  } catch (const ExactParseError& e) {
    throw InputError(key, "\"" + text + "\"", e.what());
  }
}

}  // namespace rotleak
