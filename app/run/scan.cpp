#include "run/scan.hpp"

#include <mpfr.h>

#include <gmpxx.h>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>

#include "analysis/continued_fraction.hpp"
#include "analysis/covering.hpp"
#include "analysis/omega_sets.hpp"
#include "analysis/output/run_output.hpp"
#include "io/files.hpp"
#include "io/scene_file.hpp"
#include "io/tally_file.hpp"
#include "numeric/exact.hpp"
#include "numeric/input.hpp"
#include "run/refit.hpp"
#include "run/team.hpp"

namespace rotleak {

namespace fs = std::filesystem;

namespace {

/// A rational as the text a scene reads exactly: a terminating decimal when the denominator is
/// 2^i 5^j, else p/q.
std::string exact_text(const mpq_class& q) {
  mpz_class den = q.get_den();
  unsigned twos = 0, fives = 0;
  while (mpz_divisible_ui_p(den.get_mpz_t(), 2)) {
    den /= 2;
    ++twos;
  }
  while (mpz_divisible_ui_p(den.get_mpz_t(), 5)) {
    den /= 5;
    ++fives;
  }
  if (den != 1) return q.get_num().get_str() + "/" + q.get_den().get_str();
  const unsigned digits = std::max(twos, fives);
  mpz_class ten_d;
  mpz_ui_pow_ui(ten_d.get_mpz_t(), 10, digits);
  const mpz_class scaled = q.get_num() * ten_d / q.get_den();  // exact: the denominator divides 10^digits
  const bool neg = scaled < 0;
  std::string s = (neg ? mpz_class(-scaled) : scaled).get_str();
  if (digits > 0) {
    if (s.size() <= digits) s.insert(0, digits + 1 - s.size(), '0');
    s.insert(s.size() - digits, ".");
  }
  return neg ? "-" + s : s;
}

std::vector<std::string> range_values(const std::string& option, const std::string& item, bool log) {
  const std::string name = log ? "logspace" : "linspace";
  const std::string usage = name + "(a, b, n): decimal ends" + (log ? " > 0" : "") + " and an integer n in [1, 10000]";
  if (item.back() != ')') throw InputError(option, item, usage);
  const std::vector<std::string> args = split_top(option, item.substr(name.size() + 1, item.size() - name.size() - 2));
  if (args.size() != 3) throw InputError(option, item, usage);
  mpq_class a, b;
  long n = 0;
  try {
    a = parse_decimal(args[0]);
    b = parse_decimal(args[1]);
    std::size_t used = 0;
    n = std::stol(args[2], &used);
    if (used != args[2].size()) throw std::invalid_argument("n");
  } catch (const std::exception&) {
    throw InputError(option, item, usage);
  }
  if (n < 1 || n > 10000) throw InputError(option, item, usage);
  if (log && (sgn(a) <= 0 || sgn(b) <= 0)) throw InputError(option, item, usage);
  std::vector<std::string> out;
  for (long k = 0; k < n; ++k) {
    if (k == 0 || (k == n - 1)) {
      out.push_back(k == 0 ? args[0] : args[1]);  // the ends exactly as written
      continue;
    }
    if (!log) {
      out.push_back(exact_text(a + (b - a) * k / (n - 1)));
      continue;
    }
    // 10^(log10 a + k/(n-1) (log10 b - log10 a)) = a (b/a)^(k/(n-1)), in MPFR, printed to 6 digits
    mpfr_t x, y, e;
    mpfr_inits2(128, x, y, e, static_cast<mpfr_ptr>(nullptr));
    const mpq_class ratio = b / a;
    mpfr_set_q(x, ratio.get_mpq_t(), MPFR_RNDN);
    mpfr_set_si(e, k, MPFR_RNDN);
    mpfr_div_si(e, e, n - 1, MPFR_RNDN);
    mpfr_pow(x, x, e, MPFR_RNDN);
    mpfr_set_q(y, a.get_mpq_t(), MPFR_RNDN);
    mpfr_mul(x, x, y, MPFR_RNDN);
    char buf[64];
    mpfr_snprintf(buf, sizeof buf, "%.5Re", x);
    mpfr_clears(x, y, e, static_cast<mpfr_ptr>(nullptr));
    out.push_back(buf);
  }
  if (n == 1) out.resize(1);
  return out;
}

std::string csv_number(const json& v) {
  if (v.is_null()) return "";
  if (v.is_number_unsigned()) return std::to_string(v.get<std::uint64_t>());
  if (v.is_number_integer()) return std::to_string(v.get<std::int64_t>());
  return shortest(v.get<double>());
}

/// A swept value as an exact value, where it is one ("2/3+1e-4", "golden - 1", "1e4"); a word such as a sampling
/// scheme is none.
std::optional<ExactReal> exact_value(const std::string& text) {
  try {
    return ExactReal::parse(text);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

/// A CSV field: quoted when it holds a comma or a quote.
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"") == std::string::npos) return s;
  std::string q = "\"";
  for (char ch : s) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

}  // namespace

json omega_number_theory(const Scene& scene) {
  json out;
  if (scene.on_table()) {  // 2 r omega and the covering are the stadium's theory (docs/tables.md): empty columns
    out["cf_2r_omega"] = "";
    const std::vector<LeakSpec> leaks = leak_specs(scene);  // one leak's omega; none for several
    out["omega_value"] = leaks.size() == 1 ? json(leaks[0].omega.to_double()) : json(nullptr);
    out["covering_zero_measure"] = nullptr;
    out["covering_max_zero_gap"] = nullptr;
    return out;
  }
  const ExactReal x = ExactReal::parse("2") * scene.r * scene.omega;
  const CertifiedExpansion cf = certified_cf(x, kScanPartialQuotients);
  std::string terms;
  for (std::size_t i = 0; i < cf.terms.size() && i < kScanPartialQuotients; ++i)
    terms += (i ? " " : "") + cf.terms[i].get_str();
  out["cf_2r_omega"] = terms;
  out["omega_value"] = scene.omega.to_double();  // the exact omega rounded once (MPFR, to nearest): a number to plot
  const BestApproximations best = best_approximations(x, mpz_class(static_cast<unsigned long>(kScanMaxDen)));
  if (!best.list.empty()) {
    out["best_approximation"] = best.list.back().text();
    out["best_error"] = signed_error(x, best.list.back()).approx;
  }
  CoveringInput in;
  in.omega = scene.omega;
  in.delta = ExactReal::parse(kScanCoveringDelta);
  in.lambda = scene.width;
  in.d = scene.d;
  in.r = scene.r;
  const Covering c = mupo_covering(in);
  out["covering_delta"] = kScanCoveringDelta;
  out["covering_zero_measure"] = c.zero_measure;
  out["covering_max_zero_gap"] = c.max_zero_gap;
  return out;
}

std::vector<std::string> expand_values(const std::string& option, const std::string& text) {
  std::vector<std::string> values;
  for (const std::string& item : split_top(option, text)) {
    if (item.empty()) throw InputError(option, text, "an empty value in the list");
    if (item.rfind("linspace(", 0) == 0 || item.rfind("logspace(", 0) == 0) {
      for (std::string& v : range_values(option, item, item[1] == 'o')) values.push_back(std::move(v));
    } else if (auto set = expand_omega_set(option, item)) {
      for (std::string& v : *set) values.push_back(std::move(v));
    } else {
      values.push_back(item);
    }
  }
  return values;
}

ScanAxis parse_axis(const std::string& text) {
  const auto eq = text.find('=');
  const std::string allowed =
      "KEY=VALUES with KEY a scene key section.key and VALUES a comma list of values, linspace(a, b, n), "
      "logspace(a, b, n), rationals(qmax=Q), near(x, e1, ... [, signs=both]), nobles(n) or sqrtfrac(a, b)";
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) throw InputError("--over", text, allowed);
  ScanAxis axis;
  axis.key = trim(text.substr(0, eq));
  if (axis.key.find('.') == std::string::npos) throw InputError("--over", text, allowed);
  axis.values = expand_values("--over " + axis.key, text.substr(eq + 1));
  // each point once: a value listed twice (1,1, or 1 and 1.0 of an exact key) once ran its point twice
  std::vector<std::string> seen;
  for (const std::string& v : axis.values) {
    const std::optional<ExactReal> x = exact_value(v);
    const std::string same = x ? x->text() : v;  // the value's canonical spelling, where it is an exact value
    if (std::find(seen.begin(), seen.end(), same) != seen.end())
      throw InputError("--over", text, "gives " + axis.key + " = " + v + " twice: list each value once");
    seen.push_back(same);
  }
  return axis;
}

