// libFuzzer target: survival.csv read back (analysis/output/run_output.hpp read_survival_csv), as rotleak fit and the
// scan's refits read it, for a scene whose grid has 51 rows (t_max 50, survival_dt 1); and, for an input
// holding a line "#--lines", a split run's survival.csv and lines.csv (read_lines_csv). Damage must be a
// std::runtime_error naming the file; a file that is read holds exactly the grid's rows.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "analysis/output/run_output.hpp"
#include "io/scene_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const rotleak::Scene scene = rotleak::parse_scene("[run]\nt_max = 50\n[fit]\nkappa_window = [0, 40]\n");
  // a split run's pair: survival.csv, a line "#--lines", then its lines.csv (read_lines_csv)
  static const rotleak::Scene split = rotleak::parse_scene(
      "[ensemble]\nparticles = 200\nsampling = \"mupo\"\n[run]\nt_max = 50\nsplitting = true\nsplit_every = 10\n"
      "[fit]\nkappa_window = [0, 40]\n");
  // a run of splitting over starts: a first line "#--starts", then its survival.csv
  static const rotleak::Scene starts = rotleak::parse_scene(
      "[run]\nt_max = 50\n[start_splitting]\non = true\nreplicates = 4\n[fit]\nkappa_window = [0, 40]\n");
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::string first = "#--starts\n";
  if (text.rfind(first, 0) == 0) {
    try {
      const rotleak::SurvivalCurve c = rotleak::read_survival_csv(text.substr(first.size()), starts);
      if (!c.replicated || c.E.size() != c.t.size() || c.G.size() != c.t.size()) __builtin_trap();
      for (std::size_t i = 0; i < c.t.size(); ++i) (void)c.P_err(i), (void)c.effective(i), (void)c.log_cov(i, 0);
    } catch (const std::runtime_error& e) {
      if (std::string(e.what()).rfind("survival.csv", 0) != 0) __builtin_trap();
    }
    return 0;
  }
  const std::string mark = "\n#--lines\n";
  if (const auto cut = text.find(mark); cut != std::string::npos) {
    try {
      rotleak::SurvivalCurve c = rotleak::read_survival_csv(text.substr(0, cut + 1), split);
      try {
        rotleak::read_lines_csv(text.substr(cut + mark.size()), split, c);
        for (std::size_t i = 0; i < c.t.size(); ++i) (void)c.P_err(i);
        if (c.G.size() != c.t.size()) __builtin_trap();
      } catch (const std::runtime_error& e) {
        if (std::string(e.what()).rfind("lines.csv", 0) != 0) __builtin_trap();
      }
    } catch (const std::runtime_error& e) {
      if (std::string(e.what()).rfind("survival.csv", 0) != 0) __builtin_trap();
    }
    return 0;
  }
  try {
    const rotleak::SurvivalCurve c = rotleak::read_survival_csv(text, scene);
    if (c.t.size() != scene.survival_bins() + 1) __builtin_trap();
  } catch (const std::runtime_error& e) {
    if (std::string(e.what()).rfind("survival.csv", 0) != 0) __builtin_trap();
  }
  return 0;
}
