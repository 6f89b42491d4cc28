// rotleak audit SCENE --sample K [--json] [--out DIR]
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "io/files.hpp"
#include "verify/audit.hpp"

namespace rotleak::cli {

namespace {

using json = nlohmann::ordered_json;

struct AuditArgs {
  std::string scene, out, tiers = "float,double,long_double,dd,float128,mpfr:256";
  std::vector<std::string> sets;
  long long sample = 1000, stats = 1000000, stratify = 200000, max_collisions = 1500;
  double tolerance = 1e-6;
  int threads = 0;
  bool json_out = false, force = false;
};

json q_json(const Quantiles& q) {
  return {{"q10", q.q10}, {"q25", q.q25}, {"median", q.median}, {"q75", q.q75}, {"q90", q.q90}, {"n", q.n}};
}

int run_audit(const AuditArgs& a) {
  const Scene scene = load_scene(a.scene, a.sets);
  if (a.sample < 4 || a.sample > 1000000) throw InputError("--sample", std::to_string(a.sample), "must be in [4, 10^6]");
  if (a.stats < 1000) throw InputError("--stats-particles", std::to_string(a.stats), "must be >= 1000");
  if (a.max_collisions < 10) throw InputError("--max-collisions", std::to_string(a.max_collisions), "must be >= 10");
  AuditOptions opt;
  try {
    opt.tiers = parse_tier_list(a.tiers, false);
  } catch (const std::invalid_argument& e) {
    throw InputError("--tiers", "\"" + std::string(e.what()) + "\"", "allowed: float, double, long_double, dd, float128, mpfr:BITS");
  }
  opt.sample = static_cast<std::size_t>(a.sample);
  opt.stats_particles = static_cast<std::uint64_t>(a.stats);
  opt.stratify_particles = static_cast<std::uint64_t>(a.stratify);
  opt.max_collisions = static_cast<std::size_t>(a.max_collisions);
  opt.tolerance = a.tolerance;
  opt.threads = a.threads;
  opt.progress = ::isatty(2);
  std::unique_ptr<RunDirectory> dir;
  if (!a.out.empty()) dir = std::make_unique<RunDirectory>(a.out, a.force);

  const AuditReport r = audit(scene, opt);
  json doc;
  doc["scene"] = scene.source;
  doc["sample"] = r.sample;
  doc["seconds"] = r.seconds;
  doc["max_truth_bits"] = r.max_truth_bits;
  doc["lyapunov"] = {{"per_time", r.lyapunov_tangent.per_time},
                     {"per_collision", r.lyapunov_tangent.per_collision},
                     {"tangent", {{"per_time", r.lyapunov_tangent.per_time}, {"error", r.lyapunov_tangent.per_time_error}}},
                     {"divergence", {{"per_time", r.lyapunov_divergence.per_time},
                                     {"error", r.lyapunov_divergence.per_time_error},
                                     {"per_collision", r.lyapunov_divergence.per_collision},
                                     {"particles", r.lyapunov_divergence.samples}}}};
  json tiers = json::array();
  for (const auto& t : r.tiers)
    tiers.push_back({{"name", t.name},
                     {"median_horizon_collisions", t.horizon_collisions.median},
                     {"median_horizon_time", t.horizon_time.median},
                     {"escape_time_exact_fraction", t.escape_time_exact_fraction},
                     {"escapes_compared", t.escapes_compared},
                     {"beyond_horizon", t.beyond_horizon},
                     {"horizon_collisions", q_json(t.horizon_collisions)},
                     {"horizon_time", q_json(t.horizon_time)},
                     {"horizon_collisions_mupo", q_json(t.horizon_collisions_mupo)},
                     {"horizon_collisions_chaotic", q_json(t.horizon_collisions_chaotic)},
                     {"growth_per_collision_mupo", t.growth.mupo_per_collision},
                     {"growth_per_collision_chaotic", t.growth.chaotic_per_collision}});
  doc["tiers"] = tiers;
  json stats = json::array();
  for (const auto& s : r.statistics) {
    json w = json::array();
    for (const auto& x : s.windows)
      w.push_back({{"from", x.from}, {"to", x.to}, {"escapes", x.escapes_tier}, {"at_risk", x.at_risk_tier},
                   {"escapes_ref", x.escapes_ref}, {"at_risk_ref", x.at_risk_ref}, {"z", x.z}});
    stats.push_back({{"tier", s.tier}, {"windows", w}, {"max_abs_z", s.max_abs_z}, {"kappa", s.kappa},
                     {"kappa_error", s.kappa_error}, {"kappa_diff", s.kappa_diff}, {"kappa_diff_error", s.kappa_diff_error},
                     {"alpha", s.alpha ? json(*s.alpha) : json(nullptr)}, {"alpha_error", s.alpha_error},
                     {"alpha_diff", s.alpha_diff ? json(*s.alpha_diff) : json(nullptr)}, {"alpha_diff_error", s.alpha_diff_error},
                     {"consistent", s.consistent}, {"identical_to_scalar_double", s.identical_to_scalar_double}});
  }
  doc["statistics"] = stats;
  json scal = json::array();
  for (const auto& s : r.scalars)
    scal.push_back({{"tier", s.tier}, {"phase_error_at_tmax", s.phase_error_at_tmax}, {"omega_single_drift", s.omega_single_drift},
                    {"omega_split_drift", s.omega_split_drift}, {"time_ulp_at_tmax", s.time_ulp_at_tmax},
                    {"omega_is_rounded", s.omega_is_rounded}, {"phase_resolved", s.phase_resolved}, {"note", s.note}});
  doc["scalars"] = scal;
  json verdicts = json::array();
  for (const auto& v : r.verdicts)
    verdicts.push_back({{"tier", v.tier}, {"statistic", v.statistic}, {"verdict", v.verdict}, {"reason", v.reason}});
  doc["verdicts"] = verdicts;
  if (dir) {
    write_file_atomic(dir->file("audit.json"), doc.dump(2) + "\n");
    write_file_atomic(dir->file("summary.json"), doc.dump(2) + "\n");
    dir->commit();
  }
  if (a.json_out) {
    std::cout << doc.dump(2) << "\n";
    return 0;
  }
  std::printf("audit of %s: %zu particles shadowed (truth up to %ld bits), %.1f s\n", scene.source.c_str(), r.sample,
              r.max_truth_bits, r.seconds);
  std::printf("Lyapunov exponent: %.4f per time, %.4f per collision (tangent); shadow divergence %.4f +- %.4f per time\n",
              r.lyapunov_tangent.per_time, r.lyapunov_tangent.per_collision, r.lyapunov_divergence.per_time,
              r.lyapunov_divergence.per_time_error);
  std::printf("trust horizons in collisions (quantiles over particles that reached theirs; 'later' = escaped first),\n"
              "escape times reproduced, ln-divergence growth per collision by class:\n");
  std::printf("%-12s %6s %6s %6s %8s %6s %6s %6s %10s %9s %9s\n", "tier", "h10", "h50", "h90", "h50 time", "n", "later",
              "h50 MUPO", "escape ok", "g(MUPO)", "g(chaos)");
  for (const auto& t : r.tiers) {
    const std::string mupo = t.horizon_collisions_mupo.n ? std::to_string(static_cast<long>(t.horizon_collisions_mupo.median)) : "-";
    std::printf("%-12s %6.0f %6.0f %6.0f %8.1f %6zu %6zu %6s %9.1f%% %9.3f %9.3f\n", t.name.c_str(), t.horizon_collisions.q10,
                t.horizon_collisions.median, t.horizon_collisions.q90, t.horizon_time.median, t.horizon_collisions.n,
                t.beyond_horizon, mupo.c_str(), 100 * t.escape_time_exact_fraction, t.growth.mupo_per_collision,
                t.growth.chaotic_per_collision);
  }
  std::printf("statistics (same ids, %s ensembles):\n", "float / double / long double");
  for (const auto& s : r.statistics)
    std::printf("  %-12s max |z| %.2f, kappa %.5g (diff %.2g +- %.1g): %s\n", s.tier.c_str(), s.max_abs_z, s.kappa, s.kappa_diff,
                s.kappa_diff_error, s.consistent ? "consistent" : "DIFFERS");
  std::printf("scalars:\n");
  for (const auto& s : r.scalars) std::printf("  %-12s %s\n", s.tier.c_str(), s.note.c_str());
  std::printf("verdicts:\n");
  for (const auto& v : r.verdicts)
    std::printf("  %-12s %-12s %-22s %s\n", v.tier.c_str(), v.statistic.c_str(), v.verdict.c_str(), v.reason.c_str());
  return 0;
}

}  // namespace

Command add_audit(CLI::App& app) {
  auto a = std::make_shared<AuditArgs>();
  CLI::App* sub = app.add_subcommand("audit", "Which trajectories, statistics and scalars of a scene can be trusted, per tier");
  sub->add_option("scene", a->scene, "Scene file (TOML)")->required();
  sub->add_option("--sample", a->sample, "Particles to shadow, stratified by escape time (default 1000)");
  sub->add_option("--tiers", a->tiers, "Comma list of tiers to shadow");
  sub->add_option("--stats-particles", a->stats, "Ensemble size of the float/double/long double comparison (default 1e6)");
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
