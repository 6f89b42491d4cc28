// The verify report: JSON and the table rotleak verify prints.
#include "verify/reference.hpp"

#include "io/text.hpp"
#include "verify/reference_detail.hpp"

namespace rotleak {

using namespace reference_detail;

json verify_json(const VerifyReport& rep) {
  json doc;
  doc["reference"] = rep.reference_dir;
  doc["provenance"] = json::parse(rep.provenance_json);
  doc["error_model"] = error_model_json();
  doc["pass"] = rep.pass;
  json tiers = json::array();
  for (const TierCheck& t : rep.tiers)
    tiers.push_back({{"tier", t.tier},
                     {"case", t.case_name},
                     {"collisions", t.collisions},
                     {"must_reach", t.must_reach},
                     {"matched_through", t.matched_through},
                     {"worst_error_over_model", t.worst_ratio},
                     {"decisions_required", t.decisions_required},
                     {"decisions_reproduced", t.decisions_reproduced},
                     {"first_wrong_decision", nullable(t.first_wrong_decision)},
                     {"bits", t.bits},
                     {"stopped", t.stopped},
                     {"pass", t.pass}});
  doc["tiers"] = tiers;
  json engines = json::array();
  for (const EngineCheck& e : rep.engines)
    engines.push_back({{"engine", e.engine},
                       {"case", e.case_name},
                       {"checked", e.checked},
                       {"horizon", e.horizon},
                       {"expected", e.expected},
                       {"got", e.got},
                       {"pass", e.pass}});
  doc["engines"] = engines;
  json orbits = json::array();
  for (const OrbitReplay& o : rep.orbits)
    orbits.push_back({{"code", o.code},
                      {"tier", o.tier},
                      {"departure", o.departure},
                      {"predicted", o.predicted},
                      {"low", o.low},
                      {"high", o.high},
                      {"wrong_piece", o.wrong_piece},
                      {"pass", o.pass}});
  doc["orbits"] = orbits;
  return doc;
}

namespace {

/// Why a tier's case failed, in one line.
std::string tier_failure(const TierCheck& t) {
  std::string why;
  appendf(why, "%s %s: matched through collision %zu of %zu required", t.tier.c_str(), t.case_name.c_str(),
          t.matched_through, t.must_reach);
  if (t.first_wrong_decision) appendf(why, "; escape decision wrong at collision %zu", *t.first_wrong_decision);
  if (!t.bits_ok) why += "; bits " + t.bits;
  if (!t.stopped.empty()) why += "; " + t.stopped;
  return why;
}

/// One row of the tiers' table from the checks [i, end) of one tier; their failures appended.
void tier_row(std::string& out, const std::vector<TierCheck>& checks, std::size_t& i,
              std::vector<std::string>& failures) {
  const std::string& name = checks[i].tier;
  std::size_t cases = 0, reached = 0, req = 0, rep_ok = 0, bits_ok = 0, bits_compared = 0, pass = 0, must = 0;
  double worst = 0;
  for (; i < checks.size() && checks[i].tier == name; ++i) {
    const TierCheck& t = checks[i];
    ++cases;
    must += t.must_reach;
    reached += t.matched_through >= t.must_reach;
    req += t.decisions_required;
    rep_ok += t.decisions_reproduced;
    bits_compared += t.bits_compared;
    bits_ok += t.bits_compared && t.bits_ok;
    pass += t.pass;
    worst = std::max(worst, t.worst_ratio);
    if (!t.pass) failures.push_back(tier_failure(t));
  }
  // an interval tier is checked by containment: no error ratio, its decisions are its own proofs
  const bool interval = Tier::parse(name) && Tier::parse(name)->interval();
  char dec[32], bits[32], ratio[32];
  std::snprintf(dec, sizeof dec, "%zu/%zu", rep_ok, req);
  if (bits_compared)
    std::snprintf(bits, sizeof bits, "%zu/%zu", bits_ok, bits_compared);
  else
    std::snprintf(bits, sizeof bits, "none");  // no fingerprints of this tier: nothing was compared
  std::snprintf(ratio, sizeof ratio, "%.3g", worst);
  appendf(out, "%-12s %6zu %9.1f %4zu/%-4zu %9s %10s %7s  %s\n", name.c_str(), cases,
          static_cast<double>(must) / static_cast<double>(cases), reached, cases, interval ? "contained" : ratio,
          interval ? "-" : dec, interval ? "-" : bits, pass == cases ? "pass" : "FAIL");
}

/// The engines' table (nothing when no engine was checked); their failures appended.
void engine_rows(std::string& out, const std::vector<EngineCheck>& engines, std::vector<std::string>& failures) {
  if (engines.empty()) return;
  appendf(out, "\n%-12s %6s %8s %7s  %s\n", "engine", "cases", "checked", "agree", "verdict");
  for (std::size_t i = 0; i < engines.size();) {
    const std::string& name = engines[i].engine;
    std::size_t cases = 0, checked = 0, agree = 0;
    bool ok = true;
    for (; i < engines.size() && engines[i].engine == name; ++i) {
      const EngineCheck& e = engines[i];
      ++cases;
      checked += e.checked;
      agree += e.checked && e.pass;
      ok = ok && e.pass;
      if (!e.pass) failures.push_back(e.engine + " " + e.case_name + ": expected " + e.expected + ", got " + e.got);
    }
    appendf(out, "%-12s %6zu %8zu %7zu  %s\n", name.c_str(), cases, checked, agree, ok ? "pass" : "FAIL");
  }
}

/// The orbit replays (docs/model.md, "Periodic orbits"): per code and tier, the collision where the tier
/// leaves the orbit against its window; failures appended.
void orbit_rows(std::string& out, const std::vector<OrbitReplay>& orbits, std::vector<std::string>& failures) {
  if (orbits.empty()) return;
  appendf(out, "\n%-12s %-12s %9s %16s  %s\n", "orbit", "tier", "departs", "window", "verdict");
  for (const OrbitReplay& o : orbits) {
    appendf(out, "%-12s %-12s %9zu %7.1f..%-7.1f  %s\n", o.code.c_str(), o.tier.c_str(), o.departure, o.low, o.high,
            o.pass ? "pass" : "FAIL");
    if (!o.pass)
      failures.push_back("orbit " + o.code + " " + o.tier + ": leaves it at collision " + std::to_string(o.departure) +
                         (o.wrong_piece ? " (a wrong piece at " + std::to_string(o.wrong_piece) + ")" : std::string()) +
                         ", the error model says " + std::to_string(o.low) + " .. " + std::to_string(o.high));
  }
}

}  // namespace

std::string verify_text(const VerifyReport& rep) {
  std::string out;
  const json prov = json::parse(rep.provenance_json);
  appendf(out, "reference: %s (%zu cases; made by %s, %s)\n", rep.reference_dir.c_str(), rep.cases,
          prov.value("version", std::string("?")).c_str(), prov.value("date", std::string("?")).c_str());
  appendf(out,
          "error model: |tier - reference| <= %g u W_k + the reference's radius through the tier's horizon (u W_k <= "
          "%g); worst: the largest error in units of that bound / %g\n\n",
          kErrorModelSafety, kHorizonTolerance, kErrorModelSafety);
  appendf(out, "%-12s %6s %9s %9s %9s %10s %7s  %s\n", "tier", "cases", "horizon", "reached", "worst", "decisions",
          "bits", "verdict");
  std::vector<std::string> failures;
  for (std::size_t i = 0; i < rep.tiers.size();) tier_row(out, rep.tiers, i, failures);
  engine_rows(out, rep.engines, failures);
  orbit_rows(out, rep.orbits, failures);
  out += "\n";
  for (const std::string& f : failures) out += "FAIL " + f + "\n";
  out += rep.pass ? "verify: pass\n" : "verify: FAIL (" + std::to_string(failures.size()) + " checks)\n";
  return out;
}

}  // namespace rotleak
