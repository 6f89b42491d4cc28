// The run directory's CSV files (survival.csv, fc.csv, escapes.csv): written from a run's tallies, and
// survival.csv read back (refits, calibrate, merge) with the grammar the Python reader checks too.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string_view>

#include "io/run_output.hpp"
#include "io/text.hpp"

namespace rotleak {

std::string survival_csv(const SurvivalCurve& curve) {
  std::string out = "t,survivors,P,P_err\n";
  out.reserve(curve.survivors.size() * 48);
  for (std::size_t k = 0; k < curve.survivors.size(); ++k) {
    out += shortest(curve.t[k]);
    out += ',';
    out += std::to_string(curve.survivors[k]);
    out += ',';
    out += shortest(curve.P(k));
    out += ',';
    out += shortest(curve.P_err(k));
    out += '\n';
  }
  return out;
}

namespace {

/// A decimal field as rotleak writes it: -?digits[.digits][e[+-]digits], or inf, -inf, nan. The Python
/// reader (python/rotleak/readers.py) checks the same grammar, so both refuse the same damage.
bool decimal_field(std::string_view f, bool integer) {
  if (!integer && (f == "inf" || f == "-inf" || f == "nan")) return true;
  std::size_t i = 0;
  const auto digits = [&] {
    const std::size_t from = i;
    while (i < f.size() && f[i] >= '0' && f[i] <= '9') ++i;
    return i > from;
  };
  if (integer) return digits() && i == f.size();
  if (i < f.size() && f[i] == '-') ++i;
  if (!digits()) return false;
  if (i < f.size() && f[i] == '.') {
    ++i;
    if (!digits()) return false;
  }
  if (i < f.size() && (f[i] == 'e' || f[i] == 'E')) {
    ++i;
    if (i < f.size() && (f[i] == '+' || f[i] == '-')) ++i;
    if (!digits()) return false;
  }
  return i == f.size();
}

}  // namespace

SurvivalCurve read_survival_csv(const std::string& text, const Scene& scene) {
  SurvivalCurve c;
  c.particles = scene.particles;
  c.lines = scene.splitting.on;
  c.weighted = scene.sampling.weighted() || c.lines;
  c.max_weight = scene.sampling.max_weight();
  const double n = static_cast<double>(scene.particles);
  const std::string header = "t,survivors,P,P_err\n";
  if (text.compare(0, header.size(), header) != 0)
    throw std::runtime_error("survival.csv: expected the header t,survivors,P,P_err");
  if (text.back() != '\n') throw std::runtime_error("survival.csv: ends inside a row (truncated)");
  std::size_t line = 1;
  for (std::size_t pos = header.size(); pos < text.size();) {
    const std::size_t end = text.find('\n', pos);
    const std::string_view row(text.data() + pos, end - pos);
    pos = end + 1;
    ++line;
    std::string_view field[4];
    std::size_t from = 0, count = 0;
    for (std::size_t i = 0; i <= row.size() && count < 5; ++i)
      if (i == row.size() || row[i] == ',') {
        if (count < 4) field[count] = row.substr(from, i - from);
        ++count;
        from = i + 1;
      }
    double t = 0, P = 0, err = 0;
    unsigned long long k = 0;
    const auto number = [](std::string_view f, double& x) {
      const std::string s(f);  // strtod: inf and nan as written; the grammar was checked first
      x = std::strtod(s.c_str(), nullptr);
    };
    if (count != 4 || !decimal_field(field[0], false) || !decimal_field(field[1], true) ||
        !decimal_field(field[2], false) || !decimal_field(field[3], false) ||
        std::from_chars(field[1].data(), field[1].data() + field[1].size(), k).ec != std::errc())
      throw std::runtime_error("survival.csv line " + std::to_string(line) + ": expected t,survivors,P,P_err");
    number(field[0], t);
    number(field[2], P);
    number(field[3], err);
    c.t.push_back(t);
    c.survivors.push_back(k);
    if (c.lines) {  // P_err = P sqrt((R - 1) / N); lines alive are not in the file
      c.P_w.push_back(P);
      c.R.push_back(P > 0 ? 1 + n * (err / P) * (err / P) : 0.0);
      c.G.push_back(std::max(c.G.empty() ? 0.0 : c.G.back(), P > 0 ? (err / P) * (err / P) : 0.0));
      c.lines_alive.push_back(0);
    } else if (c.weighted) {
      c.P_w.push_back(P);
      c.Q.push_back(err * err * n + P * P);  // P_err = sqrt((Q - P^2) / N)
    }
  }
  const std::size_t grid = scene.survival_bins() + 1;
  if (c.t.size() != grid)
    throw std::runtime_error("survival.csv: " + std::to_string(c.t.size()) +
                             " rows where the grid t = k * survival_dt up to t_max has " + std::to_string(grid) +
                             " (truncated or of another scene)");
  return c;
}

std::string density_csv(const Scene& scene, const Tally& tally) {
  const auto& spec = *scene.collision_density;
  const std::size_t bins = static_cast<std::size_t>(spec.bins);
  std::string out = "s";
  std::vector<std::uint64_t> totals(spec.windows.size(), 0);
  std::vector<FixedSum> weight_totals(spec.windows.size());
  for (std::size_t w = 0; w < spec.windows.size(); ++w) {
    const std::string tag = "[" + shortest(spec.windows[w].from) + ":" + shortest(spec.windows[w].to) + "]";
    out += ",fc" + tag + ",count" + tag;
    for (std::size_t b = 0; b < bins; ++b) totals[w] += tally.collision_density[w * bins + b];
    if (tally.weighted())
      for (std::size_t b = 0; b < bins; ++b) weight_totals[w].merge(tally.collision_density_w[w * bins + b]);
  }
  out += '\n';
  for (std::size_t b = 0; b < bins; ++b) {
    out += shortest((static_cast<double>(b) + 0.5) / static_cast<double>(bins));
    for (std::size_t w = 0; w < spec.windows.size(); ++w) {
      const std::uint64_t c = tally.collision_density[w * bins + b];
      // weighted runs: f_c from the weights (the count column stays the raw number of collisions)
      const double density =
          tally.weighted() ? (weight_totals[w].value() > 0 ? tally.collision_density_w[w * bins + b].value() *
                                                                 static_cast<double>(bins) / weight_totals[w].value()
                                                           : 0.0)
          : totals[w]      ? static_cast<double>(c) * static_cast<double>(bins) / static_cast<double>(totals[w])
                           : 0.0;
      out += ',' + shortest(density) + ',' + std::to_string(c);
    }
    out += '\n';
  }
  return out;
}

std::string escapes_csv(std::uint64_t first_id, const std::vector<EscapeRecord>& records) {
  std::string out = "id,fate,t,s,collisions\n";
  static const char* names[] = {"escaped", "survived", "stuck"};
  for (std::size_t i = 0; i < records.size(); ++i) {
    const EscapeRecord& r = records[i];
    out += std::to_string(first_id + i) + ',' + names[static_cast<int>(r.fate)] + ',' + shortest(r.t) + ',' +
           (r.fate == Fate::escaped ? shortest(r.s) : std::string()) + ',' + std::to_string(r.collisions) + '\n';
  }
  return out;
}

}  // namespace rotleak
