// `rotleak calibrate SCENE --seeds K --out DIR`: are my error bars honest here? K runs of the scene
// that differ only in ensemble.seed (first_seed .. first_seed + K - 1) are run as a scan over the seed
// (DIR/points/, table.csv, scan.json: threads, MPI ranks, resume and refit as for any scan), and the
// spread of every statistic across them is compared with the errors each run reports (analysis/
// calibration.hpp): DIR/calibration.csv for P(t) at every grid time, DIR/calibration.json for P's
// summary, every statistic summary.json reports with an error (kappa, alpha, ...; stat. alone and
// with its systematic), alpha's upper bounds, and the fits of the pooled curve (all K runs as one).
// Schemas in docs/output.md; the picture is calibration.png (rotleak plot DIR).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/json.hpp"
#include "run/pipeline.hpp"

namespace rotleak {

struct CalibrateRequest {
  std::string scene_path;
  std::optional<std::string> scene_text;  ///< the scene itself (a Python Scene's TOML); scene_path then names it
  std::vector<std::string> overrides;     ///< --set, for every seed
  std::uint64_t seeds = 0;                ///< K >= 2
  std::uint64_t first_seed = 1;
  std::filesystem::path out;
  bool force = false;  ///< redo every seed's run
  RunOptions run;
  Note note;
  const Team* team = nullptr;  ///< null: current_team()
};

struct CalibrateOutcome {
  std::filesystem::path dir;
  std::size_t ran = 0, skipped = 0;
  json document;    ///< calibration.json as written (rank 0)
  std::string csv;  ///< calibration.csv as written (rank 0)
};

/// Runs the seeds not yet complete, then writes calibration.csv and calibration.json (last) under the
/// scan's lock. Throws InputError for bad input (--seeds below 2, seeds past 2^64 - 1, a bad scene).
CalibrateOutcome calibrate(const CalibrateRequest& request);

/// calibration.json from the K runs in `point_dirs` (each a complete run directory of the same scene
/// but its seed); `csv` receives calibration.csv. What calibrate writes, without running anything.
json calibration_document(const std::vector<std::filesystem::path>& point_dirs, std::string& csv);

/// What a person reads on the terminal: the statistics' table and P's summary over its resolved times.
std::string calibration_text(const json& document);

}  // namespace rotleak
