#include "run/regimes_search.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>

#include "io/files.hpp"
#include "numeric/exact.hpp"
#include "numeric/input.hpp"

namespace rotleak {

namespace fs = std::filesystem;

namespace {

struct Probe {
  std::string omega;  ///< exact text
  double value = 0;
  std::string regime, tail;
  json alpha;
  double crossing_time = 0;
  std::uint64_t particles = 0;
  std::uint64_t resolve = 0;  ///< undecided: about the particles that would decide it (0: none said)

  /// no tail seen, but the bound lies above fit.tail_floor: neither mid nor high at this resolution
  bool open() const { return regime == "undecided" && tail == "none"; }
  /// low, or undecided with a tail that tau2 came too late to show removed (the search's low side)
  bool low_side() const { return regime == "low" || (regime == "undecided" && tail != "none"); }
};

Probe probe_of(const json& row, const std::string& omega) {
  Probe p;
  p.omega = omega;
  p.value = std::strtod(omega.c_str(), nullptr);  // for ordering and reporting; the probe runs the exact text
  p.regime = row.at("tail").at("regime");
  p.tail = row.at("tail").at("class");
  p.alpha = row.at("alpha");
  if (!p.alpha.at("crossing_time").is_null()) p.crossing_time = p.alpha.at("crossing_time");
  p.particles = row.at("particles");
  if (row.at("tail").contains("resolve_particles") && row.at("tail").at("resolve_particles").is_number())
    p.resolve = row.at("tail").at("resolve_particles");
  return p;
}

/// The geometric mean of two omegas, as an exact decimal with 3 significant digits.
std::string log_midpoint(double a, double b) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2e", std::sqrt(a * b));
  return buf;
}

json probe_json(const Probe& p) {
  return {{"omega", p.omega}, {"regime", p.regime}, {"tail", p.tail}, {"alpha", p.alpha}, {"particles", p.particles}};
}

/// "the probes at omega = a, b are undecided ...: about N particles would decide them", or empty.
std::string open_probes(const std::vector<Probe>& probes) {
  std::string omegas;
  std::uint64_t most = 0;
  for (const Probe& p : probes)
    if (p.open()) {
      omegas += (omegas.empty() ? "" : ", ") + p.omega;
      most = std::max(most, p.resolve);
    }
  if (omegas.empty()) return "";
  char line[160];
  std::snprintf(line, sizeof line, "about %.2g particles a probe would decide them", static_cast<double>(most));
  return "undecided at this resolution (no tail seen, but the alpha bound lies above fit.tail_floor) at omega = " +
         omegas + ": " + line;
}

}  // namespace

namespace {

/// A scan of the request's scene over leak.omega = values into out.
ScanOutcome scan_omegas(const RegimesRequest& req, const fs::path& out, const std::vector<std::string>& values) {
  ScanRequest s;
  s.scene_path = req.scene_path;
  s.scene_text = req.scene_text;
  s.overrides = req.overrides;
  s.axes = {ScanAxis{"leak.omega", values}};
  s.out = out;
  s.run = req.run;
  s.note = req.note;
  return scan(s);
}

/// Bisects in log omega between a probe on the lower side of a boundary and one above it, at most
/// req.steps probes; a probe this resolution cannot classify stops it, and the boundary is flagged
/// (unplaced).
json bisect_boundary(const RegimesRequest& req, const fs::path& dir, const std::string& name, Probe lo, Probe hi,
                     const std::function<bool(const Probe&)>& lower_side) {
  json steps = json::array();
  std::string unplaced;
  for (int k = 0; k < req.steps && hi.value / lo.value > 1.1; ++k) {
    const std::string mid = log_midpoint(lo.value, hi.value);
    if (req.note) req.note("[regimes] " + name + ": probe omega = " + mid + " in [" + lo.omega + ", " + hi.omega + "]");
    const ScanOutcome o = scan_omegas(req, dir / name / ("probe-" + std::to_string(k)), {mid});
    const Probe p = probe_of(o.document.at("points")[0], mid);
    steps.push_back(probe_json(p));
    if (p.open()) {
      unplaced = "the boundary lies in [" + lo.omega + ", " + hi.omega + "] only: the probe " + open_probes({p});
      break;
    }
    (lower_side(p) ? lo : hi) = p;
  }
  return json{{"unplaced", unplaced.empty() ? json(nullptr) : json(unplaced)},
              {"lo", lo.value},
              {"hi", hi.value},
              {"lo_omega", lo.omega},
              {"hi_omega", hi.omega},
              {"lo_regime", lo.regime},
              {"hi_regime", hi.regime},
              {"particles", std::max(lo.particles, hi.particles)},
              {"probes", steps}};
}

/// The geometry's predictions: low/mid where the leak reaches the lower edge (tau1) just when the tail would
/// form (the crossing time of the lowest probe); mid/high at omega_sweep = lambda / 2r.
json predicted_boundaries(const json& coarse_points, const std::vector<Probe>& probes) {
  json predicted = json::object();
  predicted["omega_sweep"] = coarse_points[0].at("predicted").at("omega_sweep");
  const Probe& slowest = probes.front();
  if (slowest.crossing_time > 0) {
    // tau1 * omega is the distance (in s) from the leading edge to the lower edge, the same for every omega
    double dist = 0;
    for (const json& r : coarse_points)
      if (r.at("values").at("leak.omega") == slowest.omega)
        dist = r.at("predicted").at("tau1").get<double>() * slowest.value;
    predicted["low_mid"] = dist / slowest.crossing_time;
    predicted["low_mid_rule"] =
        "omega at which the leak's leading edge reaches the lower straight edge (tau1) at the alpha crossing time "
        "of the slowest probe, t = " +
        std::to_string(slowest.crossing_time);
  }
  return predicted;
}

}  // namespace

