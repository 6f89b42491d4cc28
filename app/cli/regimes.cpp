// rotleak regimes SCENE --out DIR [--coarse VALUES] [--steps N] [--particles N] [--set key=value]... [--json]
#include <unistd.h>

#include <cstdio>
#include <iostream>

#include "cli/commands.hpp"
#include "io/progress.hpp"
#include "numeric/input.hpp"
#include "run/regimes_search.hpp"

namespace rotleak::cli {

namespace {

struct RegimesArgs {
  RegimesRequest request;
  std::string particles;  ///< empty: the scene's
  bool particles_given = false, json_out = false;
  int threads = 0;
};

std::string interval(const json& b) {
  if (b.is_null()) return "not found";
  char buf[200];
  std::snprintf(buf, sizeof buf, "omega in [%s, %s] (%s below, %s above; %llu particles a probe)",
                b.at("lo_omega").get<std::string>().c_str(), b.at("hi_omega").get<std::string>().c_str(),
                b.at("lo_regime").get<std::string>().c_str(), b.at("hi_regime").get<std::string>().c_str(),
                static_cast<unsigned long long>(b.at("particles").get<std::uint64_t>()));
  // a boundary its own resolution cannot place is flagged, never printed as if measured
  if (b.contains("unplaced") && b.at("unplaced").is_string())
    return std::string("NOT PLACED at this resolution: ") + b.at("unplaced").get<std::string>();
  return buf;
}

int run_regimes(RegimesArgs a) {
  if (a.particles_given) {
    a.request.overrides.push_back("ensemble.particles=" + std::to_string(parse_count("--particles", a.particles)));
  }
  if (a.request.steps < 0 || a.request.steps > 30)
    throw InputError("--steps", std::to_string(a.request.steps), "must be in [0, 30]");
  a.request.run.threads = a.threads;
  a.request.run.progress = progress_on_stderr(::isatty(2));
  a.request.note = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };
  const json doc = find_regimes(a.request);
  if (a.json_out) {
    std::cout << doc.dump(2) << "\n";
    return 0;
  }
  const json& b = doc.at("boundaries");
  std::printf("low/mid:  %s\nmid/high: %s\n", interval(b.at("low_mid")).c_str(), interval(b.at("mid_high")).c_str());
  for (auto& [k, v] : doc.at("reasons").items()) std::printf("  %s: %s\n", k.c_str(), v.get<std::string>().c_str());
  const json& p = doc.at("predicted");
  if (p.contains("low_mid"))
    std::printf("predicted low/mid %.3g (%s)\n", p.at("low_mid").get<double>(),
                p.at("low_mid_rule").get<std::string>().c_str());
  std::printf("predicted mid/high %.3g (omega_sweep = lambda / 2r)\nwrote %s/regimes.json\n",
              p.at("omega_sweep").get<double>(), a.request.out.c_str());
  return 0;
}

}  // namespace

Command add_regimes(CLI::App& app) {
  auto args = std::make_shared<RegimesArgs>();
  CLI::App* sub = app.add_subcommand(
      "regimes", "Locate the low/mid and mid/high omega boundaries: coarse log scan, then bisection (resumable)");
  sub->add_option("scene", args->request.scene_path, "Scene file (TOML); its leak size is the one studied")->required();
  sub->add_option("--out", args->request.out, "Directory for the probes (scan directories) and regimes.json")
      ->required();
  sub->add_option("--coarse", args->request.coarse, "Coarse omega values (default logspace(1e-5,1e-1,9))");
  sub->add_option("--steps", args->request.steps, "Bisection steps per boundary (default 4)");
  sub->add_option("--particles", args->particles, "Override ensemble.particles (1000000, 1e6)")
      ->each([args](const std::string&) { args->particles_given = true; });
  sub->add_option("--threads", args->threads, "OpenMP threads per probe (default: all cores)");
  sub->add_option("--set", args->request.overrides, "Override a scene key for every probe");
  sub->add_flag("--json", args->json_out, "Print regimes.json on stdout");
  return {sub, [args] { return run_regimes(*args); }};
}

}  // namespace rotleak::cli
