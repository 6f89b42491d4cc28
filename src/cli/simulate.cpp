// rotleak simulate SCENE [--particles N] [--threads K] [--set key=value]... --out DIR
#include <unistd.h>

#include <cstdio>
#include <iostream>

#include "cli/commands.hpp"
#include "io/progress.hpp"
#include "io/run_output.hpp"
#include "run/pipeline.hpp"

namespace rotleak::cli {

namespace {

struct SimulateArgs {
  SimulateRequest request;
  long long particles = 0;
  bool particles_given = false;
  int threads = 0;
  bool json_out = false, plot = false, progress = false, no_progress = false;
};

int run_simulate(SimulateArgs a) {
  if (a.particles_given) {
    if (a.particles < 1) throw InputError("--particles", std::to_string(a.particles), "must be an integer >= 1");
    a.request.overrides.push_back("ensemble.particles=" + std::to_string(a.particles));
  }
  if (a.threads < 0) throw InputError("--threads", std::to_string(a.threads), "must be >= 0 (0: all cores)");
  a.request.run.threads = a.threads;
  a.request.run.progress = progress_on_stderr(!a.no_progress && (a.progress || ::isatty(2)));
  if (!a.json_out) a.request.note = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };

  const SimulateOutcome out = simulate(a.request);
  if (a.json_out)
    std::cout << out.document.dump(2) << "\n";
  else
    std::printf("%swrote %s/\n", summary_text(out.summary).c_str(), out.dir.c_str());
  return a.plot ? plot_after_run(out.dir.string(), "plot_run.py", a.json_out) : 0;
}

}  // namespace

Command add_simulate(CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* sub =
      app.add_subcommand("simulate", "Run a scene's ensemble; write survival.csv, summary.json (and fc.csv)");
  sub->add_option("scene", args->request.scene_path, "Scene file (TOML)")->required();
  sub->add_option("--out", args->request.out, "Run directory to create")->required();
  sub->add_option("--particles", args->particles, "Override ensemble.particles")->each([args](const std::string&) {
    args->particles_given = true;
  });
  sub->add_option("--threads", args->threads, "OpenMP threads (default: all cores)");
  sub->add_option("--set", args->request.overrides, "Override a scene key: section.key=value (repeatable)");
  sub->add_option("--engine", args->request.engine,
                  "auto (vectorised when the CPU has AVX2+FMA and the scene allows), scalar, simd");
  sub->add_flag("--force", args->request.force, "Replace an existing run directory");
  sub->add_flag("--json", args->json_out, "Print summary.json on stdout (nothing else there)");
  sub->add_flag("--plot", args->plot, "Draw the PNGs (rotleak plot) after the run");
  sub->add_flag("--progress", args->progress, "Progress line on stderr even when it is not a terminal");
  sub->add_flag("--no-progress", args->no_progress, "No progress line");
  return {sub, [args] { return run_simulate(*args); }};
}

}  // namespace rotleak::cli