std::string point_slug(std::size_t index, std::size_t count, const std::vector<ScanAxis>& axes,
                       const std::vector<std::size_t>& choice) {
  const int width = static_cast<int>(std::to_string(count > 0 ? count - 1 : 0).size());
  char head[32];
  std::snprintf(head, sizeof head, "p%0*zu", width, index);
  std::string slug = head;
  for (std::size_t a = 0; a < axes.size(); ++a) {
    const std::string& key = axes[a].key;
    slug += "_" + key.substr(key.rfind('.') + 1) + "-";
    for (char ch : axes[a].values[choice[a]]) {
      if (std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '+' || ch == '-')
        slug += ch;
      else if (ch == '/')
        slug += 'o';  // 2/3 -> 2o3
      else
        slug += '_';
    }
  }
  if (slug.size() > 120) slug.resize(120);  // the index keeps it unique
  return slug;
}

std::string scan_table_csv(const std::vector<ScanAxis>& axes, const std::vector<json>& summaries) {
  std::string out;
  for (const ScanAxis& a : axes) out += csv_field(a.key) + ",";
  out +=
      "omega_value,kappa,kappa_err,alpha,alpha_err,alpha_syst,alpha_bound,tail,regime,tail_end,tail_amplitude,tail_"
      "amplitude_err,"
      "tail_amplitude_syst,predicted_tail,predicted_amplitude,predicted_tail_end,tau1,tau2,omega_sweep,cf_2r_omega,"
      "best_approximation,best_error,covering_zero_measure,covering_max_zero_gap,particles,collisions\n";
  for (const json& s : summaries) {
    const json& swept = s.at("scan_values");
    for (const ScanAxis& a : axes) out += csv_field(swept.at(a.key).get<std::string>()) + ",";
    // the point's omega as a number (empty where its number theory was saved before omega_value existed)
    const json& theory = s.at("number_theory");
    out += (theory.contains("omega_value") ? csv_number(theory.at("omega_value")) : std::string()) + ",";
    const json& k = s.at("kappa");
    const json& al = s.at("alpha");
    out += csv_number(k.at("value")) + "," + (k.at("value").is_null() ? "" : csv_number(k.at("error"))) + ",";
    // alpha's window systematic (absent from summaries written before it existed: empty)
    const std::string syst = al.contains("systematic") ? csv_number(al.at("systematic")) : std::string();
    out += csv_number(al.at("value")) + "," + csv_number(al.at("error")) + "," + syst + "," +
           csv_number(al.at("upper_bound")) + ",";
    const json& tail = s.at("tail");
    const json& pred = s.at("predicted");
    out += tail.at("class").get<std::string>() + "," + tail.at("regime").get<std::string>() + "," +
           csv_number(tail.at("tail_end")) + ",";
    // the tail amplitude (absent from summaries written before it existed: empty)
    if (tail.contains("amplitude")) {
      const json& am = tail.at("amplitude");
      out +=
          csv_number(am.at("value")) + "," + csv_number(am.at("error")) + "," + csv_number(am.at("systematic")) + ",";
    } else {
      out += ",,,";
    }
    // the covering model's tail (absent from summaries written before it existed: empty)
    if (pred.contains("tail") && pred.at("tail").is_object()) {
      const json& pt = pred.at("tail");
      out += std::string(pt.at("forms").get<bool>() ? "forms" : "none") + "," + csv_number(pt.at("amplitude")) + "," +
             csv_number(pt.at("end")) + ",";
    } else {
      out += ",,,";
    }
    out += csv_number(pred.at("tau1")) + "," + csv_number(pred.at("tau2")) + "," + csv_number(pred.at("omega_sweep")) +
           ",";
    const json& nt = s.at("number_theory");
    out += nt.at("cf_2r_omega").get<std::string>() + "," + nt.value("best_approximation", std::string()) + "," +
           (nt.contains("best_error") ? csv_number(nt.at("best_error")) : std::string()) + "," +
           csv_number(nt.at("covering_zero_measure")) + "," + csv_number(nt.at("covering_max_zero_gap")) + ",";
    out += csv_number(s.at("particles")) + "," + csv_number(s.at("collisions")) + "\n";
  }
  return out;
}

