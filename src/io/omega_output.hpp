// An OmegaReport as JSON ({"omega": {...}}) and as the lines a person reads.
#pragma once

#include <string>

#include "analysis/omega_report.hpp"
#include "io/json.hpp"

namespace rotleak {

json omega_json(const OmegaReport& r, const std::string& eps_text);
std::string omega_text(const OmegaReport& r, const std::string& eps_text);

}  // namespace rotleak
