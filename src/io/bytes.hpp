// Bytes that carry exact values between processes and files: little-endian 64-bit words, doubles as
// their bit patterns (so infinities, NaNs and -0 come back as they went), strings with their length.
// The tally files (io/tally_file.hpp) and the MPI transport of verify's results are written with it.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace rotleak {

static_assert(std::endian::native == std::endian::little, "bytes are written as little-endian words");

/// FNV's 64-bit offset basis, where an FNV-1a hash starts.
inline constexpr std::uint64_t kFnvOffset = 14695981039346656037ULL;
/// FNV-1a, 64 bits, of n bytes, going on from h (kFnvOffset for a new hash).
inline std::uint64_t fnv1a(const void* data, std::size_t n, std::uint64_t h = kFnvOffset) {
  const auto* b = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) {
    h ^= b[i];
    h *= 1099511628211ULL;
  }
  return h;
}

struct ByteWriter {
  std::string out;
  void word(std::uint64_t w) { out.append(reinterpret_cast<const char*>(&w), 8); }
  void real(double x) { word(std::bit_cast<std::uint64_t>(x)); }
  void flag(bool b) { word(b ? 1 : 0); }
  void text(const std::string& s) {
    word(s.size());
    out.append(s);
  }
  void words(const std::vector<std::uint64_t>& v) { out.append(reinterpret_cast<const char*>(v.data()), v.size() * 8); }
  /// A vector with its length first (words() writes a vector whose length the reader knows).
  template <class T>
  void list(const std::vector<T>& v) {
    word(v.size());
    for (const T& x : v) one(x);
  }
  void maybe(const std::optional<std::size_t>& v) {
    flag(v.has_value());
    word(v.value_or(0));
  }

 private:
  void one(double x) { real(x); }
  void one(long x) { word(static_cast<std::uint64_t>(x)); }
  void one(unsigned char x) { word(x); }
};

/// Reads what a ByteWriter wrote; throws std::runtime_error naming `where` when the bytes end early.
struct ByteReader {
  const std::string& in;
  std::size_t at;
  std::string where;
  std::uint64_t word() {
    if (at + 8 > in.size()) throw std::runtime_error(where + ": ends early");
    std::uint64_t w;
    std::memcpy(&w, in.data() + at, 8);
    at += 8;
    return w;
  }
  double real() { return std::bit_cast<double>(word()); }
  bool flag() { return word() != 0; }
  std::string text() {
    const std::uint64_t n = word();
    if (n > in.size() - at) throw std::runtime_error(where + ": ends early");
    std::string s = in.substr(at, n);
    at += n;
    return s;
  }
  void words(std::vector<std::uint64_t>& v) {
    for (auto& w : v) w = word();
  }
  template <class T>
  void list(std::vector<T>& v) {
    const std::uint64_t n = word();
    if (n > (in.size() - at) / 8) throw std::runtime_error(where + ": ends early");
    v.resize(n);
    for (T& x : v) one(x);
  }
  std::optional<std::size_t> maybe() {
    const bool has = flag();
    const std::uint64_t v = word();
    return has ? std::optional<std::size_t>(v) : std::nullopt;
  }

 private:
  void one(double& x) { x = real(); }
  void one(long& x) { x = static_cast<long>(word()); }
  void one(unsigned char& x) { x = static_cast<unsigned char>(word()); }
};

}  // namespace rotleak
