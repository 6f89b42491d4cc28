// rotleak simulate SCENE [--particles N] [--threads K] [--set key=value]... --out DIR
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "analysis/fits.hpp"
#include "cli/commands.hpp"
#include "io/files.hpp"
#include "io/run_output.hpp"
#include "sim/engine.hpp"
#include "sim/scene.hpp"
#include "verify/auto_tier.hpp"
#include "version.hpp"

namespace rotleak::cli {

namespace {

using json = nlohmann::ordered_json;

struct SimulateArgs {
  std::string scene;
  std::string out;
  long long particles = -1;
  int threads = 0;
  std::vector<std::string> sets;
  std::string engine = "auto";
  bool force = false, json_out = false, plot = false, progress = false, no_progress = false;
};

json scene_json(const Scene& s) {
  json j;
  j["source"] = s.source;
  j["stadium"] = {{"d", s.d_text}, {"r", s.r_text}};
  j["leak"] = {{"width", s.width_text}, {"start", s.start_text}, {"omega", s.omega_text}};
  j["ensemble"] = {{"particles", s.particles}, {"seed", s.seed}, {"init", to_string(s.init)},
                   {"creation_window", s.creation_window}};
  j["run"] = {{"t_max", s.t_max}, {"tier", to_string(s.tier)}, {"fast_forward", s.fast_forward}};
  json obs = {{"survival_dt", s.survival_dt}, {"escapes", s.escape_records}};
  if (s.collision_density) {
    json w = json::array();
    for (const auto& win : s.collision_density->windows) w.push_back({win.from, win.to});
    obs["collision_density"] = {{"bins", s.collision_density->bins}, {"windows", w}};
  }
  j["observe"] = obs;
  j["fit"] = {{"kappa_window", {s.kappa_window.from, s.kappa_window.to}}};
  return j;
}

json nullable(const std::optional<double>& v) { return v ? json(*v) : json(nullptr); }

int run_simulate(const SimulateArgs& a) {
  std::vector<std::string> sets = a.sets;
  if (a.particles == 0) throw InputError("--particles", "0", "must be an integer >= 1");
  if (a.particles > 0) sets.push_back("ensemble.particles=" + std::to_string(a.particles));
  if (a.threads < 0) throw InputError("--threads", std::to_string(a.threads), "must be >= 0 (0: all cores)");
  Scene scene = load_scene(a.scene, sets);
  RunDirectory dir(a.out, a.force);  // validated and staged before any work
  std::optional<TierChoice> choice;
  if (scene.tier == Tier::auto_) {
    if (!a.json_out) std::fprintf(stderr, "[rotleak] run.tier = auto: auditing float, double, long double on this scene...\n");
    choice = choose_tier(scene, a.threads);
    scene.tier = choice->tier;
  }

  RunOptions opt;
  opt.threads = a.threads;
  if (a.engine != "auto" && a.engine != "scalar" && a.engine != "simd")
    throw InputError("--engine", a.engine, "allowed: auto, scalar, simd");
  opt.engine = a.engine == "scalar" ? Engine::scalar : a.engine == "simd" ? Engine::simd : Engine::automatic;
  try {
    resolve_engine(opt.engine, scene);
  } catch (const std::runtime_error& e) {
    throw InputError("--engine", a.engine, e.what());
  }
  opt.progress = !a.no_progress && (a.progress || ::isatty(2));
  const RunResult res = run_ensemble(scene, opt);

  SurvivalCurve curve{survival_times(scene), survivors_on_grid(scene, res.tally), scene.particles};
  const KappaFit kappa = fit_kappa(curve, scene.kappa_window.from, scene.kappa_window.to);
  const AlphaResult alpha = find_alpha(curve, kappa);
  const TailFit tail = fit_tail(curve, alpha);

  std::vector<std::string> files{"survival.csv"};
  write_file_atomic(dir.file("survival.csv"), survival_csv(scene, res.tally));
  if (scene.collision_density) {
    write_file_atomic(dir.file("fc.csv"), density_csv(scene, res.tally));
    files.push_back("fc.csv");
  }
  if (scene.escape_records) {
    write_file_atomic(dir.file("escapes.csv"), escapes_csv(0, res.records));
    files.push_back("escapes.csv");
  }
  write_file_atomic(dir.file("scene.toml"), scene_to_toml(scene));
  files.push_back("scene.toml");

  json s;
  s["rotleak"] = {{"version", kVersion}, {"git", kGitDescribe}};
  s["command"] = "simulate";
  s["scene"] = scene_json(scene);
  s["seed"] = scene.seed;
  s["tier"] = to_string(scene.tier);
  if (choice) s["tier_choice"] = {{"requested", "auto"}, {"chosen", to_string(choice->tier)}, {"reason", choice->reason}};
  s["engine"] = to_string(res.engine);
  s["threads"] = res.threads;
  s["particles"] = scene.particles;
  s["wall_seconds"] = res.wall_seconds;
  s["collisions"] = res.tally.collisions;
  s["collisions_per_second"] = res.wall_seconds > 0 ? static_cast<double>(res.tally.collisions) / res.wall_seconds : 0.0;
  s["escaped"] = res.tally.escaped;
  s["survivors_at_t_max"] = res.tally.survived;
  s["stuck"] = res.tally.stuck;
  s["kappa"] = {{"value", kappa.ok ? json(kappa.value) : json(nullptr)},
                {"error", kappa.std_error},
                {"window", {kappa.from, kappa.to}},
                {"points", kappa.points},
                {"log_amplitude", kappa.log_amplitude},
                {"method", kappa.method}};
  s["alpha"] = {{"value", nullable(alpha.value)},
                {"error", alpha.value ? json(alpha.std_error) : json(nullptr)},
                {"upper_bound", nullable(alpha.upper_bound)},
                {"crossing_time", alpha.value ? json(alpha.crossing_time) : json(nullptr)},
                {"factor", alpha.factor},
                {"min_survivors", alpha.min_survivors},
                {"resolved_until", alpha.resolved_until},
                {"note", alpha.note}};
  s["tail_exponent"] = {{"value", nullable(tail.z)},
                        {"error", tail.z ? json(tail.std_error) : json(nullptr)},
                        {"window", {tail.from, tail.to}},
                        {"points", tail.points},
                        {"method", tail.method}};
  files.push_back("summary.json");
  s["files"] = files;
  write_file_atomic(dir.file("summary.json"), s.dump(2) + "\n");  // last: its presence marks a complete run
  dir.commit();

  if (a.json_out) {
    std::cout << s.dump(2) << "\n";
  } else {
    std::printf("%s: %llu particles, %s tier, %d threads, %.2f s, %.3g collisions/s\n", scene.source.c_str(),
                static_cast<unsigned long long>(scene.particles), to_string(scene.tier).c_str(), res.threads,
                res.wall_seconds, s["collisions_per_second"].get<double>());
    if (kappa.ok)
      std::printf("kappa = %.5g +- %.2g   (least squares of ln P on [%g, %g])\n", kappa.value, kappa.std_error,
                  kappa.from, kappa.to);
    else
      std::printf("kappa: not resolved (too few points in [%g, %g])\n", kappa.from, kappa.to);
    if (alpha.value)
      std::printf("alpha = %.3g +- %.2g   (P at t = %g, first time P > %g x exponential fit)\n", *alpha.value,
                  alpha.std_error, alpha.crossing_time, alpha.factor);
    else if (alpha.upper_bound)
      std::printf("alpha < %.3g   (no crossing up to t = %g while >= %llu survive)\n", *alpha.upper_bound,
                  alpha.resolved_until, static_cast<unsigned long long>(alpha.min_survivors));
    if (tail.z) std::printf("z     = %.3g +- %.2g   (P ~ t^-z on [%g, %g])\n", *tail.z, tail.std_error, tail.from, tail.to);
    if (res.tally.stuck) std::printf("warning: %llu particles stuck (zero-length flights); counted as not escaped\n",
                                     static_cast<unsigned long long>(res.tally.stuck));
    std::printf("wrote %s/\n", dir.final_path().c_str());
  }
  if (a.plot) {
    std::fflush(stdout);  // our lines first, then the plotter's
    const int rc = draw_plots(dir.final_path().string());
    if (rc != 0) {
      std::cerr << "rotleak: plotting failed (exit " << rc << "); the run itself is complete\n";
      return 1;
    }
  }
  return 0;
}

}  // namespace

Command add_simulate(CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* sub = app.add_subcommand("simulate", "Run a scene's ensemble; write survival.csv, summary.json (and fc.csv)");
  sub->add_option("scene", args->scene, "Scene file (TOML)")->required();
  sub->add_option("--out", args->out, "Run directory to create")->required();
  sub->add_option("--particles", args->particles, "Override ensemble.particles");
  sub->add_option("--threads", args->threads, "OpenMP threads (default: all cores)");
  sub->add_option("--set", args->sets, "Override a scene key: section.key=value (repeatable)");
  sub->add_option("--engine", args->engine, "auto (vectorised when the CPU has AVX2+FMA and the scene allows), scalar, simd");
  sub->add_flag("--force", args->force, "Replace an existing run directory");
  sub->add_flag("--json", args->json_out, "Print summary.json on stdout (nothing else there)");
  sub->add_flag("--plot", args->plot, "Draw the PNGs (rotleak plot) after the run");
  sub->add_flag("--progress", args->progress, "Progress line on stderr even when it is not a terminal");
  sub->add_flag("--no-progress", args->no_progress, "No progress line");
  return {sub, [args] { return run_simulate(*args); }};
}

}  // namespace rotleak::cli