std::string scan_table_text(const json& document) {
  const auto g3 = [](const json& v) {
    if (!v.is_number()) return std::string("-");
    char b[32];
    std::snprintf(b, sizeof b, "%.3g", v.get<double>());
    return std::string(b);
  };
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> head;
  for (const json& a : document.at("axes")) head.push_back(a.at("key").get<std::string>());
  for (const char* h : {"kappa", "alpha", "C", "C model", "tail", "regime", "particles"}) head.emplace_back(h);
  rows.push_back(head);
  for (const json& p : document.at("points")) {
    std::vector<std::string> r;
    for (const json& a : document.at("axes")) r.push_back(p.at("values").at(a.at("key").get<std::string>()));
    const json &k = p.at("kappa"), &al = p.at("alpha");
    r.push_back(k.at("value").is_number() ? g3(k.at("value")) + " +- " + g3(k.at("error")) : "-");
    const std::string syst =
        al.contains("systematic") && al.at("systematic").is_number() ? " +- " + g3(al.at("systematic")) : "";
    r.push_back(al.at("value").is_number()         ? g3(al.at("value")) + " +- " + g3(al.at("error")) + syst
                : al.at("upper_bound").is_number() ? "< " + g3(al.at("upper_bound"))
                                                   : "-");
    const json& tail = p.at("tail");
    const json am = tail.contains("amplitude") ? tail.at("amplitude") : json::object();
    r.push_back(am.contains("value") && am.at("value").is_number()
                    ? g3(am.at("value")) + " +- " + g3(am.at("error")) + " +- " + g3(am.at("systematic"))
                    : "-");
    // the covering model's C where it predicts a tail ("none" where it does not; "-" before it existed)
    const json& pred = p.at("predicted");
    const json model = pred.contains("tail") ? pred.at("tail") : json(nullptr);
    r.push_back(model.is_object() ? (model.at("forms").get<bool>() ? g3(model.at("amplitude")) : "none") : "-");
    r.push_back(p.at("tail").at("class").get<std::string>());
    r.push_back(p.at("tail").at("regime").get<std::string>());
    r.push_back(csv_number(p.at("particles")));
    rows.push_back(std::move(r));
  }
  std::vector<std::size_t> width(head.size(), 0);
  for (const auto& r : rows)
    for (std::size_t c = 0; c < r.size(); ++c) width[c] = std::max(width[c], r[c].size());
  std::string out;
  for (const auto& r : rows) {
    for (std::size_t c = 0; c < r.size(); ++c)
      out += r[c] + (c + 1 < r.size() ? std::string(width[c] - r[c].size() + 2, ' ') : std::string());
    out += '\n';
  }
  return out;
}

