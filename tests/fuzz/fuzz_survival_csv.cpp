// libFuzzer target: survival.csv read back (io/run_output.hpp read_survival_csv), as rotleak fit and the
// scan's refits read it, for a scene whose grid has 51 rows (t_max 50, survival_dt 1). Damage must be a
// std::runtime_error naming the file and line; a file that is read holds exactly the grid's rows.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "io/run_output.hpp"
#include "io/scene_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const rotleak::Scene scene = rotleak::parse_scene("[run]\nt_max = 50\n[fit]\nkappa_window = [0, 40]\n");
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const rotleak::SurvivalCurve c = rotleak::read_survival_csv(text, scene);
    if (c.t.size() != scene.survival_bins() + 1) __builtin_trap();
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).rfind("survival.csv", 0) != 0) __builtin_trap();
  }
  return 0;
}
