#include "verify/auto_tier.hpp"

#include <algorithm>
#include <cstdio>

#include "verify/audit.hpp"

namespace rotleak {

TierChoice choose_tier(const Scene& scene, int threads) {
  AuditOptions opt;
  opt.tiers = {"float", "double", "long_double"};  // choose_from_audit reads its scalars in this order
  opt.sample = 64;
  opt.stratify_particles = std::min<std::uint64_t>(20000, scene.particles);
  opt.stats_particles = std::min<std::uint64_t>(1000000, scene.particles);
  opt.max_collisions = 300;
  opt.threads = threads;
  Scene s = scene;
  s.tier = Tier::double_;
  return choose_from_audit(scene, audit(s, opt), opt.stats_particles);
}

TierChoice choose_from_audit(const Scene& scene, const AuditReport& rep, std::uint64_t compared) {
  // the trusted tiers, each at its wall time on the audit's ensemble (the same ids): double runs the
  // vectorised engine when the CPU has one and the audit found its curve identical to the scalar one
  const auto seconds_of = [&rep](const std::string& name) {
    for (const auto& [tier, secs] : rep.ensemble_seconds_by_tier)
      if (tier == name) return secs;
    return -1.0;
  };
  const Tier tiers[] = {Tier::float_, Tier::double_, Tier::long_double};
  std::string rejected, timings;
  int best = -1;
  double best_seconds = 0;
  std::string best_verdict;
  for (std::size_t k = 0; k < 3; ++k) {
    const std::string name = to_string(tiers[k]);  // as the audit names its verdicts and ensembles
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
    if (!ok) {
      rejected += (rejected.empty() ? "" : "; ") + name + " (" + why + ")";
      continue;
    }
    double seconds = seconds_of(name);
    std::string engine = name;
    if (name == "double")
      for (const StatisticsCheck& st : rep.statistics)
        if (st.tier == "double_simd" && st.identical_to_scalar_double && seconds_of("double_simd") >= 0 &&
            seconds_of("double_simd") < seconds)
          seconds = seconds_of("double_simd"), engine = "double (vectorised)";
    char t[96];
    std::snprintf(t, sizeof t, "%s %.3g s", engine.c_str(), seconds);
    timings += (timings.empty() ? "" : ", ") + std::string(t);
    if (best < 0 || seconds < best_seconds) {
      best = static_cast<int>(k), best_seconds = seconds;
      best_verdict.clear();
      for (const Verdict& v : rep.verdicts)
        if (v.tier == name && v.statistic == "P(t)") best_verdict = v.verdict + ": " + v.reason;
    }
  }
  if (best < 0)
    return {Tier::long_double,
            "no ensemble tier passed the audit; ran the most precise one (long_double). Rejected: " + rejected};
  return {tiers[best], "fastest tier the audit trusts for P(t), kappa and alpha, by wall time on the audit's " +
                           std::to_string(compared) + " particles (" + timings +
                           "; the same ids compared with long double): " + to_string(tiers[best]) + ", " +
                           best_verdict + (rejected.empty() ? "" : "; rejected: " + rejected)};
}

}  // namespace rotleak
