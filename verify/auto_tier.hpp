// run.tier = "auto": the fastest ensemble tier, by wall time on the audit's own ensembles (double on
// the vectorised engine where it runs), whose audit verdict trusts the statistics the scene asks for
// (P(t), kappa, alpha), with its leak phase resolved and its time grid fine enough.
#pragma once

#include <string>

#include "sim/model/scene.hpp"

namespace rotleak {

struct TierChoice {
  Tier tier = Tier::double_;
  std::string reason;
};

/// Runs a small audit of float, double and long double on the scene (seconds for 10^6 particles).
TierChoice choose_tier(const Scene& scene, int threads = 0);

struct AuditReport;
/// The choice from an audit of float, double and long double (its verdicts, scalar checks and
/// per-ensemble wall times); `compared`: the particles its ensembles ran.
TierChoice choose_from_audit(const Scene& scene, const AuditReport& report, std::uint64_t compared);

}  // namespace rotleak
