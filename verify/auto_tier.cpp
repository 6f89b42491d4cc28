#include "verify/auto_tier.hpp"

#include <algorithm>

#include "verify/audit.hpp"

namespace rotleak {

TierChoice choose_tier(const Scene& scene, int threads) {
  AuditOptions opt;
  opt.tiers = {"float", "double", "long_double"};  // in order of cost
  opt.sample = 64;
  opt.stratify_particles = std::min<std::uint64_t>(20000, scene.particles);
  opt.stats_particles = std::min<std::uint64_t>(1000000, scene.particles);
  opt.max_collisions = 300;
  opt.threads = threads;
  Scene s = scene;
  s.tier = Tier::double_;
  const AuditReport rep = audit(s, opt);
  const Tier tiers[] = {Tier::float_, Tier::double_, Tier::long_double};
  std::string rejected;
  for (std::size_t k = 0; k < 3; ++k) {
    const std::string& name = opt.tiers[k];
    bool ok = true;
    std::string why;
    for (const Verdict& v : rep.verdicts)
      if (v.tier == name && v.statistic != "trajectories" && v.verdict == "not trusted") {
        ok = false;
        why = v.statistic + " not trusted: " + v.reason;
      }
    const ScalarCheck& sc = rep.scalars[k];
    if (ok && !sc.phase_resolved && scene.omega.sign() != 0) ok = false, why = "leak phase: " + sc.note;
    if (ok && sc.time_ulp_at_tmax > scene.survival_dt / 100)
      ok = false,
      why = "time resolution at t_max " + std::to_string(sc.time_ulp_at_tmax) + " is coarse against survival_dt";
    if (ok) {
      std::string verdict;
      for (const Verdict& v : rep.verdicts)
        if (v.tier == name && v.statistic == "P(t)") verdict = v.verdict + ": " + v.reason;
      return {tiers[k], "cheapest tier the audit trusts for P(t), kappa and alpha (" +
                            std::to_string(opt.stats_particles) +
                            " particles compared with the same ids in long double): " + name + ", " + verdict +
                            (rejected.empty() ? "" : "; rejected: " + rejected)};
    }
    rejected += (rejected.empty() ? "" : "; ") + name + " (" + why + ")";
  }
  return {Tier::long_double,
          "no ensemble tier passed the audit; ran the most precise one (long_double). Rejected: " + rejected};
}

}  // namespace rotleak
