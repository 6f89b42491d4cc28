#include "verify/auto_tier.hpp"

#include <algorithm>
#include <cstdio>

#include "numeric/input.hpp"
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
  std::string rejected, rejected_short, timings;
  int best = -1;
  double best_seconds = 0;
  std::string best_verdict;
  for (std::size_t k = 0; k < 3; ++k) {
    const std::string name = to_string(tiers[k]);  // as the audit names its verdicts and ensembles
    // the audit's one rule: every statistic trusted (an untested one is not chosen), the scalars passing
    bool ok = true;
    std::string why;
    for (const Verdict& v : rep.verdicts)
      if (ok && v.tier == name && v.statistic != "trajectories" && v.verdict != "trusted" &&
          v.verdict != "trusted as a statistic") {
        ok = false;
        why = v.statistic + " " + v.verdict + ": " + v.reason;
      }
    if (const auto out = scalar_rejection(scene, rep.scalars[k]); ok && out) ok = false, why = *out;
    if (!ok) {
      rejected += (rejected.empty() ? "" : "; ") + name + " (" + why + ")";
      // the one-line refusal keeps each reason's first clause
      rejected_short += (rejected_short.empty() ? "" : "; ") + name + ": " + why.substr(0, why.find(';'));
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
    throw InputError("run.tier", "auto",
                     "no ensemble tier is trusted on this scene (" + rejected_short +
                         "); name a tier to run it anyway (simulate then warns), or shorten t_max");
  return {tiers[best], "fastest tier the audit trusts for P(t), kappa and alpha, by wall time on the audit's " +
                           std::to_string(compared) + " particles (" + timings +
                           "; the same ids compared with long double): " + to_string(tiers[best]) + ", " +
                           best_verdict + (rejected.empty() ? "" : "; rejected: " + rejected)};
}

}  // namespace rotleak
