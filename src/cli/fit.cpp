// rotleak fit RUN_OR_SCAN_DIR [--set fit.key=value]... [--json]
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <vector>

#include "cli/commands.hpp"
#include "run/refit.hpp"

namespace rotleak::cli {

namespace {

struct FitArgs {
  std::string dir;
  std::vector<std::string> overrides;
  bool json_out = false;
};

/// The pictures drawn from the old fit are removed and drawn again from the new one, so that no picture
/// shows a fit summary.json no longer holds (a drawing that fails leaves none). Returns the plotter's status.
int redraw(const std::string& dir, bool scan, bool quiet) {
  namespace fs = std::filesystem;
  std::vector<fs::path> stale;
  const auto collect = [&](const fs::path& d, bool top) {
    if (!fs::is_directory(d)) return;
    for (const auto& e : fs::directory_iterator(d)) {
      const std::string name = e.path().filename().string();
      if (e.path().extension() == ".png" && ((top && scan && name.rfind("scan_", 0) == 0) ||
                                             ((!top || !scan) && (name == "survival.png" || name == "fc.png"))))
        stale.push_back(e.path());
    }
  };
  collect(dir, true);
  const bool drawn_at_top = !stale.empty();
  if (scan)
    for (const auto& p : fs::directory_iterator(fs::path(dir) / "points")) collect(p.path(), false);
  for (const auto& p : stale) fs::remove(p);
  if (!stale.empty() && !quiet)
    std::fprintf(stderr, "rotleak: removed %zu picture(s) of the previous fit%s\n", stale.size(),
                 drawn_at_top ? "; drawing the new one" : " (redraw with rotleak plot)");
  return drawn_at_top ? plot_after_run(dir, quiet) : 0;
}

int run_fit(const FitArgs& a) {
  const Note note = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  const RefitOutcome out = refit(a.dir, a.overrides, a.json_out ? Note{} : note);
  if (a.json_out) {
    std::cout << out.document.dump(2) << "\n";
    return redraw(a.dir, out.scan, true);
  }
  if (out.scan) {
    std::printf(
        "refitted %zu points; wrote %s/table.csv and scan.json (each point's previous summary kept as "
        "summary.prev.json)\n",
        out.runs, a.dir.c_str());
    return redraw(a.dir, true, false);
  }
  const json& s = out.document;
  const json &k = s.at("kappa"), &al = s.at("alpha"), &t = s.at("tail");
  if (!k.at("value").is_null())
    std::printf("kappa = %.5g +- %.2g   (least squares of ln P on [%g, %g])\n", k.at("value").get<double>(),
                k.at("error").get<double>(), k.at("window")[0].get<double>(), k.at("window")[1].get<double>());
  if (!al.at("value").is_null())
    std::printf(
        "alpha = %.3g +- %.2g   (P at t = %g, first time P > %g x exponential fit, %g standard errors above it)\n",
        al.at("value").get<double>(), al.at("error").get<double>(), al.at("crossing_time").get<double>(),
        al.at("factor").get<double>(), al.at("sigma").get<double>());
  else if (!al.at("upper_bound").is_null())
    std::printf("alpha < %.3g   (%s)\n", al.at("upper_bound").get<double>(), al.at("note").get<std::string>().c_str());
  std::printf("tail  = %s, regime %s\nrewrote %s/summary.json (the previous one is summary.prev.json)\n",
              t.at("class").get<std::string>().c_str(), t.at("regime").get<std::string>().c_str(), a.dir.c_str());
  return redraw(a.dir, false, false);
}

}  // namespace

Command add_fit(CLI::App& app) {
  auto args = std::make_shared<FitArgs>();
  CLI::App* sub = app.add_subcommand(
      "fit", "Re-analyse saved runs (a run or every point of a scan) under new fit.* keys, without simulating");
  sub->add_option("dir", args->dir, "Run directory (rotleak simulate) or scan directory (rotleak scan)")->required();
  sub->add_option("--set", args->overrides,
                  "fit.kappa_window=[a, b], fit.alpha_factor=F, fit.alpha_sigma=S, fit.min_survivors=N (repeatable)");
  sub->add_flag("--json", args->json_out, "Print the new summary.json (or scan.json) on stdout");
  return {sub, [args] { return run_fit(*args); }};
}

}  // namespace rotleak::cli
