// rotleak lyapunov SCENE [--particles M] [--collisions K] [--tier float128] [--tangent-collisions N] [--json]
#include <cstdio>
#include <iostream>

#include "cli/commands.hpp"
#include "io/scene_file.hpp"
#include "verify/reports.hpp"

namespace rotleak::cli {

namespace {

struct LyapunovArgs {
  std::string scene, tier = "float128";
  std::vector<std::string> sets;
  long long particles = 200, collisions = 100, tangent = 2000000;
  double from = 10, to = 150, mupo_p = 1e-4;
  int threads = 0;
  bool json_out = false;
};

int run_lyapunov(const LyapunovArgs& a) {
  const Scene scene = load_scene(a.scene, a.sets);
  if (a.particles < 2 || static_cast<std::uint64_t>(a.particles) > scene.particles)
    throw InputError("--particles", std::to_string(a.particles), "must be in [2, ensemble.particles]");
  if (a.collisions < 10) throw InputError("--collisions", std::to_string(a.collisions), "must be >= 10");
  if (a.tangent < 1000) throw InputError("--tangent-collisions", std::to_string(a.tangent), "must be >= 1000");
  const auto tier = Tier::parse(a.tier);
  if (!tier || tier->automatic() || tier->interval())
    throw InputError("--tier", a.tier, "allowed: " + tier_names_allowed(false));
  if (!(a.from >= 0 && a.from < a.to))
    throw InputError("--window", std::to_string(a.from) + "," + std::to_string(a.to), "needs 0 <= from < to");

  LyapunovStudyOptions opt;
  opt.tier = a.tier;
  opt.particles = static_cast<std::size_t>(a.particles);
  opt.collisions = static_cast<std::size_t>(a.collisions);
  opt.tangent_collisions = static_cast<std::size_t>(a.tangent);
  opt.from = a.from;
  opt.to = a.to;
  opt.mupo_p = a.mupo_p;
  opt.threads = a.threads;
  const LyapunovStudy study = lyapunov_study(scene, opt);
  if (a.json_out)
    std::cout << lyapunov_json(study).dump(2) << "\n";
  else
    std::fputs(lyapunov_text(study, scene.source).c_str(), stdout);
  return 0;
}

}  // namespace

Command add_lyapunov(CLI::App& app) {
  auto a = std::make_shared<LyapunovArgs>();
  CLI::App* sub = app.add_subcommand(
      "lyapunov", "Lyapunov exponent two ways (tangent dynamics, shadow divergence) and MUPO growth");
  sub->add_option("scene", a->scene, "Scene file (TOML): the stadium (the leak plays no part)")->required();
  sub->add_option("--particles", a->particles, "Shadow runs for the divergence estimate (default 200)");
  sub->add_option("--collisions", a->collisions, "Collisions per shadow run (default 100)");
  sub->add_option("--tier", a->tier, "Tier whose divergence from the truth is fitted (default float128)");
  sub->add_option("--tangent-collisions", a->tangent, "Length of the tangent-dynamics trajectory (default 2e6)");
  sub->add_option("--from", a->from, "Fit window start in time since creation (default 10)");
  sub->add_option("--to", a->to, "Fit window end (default 150)");
  sub->add_option("--threads", a->threads, "OpenMP threads (default: all cores)");
  sub->add_option("--set", a->sets, "Override a scene key (repeatable)");
  sub->add_flag("--json", a->json_out, "One JSON document on stdout");
  return {sub, [a] { return run_lyapunov(*a); }};
}

}  // namespace rotleak::cli
