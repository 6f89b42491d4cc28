// rotleak simulate SCENE [--particles N] [--threads K] [--set key=value]... --out DIR | --resume DIR [--ids A:B]
// rotleak merge OUT SHARD_DIR...
#include <unistd.h>

#include <atomic>
#include <charconv>
#include <csignal>
#include <cstdio>
#include <iostream>

#include "analysis/output/run_output.hpp"
#include "cli/commands.hpp"
#include "io/progress.hpp"
#include "run/pipeline.hpp"

namespace rotleak::cli {

namespace {

/// Set by SIGINT / SIGTERM: the run finishes its blocks, writes a checkpoint and stops. A second
/// signal kills at once (the handler restores the default).
std::atomic<bool> g_stop{false};
volatile std::sig_atomic_t g_signal = 0;

extern "C" void on_stop_signal(int sig) {
  g_signal = sig;
  g_stop.store(true);
  std::signal(sig, SIG_DFL);
}

/// "A:B" as two exact unsigned integers.
std::pair<std::uint64_t, std::uint64_t> parse_ids(const std::string& text) {
  const auto colon = text.find(':');
  std::uint64_t v[2] = {0, 0};
  bool ok = colon != std::string::npos;
  for (int i = 0; ok && i < 2; ++i) {
    const std::string part = i == 0 ? text.substr(0, colon) : text.substr(colon + 1);
    const auto r = std::from_chars(part.data(), part.data() + part.size(), v[i]);
    ok = !part.empty() && r.ec == std::errc() && r.ptr == part.data() + part.size();
  }
  if (!ok) throw InputError("--ids", text, "must be A:B, two integers: the particle ids [A, B) of the run");
  return {v[0], v[1]};
}

struct SimulateArgs {
  SimulateRequest request;
  std::string resume_dir, ids, engine = "auto";
  std::string particles;  ///< empty: the scene's
  bool particles_given = false;
  int threads = 0;
  bool json_out = false, plot = false, progress = false, no_progress = false;
};

int run_simulate(SimulateArgs a) {
  if (a.particles_given) {
    a.request.overrides.push_back("ensemble.particles=" + std::to_string(parse_count("--particles", a.particles)));
  }
  if (a.threads < 0) throw InputError("--threads", std::to_string(a.threads), "must be >= 0 (0: all cores)");
  a.request.run.threads = a.threads;
  a.request.run.engine = parse_engine("--engine", a.engine);
  const bool lead = current_team().rank() == 0;  // under MPI only rank 0 reports
  a.request.run.progress = progress_on_stderr(lead && !a.no_progress && (a.progress || ::isatty(2)));
  if (!a.json_out && lead) a.request.note = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };

  if (!a.resume_dir.empty()) {
    if (!a.request.out.empty() && RunDirectory::normalise(a.request.out) != RunDirectory::normalise(a.resume_dir))
      throw InputError("--resume", a.resume_dir, "names the run directory itself; give --out or --resume, not two");
    a.request.out = a.resume_dir;
    a.request.resume = Resume::yes;
  }
  if (a.request.out.empty())
    throw InputError("--out", "(missing)", "give the run directory: --out DIR (or --resume DIR)");
  if (!a.ids.empty()) a.request.ids = parse_ids(a.ids);
  a.request.run.stop = &g_stop;
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
  SimulateOutcome out;
  try {
    out = simulate(a.request);
  } catch (const RunInterrupted& e) {
    if (!lead) return 128 + (g_signal ? static_cast<int>(g_signal) : SIGINT);
    std::fprintf(stderr,
                 "rotleak: %s after %llu of %llu particles; checkpoint written to %s\n"
                 "rotleak: continue with the same command, --out replaced by --resume %s%s\n",
                 g_signal == SIGTERM ? "terminated" : "interrupted", static_cast<unsigned long long>(e.done),
                 static_cast<unsigned long long>(e.total), e.checkpoint.c_str(),
                 RunDirectory::normalise(a.request.out).c_str(),
                 current_team().size() > 1 ? " (and the same number of MPI ranks)" : "");
    return 128 + (g_signal ? static_cast<int>(g_signal) : SIGINT);
  }
  if (!lead) return 0;
  if (a.json_out)
    std::cout << out.document.dump(2) << "\n";
  else
    std::printf("%swrote %s/\n", summary_text(out.summary).c_str(), out.dir.c_str());
  return a.plot ? plot_after_run(out.dir.string(), a.json_out) : 0;
}

}  // namespace

Command add_simulate(CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* sub =
      app.add_subcommand("simulate", "Run a scene's ensemble; write survival.csv, summary.json (and fc.csv)");
  sub->add_option("scene", args->request.scene_path, "Scene file (TOML)")->required();
  sub->add_option("--out", args->request.out, "Run directory to create");
  sub->add_option("--resume", args->resume_dir,
                  "Continue the killed or interrupted run of this directory from its checkpoint DIR.checkpoint "
                  "(same scene and options; refused if they differ)");
  sub->add_option("--ids", args->ids,
                  "A:B: run only particle ids [A, B) of ensemble.particles, a shard for rotleak merge (writes "
                  "tally.bin)");
  sub->add_option("--particles", args->particles, "Override ensemble.particles (1000000, 1e6)")
      ->each([args](const std::string&) { args->particles_given = true; });
  sub->add_option("--threads", args->threads, "OpenMP threads (default: all cores)");
  sub->add_option("--set", args->request.overrides, "Override a scene key: section.key=value (repeatable)");
  sub->add_option("--engine", args->engine,
                  "auto (vectorised when the CPU has AVX2+FMA and the scene allows), scalar, simd, gpu (a CUDA "
                  "device: docs/model.md, \"The GPU engine\")");
  sub->add_flag("--force", args->request.force, "Replace an existing run directory");
  sub->add_flag("--json", args->json_out, "Print summary.json on stdout (nothing else there)");
  sub->add_flag("--plot", args->plot, "Draw the PNGs (rotleak plot) after the run");
  sub->add_flag("--progress", args->progress, "Progress line on stderr even when it is not a terminal");
  sub->add_flag("--no-progress", args->no_progress, "No progress line");
  return {sub, [args] { return run_simulate(*args); }};
}

Command add_merge(CLI::App& app) {
  auto req = std::make_shared<MergeRequest>();
  auto json_out = std::make_shared<bool>(false);
  CLI::App* sub = app.add_subcommand(
      "merge", "Combine shards (simulate --ids A:B) into the run of their whole id range, as one run would write it");
  sub->add_option("out", req->out, "Run directory to create")->required();
  sub->add_option("shards", req->shards, "Shard run directories (each with tally.bin)")->required();
  sub->add_flag("--force", req->force, "Replace an existing run directory");
  sub->add_flag("--json", *json_out, "Print summary.json on stdout (nothing else there)");
  return {sub, [req, json_out] {
            if (!*json_out) req->note = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
            const SimulateOutcome out = merge_shards(*req);
            if (*json_out)
              std::cout << out.document.dump(2) << "\n";
            else
              std::printf("%swrote %s/\n", summary_text(out.summary).c_str(), out.dir.c_str());
            return 0;
          }};
}

}  // namespace rotleak::cli
