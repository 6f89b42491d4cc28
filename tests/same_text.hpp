// Bit-identity of whole files without a diff: a failure names the first differing line, both sizes and
// both hashes, and costs nothing beyond the two texts. (GoogleTest's EXPECT_EQ on two multi-megabyte
// strings builds a full edit-script diff: one failing comparison ran 845 s and passed 24 GB.)
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <string>

namespace rotleak::test {

/// FNV-1a 64 of a text, in hex: what a failure prints to tell two files apart.
inline std::string text_hash(const std::string& s) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
  return out;
}

/// Success when a == b; otherwise the first line where they differ (as far as 200 characters of each),
/// its number, and both sizes and hashes.
inline ::testing::AssertionResult same_text(const std::string& a, const std::string& b) {
  if (a == b) return ::testing::AssertionSuccess();
  std::size_t line = 1, i = 0;
  while (i < a.size() && i < b.size() && a[i] == b[i]) line += a[i++] == '\n';
  const auto row = [&](const std::string& s) {
    const std::size_t from = i == 0 ? std::string::npos : s.rfind('\n', i - 1);
    const std::size_t start = from == std::string::npos ? 0 : from + 1;
    const std::size_t end = s.find('\n', start);
    return s.substr(start, std::min<std::size_t>(200, (end == std::string::npos ? s.size() : end) - start));
  };
  return ::testing::AssertionFailure() << "texts differ from line " << line << ": \"" << row(a) << "\" vs \"" << row(b)
                                       << "\" (" << a.size() << " bytes, hash " << text_hash(a) << "; " << b.size()
                                       << " bytes, hash " << text_hash(b) << ")";
}

}  // namespace rotleak::test
