// run.tier = "auto": the cheapest ensemble tier whose audit verdict trusts the statistics the scene
// asks for (P(t), kappa, alpha), with its leak phase resolved and its time grid fine enough.
#pragma once

#include <string>

#include "sim/scene.hpp"

namespace rotleak {

struct TierChoice {
  Tier tier = Tier::double_;
  std::string reason;
};

/// Runs a small audit of float, double and long double on the scene (seconds for 10^6 particles).
TierChoice choose_tier(const Scene& scene, int threads = 0);

}  // namespace rotleak
