// rotleak shadow SCENE --particle ID [--tiers double,dd,mpfr:256] [--collisions K] [--tolerance T] [--json] [--out DIR]
#include <cstdio>
#include <iostream>

#include "cli/commands.hpp"
#include "io/files.hpp"
#include "io/scene_file.hpp"
#include "verify/reports.hpp"

namespace rotleak::cli {

namespace {

struct ShadowArgs {
  std::string scene, out, tiers = "float,double,long_double,dd,float128,mpfr:256";
  std::vector<std::string> sets;
  long long particle = 0;
  long long collisions = 0;
  double tolerance = 1e-6;
  bool json_out = false, force = false, plot = true;
};

int run_shadow(const ShadowArgs& a) {
  const Scene scene = load_scene(a.scene, a.sets);
  if (a.particle < 0 || static_cast<std::uint64_t>(a.particle) >= scene.particles)
    throw InputError("--particle", std::to_string(a.particle),
                     "must be a particle id in [0, " + std::to_string(scene.particles) + ")");
  if (a.collisions < 0)
    throw InputError("--collisions", std::to_string(a.collisions), "must be >= 0 (0: until the truth escapes)");
  if (!(a.tolerance > 0 && a.tolerance < 1))
    throw InputError("--tolerance", std::to_string(a.tolerance), "must be in (0, 1)");
  ShadowOptions opt;
  try {
    opt.tiers = parse_tier_list(a.tiers, true);
  } catch (const std::invalid_argument& e) {
    throw InputError("--tiers", "\"" + std::string(e.what()) + "\"", "allowed: " + tier_names_allowed(true));
  }
  opt.collisions = static_cast<std::size_t>(a.collisions);
  opt.tolerance = a.tolerance;
  std::unique_ptr<RunDirectory> dir;
  if (!a.out.empty()) dir = std::make_unique<RunDirectory>(a.out, a.force);

  const ShadowResult r = shadow(scene, static_cast<std::uint64_t>(a.particle), opt);
  const json doc = shadow_json(r, a.tolerance);
  if (dir) {
    write_file_atomic(dir->file("shadow.csv"), shadow_csv(r));
    write_file_atomic(dir->file("summary.json"), doc.dump(2) + "\n");
    dir->commit();
  }
  if (a.json_out)
    std::cout << doc.dump(2) << "\n";
  else
    std::fputs(shadow_text(r).c_str(), stdout);
  return dir && a.plot ? plot_after_run(dir->final_path().string(), a.json_out) : 0;
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
