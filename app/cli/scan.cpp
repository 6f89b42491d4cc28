// rotleak scan SCENE --over KEY=VALUES [--over KEY=VALUES]... --out DIR [--set key=value]...
#include <unistd.h>

#include <cstdio>
#include <iostream>

#include "cli/commands.hpp"
#include "io/progress.hpp"
#include "numeric/input.hpp"
#include "run/scan.hpp"
#include "run/team.hpp"

namespace rotleak::cli {

namespace {

struct ScanArgs {
  ScanRequest request;
  std::vector<std::string> over;
  std::string engine = "auto";
  std::string particles;  ///< empty: the scene's
  bool particles_given = false;
  int threads = 0;
  bool json_out = false, no_progress = false;
};

int run_scan(ScanArgs a) {
  for (const std::string& o : a.over) a.request.axes.push_back(parse_axis(o));
  if (a.particles_given) {
    a.request.overrides.push_back("ensemble.particles=" + std::to_string(parse_count("--particles", a.particles)));
  }
  scan_run_options(a.threads, a.engine, a.no_progress, a.request.run, a.request.note);
  const ScanOutcome out = scan(a.request);
  if (current_team().rank() != 0) return 0;  // under MPI rank 0 reports
  if (a.json_out)
    std::cout << out.document.dump(2) << "\n";
  else
    std::printf("%s\n%zu points (%zu run, %zu already complete); wrote %s/table.csv and scan.json\n",
                scan_table_text(out.document).c_str(), out.points, out.ran, out.skipped, out.dir.c_str());
  return 0;
}

}  // namespace

void scan_run_options(int threads, const std::string& engine, bool no_progress, RunOptions& run, Note& note) {
  if (threads < 0) throw InputError("--threads", std::to_string(threads), "must be >= 0 (0: all cores)");
  run.threads = threads;
  run.engine = parse_engine("--engine", engine);
  run.progress = progress_on_stderr(!no_progress && ::isatty(2));
  if (!no_progress) note = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
}

Command add_scan(CLI::App& app) {
  auto args = std::make_shared<ScanArgs>();
  CLI::App* sub = app.add_subcommand(
      "scan", "Run the product of swept scene values, one run directory per point; table.csv and scan.json");
  sub->add_option("scene", args->request.scene_path, "Scene file (TOML)")->required();
  sub->add_option("--over", args->over,
                  "KEY=VALUES: a comma list (exact texts kept: 2/3,ln(19)), linspace(a,b,n), logspace(a,b,n), "
                  "rationals(qmax=Q), near(x,e1,...[,signs=both]), nobles(n), sqrtfrac(a,b); "
                  "repeatable (product)")
      ->required();
  sub->add_option("--out", args->request.out, "Scan directory (points/, table.csv, scan.json)")->required();
  sub->add_option("--particles", args->particles, "Override ensemble.particles (1000000, 1e6)")
      ->each([args](const std::string&) { args->particles_given = true; });
  sub->add_option("--threads", args->threads, "OpenMP threads per point (default: all cores)");
  sub->add_option("--set", args->request.overrides, "Override a scene key for every point: section.key=value");
  sub->add_option("--engine", args->engine, "auto, scalar, simd, gpu");
  sub->add_flag("--force", args->request.force, "Redo every point, complete or not");
  sub->add_flag("--json", args->json_out, "Print scan.json on stdout");
  sub->add_flag("--no-progress", args->no_progress, "No progress lines");
  return {sub, [args] { return run_scan(*args); }};
}

}  // namespace rotleak::cli
