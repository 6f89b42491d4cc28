// Re-analysis without simulating: `rotleak fit RUN_OR_SCAN_DIR [--set fit.key=value]...` reads a saved
// run's survival.csv back, fits it under the scene's fit keys with the overrides, and rewrites
// summary.json (the previous one kept as summary.prev.json) and scene.toml, each atomically,
// summary.json last. A scan directory is refitted point by point, then its table.csv and scan.json.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "io/json.hpp"
#include "run/pipeline.hpp"
#include "sim/model/scene.hpp"

namespace rotleak {

/// Only fit.* keys can change without simulating; throws InputError("--set", ...) for any other.
void check_fit_overrides(const std::vector<std::string>& overrides);

/// The saved run in `dir` refitted under `scene` (its own scene with new fit keys); returns the new
/// summary.json, written as above.
json refit_run(const std::filesystem::path& dir, const Scene& scene, std::string* text = nullptr);

/// The scene a run directory was made from, with `overrides` applied (its source kept).
Scene saved_scene(const std::filesystem::path& dir, const std::vector<std::string>& overrides);

struct RefitOutcome {
  bool scan = false;
  std::size_t runs = 0;
  json document;  ///< summary.json of the run, or scan.json of the scan
  std::string
      text;  ///< a run's fits as simulate prints them (analysis/output/run_output.hpp, fit_text); empty for a scan
};

/// A run directory or a scan directory (scan.json), refitted with `overrides` (fit.* keys).
RefitOutcome refit(const std::filesystem::path& dir, const std::vector<std::string>& overrides, const Note& note = {});

}  // namespace rotleak
