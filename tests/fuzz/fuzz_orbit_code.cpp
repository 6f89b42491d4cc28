// libFuzzer target: the orbit-code parser (geometry/orbit_codes.hpp), which reads `rotleak orbits --code` and
// `rotleak verify --orbit`. Any text must parse or be an InputError naming the key (never a crash); a code that
// parses must spell back to the same letters (upper case), and its canonical class and mirror images must be
// codes again (admissible: no TT or BB, cyclically).
#include <cctype>
#include <cstddef>
#include <cstdint>
#include <string>

#include "geometry/orbit_codes.hpp"
#include "numeric/input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  rotleak::OrbitCode code;
  try {
    code = rotleak::parse_orbit_code(text);
  } catch (const rotleak::InputError&) {
    return 0;
  }
  std::string upper;
  for (char c : text) upper += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (rotleak::orbit_code_text(code) != upper) __builtin_trap();
  const rotleak::MpfrPrecision guard(64);
  const std::vector<rotleak::Mpfr> u(code.size(), rotleak::Mpfr(0.25));
  for (const auto& [mx, my] : {std::pair{true, false}, {false, true}, {true, true}}) {
    const auto image = rotleak::mirror_orbit(code, u, mx, my);
    if (image.first.size() != code.size() || image.second.size() != code.size()) __builtin_trap();
    // the image parses again: admissible
    rotleak::parse_orbit_code(rotleak::orbit_code_text(image.first));
  }
  return 0;
}
