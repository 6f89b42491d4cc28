// libFuzzer target: the orbit search's checkpoint reader (verify/orbit_checkpoint.hpp), which reads
// DIR.checkpoint when `rotleak orbits` resumes. A damaged file must be a std::runtime_error naming it (never a
// crash or a hang); a file that is read holds periods in order, each with the orbits its line announced.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "verify/orbit_checkpoint.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const rotleak::OrbitCheckpoint c = rotleak::parse_orbit_checkpoint(text, "fuzz.checkpoint");
    std::size_t orbits = 0;
    for (std::size_t i = 0; i < c.periods.size(); ++i) {
      if (c.periods[i].period != static_cast<int>(i) + 2) __builtin_trap();
      orbits += c.periods[i].proven;
    }
    if (orbits != c.orbits.size()) __builtin_trap();
  } catch (const std::runtime_error&) {
  }
  return 0;
}
