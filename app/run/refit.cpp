#include "run/refit.hpp"

#include <fstream>
#include <sstream>

#include "analysis/output/run_output.hpp"
#include "analysis/run_summary.hpp"
#include "io/files.hpp"
#include "io/scene_file.hpp"
#include "io/tally_file.hpp"
#include "numeric/input.hpp"
#include "run/pipeline.hpp"
#include "run/scan.hpp"

namespace rotleak {

namespace fs = std::filesystem;

void check_fit_overrides(const std::vector<std::string>& overrides) {
  for (const std::string& o : overrides)
    if (o.rfind("fit.", 0) != 0)
      throw InputError("--set", o, "only fit.* keys change without simulating (run simulate again for the others)");
}

namespace {

/// What `rotleak fit DIR` reads, said when DIR is not one.
InputError not_a_result_directory(const fs::path& dir) {
  return InputError("DIR", "\"" + dir.string() + "\"",
                    "must be a complete run directory (summary.json, survival.csv) or a scan directory (scan.json)");
}

/// The run's survival curve: rebuilt exactly from DIR/tally.bin where the run keeps its tallies (split runs,
/// shards: keeps_tally), else read from survival.csv. A tally that is damaged or made with other
/// inputs than scene.toml's is bad input (exit 2).
SurvivalCurve saved_curve(const fs::path& dir, const Scene& scene, const json& summary) {
  const std::string shown = "\"" + dir.string() + "\"";
  try {
    if (!fs::exists(dir / "tally.bin")) return read_run_curve(dir, scene);
    const TallyFile f = read_tally_file(dir / "tally.bin");
    check_tally_inputs(f, scene, saved_engine(summary), shown);
    if (!f.complete() || f.particles != scene.particles)
      throw InputError("DIR", shown, "tally.bin holds an incomplete run or another particle count");
    return survival_curve(scene, f.tally);
  } catch (const InputError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw InputError("DIR", shown, e.what());  // a damaged file is bad input: exit 2
  }
}

}  // namespace

Scene saved_scene(const fs::path& dir, const std::vector<std::string>& overrides) {
  if (!fs::exists(dir / "summary.json") || !fs::exists(dir / "survival.csv")) throw not_a_result_directory(dir);
  Scene scene = load_scene((dir / "scene.toml").string(), overrides);
  const json old = read_run_summary(dir, read_file(dir / "summary.json"));
  scene.source = old.at("scene").value("source", scene.source);
  return scene;
}

json refit_run(const fs::path& dir, const Scene& scene, std::string* text) {
  const std::string old_text = read_file(dir / "summary.json");
  json s = read_run_summary(dir, old_text);
  RunSummary r;
  r.scene = scene;
  r.curve = saved_curve(dir, scene, s);
  fit_curve(r);
  if (text) *text = fit_text(r);
  s["scene"] = scene_json(scene);
  put_fits(s, r);
  write_file_atomic(dir / "summary.prev.json", old_text);
  write_file_atomic(dir / "scene.toml", scene_to_toml(scene));
  write_file_atomic(dir / "summary.json", s.dump(2) + "\n");  // last: the run is consistent again
  return s;
}

RefitOutcome refit(const fs::path& dir, const std::vector<std::string>& overrides, const Note& note) {
  check_fit_overrides(overrides);
  // a refit rewrites summary.json: refused while a simulate --force or a scan writes the directory
  // (the refit was once silently lost to a run that swapped its directory in afterwards)
  if (!fs::is_directory(dir)) throw not_a_result_directory(dir);
  const DirectoryLock lock(dir, "DIR", "\"" + dir.string() + "\"");
  RefitOutcome out;
  if (!fs::exists(dir / "scan.json")) {
    out.document = refit_run(dir, saved_scene(dir, overrides), &out.text);
    out.runs = 1;
    return out;
  }
  out.scan = true;
  json doc = read_scan_document(dir, read_file(dir / "scan.json"));
  std::vector<ScanAxis> axes;
  for (const json& a : doc.at("axes")) axes.push_back({a.at("key"), a.at("values").get<std::vector<std::string>>()});
  std::vector<json> summaries;
  for (json& row : doc.at("points")) {
    const fs::path pdir = dir / "points" / row.at("point").get<std::string>();
    json s = refit_run(pdir, saved_scene(pdir, overrides));
    for (const char* key : {"kappa", "alpha", "tail", "predicted", "rate_jumps"}) row[key] = s.at(key);
    s["scan_values"] = row.at("values");
    s["number_theory"] = row.at("number_theory");
    summaries.push_back(std::move(s));
    ++out.runs;
    if (note) note("[fit] " + pdir.filename().string() + " refitted");
  }
  json given = doc.value("fit_overrides", json::array());
  for (const std::string& o : overrides) given.push_back(o);
  doc["fit_overrides"] = given;
  write_file_atomic(dir / "table.csv", scan_table_csv(axes, summaries));
  write_file_atomic(dir / "scan.json", doc.dump(2) + "\n");
  out.document = doc;
  return out;
}

}  // namespace rotleak