json find_regimes(const RegimesRequest& req) {
  const fs::path dir = RunDirectory::normalise(req.out);
  const std::vector<std::string> coarse_values = expand_values("--coarse", req.coarse);
  for (const std::string& v : coarse_values) {
    const mpq_class q = parse_decimal(v);  // decimals only: the search bisects numerically
    if (sgn(q) <= 0) throw InputError("--coarse", req.coarse, "positive decimal omegas");
  }
  if (req.note) req.note("[regimes] coarse scan over omega = " + req.coarse);
  const ScanOutcome coarse = scan_omegas(req, dir / "coarse", coarse_values);
  std::vector<Probe> probes;
  for (std::size_t i = 0; i < coarse_values.size(); ++i)
    probes.push_back(probe_of(coarse.document.at("points")[i], coarse_values[i]));
  std::sort(probes.begin(), probes.end(), [](const Probe& a, const Probe& b) { return a.value < b.value; });
  const auto is_low = [](const Probe& p) { return p.low_side(); };
  const auto is_below_high = [](const Probe& p) { return p.regime != "high"; };
  // low/mid: the last low (or undecided) probe below the first mid probe after it; mid/high: the first mid
  // probe followed by a high one, above the low/mid boundary
  std::optional<std::size_t> lm, mh;
  for (std::size_t i = 0; i + 1 < probes.size() && !lm; ++i)
    if (is_low(probes[i]) && probes[i + 1].regime == "mid") lm = i;
  for (std::size_t i = lm ? *lm + 1 : 0; i + 1 < probes.size() && !mh; ++i)
    if (probes[i].regime == "mid" && probes[i + 1].regime == "high") mh = i;
  json boundaries = json::object(), reasons = json::object();
  const std::string open = open_probes(probes);
  const std::string open_note = open.empty() ? std::string() : "; " + open;
  boundaries["low_mid"] = lm ? bisect_boundary(req, dir, "low_mid", probes[*lm], probes[*lm + 1], is_low) : nullptr;
  if (!lm)
    reasons["low_mid"] =
        "the coarse scan has no low (or undecided with a tail) omega directly below a mid one" + open_note;
  boundaries["mid_high"] =
      mh ? bisect_boundary(req, dir, "mid_high", probes[*mh], probes[*mh + 1], is_below_high) : nullptr;
  if (!mh)
    reasons["mid_high"] =
        "the coarse scan has no mid omega directly below a high one (above the low/mid boundary)" + open_note;
  json coarse_rows = json::array();
  for (const Probe& p : probes) coarse_rows.push_back(probe_json(p));
  json doc = {{"scene", req.scene_path},
              {"overrides", req.overrides},
              {"boundaries", boundaries},
              {"reasons", reasons},
              {"predicted", predicted_boundaries(coarse.document.at("points"), probes)},
              {"coarse", coarse_rows}};
  write_file_atomic(dir / "regimes.json", doc.dump(2) + "\n");
  return doc;
}

}  // namespace rotleak