namespace {

/// One point of a scan: its overrides (--set, then one value per axis), directory name, swept values,
/// its plan, the scene validated once (checked_plan), and what is recorded about it.
struct ScanPoint {
  std::vector<std::string> overrides;
  std::string slug;
  std::string inputs;  ///< the simulation's inputs, fit keys left out: a point whose fits differ is refitted
  json values, number_theory, fit;
  std::optional<RunPlan> plan;  ///< set for every point by scan_points
};

/// Every point of the scan (the last axis varies fastest), each validated before any work.
std::vector<ScanPoint> scan_points(const ScanRequest& req) {
  if (req.axes.empty()) throw InputError("--over", "", "at least one KEY=VALUES");
  for (std::size_t a = 0; a < req.axes.size(); ++a)
    for (std::size_t b = 0; b < a; ++b)
      if (req.axes[a].key == req.axes[b].key) throw InputError("--over", req.axes[a].key, "each key swept once");
  std::size_t count = 1;
  for (const ScanAxis& a : req.axes) count *= a.values.size();
  if (count > 100000) throw InputError("--over", std::to_string(count) + " points", "at most 100000 points");
  std::vector<ScanPoint> points(count);
  std::vector<std::size_t> choice(req.axes.size(), 0);
  for (std::size_t i = 0; i < count; ++i) {
    std::size_t rest = i;
    for (std::size_t a = req.axes.size(); a-- > 0;) {
      choice[a] = rest % req.axes[a].values.size();
      rest /= req.axes[a].values.size();
    }
    ScanPoint& p = points[i];
    p.overrides = req.overrides;
    p.values = json::object();
    for (std::size_t a = 0; a < req.axes.size(); ++a) {
      p.overrides.push_back(req.axes[a].key + "=" + req.axes[a].values[choice[a]]);
      p.values[req.axes[a].key] = req.axes[a].values[choice[a]];
    }
    p.slug = point_slug(i, count, req.axes, choice);
    p.plan = checked_plan(req.scene_path, p.overrides, req.run, req.scene_text);
    const Scene& scene = p.plan->scene();
    p.inputs = simulation_inputs(scene, to_string(req.run.engine));
    p.fit = scene_json(scene).at("fit");
    p.number_theory = omega_number_theory(scene);
  }
  return points;
}

/// The scan directory, made and locked by rank 0 for the whole scan: a second scan (or a refit, or a
/// simulate into it) is refused while this one holds it; one once returned 0 with its points orphaned
/// from the table. The files `finish` writes are removed first.
std::unique_ptr<DirectoryLock> lock_scan_directory(const ScanRequest& req, const fs::path& dir) {
  const std::string shown = "\"" + req.out.string() + "\"";
  std::error_code ec;
  if (!dir.parent_path().empty()) fs::create_directories(dir.parent_path(), ec);
  if (ec) throw InputError("--out", shown, "cannot create " + dir.parent_path().string() + " (" + ec.message() + ")");
  auto lock = std::make_unique<DirectoryLock>(dir, "--out", shown);
  fs::create_directories(dir / "points", ec);
  if (ec) throw InputError("--out", shown, "cannot create " + (dir / "points").string() + " (" + ec.message() + ")");
  for (auto it = req.finish_files.rbegin(); it != req.finish_files.rend(); ++it) fs::remove(dir / *it, ec);
  return lock;
}

/// points.json: slug -> the inputs its run was made from, updated after each point commits. A point
/// counts as done only when its directory is complete and its recorded inputs equal this point's.
class ScanManifest {
 public:
  explicit ScanManifest(fs::path path) : path_(std::move(path)) {
    if (!fs::exists(path_)) return;
    try {
      doc_ = json::parse(read_file(path_));
    } catch (const std::exception&) {
      doc_ = json::object();  // unreadable: no point is recorded
    }
    // not an object ([] once failed the first record with exit 1): no point is recorded either, so a
    // complete point is replaced only under --force
    if (!doc_.is_object()) doc_ = json::object();
  }
  std::optional<std::string> recorded(const std::string& slug) const {
    if (!doc_.contains(slug) || !doc_[slug].is_string()) return std::nullopt;
    return doc_[slug].get<std::string>();
  }
  void record(const ScanPoint& p, bool write) {
    doc_[p.slug] = p.inputs;
    if (write) write_file_atomic(path_, doc_.dump(1) + "\n");
  }
  void forget(const std::string& slug, bool write) {
    if (doc_.erase(slug) && write) write_file_atomic(path_, doc_.dump(1) + "\n");
  }

