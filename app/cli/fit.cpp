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
  // the same lines simulate prints of its fits: kappa with its window systematic, alpha, alpha_C, z, C, the
  // tail's class with the model's verdict (fit once printed three of them)
  std::fputs(out.text.c_str(), stdout);
  std::printf("rewrote %s/summary.json (the previous one is summary.prev.json)\n", a.dir.c_str());
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
