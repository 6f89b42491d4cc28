// libFuzzer target: a certified sample's checkpoint reader (verify/certify_checkpoint.hpp), which reads
// DIR.checkpoint when `rotleak certify --sample` resumes. A damaged file must be a std::runtime_error naming it
// (never a crash or a hang); a file that is read holds distinct ids, finite times in order, bits in range.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <set>
#include <stdexcept>
#include <string>

#include "verify/certify_checkpoint.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const rotleak::CertifyCheckpoint c = rotleak::parse_certify_checkpoint(text, "fuzz.checkpoint");
    std::set<std::uint64_t> ids;
    for (const rotleak::ParticleEscape& e : c.particles) {
      if (!ids.insert(e.id).second) __builtin_trap();
      if (!(std::isfinite(e.t_lo) && std::isfinite(e.t_hi) && e.t_lo <= e.t_hi)) __builtin_trap();
      if (e.bits < 0 || e.bits > (1L << 22)) __builtin_trap();
    }
  } catch (const std::runtime_error&) {
  }
  return 0;
}
