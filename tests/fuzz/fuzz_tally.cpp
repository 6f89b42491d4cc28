// libFuzzer target: the tally-file reader (io/tally_file.hpp), which reads checkpoints (DIR.checkpoint),
// shards' tally.bin and what MPI ranks send. A damaged or foreign file must be a std::runtime_error
// naming it (never a crash, an allocation of what the header claims, or a hang); a file that is read
// must encode to bytes that decode to the same encoding.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "io/tally_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string bytes(reinterpret_cast<const char*>(data), size);
  // Most mutations break the checksum, and the reader stops there. Inputs that end in "#seal" are sealed
  // without those 5 bytes (a valid checksum over the mutated contents), so the header, the sizes and the
  // arrays behind the checksum are fuzzed too.
  if (bytes.size() >= 13 && bytes.compare(bytes.size() - 5, 5, "#seal") == 0) {
    bytes.resize(bytes.size() - 5 - 8);
    bytes = rotleak::sealed_tally_bytes(std::move(bytes));
  }
  try {
    const rotleak::TallyFile f = rotleak::decode_tally_file(bytes, "fuzz.bin");
    const std::string again = rotleak::encode_tally_file(f);
    if (rotleak::encode_tally_file(rotleak::decode_tally_file(again, "again")) != again) __builtin_trap();
  } catch (const std::runtime_error&) {
  }
  return 0;
}
