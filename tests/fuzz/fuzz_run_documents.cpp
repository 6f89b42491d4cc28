// libFuzzer target: the JSON documents of run and scan directories as rotleak fit reads them
// (analysis/output/run_output.hpp: read_run_summary, read_scan_document). The first byte picks the reader. Damage
// must be an InputError with one line naming DIR; a document that is accepted must have what its
// readers then take from it (a summary's scene; a scan's axes, points and their values).
#include <cstddef>
#include <cstdint>
#include <string>

#include "analysis/output/run_output.hpp"
#include "numeric/input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    if (data[0] & 1) {
      const rotleak::json doc = rotleak::read_scan_document("fuzz", text);
      for (const rotleak::json& p : doc.at("points"))
        for (const rotleak::json& a : doc.at("axes"))
          (void)p.at("values").at(a.at("key").get<std::string>()).get<std::string>();
    } else {
      (void)rotleak::read_run_summary("fuzz", text).at("scene").value("source", std::string());
    }
  } catch (const rotleak::InputError& e) {
    if (std::string(e.what()).rfind("DIR = ", 0) != 0) __builtin_trap();
  }
  return 0;
}
