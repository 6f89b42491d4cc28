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
/// A covering computation as the command line and Python ask for it: every omega at every delta,
/// each an exact text ("2/3", "1e-4", "ln(19)").
struct CoveringRequest {
  std::vector<std::string> omegas;
  std::vector<std::string> deltas{"1e-7"};
  std::string lambda = "0.01", d = "2", r = "1";
};
struct CoveringOutcome {
  std::vector<std::string> labels;  ///< the omega, or "omega @ delta D" when there are several deltas
  std::vector<Covering> results;
  std::string delta_list;  ///< the deltas, comma-separated
  json document;           ///< summary.json
};
/// Checks every input against its range: an InputError naming --omega, --delta, --lambda, --d or --r.
void check_covering_request(const CoveringRequest& request);
/// check_covering_request, then every covering.
CoveringOutcome compute_coverings(const CoveringRequest& request);

/// One line per omega.
std::string covering_text(const std::vector<std::string>& omegas, const std::vector<Covering>& results);

}  // namespace rotleak
