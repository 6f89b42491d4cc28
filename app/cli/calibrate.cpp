// rotleak calibrate SCENE --seeds K --out DIR [--first-seed S] [--set key=value]...
#include <unistd.h>

#include <cstdio>
#include <iostream>

#include "cli/commands.hpp"
#include "numeric/input.hpp"
#include "run/calibrate.hpp"
#include "run/team.hpp"

namespace rotleak::cli {

namespace {

struct CalibrateArgs {
  CalibrateRequest request;
  std::string seeds, first_seed = "1", particles, engine = "auto";
  int threads = 0;
  bool json_out = false, no_progress = false, plot = false;
};

int run_calibrate(CalibrateArgs a) {
  a.request.seeds = parse_count("--seeds", a.seeds);
  a.request.first_seed = parse_count("--first-seed", a.first_seed);
  if (!a.particles.empty())
    a.request.overrides.push_back("ensemble.particles=" + std::to_string(parse_count("--particles", a.particles)));
  scan_run_options(a.threads, a.engine, a.no_progress, a.request.run, a.request.note);
  const CalibrateOutcome out = calibrate(a.request);
  if (current_team().rank() != 0) return 0;  // under MPI rank 0 reports
  if (a.json_out)
    std::cout << out.document.dump(2) << "\n";
  else
    std::printf("%s%zu seeds run, %zu already complete; wrote %s/calibration.csv and calibration.json\n",
                calibration_text(out.document).c_str(), out.ran, out.skipped, out.dir.c_str());
  return a.plot ? plot_after_run(out.dir.string(), a.json_out) : 0;
}

}  // namespace

Command add_calibrate(CLI::App& app) {
  auto args = std::make_shared<CalibrateArgs>();
  CLI::App* sub = app.add_subcommand(
      "calibrate",
      "Are my error bars honest here? K seeds of a scene: their spread against the errors each run reports");
  sub->add_option("scene", args->request.scene_path, "Scene file (TOML)")->required();
  sub->add_option("--seeds", args->seeds, "Number of seeds K (>= 2; 100 for a calibration worth the name)")->required();
  sub->add_option("--first-seed", args->first_seed, "First seed (default 1): seeds S .. S + K - 1");
  sub->add_option("--out", args->request.out, "Directory (points/, calibration.csv, calibration.json)")->required();
  sub->add_option("--particles", args->particles, "Override ensemble.particles (100000, 1e5)");
  sub->add_option("--threads", args->threads, "OpenMP threads per seed (default: all cores)");
  sub->add_option("--set", args->request.overrides, "Override a scene key for every seed: section.key=value");
  sub->add_option("--engine", args->engine, "auto, scalar, simd, gpu");
  sub->add_flag("--force", args->request.force, "Redo every seed, complete or not");
  sub->add_flag("--plot", args->plot, "Draw calibration.png (rotleak plot DIR)");
  sub->add_flag("--json", args->json_out, "Print calibration.json on stdout");
  sub->add_flag("--no-progress", args->no_progress, "No progress lines");
  return {sub, [args] { return run_calibrate(*args); }};
}

}  // namespace rotleak::cli
