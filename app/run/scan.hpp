// Families of scenes: `rotleak scan SCENE --over KEY=VALUES ... --out DIR` runs the product of the
// listed values, each point an ordinary run directory DIR/points/<slug> (run by simulate(), so
// everything that reads a run reads a point), then writes DIR/table.csv and DIR/scan.json from the
// points' summary.json files. Points run one after another with all threads inside each, so the
// table depends only on the inputs. A point whose directory holds a complete run of the same scene
// (its scene.toml compared with the point's scene, not assumed) is skipped: an interrupted scan
// resumes at its unfinished point.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "io/json.hpp"
#include "run/pipeline.hpp"

namespace rotleak {

/// One swept key and its values, each an exact text handed to the scene like `--set KEY=VALUE`.
struct ScanAxis {
  std::string key;
  std::vector<std::string> values;
};

/// Expands a value list: comma-separated items (commas inside parentheses belong to the item),
/// each a literal value kept verbatim (`2/3`, `ln(19)`, `4001/7000`), or
/// `linspace(a, b, n)`: n exact values a + k (b - a) / (n - 1) from decimal a, b (rational
/// arithmetic; printed as a terminating decimal when there is one, else p/q), or
/// `logspace(a, b, n)`: n values from a to b (a, b > 0 decimals) equally spaced in log, the ends as
/// written and the others rounded to 6 significant digits (computed in MPFR, 128 bits), or
/// an omega set (analysis/omega_sets.hpp: rationals(qmax=Q), near(x, e...), nobles(n), sqrtfrac(a, b)).
/// Throws InputError naming `option` and the offending text.
std::vector<std::string> expand_values(const std::string& option, const std::string& text);

/// "KEY=VALUES" (the --over argument). Throws InputError("--over", ...).
ScanAxis parse_axis(const std::string& text);

/// The directory name of a point: its index (zero-padded) and its values, in [A-Za-z0-9.+-_] only.
std::string point_slug(std::size_t index, std::size_t count, const std::vector<ScanAxis>& axes,
                       const std::vector<std::size_t>& choice);

struct ScanOutcome;

struct ScanRequest {
  std::string scene_path;
  std::optional<std::string> scene_text;  ///< the scene itself (a Python Scene's TOML); scene_path then names it
  std::vector<std::string> overrides;     ///< --set, applied before the swept keys
  std::vector<ScanAxis> axes;
  std::filesystem::path out;
  bool force = false;  ///< redo every point
  RunOptions run;      ///< engine, threads and the per-point progress line
  Note note;           ///< per-point status lines (points done, ETA)
  /// The processes sharing the scan (null: current_team()): under mpirun every point's particles are
  /// shared by all ranks (as `rotleak simulate` shares them); rank 0 alone writes and reports.
  const Team* team = nullptr;
  /// Called on rank 0 with the outcome once table.csv and scan.json are written, while the scan still
  /// holds the directory's lock (`rotleak calibrate` writes its files there); may be empty.
  std::function<void(const ScanOutcome&)> finish;
  /// The files finish writes: removed as soon as the lock is held, so that while points run the
  /// directory never shows them from an earlier scan as if complete.
  std::vector<std::string> finish_files;
};

struct ScanOutcome {
  std::filesystem::path dir;
  std::size_t points = 0, ran = 0, skipped = 0;
  json document;    ///< scan.json as written
  std::string csv;  ///< table.csv as written
};

/// The number theory beside a point's omega: the first kScanPartialQuotients certified partial quotients of
/// x = 2 r omega (space-separated), its best approximation of the first kind with denominator <=
/// kScanMaxDen and the signed error x - p/q, and the MUPO covering's zero measure and largest zero gap
/// at delta = kScanCoveringDelta (analysis/covering.hpp).
inline constexpr std::size_t kScanPartialQuotients = 8;
inline constexpr unsigned long kScanMaxDen = 20;  // the small denominators that keep a tail
inline constexpr const char* kScanCoveringDelta = "1e-7";
json omega_number_theory(const Scene& scene);

/// Validates every point's scene first (a bad value fails before any work), runs the points that
/// are not complete, writes table.csv and scan.json atomically. Under MPI every rank calls it; the
/// outcome's document and csv are rank 0's (other ranks get the counts only).
ScanOutcome scan(const ScanRequest& request);

/// table.csv from a scan directory's points (the swept keys, then kappa, kappa_err, alpha,
/// alpha_err, alpha_syst, alpha_bound, tail, regime, tail_end, tau1, tau2, omega_sweep, cf_2r_omega,
/// best_approximation, best_error, covering_zero_measure, covering_max_zero_gap, particles,
/// collisions); summaries carry "scan_values" and "number_theory" beside summary.json's fields; inputs-only, so
/// byte-identical for any thread count and for a resumed scan. Timings are in scan.json only.
std::string scan_table_csv(const std::vector<ScanAxis>& axes, const std::vector<json>& summaries);
/// The scan's table as a person reads it on a terminal (scan.json's points): the swept values, kappa
/// with its error, alpha with its error or its bound ("< 2.3e-3"), the tail class and regime, the
/// particles; aligned columns, three significant digits. table.csv keeps every digit.
std::string scan_table_text(const json& document);

}  // namespace rotleak