 private:
  fs::path path_;
  json doc_ = json::object();
};

/// A point already run from other inputs is replaced only with --force (a 3*10^5-particle point was once
/// overwritten by a 1000-particle one): refused before anything runs.
void refuse_other_inputs(const ScanRequest& req, const std::vector<ScanPoint>& points, const ScanManifest& manifest,
                         const fs::path& points_dir) {
  if (req.force) return;
  for (const ScanPoint& p : points) {
    if (!fs::exists(points_dir / p.slug / "summary.json")) continue;
    const std::optional<std::string> before = manifest.recorded(p.slug);
    if (before == p.inputs) continue;
    throw InputError("--out", "\"" + req.out.string() + "\"",
                     "point " + p.slug + " holds a run of other inputs (" +
                         (before ? inputs_difference(*before, p.inputs) + ", there vs here"
                                 : std::string("not recorded in points.json")) +
                         "); pass --force to replace it, or choose another --out");
  }
}

/// Finished points in the directory that this scan does not list would stay on disk, out of its table (a scan
/// of omega = 1/5 into a scan of 1, 2/3, 3/4 once rewrote the table with its own point alone): refused, naming
/// them, before anything runs; under --force they are removed, so the directory holds this scan only.
void refuse_points_left_out(const ScanRequest& req, const std::vector<ScanPoint>& points, ScanManifest& manifest,
                            const fs::path& points_dir, bool lead) {
  std::vector<std::string> listed, left;
  for (const ScanPoint& p : points) listed.push_back(p.slug);
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(points_dir, ec)) {
    const std::string slug = e.path().filename().string();
    if (e.is_directory() && fs::exists(e.path() / "summary.json") &&
        std::find(listed.begin(), listed.end(), slug) == listed.end())
      left.push_back(slug);
  }
  if (left.empty()) return;
  std::sort(left.begin(), left.end());
  if (!req.force) {
    std::string names;
    for (std::size_t i = 0; i < left.size() && i < 4; ++i) names += (i ? ", " : "") + left[i];
    if (left.size() > 4) names += ", ... (" + std::to_string(left.size()) + ")";
    throw InputError("--out", "\"" + req.out.string() + "\"",
                     "holds finished points this scan does not list (" + names +
                         "): give their values too, in their order, to extend that scan (finished points are "
                         "kept), pass --force to remove them, or choose another --out");
  }
  if (!lead) return;
  for (const std::string& slug : left) {
    fs::remove_all(points_dir / slug, ec);
    manifest.forget(slug, true);
  }
}

