// Bad input, named: every layer that reads user text throws this, and the command line prints it as
// one line and exits 2.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "numeric/exact.hpp"

namespace rotleak {

/// Bad input. what() is one line: "<key> = <value>: <what is allowed>".
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& key, const std::string& value, const std::string& allowed)
      : std::runtime_error(key + " = " + quoted_prefix(value, 120) + ": " + quoted_prefix(allowed, 400)), key_(key) {}
  const std::string& key() const { return key_; }

 private:
  /// A text longer than `limit` bytes is quoted by a prefix and its length: the message stays one readable
  /// line even when it quotes an exact value of 100 KB.
  static std::string quoted_prefix(const std::string& raw, std::size_t limit) {
    // control characters as escapes: a value holding a newline (a TOML string) keeps the message one line
    std::string value;
    for (const char ch : raw) {
      const auto u = static_cast<unsigned char>(ch);
      if (u >= 0x20 && u != 0x7f) {
        value += ch;
      } else {
        static const char* hex = "0123456789abcdef";
        value += ch == '\n'   ? std::string("\\n")
                 : ch == '\t' ? std::string("\\t")
                 : ch == '\r' ? std::string("\\r")
                              : std::string("\\x") + hex[u >> 4] + hex[u & 15];
      }
    }
    if (value.size() <= limit) return value;
    std::size_t cut = limit - 20;
    while (cut > 0 && (static_cast<unsigned char>(value[cut]) & 0xC0) == 0x80) --cut;  // not inside a UTF-8 character
    return value.substr(0, cut) + "... (" + std::to_string(value.size()) + " characters)";
  }

  std::string key_;
};

/// s without leading and trailing blanks and tabs.
inline std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t");
  if (a == std::string::npos) return "";
  const auto b = s.find_last_not_of(" \t");
  return s.substr(a, b - a + 1);
}

/// Splits a list at commas outside parentheses, each item trimmed; unbalanced parentheses are an
/// InputError naming `option`.
inline std::vector<std::string> split_top(const std::string& option, const std::string& text) {
  std::vector<std::string> items;
  std::string cur;
  int depth = 0;
  for (char ch : text) {
    if (ch == '(') ++depth;
    if (ch == ')' && --depth < 0) throw InputError(option, text, "unbalanced ')'");
    if (ch == ',' && depth == 0) {
      items.push_back(trim(cur));
      cur.clear();
    } else {
      cur += ch;
    }
  }
  if (depth != 0) throw InputError(option, text, "unbalanced '('");
  items.push_back(trim(cur));
  return items;
}

/// An exact value read from user text; bad text, and a value whose sign cannot be decided (pi-pi: a
/// zero that no precision proves), are an InputError naming `key`.
inline ExactReal parse_exact_input(const std::string& key, const std::string& text) {
  try {
    ExactReal x = ExactReal::parse(text);
    (void)x.sign();  // every use compares it with something: decide it now, with the key at hand
    return x;
  } catch (const ExactParseError& e) {
    throw InputError(key, "\"" + text + "\"", e.what());
  } catch (const std::domain_error& e) {
    throw InputError(key, "\"" + text + "\"", std::string("cannot be used: ") + e.what());
  }
}

/// A count given as text, exactly: "1000000", "1e6", "2.5e5", "1E+6" (read by parse_decimal, never
/// through a double; no sign, no negative exponent); it must be an integer in [min, 2^63). Anything else
/// is an InputError naming `key`.
inline std::uint64_t parse_count(const std::string& key, const std::string& text, std::uint64_t min = 1) {
  const auto bad = [&](const char* why) {
    return InputError(key, text,
                      std::string(why) + " (an integer >= " + std::to_string(min) + ": 1000000, 1e6 or 2.5e5)");
  };
  if (text.empty() || text[0] == '+' || text[0] == '-' || text.find("e-") != std::string::npos ||
      text.find("E-") != std::string::npos)
    throw bad("not a number");
  mpq_class q;
  try {
    q = parse_decimal(text);
  } catch (const ExactParseError&) {
    throw bad("not a number");
  }
  if (q.get_den() != 1) throw bad("not an integer");
  if (q.get_num() > mpz_class("9223372036854775807")) throw bad("too large");
  const std::uint64_t n = q.get_num().get_ui();
  if (n < min) throw bad("too small");
  return n;
}

}  // namespace rotleak
