#include "run/calibrate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "analysis/calibration.hpp"
#include "analysis/output/run_output.hpp"
#include "io/files.hpp"
#include "io/scene_file.hpp"
#include "io/text.hpp"
#include "numeric/input.hpp"
#include "run/refit.hpp"
#include "run/scan.hpp"

namespace rotleak {

namespace fs = std::filesystem;

namespace {

/// model_seeds: how many of the seeds took their value past their unresolved_from (spread_verdict).
json spread_json(const SeedSpread& s, std::size_t model_seeds = 0) {
  const double share = s.n ? static_cast<double>(model_seeds) / static_cast<double>(s.n) : 0.0;
  return {{"seeds", s.n},
          {"pooled", s.pooled},
          {"pooled_err", s.pooled_err},
          {"sd", s.sd},
          {"median_err", s.median_err},
          {"sd_over_err", s.sd_over_err},
          {"chi2_dof", s.chi2_dof},
          {"coverage1", s.coverage1},
          {"coverage2", s.coverage2},
          {"max_over_median", s.max_over_median},
          {"model_seeds", model_seeds},
          {"verdict", spread_verdict(s, share)}};
}

/// The number at obj[key] when it is one.
std::optional<double> number_at(const json& obj, const char* key) {
  if (!obj.contains(key) || !obj.at(key).is_number()) return std::nullopt;
  return obj.at(key).get<double>();
}

}  // namespace

namespace {

/// The seeds' runs read back: their survival curves, their summaries and the first one's scene.
struct Seeds {
  std::vector<SurvivalCurve> curves;
  std::vector<json> summaries;
  Scene scene;
};

Seeds read_seeds(const std::vector<fs::path>& point_dirs) {
  Seeds out;
  for (const fs::path& d : point_dirs) {
    const Scene s = saved_scene(d, {});
    out.summaries.push_back(read_run_summary(d, read_file(d / "summary.json")));
    try {
      out.curves.push_back(read_run_curve(d, s));
    } catch (const std::runtime_error& e) {
      throw InputError("DIR", "\"" + d.string() + "\"", e.what());
    }
    if (out.curves.size() == 1) out.scene = s;
  }
  return out;
}

/// Each seed's unresolved_from (split runs: summary.json splitting.unsplit_allowance; infinity where there
/// is none), in seed order.
std::vector<double> unresolved_from(const std::vector<json>& summaries) {
  std::vector<double> from;
  for (const json& s : summaries) {
    double f = std::numeric_limits<double>::infinity();
    if (s.contains("splitting") && s.at("splitting").contains("unsplit_allowance")) {
      const json& a = s.at("splitting").at("unsplit_allowance");
      if (a.is_object() && a.contains("unresolved_from") && a.at("unresolved_from").is_number())
        f = a.at("unresolved_from").get<double>();
    }
    from.push_back(f);
  }
  return from;
}

/// P(t) at every grid time: calibration.csv's rows into csv, and P's summary over the times judged (P
/// resolved in the seeds, before model_from, with an error to judge: P(0) = 1 exactly in a uniform run has none).
json judge_P(const Seeds& seeds, const SurvivalCurve& pooled, double model_from, std::string& csv) {
  const std::size_t K = seeds.curves.size(), points = seeds.curves.front().t.size();
  const double min_eff = static_cast<double>(seeds.scene.min_survivors);
  csv = "t,resolved,seeds,P,P_err,P_err_model,sd_over_err,chi2_dof,coverage1,coverage2,max_over_median\n";
  double lo = std::numeric_limits<double>::infinity(), hi = 0, worst_cov = 1, t_lo = 0, t_hi = 0, t_cov = 0;
  double first = 0, last = 0;
  std::vector<double> x(K), e(K);
  std::vector<SeedSpread> judged;  // the times judged, as one verdict over all of them (curve_verdict)
  for (std::size_t i = 0; i < points; ++i) {
    for (std::size_t k = 0; k < K; ++k) {
      x[k] = seeds.curves[k].P(i);
      e[k] = seeds.curves[k].P_err(i);
    }
    const SeedSpread s = seed_spread(x, e);
    const double t = seeds.curves.front().t[i];
    const bool ok = resolved_in_seeds(seeds.curves, i, min_eff) && t < model_from && s.median_err > 0;
    appendf(csv, "%s,%d,%zu,%s,%s,%s,%s,%s,%s,%s,%s\n", shortest(t).c_str(), ok ? 1 : 0, K, shortest(s.pooled).c_str(),
            shortest(s.pooled_err).c_str(), shortest(pooled.P_err(i)).c_str(), shortest(s.sd_over_err).c_str(),
            shortest(s.chi2_dof).c_str(), shortest(s.coverage1).c_str(), shortest(s.coverage2).c_str(),
            shortest(s.max_over_median).c_str());
    if (!ok) continue;
    if (judged.empty()) first = t;
    judged.push_back(s);
    last = t;
    if (s.sd_over_err < lo) lo = s.sd_over_err, t_lo = t;
    if (s.sd_over_err > hi) hi = s.sd_over_err, t_hi = t;
    if (s.coverage2 < worst_cov) worst_cov = s.coverage2, t_cov = t;
  }
  const CurveVerdict v = curve_verdict(judged);
  const HonestBand band = judged.empty() ? honest_band(K) : v.band;
  json P = {{"resolved_times", judged.size()},
            {"min_effective", min_eff},
            {"band", {band.lo, band.hi}},
            {"coverage2_floor", band.coverage2_floor},
            {"coverage2_expected", band.coverage2_expected},
            {"false_alarm", kCalibrationFalseAlarm},
            {"false_alarm_each", band.false_alarm_each},
            {"model_from", std::isinf(model_from) ? json(nullptr) : json(model_from)}};
  if (judged.empty()) {
    P["honest"] = nullptr;
    return P;
  }
  P["from"] = first;
  P["to"] = last;
  P["sd_over_err_min"] = {{"value", lo}, {"t", t_lo}};
  P["sd_over_err_max"] = {{"value", hi}, {"t", t_hi}};
  P["coverage2_min"] = {{"value", worst_cov}, {"t", t_cov}};
  P["times_outside_band"] = v.outside;
  P["times_under_coverage"] = v.uncovered;
  P["honest"] = v.honest();
  return P;
}

/// Every statistic summary.json reports with an error (an object with a value and an error, at the top level
/// or one level down: tail.amplitude as tail_amplitude): stat. alone, and with its systematic beside it.
json judge_statistics(const std::vector<json>& summaries, const std::vector<double>& seed_model_from) {
  json stats = json::object();
  const auto add_statistic = [&](const std::string& name, const std::vector<std::string>& path) {
    std::vector<double> v, stat, total;
    bool syst = false;
    std::size_t model_seeds = 0;  // values read at a time (crossing_time) past the seed's unresolved_from
    for (std::size_t k = 0; k < summaries.size(); ++k) {
      const json* o = &summaries[k];
      for (const std::string& key : path) o = o && o->is_object() && o->contains(key) ? &o->at(key) : nullptr;
      if (!o || !o->is_object()) continue;
      const auto value = number_at(*o, "value"), err = number_at(*o, "error");
      if (!value || !err) continue;
      if (const auto at = number_at(*o, "crossing_time"); at && *at >= seed_model_from[k]) ++model_seeds;
      auto sy = number_at(*o, "systematic");
      if (!sy) sy = number_at(*o, "window_systematic");
      syst = syst || sy.has_value();
      v.push_back(*value);
      stat.push_back(*err);
      total.push_back(std::hypot(*err, sy.value_or(0.0)));
    }
    if (v.size() < 2) {
      stats[name] = {{"seeds", v.size()}, {"verdict", "fewer than 2 seeds give a value"}};
      return;
    }
    stats[name] = spread_json(seed_spread(v, stat), model_seeds);
    if (syst) stats[name + "_total"] = spread_json(seed_spread(v, total), model_seeds);
  };
  const auto has_value = [](const json& o) { return o.is_object() && o.contains("value") && o.contains("error"); };
  for (const auto& [name, obj] : summaries.front().items()) {
    if (has_value(obj)) {
      add_statistic(name, {name});
    } else if (obj.is_object()) {
      for (const auto& [inner, o] : obj.items())
        if (has_value(o)) add_statistic(name + "_" + inner, {name, inner});
    }
  }
  return stats;
}

/// alpha's upper bounds against the pooled alpha: a bound below it is a bound that failed.
json judge_bounds(const std::vector<json>& summaries, const std::optional<double>& pooled_alpha) {
  std::size_t n = 0, below = 0;
  for (const json& s : summaries)
    if (const auto b = number_at(s.at("alpha"), "upper_bound")) {
      ++n;
      if (pooled_alpha && *b < *pooled_alpha) ++below;
    }
  json bounds = {{"seeds", n}};
  bounds["pooled_alpha"] = nullable(pooled_alpha);
  bounds["below_pooled_alpha"] = pooled_alpha ? json(below) : json(nullptr);
  return bounds;
}

}  // namespace

json calibration_document(const std::vector<fs::path>& point_dirs, std::string& csv) {
  if (point_dirs.size() < 2) throw InputError("--seeds", std::to_string(point_dirs.size()), "at least 2 runs");
  const Seeds seeds = read_seeds(point_dirs);
  SurvivalCurve pooled;  // the K runs as one run of K N particles
  try {
    pooled = pool_curves(seeds.curves, &seeds.scene);
  } catch (const std::invalid_argument&) {
    throw InputError("DIR", "\"" + point_dirs.front().parent_path().string() + "\"",
                     "the runs are not one scene with different seeds (grid, sampling or particles differ)");
  }
  // split runs: P is judged only before the median seed's allowance for unsplit lines not drawn holds a
  // third of its variance (summary.json splitting.unsplit_allowance.unresolved_from; none: never)
  const std::vector<double> seed_model_from = unresolved_from(seeds.summaries);
  std::vector<double> sorted = seed_model_from;
  std::sort(sorted.begin(), sorted.end());
  const double model_from = sorted[sorted.size() / 2];
  const json P = judge_P(seeds, pooled, model_from, csv);
  const json stats = judge_statistics(seeds.summaries, seed_model_from);
  // the pooled curve: all K runs as one run of K N particles, fitted as any run
  RunSummary all;
  all.scene = seeds.scene;
  all.scene.particles = pooled.particles;
  all.curve = pooled;
  fit_curve(all);
  json fits = json::object();
  put_fits(fits, all);
  const json pooled_doc = {{"particles", pooled.particles},
                           {"kappa", fits.at("kappa")},
                           {"alpha", fits.at("alpha")},
                           {"tail", fits.at("tail")}};
  std::vector<std::uint64_t> seed_numbers;
  for (const json& s : seeds.summaries) seed_numbers.push_back(s.at("seed").get<std::uint64_t>());
  return {{"command", "calibrate"},
          {"schema", kRunSchema},
          {"scene", seeds.summaries.front().at("scene").value("source", std::string())},
          {"seeds", seed_numbers},
          {"particles", seeds.scene.particles},
          {"P", P},
          {"statistics", stats},
          {"alpha_bounds", judge_bounds(seeds.summaries, all.alpha.value)},
          {"pooled", pooled_doc},
          {"files", {"calibration.csv", "calibration.json"}}};
}

std::string calibration_text(const json& d) {
  std::string out;
  const json& P = d.at("P");
  appendf(out, "%zu seeds of %s particles each\n", d.at("seeds").size(),
          std::to_string(d.at("particles").get<std::uint64_t>()).c_str());
  appendf(out, "%-20s %5s %12s %11s %8s %8s %6s %6s %9s  %s\n", "statistic", "seeds", "pooled", "+-", "sd/err",
          "chi2/dof", "in 1", "in 2", "max/med", "verdict");
  const auto row = [&out](const std::string& name, const json& s) {
    if (!s.contains("pooled")) {
      appendf(out, "%-20s %5zu  %s\n", name.c_str(), s.at("seeds").get<std::size_t>(),
              s.at("verdict").get<std::string>().c_str());
      return;
    }
    appendf(out, "%-20s %5zu %12.5g %11.3g %8.3g %8.3g %5.0f%% %5.0f%% %9.3g  %s\n", name.c_str(),
            s.at("seeds").get<std::size_t>(), s.at("pooled").get<double>(), s.at("pooled_err").get<double>(),
            s.at("sd_over_err").get<double>(), s.at("chi2_dof").get<double>(), 100 * s.at("coverage1").get<double>(),
            100 * s.at("coverage2").get<double>(), s.at("max_over_median").get<double>(),
            s.at("verdict").get<std::string>().c_str());
  };
  for (const auto& [name, s] : d.at("statistics").items()) row(name, s);
  if (P.at("resolved_times").get<std::size_t>() == 0) {
    out += "P(t): resolved at no grid time (every seed P > 0 with the median seed's effective survivors >= " +
           shortest(P.at("min_effective").get<double>()) + ")\n";
  } else {
    appendf(out,
            "P(t), %zu resolved grid times in [%g, %g]: sd/err from %.3g (t = %g) to %.3g (t = %g), coverage at 2 "
            "errors >= %.0f%% (t = %g); %zu times outside [%g, %g], %zu under %.0f%% (each time at %.2g): %s\n",
            P.at("resolved_times").get<std::size_t>(), P.at("from").get<double>(), P.at("to").get<double>(),
            P.at("sd_over_err_min").at("value").get<double>(), P.at("sd_over_err_min").at("t").get<double>(),
            P.at("sd_over_err_max").at("value").get<double>(), P.at("sd_over_err_max").at("t").get<double>(),
            100 * P.at("coverage2_min").at("value").get<double>(), P.at("coverage2_min").at("t").get<double>(),
            P.at("times_outside_band").get<std::size_t>(), P.at("band")[0].get<double>(), P.at("band")[1].get<double>(),
            P.at("times_under_coverage").get<std::size_t>(), 100 * P.at("coverage2_floor").get<double>(),
            P.at("false_alarm_each").get<double>(), P.at("honest").get<bool>() ? "honest" : "NOT honest");
  }
  const json& b = d.at("alpha_bounds");
  if (b.at("seeds").get<std::size_t>() > 0 && b.at("pooled_alpha").is_number())
    appendf(out, "alpha upper bounds: %zu of %zu below the pooled alpha %.4g\n",
            b.at("below_pooled_alpha").get<std::size_t>(), b.at("seeds").get<std::size_t>(),
            b.at("pooled_alpha").get<double>());
  const json& pa = d.at("pooled").at("alpha");
  if (pa.at("value").is_number())
    appendf(out, "pooled curve (%s particles): alpha = %.4g +- %.2g\n",
            std::to_string(d.at("pooled").at("particles").get<std::uint64_t>()).c_str(), pa.at("value").get<double>(),
            pa.at("error").get<double>());
  return out;
}

CalibrateOutcome calibrate(const CalibrateRequest& req) {
  if (req.seeds < 2) throw InputError("--seeds", std::to_string(req.seeds), "at least 2 (independent runs to compare)");
  if (req.seeds > 100000) throw InputError("--seeds", std::to_string(req.seeds), "at most 100000");
  if (req.first_seed > std::numeric_limits<std::uint64_t>::max() - (req.seeds - 1))
    throw InputError("--first-seed", std::to_string(req.first_seed), "the seeds must stay below 2^64");
  for (const std::string& o : req.overrides)
    if (o.rfind("ensemble.seed=", 0) == 0)
      throw InputError("--set", o, "calibrate chooses the seeds (--first-seed, --seeds), not --set");
  ScanRequest sr;
  sr.scene_path = req.scene_path;
  sr.scene_text = req.scene_text;
  sr.overrides = req.overrides;
  ScanAxis seeds{"ensemble.seed", {}};
  for (std::uint64_t k = 0; k < req.seeds; ++k) seeds.values.push_back(std::to_string(req.first_seed + k));
  sr.axes = {seeds};
  sr.out = req.out;
  sr.force = req.force;
  sr.run = req.run;
  sr.note = req.note;
  sr.team = req.team;
  sr.finish_files = {"calibration.csv", "calibration.json"};
  CalibrateOutcome out;
  sr.finish = [&out](const ScanOutcome& scan) {
    std::vector<fs::path> dirs;
    for (const json& p : scan.document.at("points"))
      dirs.push_back(scan.dir / "points" / p.at("point").get<std::string>());
    out.document = calibration_document(dirs, out.csv);
    write_file_atomic(scan.dir / "calibration.csv", out.csv);
    write_file_atomic(scan.dir / "calibration.json", out.document.dump(2) + "\n");  // last: complete
  };
  const ScanOutcome scan_out = scan(sr);
  out.dir = scan_out.dir;
  out.ran = scan_out.ran;
  out.skipped = scan_out.skipped;
  return out;
}

}  // namespace rotleak
