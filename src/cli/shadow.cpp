// rotleak shadow SCENE --particle ID [--tiers double,dd,mpfr:256] [--collisions K] [--tolerance T] [--json] [--out DIR]
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "io/files.hpp"
#include "verify/shadow.hpp"

namespace rotleak::cli {

namespace {

using json = nlohmann::ordered_json;

struct ShadowArgs {
  std::string scene, out, tiers = "float,double,long_double,dd,float128,mpfr:256";
  std::vector<std::string> sets;
  long long particle = 0;
  long long collisions = 0;
  double tolerance = 1e-6;
  bool json_out = false, force = false, plot = true;
};

json opt_size(const std::optional<std::size_t>& v) { return v ? json(*v) : json(nullptr); }

json tier_json(const TierShadow& t) {
  return {{"name", t.name},
          {"collisions", t.collisions},
          {"horizon_collision", opt_size(t.horizon)},
          {"horizon_time", t.horizon ? json(t.horizon_time) : json(nullptr)},
          {"decision_differs_at", opt_size(t.decision)},
          {"escape_collision", opt_size(t.escape)},
          {"escape_time", t.escape ? json(t.escape_time) : json(nullptr)},
          {"escape_time_exact", t.escape_exact},
          {"growth_per_collision", t.growth_per_collision},
          {"growth_per_time", t.growth_per_time},
          {"growth_points", t.growth_points},
          {"stopped", t.stopped},
          {"seconds", t.seconds}};
}

int run_shadow(const ShadowArgs& a) {
  const Scene scene = load_scene(a.scene, a.sets);
  if (a.particle < 0 || static_cast<std::uint64_t>(a.particle) >= scene.particles)
    throw InputError("--particle", std::to_string(a.particle),
                     "must be a particle id in [0, " + std::to_string(scene.particles) + ")");
  if (a.collisions < 0) throw InputError("--collisions", std::to_string(a.collisions), "must be >= 0 (0: until the truth escapes)");
  if (!(a.tolerance > 0 && a.tolerance < 1)) throw InputError("--tolerance", std::to_string(a.tolerance), "must be in (0, 1)");
  ShadowOptions opt;
  try {
    opt.tiers = parse_tier_list(a.tiers, true);
  } catch (const std::invalid_argument& e) {
    throw InputError("--tiers", "\"" + std::string(e.what()) + "\"",
                     "allowed: float, double, long_double, dd, float128, mpfr:BITS, mpfi:BITS (BITS 24..2^20)");
  }
  opt.collisions = static_cast<std::size_t>(a.collisions);
  opt.tolerance = a.tolerance;
  std::unique_ptr<RunDirectory> dir;
  if (!a.out.empty()) dir = std::make_unique<RunDirectory>(a.out, a.force);

  const ShadowResult r = shadow(scene, static_cast<std::uint64_t>(a.particle), opt);
  json doc;
  doc["particle"] = r.id;
  doc["initial"] = {{"s", r.draw.s}, {"p", r.draw.p}, {"tau", r.draw.tau}};
  doc["collisions"] = r.horizon_collisions;
  doc["tolerance"] = a.tolerance;
  std::size_t mupo = 0;
  for (auto m : r.truth.mupo) mupo += m;
  doc["truth"] = {{"bits", r.truth.bits}, {"bits_tried", r.truth.bits_tried}, {"agreement", r.truth.agreement},
                  {"escape_collision", opt_size(r.truth.escape)},
                  {"escape_time", r.truth.escape ? json(r.truth.t[*r.truth.escape - 1]) : json(nullptr)},
                  {"mupo_collisions", mupo}};
  json tiers = json::array();
  for (const auto& t : r.tiers) tiers.push_back(tier_json(t));
  doc["tiers"] = tiers;

  if (dir) {
    std::string csv = "k,t,s,p,in_leak,mupo";
    for (const auto& t : r.tiers) csv += ",div_" + t.name + ",t_" + t.name + ",s_" + t.name + ",p_" + t.name;
    csv += "\n";
    for (std::size_t i = 0; i < r.truth.t.size(); ++i) {
      csv += std::to_string(i + 1) + "," + shortest(r.truth.t[i]) + "," + shortest(r.truth.s[i]) + "," +
             shortest(r.truth.p[i]) + "," + std::to_string(r.truth.in_leak[i]) + "," + std::to_string(r.truth.mupo[i]);
      for (const auto& t : r.tiers)
        csv += i < t.collisions ? "," + shortest(t.divergence[i]) + "," + shortest(t.t[i]) + "," + shortest(t.s[i]) + "," +
                                      shortest(t.p[i])
                                : ",,,,";
      csv += "\n";
    }
    write_file_atomic(dir->file("shadow.csv"), csv);
    write_file_atomic(dir->file("summary.json"), doc.dump(2) + "\n");
    dir->commit();
  }
  if (a.json_out) {
    std::cout << doc.dump(2) << "\n";
  } else {
    std::printf("particle %llu: s0 = %.17g, p0 = %.17g, created at t = %.17g; %zu collisions, %zu in MUPO phases\n",
                static_cast<unsigned long long>(r.id), r.draw.s, r.draw.p, r.draw.tau, r.horizon_collisions, mupo);
    std::printf("truth: MPFR at %ld bits (%ld bits agree to %.1e)", r.truth.bits, r.truth.bits / 2, r.truth.agreement);
    if (r.truth.escape) std::printf(", escapes at collision %zu, t = %.12g\n", *r.truth.escape, r.truth.t[*r.truth.escape - 1]);
    else std::printf(", does not escape within the horizon\n");
    std::printf("%-12s %10s %12s %10s %10s %8s %11s %9s\n", "tier", "horizon", "horizon t", "decision", "escape", "exact",
                "ln-growth/k", "seconds");
    for (const auto& t : r.tiers) {
      std::printf("%-12s %10s %12s %10s %10s %8s %11.3g %9.3g%s\n", t.name.c_str(),
                  t.horizon ? std::to_string(*t.horizon).c_str() : "-", t.horizon ? shortest(t.horizon_time).c_str() : "-",
                  t.decision ? std::to_string(*t.decision).c_str() : "-", t.escape ? std::to_string(*t.escape).c_str() : "-",
                  t.escape_exact ? "yes" : "no", t.growth_per_collision, t.seconds,
                  t.stopped.empty() ? "" : ("  (" + t.stopped + ")").c_str());
    }
  }
  if (dir && a.plot) {
    std::fflush(stdout);
    if (run_plot_script("plot_shadow.py", dir->final_path().string()) != 0) return 1;
  }
  return 0;
}

}  // namespace

Command add_shadow(CLI::App& app) {
  auto a = std::make_shared<ShadowArgs>();
  CLI::App* sub = app.add_subcommand("shadow", "Follow one particle in several precision tiers against an MPFR truth");
  sub->add_option("scene", a->scene, "Scene file (TOML)")->required();
  sub->add_option("--particle", a->particle, "Particle id (rebuilt bit-exactly from the scene's seed)")->required();
  sub->add_option("--tiers", a->tiers, "Comma list: float,double,long_double,dd,float128,mpfr:BITS,mpfi:BITS");
  sub->add_option("--collisions", a->collisions, "Horizon in collisions (default: until the truth escapes)");
  sub->add_option("--tolerance", a->tolerance, "Divergence that ends a tier's trust horizon (default 1e-6)");
  sub->add_option("--set", a->sets, "Override a scene key: section.key=value (repeatable)");
  sub->add_option("--out", a->out, "Directory for shadow.csv, summary.json and shadow.png");
  sub->add_flag("--force", a->force, "Replace an existing output directory");
  sub->add_flag("--json", a->json_out, "One JSON document on stdout");
  return {sub, [a] { return run_shadow(*a); }};
}

}  // namespace rotleak::cli
