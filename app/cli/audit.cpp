// rotleak audit SCENE --sample K [--json] [--out DIR]; under mpirun its ensembles and shadows are shared by the ranks
#include <unistd.h>

#include <cstdio>
#include <exception>
#include <iostream>

#include "analysis/output/run_output.hpp"
#include "cli/commands.hpp"
#include "io/scene_file.hpp"
#include "run/audit_shared.hpp"
#include "verify/reports.hpp"

namespace rotleak::cli {

namespace {

struct AuditArgs {
  std::string scene, out, tiers = "float,double,long_double,dd,float128,mpfr:256";
  std::vector<std::string> sets;
  long long sample = 1000, max_collisions = 1500;
  std::string stats = "1e6", stratify = "2e5";  ///< counts as text: 1000000 or 1e6
  double tolerance = 1e-6;
  int threads = 0;
  bool json_out = false, force = false;
};

int run_audit(const AuditArgs& a) {
  const Scene scene = load_scene(a.scene, a.sets);
  check_auditable(scene);
  if (a.sample < 4 || a.sample > 1000000)
    throw InputError("--sample", std::to_string(a.sample), "must be in [4, 10^6]");
  const std::uint64_t stats = parse_count("--stats-particles", a.stats, 1000);
  const std::uint64_t stratify = parse_count("--stratify-particles", a.stratify, 1);
  if (a.max_collisions < 10) throw InputError("--max-collisions", std::to_string(a.max_collisions), "must be >= 10");
  AuditOptions opt;
  try {
    opt.tiers = parse_tier_list(a.tiers, false);
  } catch (const std::invalid_argument& e) {
    throw InputError("--tiers", "\"" + std::string(e.what()) + "\"", "allowed: " + tier_names_allowed(false));
  }
  opt.sample = static_cast<std::size_t>(a.sample);
  opt.stats_particles = stats;
  opt.stratify_particles = stratify;
  opt.max_collisions = static_cast<std::size_t>(a.max_collisions);
  opt.tolerance = a.tolerance;
  opt.threads = a.threads;
  // under mpirun every rank audits its share; rank 0 stages the directory (before any work), reports, writes
  const Team& team = current_team();
  const bool lead = team.rank() == 0;
  opt.progress = lead && ::isatty(2);
  std::unique_ptr<RunDirectory> dir;
  std::exception_ptr failure;
  try {
    if (lead && !a.out.empty()) dir = std::make_unique<RunDirectory>(a.out, a.force);
  } catch (...) {
    failure = std::current_exception();
  }
  agree(team, failure);

  const AuditReport r = audit_shared(scene, opt, team);
  if (!lead) return 0;
  const json doc = audit_json(r, scene.source);
  if (dir) {
    write_file_atomic(dir->file("audit.json"), doc.dump(2) + "\n");
    write_directory_summary(*dir, "audit", scene.source, {"audit.json"});
  }
  if (a.json_out)
    std::cout << doc.dump(2) << "\n";
  else
    std::fputs(audit_text(r, scene.source).c_str(), stdout);
  return 0;
}

}  // namespace

Command add_audit(CLI::App& app) {
  auto a = std::make_shared<AuditArgs>();
  CLI::App* sub =
      app.add_subcommand("audit", "Which trajectories, statistics and scalars of a scene can be trusted, per tier");
  sub->add_option("scene", a->scene, "Scene file (TOML)")->required();
  sub->add_option("--sample", a->sample, "Particles to shadow, stratified by escape time (default 1000)");
  sub->add_option("--tiers", a->tiers, "Comma list of tiers to shadow");
  sub->add_option("--stats-particles", a->stats,
                  "Ensemble size of the float/double/long double comparison (default 1e6)");
  sub->add_option("--stratify-particles", a->stratify, "Ids scanned to build the strata (default 2e5)");
  sub->add_option("--max-collisions", a->max_collisions, "Shadow horizon cap per particle (default 1500)");
  sub->add_option("--tolerance", a->tolerance, "Divergence that ends a trust horizon (default 1e-6)");
  sub->add_option("--threads", a->threads, "OpenMP threads (default: all cores)");
  sub->add_option("--set", a->sets, "Override a scene key (repeatable)");
  sub->add_option("--out", a->out, "Directory for audit.json");
  sub->add_flag("--force", a->force, "Replace an existing output directory");
  sub->add_flag("--json", a->json_out, "One JSON document on stdout");
  return {sub, [a] { return run_audit(*a); }};
}

}  // namespace rotleak::cli
