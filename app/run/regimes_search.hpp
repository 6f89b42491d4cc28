// `rotleak regimes SCENE --out DIR`: where the low / mid / high regimes of a rotating leak begin and
// end for the scene's leak size, measured: a coarse log scan over omega (a scan directory,
// DIR/coarse), then bisection in log omega on the measured regime (each probe a one-point scan
// directory DIR/<boundary>/probe-K, so an interrupted search resumes). Each boundary is an interval
// [lo, hi] of omega with the regimes measured at its ends and the particles that decided them.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/json.hpp"
#include "run/scan.hpp"

namespace rotleak {

struct RegimesRequest {
  std::string scene_path;
  std::optional<std::string> scene_text;  ///< the scene itself (a Python Scene's TOML); scene_path then names it
  std::vector<std::string> overrides;     ///< --set, for every probe
  std::string coarse = "logspace(1e-5,1e-1,9)";
  int steps = 4;  ///< bisection steps per boundary (each halves the interval in log omega)
  std::filesystem::path out;
  RunOptions run;
  Note note;
};

/// Runs the search and writes DIR/regimes.json; returns it. Omega values in the boundaries are numbers;
/// a boundary that could not be found is null with its reason under "reasons".
json find_regimes(const RegimesRequest& request);

}  // namespace rotleak
