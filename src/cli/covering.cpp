// rotleak covering --omega 2/3 [--omega ...] --delta 1e-7 --lambda 0.01 [--d 2 --r 1] [--json] [--out DIR]
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "analysis/covering.hpp"
#include "cli/commands.hpp"
#include "io/files.hpp"
#include "sim/scene.hpp"

namespace rotleak::cli {

namespace {

using json = nlohmann::ordered_json;

struct CoveringArgs {
  std::vector<std::string> omegas;
  std::string delta = "1e-7", lambda = "0.01", d = "2", r = "1";
  std::string out;
  int resolution = 10000;
  bool json_out = false, force = false, segments = false, plot = true;
};

json covering_json(const std::string& omega, const Covering& c) {
  json gaps = json::array();
  for (const auto& g : c.gaps) {
    json e = {{"length", g.length}, {"count", g.count}};
    if (!g.exact.empty()) e["exact"] = g.exact;
    gaps.push_back(e);
  }
  return {{"omega", omega},
          {"x", c.x_text},
          {"N", c.N},
          {"exact", c.exact},
          {"error_bound", c.error_bound},
          {"zero_measure", c.zero_measure},
          {"max_zero_gap", c.max_zero_gap},
          {"clusters", c.clusters},
          {"min", c.min},
          {"max", c.max},
          {"mean", c.mean},
          {"cv", c.cv},
          {"discrepancy", c.discrepancy},
          {"gaps", gaps},
          {"three_distance_holds", c.three_distance_holds},
          {"segments", c.segments.size()},
          {"seconds", c.seconds}};
}

int run_covering(const CoveringArgs& a) {
  if (a.omegas.empty()) throw InputError("--omega", "(none)", "give at least one omega");
  if (a.resolution < 1 || a.resolution > 10000000)
    throw InputError("--resolution", std::to_string(a.resolution), "must be in [1, 10^7]");
  CoveringInput in;
  in.delta = parse_exact_input("--delta", a.delta);
  in.lambda = parse_exact_input("--lambda", a.lambda);
  in.d = parse_exact_input("--d", a.d);
  in.r = parse_exact_input("--r", a.r);
  std::vector<ExactReal> omegas;
  for (const auto& o : a.omegas) omegas.push_back(parse_exact_input("--omega", o));
  // validate everything (and stage the output) before computing
  auto check = [](const ExactReal& v, const std::string& key, const std::string& text, bool open_unit) {
    if (v.sign() <= 0 || (open_unit && (v - ExactReal::parse("1")).sign() >= 0))
      throw InputError(key, "\"" + text + "\"", open_unit ? "must be in (0, 1)" : "must be > 0");
  };
  check(in.delta, "--delta", a.delta, true);
  check(in.lambda, "--lambda", a.lambda, true);
  check(in.d, "--d", a.d, false);
  check(in.r, "--r", a.r, false);
  std::unique_ptr<RunDirectory> dir;
  if (!a.out.empty()) dir = std::make_unique<RunDirectory>(a.out, a.force);

  std::vector<Covering> results;
  json list = json::array();
  for (std::size_t i = 0; i < omegas.size(); ++i) {
    in.omega = omegas[i];
    try {
      results.push_back(mupo_covering(in));
    } catch (const std::invalid_argument& e) {
      throw InputError("--delta", "\"" + a.delta + "\"", e.what());
    }
    list.push_back(covering_json(a.omegas[i], results.back()));
  }
  json doc;
  doc["input"] = {{"delta", a.delta}, {"lambda", a.lambda}, {"d", a.d}, {"r", a.r}};
  doc["covering"] = list.size() == 1 ? list[0] : list;

  if (dir) {
    std::string csv = "s";
    for (const auto& o : a.omegas) csv += ",f_L[" + o + "]";
    csv += "\n";
    std::vector<std::vector<double>> prof;
    for (const auto& c : results) prof.push_back(covering_profile(c, static_cast<std::size_t>(a.resolution)));
    for (int b = 0; b < a.resolution; ++b) {
      csv += shortest((b + 0.5) / a.resolution);
      for (const auto& p : prof) csv += "," + shortest(p[static_cast<std::size_t>(b)]);
      csv += "\n";
    }
    write_file_atomic(dir->file("f_L.csv"), csv);
    if (a.segments) {
      for (std::size_t i = 0; i < results.size(); ++i) {
        std::string seg = "from,to,f_L\n";
        for (const auto& s : results[i].segments) seg += shortest(s.from) + "," + shortest(s.to) + "," + std::to_string(s.value) + "\n";
        write_file_atomic(dir->file("segments_" + std::to_string(i) + ".csv"), seg);
      }
    }
    write_file_atomic(dir->file("summary.json"), doc.dump(2) + "\n");
    dir->commit();
  }
  if (a.json_out) {
    std::cout << doc.dump(2) << "\n";
  } else {
    std::printf("MUPO covering: delta = %s, lambda = %s, d = %s, r = %s\n", a.delta.c_str(), a.lambda.c_str(), a.d.c_str(), a.r.c_str());
    for (std::size_t i = 0; i < results.size(); ++i) {
      const Covering& c = results[i];
      char how[64];
      std::snprintf(how, sizeof how, c.exact ? "exact" : "certified, points within %.1e", c.error_bound);
      std::printf("omega = %s: N = %llu, %s, zero measure %.4g, longest zero gap %.4g, %llu clusters, f_L in [%llu, %llu], "
                  "mean %.4g, cv %.3g, discrepancy %.3g, %zu gap lengths%s (%.3f s)\n",
                  a.omegas[i].c_str(), static_cast<unsigned long long>(c.N), how, c.zero_measure, c.max_zero_gap,
                  static_cast<unsigned long long>(c.clusters), static_cast<unsigned long long>(c.min),
                  static_cast<unsigned long long>(c.max), c.mean, c.cv, c.discrepancy, c.gaps.size(),
                  c.three_distance_holds ? "" : " (three-distance check FAILED)", c.seconds);
    }
  }
  if (dir && a.plot) {
    std::fflush(stdout);
    const int rc = run_plot_script("plot_covering.py", dir->final_path().string());
    if (rc != 0) {
      std::cerr << "rotleak: plotting failed (exit " << rc << ")\n";
      return 1;
    }
  }
  return 0;
}

}  // namespace

Command add_covering(CLI::App& app) {
  auto a = std::make_shared<CoveringArgs>();
  CLI::App* sub = app.add_subcommand("covering", "The MUPO covering f_L(s) of the leak during a bouncing-ball crossing");
  sub->add_option("--omega", a->omegas, "omega (exact; repeat or list several to draw them together)")->required();
  sub->add_option("--delta", a->delta, "1 + delta = 1/sqrt(1 - p^2) (default 1e-7)");
  sub->add_option("--lambda", a->lambda, "leak width in s (default 0.01)");
  sub->add_option("--d", a->d, "straight edge length (default 2)");
  sub->add_option("--r", a->r, "arc radius (default 1)");
  sub->add_option("--out", a->out, "Directory for f_L.csv, summary.json and f_L.png");
  sub->add_option("--resolution", a->resolution, "Bins of the exported f_L profile (default 10000)");
  sub->add_flag("--segments", a->segments, "Also export the exact breakpoints (segments_K.csv)");
  sub->add_flag("--force", a->force, "Replace an existing output directory");
  sub->add_flag("--json", a->json_out, "One JSON document on stdout");
  return {sub, [a] { return run_covering(*a); }};
}

}  // namespace rotleak::cli
