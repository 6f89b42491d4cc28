// printf-style formatting into a std::string, for the report lines the library builds.
#pragma once

#include <cstdarg>
#include <cstdio>
#include <string>

namespace rotleak {

/// Appends printf(fmt, ...) to out.
__attribute__((format(printf, 2, 3))) inline void appendf(std::string& out, const char* fmt, ...) {
  va_list args, again;
  va_start(args, fmt);
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, fmt, args);
  va_end(args);
  if (n > 0) {
    const std::size_t at = out.size();
    out.resize(at + static_cast<std::size_t>(n) + 1);
    std::vsnprintf(out.data() + at, static_cast<std::size_t>(n) + 1, fmt, again);
    out.resize(at + static_cast<std::size_t>(n));
  }
  va_end(again);
}

}  // namespace rotleak
