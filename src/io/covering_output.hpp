// The MUPO covering as documents: summary JSON, the f_L profile and breakpoints as CSV, and the
// lines a person reads.
#pragma once

#include <string>
#include <vector>

#include "analysis/covering.hpp"
#include "io/json.hpp"

namespace rotleak {

/// The inputs as the user wrote them.
struct CoveringTexts {
  std::string delta, lambda, d, r;
};
/// summary.json of `rotleak covering`: the inputs, then one covering (or a list of them).
json covering_document(const CoveringTexts& input, const std::vector<std::string>& omegas,
                       const std::vector<Covering>& results);

/// One omega's covering (omega as the user wrote it).
json covering_json(const std::string& omega, const Covering& c);
/// f_L.csv: s (bin centre), then f_L of each covering averaged over the bin.
std::string covering_profile_csv(const std::vector<std::string>& omegas, const std::vector<Covering>& results,
                                 std::size_t resolution);
/// segments_K.csv: the exact breakpoints of one covering.
std::string covering_segments_csv(const Covering& c);
/// One line per omega.
std::string covering_text(const std::vector<std::string>& omegas, const std::vector<Covering>& results);

}  // namespace rotleak
