// An OmegaReport as JSON ({"omega": {...}}) and as the lines a person reads.
#pragma once

#include <string>

#include "analysis/omega_report.hpp"
#include "io/json.hpp"

namespace rotleak {

/// `rotleak omega` and rotleak.omega() as asked, every value an exact text.
struct OmegaRequest {
  std::string value;             ///< "70/71", "1e-4", "ln(19)", "liouville(10)", ...
  long long terms = 20;          ///< certified partial quotients, [1, 10^6]
  std::string max_den = "1000";  ///< largest denominator of the best approximations (an integer >= 1)
  std::string eps;               ///< also the smallest q with |omega - p/q| < eps (empty: not asked)
  int digits = 30;               ///< digits of the certified enclosure, [1, 10^5]
  int convergents = 12;          ///< convergents listed with their errors
};
/// Checks every input (an InputError naming omega, --terms, --max-den, --eps or --digits), then reports.
OmegaReport compute_omega(const OmegaRequest& request);

json omega_json(const OmegaReport& r, const std::string& eps_text);
std::string omega_text(const OmegaReport& r, const std::string& eps_text);

}  // namespace rotleak
