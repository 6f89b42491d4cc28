// rotleak lyapunov SCENE [--particles M] [--collisions K] [--tier float128] [--tangent-collisions N] [--json]
#include <omp.h>

#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "verify/lyapunov.hpp"

namespace rotleak::cli {

namespace {

using json = nlohmann::ordered_json;

struct LyapunovArgs {
  std::string scene, tier = "float128";
  std::vector<std::string> sets;
  long long particles = 200, collisions = 100, tangent = 2000000;
  double from = 10, to = 150, mupo_p = 1e-4;
  int threads = 0;
  bool json_out = false;
};

json estimate_json(const LyapunovEstimate& e) {
  return {{"per_time", e.per_time}, {"per_time_error", e.per_time_error}, {"per_collision", e.per_collision},
          {"per_collision_error", e.per_collision_error}, {"samples", e.samples}, {"collisions", e.collisions}};
}

int run_lyapunov(const LyapunovArgs& a) {
  const Scene scene = load_scene(a.scene, a.sets);
  if (a.particles < 2 || static_cast<std::uint64_t>(a.particles) > scene.particles)
    throw InputError("--particles", std::to_string(a.particles), "must be in [2, ensemble.particles]");
  if (a.collisions < 10) throw InputError("--collisions", std::to_string(a.collisions), "must be >= 10");
  if (a.tangent < 1000) throw InputError("--tangent-collisions", std::to_string(a.tangent), "must be >= 1000");
  if (!valid_tier_name(a.tier)) throw InputError("--tier", a.tier, "allowed: float, double, long_double, dd, float128, mpfr:BITS");
  if (!(a.from >= 0 && a.from < a.to)) throw InputError("--window", std::to_string(a.from) + "," + std::to_string(a.to), "needs 0 <= from < to");

  const InitialConditions ic = initial_conditions(scene);
  const LyapunovEstimate tangent = tangent_lyapunov(scene, ic.draw(0), static_cast<std::size_t>(a.tangent));
  ShadowOptions opt;
  opt.tiers = {a.tier};
  opt.collisions = static_cast<std::size_t>(a.collisions);
  std::vector<ShadowResult> runs(static_cast<std::size_t>(a.particles));
  const int threads = a.threads > 0 ? a.threads : omp_get_max_threads();
#pragma omp parallel for schedule(dynamic) num_threads(threads)
  for (long long i = 0; i < a.particles; ++i) runs[static_cast<std::size_t>(i)] = shadow(scene, static_cast<std::uint64_t>(i), opt);
  const LyapunovEstimate div = divergence_lyapunov(runs, 0, a.from, a.to);
  const ClassGrowth cls = class_growth(runs, 0);
  ShadowOptions bb;
  bb.tiers = {"double"};
  bb.collisions = 8000;
  const ShadowResult ball = shadow_from(scene, bouncing_ball_draw(scene, a.mupo_p), bb);
  const GrowthLaw law = growth_law(ball.tiers[0].divergence);

  const double rel = std::abs(div.per_time - tangent.per_time) / tangent.per_time;
  json doc;
  doc["lyapunov"] = {{"per_time", tangent.per_time},
                     {"per_collision", tangent.per_collision},
                     {"tangent", estimate_json(tangent)},
                     {"divergence", estimate_json(div)},
                     {"divergence_tier", a.tier},
                     {"divergence_window", {a.from, a.to}},
                     {"relative_difference", rel}};
  doc["growth_by_class"] = {{"tier", a.tier},
                            {"mupo_per_collision", cls.mupo_per_collision},
                            {"mupo_steps", cls.mupo_steps},
                            {"chaotic_per_collision", cls.chaotic_per_collision},
                            {"chaotic_steps", cls.chaotic_steps}};
  doc["mupo_orbit"] = {{"p0", a.mupo_p},       {"collisions", ball.tiers[0].collisions},
                       {"tier", "double"},     {"power", law.power},
                       {"power_r2", law.power_r2}, {"exp_rate_per_collision", law.rate},
                       {"exp_r2", law.rate_r2}, {"polynomial", law.polynomial()}};
  if (a.json_out) {
    std::cout << doc.dump(2) << "\n";
    return 0;
  }
  std::printf("Lyapunov exponent of %s\n", scene.source.c_str());
  std::printf("  tangent dynamics (%zu collisions, double): %.5f +- %.5f per time, %.5f +- %.5f per collision\n",
              tangent.collisions, tangent.per_time, tangent.per_time_error, tangent.per_collision, tangent.per_collision_error);
  std::printf("  shadow divergence (%zu particles, %s vs truth, t in [%g, %g]): %.5f +- %.5f per time, %.5f +- %.5f per collision\n",
              div.samples, a.tier.c_str(), a.from, a.to, div.per_time, div.per_time_error, div.per_collision, div.per_collision_error);
  std::printf("  relative difference: %.2f%%\n", 100 * rel);
  std::printf("growth of ln(divergence) per collision: MUPO phases %.4f (%zu steps), chaotic %.4f (%zu steps)\n",
              cls.mupo_per_collision, cls.mupo_steps, cls.chaotic_per_collision, cls.chaotic_steps);
  std::printf("bouncing-ball orbit, p0 = %g, %zu collisions in double: divergence ~ k^%.2f (R^2 %.4f) vs exp(%.4f k) (R^2 %.4f): %s\n",
              a.mupo_p, ball.tiers[0].collisions, law.power, law.power_r2, law.rate, law.rate_r2,
              law.polynomial() ? "polynomial" : "exponential");
  return 0;
}

}  // namespace

Command add_lyapunov(CLI::App& app) {
  auto a = std::make_shared<LyapunovArgs>();
  CLI::App* sub = app.add_subcommand("lyapunov", "Lyapunov exponent two ways (tangent dynamics, shadow divergence) and MUPO growth");
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
