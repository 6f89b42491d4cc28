// A simulate run directory from a RunSummary: survival.csv, fc.csv, escapes.csv, scene.toml and
// summary.json (written last: its presence marks a complete run), each written atomically. The
// summary.json schema is documented in docs/output.md.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "analysis/output/prediction_output.hpp"
#include "analysis/run_summary.hpp"
#include "analysis/tail_model.hpp"
#include "io/files.hpp"
#include "io/json.hpp"

namespace rotleak {

/// survival.csv: header t,survivors,P.
std::string survival_csv(const SurvivalCurve& curve);
/// fc.csv: s (bin centre), then per window the normalised density and the raw count.
std::string density_csv(const Scene& scene, const Tally& tally);
/// escapes.csv: id,fate,t,s,collisions, and with `leak_column` (a scene of several leaks) the escape's leak.
std::string escapes_csv(std::uint64_t first_id, const std::vector<EscapeRecord>& records, bool leak_column = false);
/// leaks.csv of a scene with several leaks: each survival bin's [t_from, t_to) and its escapes through each leak.
std::string leaks_csv(const Scene& scene, const Tally& tally);

/// A survival.csv back as a curve of the scene that wrote it (weighted runs: the second moment from
/// P_err, Q = N P_err^2 + P^2). Throws std::runtime_error naming the line on a malformed row.
SurvivalCurve read_survival_csv(const std::string& text, const Scene& scene);

/// lines.csv of a split run: per grid time t, P, R (before the allowance), lines_alive, unsplit_lines,
/// unsplit_P, then per weight class c that held unsplit lines lines_c<c>, P_c<c>, var_c<c> (docs/output.md).
std::string lines_csv(const SurvivalCurve& curve);
/// A split run's curve from survival.csv read back (c, read_survival_csv) and its lines.csv: the parts
/// finish_lines_curve rebuilds the groups and the allowance from, so that P_err, the tail's covariance and
/// unresolved_from are the run's own, bit for bit. Throws std::runtime_error naming lines.csv and the line on
/// damage, or where its P differs from survival.csv's.
void read_lines_csv(const std::string& text, const Scene& scene, SurvivalCurve& c);
/// A run directory's curve from its files: survival.csv, and lines.csv where the run is split and has one
/// (a directory written before lines.csv existed gives P_err from survival.csv, without the groups).
SurvivalCurve read_run_curve(const std::filesystem::path& dir, const Scene& scene);

/// A run's summary.json text, checked (valid JSON, an object of a simulate run with its scene);
/// otherwise an InputError (key DIR, value `dir`) with the reason the Python reader (rotleak.read_run)
/// gives.
json read_run_summary(const std::filesystem::path& dir, const std::string& text);
/// A scan's scan.json text, checked: an object of a scan whose axes hold a key and text values and whose
/// points name a directory under points/ with the swept values; otherwise an InputError (key DIR).
json read_scan_document(const std::filesystem::path& dir, const std::string& text);
/// The fit objects of summary.json (kappa, alpha, tail_exponent, tail, rate_jumps, predicted), set in
/// place: `rotleak fit` replaces them in a saved summary.json keeping every other field.
void put_fits(json& s, const RunSummary& r);
/// A scene on any table (or with several leaks): summary.json's "table" (kind, loops, area, perimeter, mean free
/// path, small-hole rate) and "leaks" (each leak's keys, its escapes and their share of the particles).
void put_table(json& s, const RunSummary& r);
/// summary.json of a run whose directory holds `files`.
/// The sampling scheme and, for weighted runs, its parameters and the effective survivors at a few times.
json sampling_json(const Scene& scene, const SurvivalCurve& curve);
/// summary.json's "splitting" of a split run: its parameters, levels, population, lines alive (docs/output.md).
json splitting_json(const Scene& scene, const Tally& tally, const SurvivalCurve& curve);
/// summary.json's "start_splitting": the stratum, levels, factors, acceptance and P at a few times.
json start_splitting_json(const Scene& scene, const IcSplitRun& run, const SurvivalCurve& curve);
json summary_json(const RunSummary& s, const std::vector<std::string>& files);
/// The few lines a person reads after a run (kappa, alpha, z, warnings).
std::string summary_text(const RunSummary& s);
/// The fits' lines of summary_text (kappa, alpha, alpha_C, z, C, the tail's class and the model's verdict): what
/// `rotleak fit` prints of a refitted run, as simulate prints them.
std::string fit_text(const RunSummary& s);

/// summary.json's "execution" (audit.json's too): everything that says how a run went, not what it
/// found: the build (`rotleak.version`, `rotleak.git`), the host, then `fields` (threads, ranks,
/// timings, the kernel). Runs that must agree compare their documents without this one key.
json execution_json(json fields);

/// For commands whose main document has its own name (audit.json): summary.json with the version,
/// the command, the scene and the files, written last; then commits the directory.
void write_directory_summary(RunDirectory& dir, const std::string& command, const std::string& scene_source,
                             std::vector<std::string> files);

/// The schema of a run's summary.json (its "schema" key); readers refuse another.
inline constexpr int kRunSchema = 1;

/// Every file of a run as the bytes write_run writes (survival.csv, fc.csv, escapes.csv, scene.toml,
/// summary.json, in that order, each only when the scene asks for it), and summary.json as a document:
/// what the Python module hands over without touching the disk. `written`: files the caller adds to
/// the directory itself (listed in summary.json).
struct RunTexts {
  std::vector<std::pair<std::string, std::string>> files;  ///< (name, content)
  json summary;
};
RunTexts run_texts(const RunSummary& s, const std::vector<std::string>& written = {});

/// Writes every file of the run (in their order: summary.json, last, marks a complete run) into the staged
/// directory and commits it; returns summary.json.
json write_run(RunDirectory& dir, RunTexts texts);

}  // namespace rotleak
