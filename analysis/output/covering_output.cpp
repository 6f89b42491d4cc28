#include "analysis/output/covering_output.hpp"

#include <cstdio>

#include "analysis/output/run_output.hpp"
#include "io/files.hpp"
#include "io/text.hpp"
#include "numeric/input.hpp"

namespace rotleak {

json covering_json(const std::string& omega, const Covering& c) {
  json gaps = json::array();
  for (const auto& g : c.gaps) {
    json e = {{"length", g.length}, {"count", g.count}};
    if (!g.exact.empty()) e["exact"] = g.exact;
    gaps.push_back(e);
  }
  return {{"omega", omega},
          {"x", c.x_text},
          {"N", c.N},
          {"exact", c.exact},
          {"error_bound", c.error_bound},
          {"zero_measure", c.zero_measure},
          {"max_zero_gap", c.max_zero_gap},
          {"clusters", c.clusters},
          {"min", c.min},
          {"max", c.max},
          {"mean", c.mean},
          {"cv", c.cv},
          {"discrepancy", c.discrepancy},
          {"gaps", gaps},
          {"three_distance_holds", c.three_distance_holds},
          {"segments", c.segments.size()}};
}

json covering_document(const CoveringTexts& in, const std::vector<std::string>& omegas,
                       const std::vector<Covering>& results) {
  json list = json::array();
  for (std::size_t i = 0; i < results.size(); ++i) list.push_back(covering_json(omegas[i], results[i]));
  json doc;
  double seconds = 0;  // timing is the one thing that differs between two computations of the same inputs
  for (const Covering& c : results) seconds += c.seconds;
  doc["execution"] = execution_json({{"seconds", seconds}});
  doc["input"] = {{"delta", in.delta}, {"lambda", in.lambda}, {"d", in.d}, {"r", in.r}};
  doc["covering"] = list.size() == 1 ? list[0] : list;
  return doc;
}

std::string covering_profile_csv(const std::vector<std::string>& omegas, const std::vector<Covering>& results,
                                 std::size_t resolution) {
  std::string csv = "s";
  for (const auto& o : omegas) csv += ",f_L[" + o + "]";
  csv += "\n";
  std::vector<std::vector<double>> prof;
  for (const auto& c : results) prof.push_back(covering_profile(c, resolution));
  for (std::size_t b = 0; b < resolution; ++b) {
    csv += shortest((static_cast<double>(b) + 0.5) / static_cast<double>(resolution));
    for (const auto& p : prof) csv += "," + shortest(p[b]);
    csv += "\n";
  }
  return csv;
}

std::string covering_segments_csv(const Covering& c) {
  std::string seg = "from,to,f_L\n";
  for (const auto& s : c.segments)
    seg += shortest(s.from) + "," + shortest(s.to) + "," + std::to_string(s.value) + "\n";
  return seg;
}

std::string covering_text(const std::vector<std::string>& omegas, const std::vector<Covering>& results) {
  std::string out;
  for (std::size_t i = 0; i < results.size(); ++i) {
    const Covering& c = results[i];
    std::string how = "exact";
    if (!c.exact) {
      how.clear();
      appendf(how, "certified, points within %.1e", c.error_bound);
    }
    appendf(out,
            "omega = %s: N = %llu, %s, zero measure %.4g, longest zero gap %.4g, %llu clusters, f_L in [%llu, %llu], "
            "mean %.4g, cv %.3g, discrepancy %.3g, %zu gap lengths%s (%.3f s)\n",
            omegas[i].c_str(), static_cast<unsigned long long>(c.N), how.c_str(), c.zero_measure, c.max_zero_gap,
            static_cast<unsigned long long>(c.clusters), static_cast<unsigned long long>(c.min),
            static_cast<unsigned long long>(c.max), c.mean, c.cv, c.discrepancy, c.gaps.size(),
            c.three_distance_holds ? "" : " (three-distance check FAILED)", c.seconds);
  }
  return out;
}

namespace {

/// The request's exact values, each checked against its range (an InputError naming its option).
struct ExactCovering {
  CoveringInput base;  ///< lambda, d, r (omega and delta: per entry, below)
  std::vector<ExactReal> omegas, deltas;
};

ExactCovering exact_covering(const CoveringRequest& a) {
  if (a.omegas.empty()) throw InputError("--omega", "(none)", "give at least one omega");
  if (a.deltas.empty()) throw InputError("--delta", "(none)", "give at least one delta");
  auto exact = [](const std::string& key, const std::string& text, bool open_unit) {
    const ExactReal v = parse_exact_input(key, text);
    if (v.sign() <= 0 || (open_unit && (v - ExactReal::parse("1")).sign() >= 0))
      throw InputError(key, "\"" + text + "\"", open_unit ? "must be in (0, 1)" : "must be > 0");
    return v;
  };
  ExactCovering e;
  for (const std::string& delta : a.deltas) e.deltas.push_back(exact("--delta", delta, true));
  e.base.lambda = exact("--lambda", a.lambda, true);
  e.base.d = exact("--d", a.d, false);
  e.base.r = exact("--r", a.r, false);
  for (const auto& o : a.omegas) e.omegas.push_back(parse_exact_input("--omega", o));
  return e;
}

}  // namespace

void check_covering_request(const CoveringRequest& request) { (void)exact_covering(request); }

CoveringOutcome compute_coverings(const CoveringRequest& a) {
  const ExactCovering e = exact_covering(a);
  CoveringInput in = e.base;

  // every omega at every delta; with several deltas each entry is labelled "omega @ delta D"
  CoveringOutcome out;
  for (const std::string& delta : a.deltas) out.delta_list += (out.delta_list.empty() ? "" : ",") + delta;
  for (std::size_t k = 0; k < e.omegas.size(); ++k)
    for (std::size_t j = 0; j < e.deltas.size(); ++j) {
      in.omega = e.omegas[k];
      in.delta = e.deltas[j];
      try {
        out.results.push_back(mupo_covering(in));
      } catch (const std::invalid_argument& err) {
        throw InputError("--delta", "\"" + a.deltas[j] + "\"", err.what());
      }
      out.labels.push_back(a.deltas.size() > 1 ? a.omegas[k] + " @ delta " + a.deltas[j] : a.omegas[k]);
    }
  out.document = covering_document({out.delta_list, a.lambda, a.d, a.r}, out.labels, out.results);
  if (a.deltas.size() > 1)  // each entry names its delta
    for (std::size_t i = 0; i < out.labels.size(); ++i)
      out.document["covering"][i]["delta"] = a.deltas[i % a.deltas.size()];
  return out;
}

}  // namespace rotleak