/// A complete point's summary as saved, refitted first if its fit keys differ from the point's.
json saved_point(const ScanPoint& p, const fs::path& pdir, bool& refitted) {
  json saved = json::parse(read_file(pdir / "summary.json"));
  refitted = !(saved.at("scene").contains("fit") && saved.at("scene").at("fit") == p.fit);
  return refitted ? refit_run(pdir, p.plan->scene()) : saved;
}

/// Runs one point into pdir (every rank: its blocks shared among them, rank 0 writes); returns its
/// summary.json as written. A point killed in the middle continues from its checkpoint
/// (points/SLUG.checkpoint) when its inputs match; --force starts every point afresh.
json run_point(const ScanRequest& req, const ScanPoint& p, const fs::path& pdir, const Team& team, const Note& note) {
  SimulateRequest sr;
  sr.scene_path = req.scene_path;
  sr.scene_text = req.scene_text;
  sr.overrides = p.overrides;
  sr.plan = p.plan;
  sr.out = pdir;
  sr.force = true;  // an incomplete or outdated point is replaced
  sr.resume = req.force ? Resume::no : Resume::if_any;
  sr.run = req.run;
  if (team.rank() != 0) sr.run.progress = {};
  sr.note = note;
  sr.team = &team;
  return simulate(sr).document;
}

/// The row scan.json keeps of a point, from its summary.
json scan_row(const ScanPoint& p, const json& s) {
  json row = {{"point", p.slug}, {"values", p.values}};
  if (p.number_theory.contains("omega_value")) row["omega_value"] = p.number_theory.at("omega_value");
  // each swept value that is a number or an exact expression ("2/3+1e-4", "golden - 1"), evaluated exactly and
  // rounded once: what a plot puts on its axis (a word, such as a sampling scheme, has none)
  json numbers = json::object();
  for (const auto& [key, v] : p.values.items())
    if (const std::optional<ExactReal> x = exact_value(v.get<std::string>())) numbers[key] = x->to_double();
  row["numbers"] = numbers;
  for (const char* key : {"kappa", "alpha", "tail", "predicted", "rate_jumps"}) row[key] = s.at(key);
  row["number_theory"] = p.number_theory;
  row["particles"] = s.at("particles");
  row["collisions"] = s.at("collisions");
  row["wall_seconds"] = s.at("execution").at("wall_seconds");
  return row;
}

/// table.csv and scan.json from the points' summaries (as run now, or as saved), written by rank 0.
void write_scan_results(const ScanRequest& req, const std::vector<ScanPoint>& points, std::vector<json> summaries,
                        const fs::path& dir, ScanOutcome& out) {
  json rows = json::array();
  for (std::size_t i = 0; i < points.size(); ++i) {
    rows.push_back(scan_row(points[i], summaries[i]));
    summaries[i]["scan_values"] = points[i].values;
    summaries[i]["number_theory"] = points[i].number_theory;
  }
  out.csv = scan_table_csv(req.axes, summaries);
  json axes = json::array();
  for (const ScanAxis& a : req.axes) axes.push_back({{"key", a.key}, {"values", a.values}});
  out.document = {{"command", "scan"}, {"schema", kRunSchema}, {"scene", req.scene_path}, {"overrides", req.overrides},
                  {"axes", axes},      {"points", rows},       {"ran", out.ran},          {"skipped", out.skipped}};
  write_file_atomic(dir / "table.csv", out.csv);
  write_file_atomic(dir / "scan.json", out.document.dump(2) + "\n");
}

}  // namespace

ScanOutcome scan(const ScanRequest& req) {
  const std::vector<ScanPoint> points = scan_points(req);
  const Team& team = req.team ? *req.team : current_team();
  const bool lead = team.rank() == 0;  // under MPI rank 0 writes and reports; every rank runs every point
  const Note note = lead ? req.note : Note{};
  const fs::path dir = RunDirectory::normalise(req.out), points_dir = dir / "points";
  const std::unique_ptr<DirectoryLock> lock = lead ? lock_scan_directory(req, dir) : nullptr;
  team.all(true);  // the directory is there before any rank looks
  ScanManifest manifest(dir / "points.json");
  refuse_other_inputs(req, points, manifest, points_dir);
  refuse_points_left_out(req, points, manifest, points_dir, lead);
  team.all(true);  // the points left out are gone before any rank runs
  ScanOutcome out;
  out.dir = dir;
  out.points = points.size();
  std::vector<json> summaries(points.size());
  double spent = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const ScanPoint& p = points[i];
    const fs::path pdir = points_dir / p.slug;
    const std::string which = "[scan] point " + std::to_string(i + 1) + "/" + std::to_string(points.size()) + " ";
    // every rank must take the same way: a point is skipped only where every rank finds it complete
    if (team.all(fs::exists(pdir / "summary.json") && manifest.recorded(p.slug) == p.inputs) && !req.force) {
      ++out.skipped;
      if (!lead) continue;
      bool refitted = false;
      summaries[i] = saved_point(p, pdir, refitted);
      if (note)
        note(which + p.slug + (refitted ? ": complete, refitted under the new fit keys" : ": complete, skipped"));
      continue;
    }
    if (note) note(which + p.slug + ": running");
    const auto t0 = std::chrono::steady_clock::now();
    summaries[i] = run_point(req, p, pdir, team, note);
    const double sec = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    manifest.record(p, lead);
    spent += sec;
    ++out.ran;
    if (note) {
      char line[200];
      std::snprintf(line, sizeof line, "[scan] point %zu/%zu done in %.1f s; %zu of %zu points complete; ETA %.0f s",
                    i + 1, points.size(), sec, i + 1, points.size(),
                    spent / static_cast<double>(out.ran) * static_cast<double>(points.size() - i - 1));
      note(line);
    }
  }
  if (!lead) return out;
  write_scan_results(req, points, std::move(summaries), dir, out);
  if (req.finish) req.finish(out);
  return out;
}

}  // namespace rotleak
