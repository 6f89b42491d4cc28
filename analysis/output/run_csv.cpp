// The run directory's CSV files (survival.csv, lines.csv, fc.csv, escapes.csv): written from a run's tallies,
// and survival.csv and lines.csv read back (refits, calibrate) with the grammar the Python reader checks too.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "analysis/output/run_output.hpp"
#include "io/files.hpp"
#include "io/text.hpp"
#include "sim/tally/estimators.hpp"

namespace rotleak {

std::string survival_csv(const SurvivalCurve& curve) {
  // an importance-sampled run (not split) keeps the survivors' weight sums its P and P_err are made from
  const bool sums = curve.weighted && !curve.lines && !curve.replicated;
  std::string out = sums ? "t,survivors,P,P_err,W,W2\n" : "t,survivors,P,P_err\n";
  out.reserve(curve.survivors.size() * (sums ? 96 : 48));
  for (std::size_t k = 0; k < curve.survivors.size(); ++k) {
    out += shortest(curve.t[k]);
    out += ',';
    out += std::to_string(curve.survivors[k]);
    out += ',';
    out += shortest(curve.P(k));
    out += ',';
    out += shortest(curve.P_err(k));
    if (sums) {
      out += ',';
      out += shortest(curve.W[k]);
      out += ',';
      out += shortest(curve.Q[k]);
    }
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

/// A row's comma-separated fields into f (as many as fit; its size is what a row must have): the count.
std::size_t split_fields(std::string_view row, std::vector<std::string_view>& f) {
  std::size_t from = 0, count = 0;
  for (std::size_t i = 0; i <= row.size() && count <= f.size(); ++i)
    if (i == row.size() || row[i] == ',') {
      if (count < f.size()) f[count] = row.substr(from, i - from);
      ++count;
      from = i + 1;
    }
  return count;
}

/// A field decimal_field accepted, as a double (strtod: inf and nan as written).
double field_value(std::string_view f) { return std::strtod(std::string(f).c_str(), nullptr); }

}  // namespace

SurvivalCurve read_survival_csv(const std::string& text, const Scene& scene) {
  SurvivalCurve c;
  c.particles = scene.particles;
  c.lines = scene.splitting.on;
  c.replicated = scene.start_splitting.on;
  c.replicates = scene.start_splitting.replicates;
  c.weighted = scene.sampling.weighted() || c.lines || c.replicated;
  c.max_weight = scene.sampling.max_weight();
  const double n = static_cast<double>(scene.particles);
  const bool sums = c.weighted && !c.lines && !c.replicated;  // the survivors' weight sums W, W2 beside P
  const std::string columns = sums ? "t,survivors,P,P_err,W,W2" : "t,survivors,P,P_err";
  const std::string header = columns + "\n";
  if (text.compare(0, header.size(), header) != 0)
    throw std::runtime_error("survival.csv: expected the header " + columns);
  if (text.back() != '\n') throw std::runtime_error("survival.csv: ends inside a row (truncated)");
  std::size_t line = 1;
  for (std::size_t pos = header.size(); pos < text.size();) {
    const std::size_t end = text.find('\n', pos);
    const std::string_view row(text.data() + pos, end - pos);
    pos = end + 1;
    ++line;
    std::vector<std::string_view> field(sums ? 6 : 4);
    const std::size_t count = split_fields(row, field);
    unsigned long long k = 0;
    bool ok = count == field.size() && decimal_field(field[1], true) &&
              std::from_chars(field[1].data(), field[1].data() + field[1].size(), k).ec == std::errc();
    for (std::size_t f = 0; ok && f < field.size(); ++f) ok = f == 1 || decimal_field(field[f], false);
    if (!ok) throw std::runtime_error("survival.csv line " + std::to_string(line) + ": expected " + columns);
    const double t = field_value(field[0]), P = field_value(field[2]), err = field_value(field[3]);
    c.t.push_back(t);
    c.survivors.push_back(k);
    if (c.replicated) {  // P and its error from the replicates' spread (G from them below)
      c.P_w.push_back(P);
      c.E.push_back(err);
    } else if (c.lines) {  // P_err = P sqrt((R - 1) / N); lines alive are not in the file
      c.P_w.push_back(P);
      c.R.push_back(P > 0 ? 1 + n * (err / P) * (err / P) : 0.0);
      c.G.push_back(std::max(c.G.empty() ? 0.0 : c.G.back(), P > 0 ? (err / P) * (err / P) : 0.0));
      c.lines_alive.push_back(0);
    } else if (sums) {  // P = W / W(0), written from these very doubles: a P that is not is damage
      c.W.push_back(field_value(field[4]));
      c.Q.push_back(field_value(field[5]));
      if (!(P == (c.W[0] > 0 ? c.W.back() / c.W[0] : 0.0)))
        throw std::runtime_error("survival.csv line " + std::to_string(line) + ": P is not W / W at t = 0");
    }
  }
  if (sums) self_normalise(c);
  if (c.replicated) running_replicate_variance(c);
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

std::string escapes_csv(std::uint64_t first_id, const std::vector<EscapeRecord>& records, bool leak_column) {
  std::string out = leak_column ? "id,fate,t,s,collisions,leak\n" : "id,fate,t,s,collisions\n";
  static const char* names[] = {"escaped", "survived", "stuck"};
  for (std::size_t i = 0; i < records.size(); ++i) {
    const EscapeRecord& r = records[i];
    const bool escaped = r.fate == Fate::escaped;
    out += std::to_string(first_id + i) + ',' + names[static_cast<int>(r.fate)] + ',' + shortest(r.t) + ',' +
           (escaped ? shortest(r.s) : std::string()) + ',' + std::to_string(r.collisions);
    if (leak_column) out += ',' + (escaped ? std::to_string(r.leak) : std::string());
    out += '\n';
  }
  return out;
}

std::string leaks_csv(const Scene& scene, const Tally& tally) {
  const std::size_t bins = tally.escapes_per_bin.size(), leaks = bins ? tally.escapes_by_leak.size() / bins : 0;
  std::string out = "t_from,t_to";
  for (std::size_t j = 0; j < leaks; ++j) out += ",escaped_" + std::to_string(j);
  out += '\n';
  for (std::size_t k = 0; k < bins; ++k) {
    const double from = static_cast<double>(k) * scene.survival_dt;
    const double to = k + 1 == bins ? scene.t_max : static_cast<double>(k + 1) * scene.survival_dt;
    out += shortest(from) + ',' + shortest(to);
    for (std::size_t j = 0; j < leaks; ++j) out += ',' + std::to_string(tally.leak_escapes(j, k));
    out += '\n';
  }
  return out;
}

std::string lines_csv(const SurvivalCurve& c) {
  std::string out = "t,P,R,lines_alive,unsplit_lines,unsplit_P";
  for (const SurvivalCurve::UnsplitGroup& k : c.unsplit_classes) {
    const std::string n = std::to_string(k.classes.front());
    out += ",lines_c" + n + ",P_c" + n + ",var_c" + n;
  }
  out += '\n';
  for (std::size_t j = 0; j < c.t.size(); ++j) {
    out += shortest(c.t[j]) + ',' + shortest(c.P_w[j]) + ',' + shortest(c.R_lines[j]) + ',' +
           std::to_string(c.lines_alive[j]) + ',' + std::to_string(c.unsplit_lines[j]) + ',' + shortest(c.unsplit_P[j]);
    for (const SurvivalCurve::UnsplitGroup& k : c.unsplit_classes)
      out += ',' + std::to_string(k.lines[j]) + ',' + shortest(k.P[j]) + ',' + shortest(k.var[j]);
    out += '\n';
  }
  return out;
}

namespace {

/// lines.csv's header: the fixed columns, then the classes (distinct, increasing, each lines_c, P_c, var_c).
std::vector<int> lines_classes(std::string_view header) {
  const std::string fixed = "t,P,R,lines_alive,unsplit_lines,unsplit_P";
  if (header.substr(0, fixed.size()) != fixed)
    throw std::runtime_error("lines.csv: expected the header to begin " + fixed);
  std::vector<int> classes;
  std::string_view rest = header.substr(fixed.size());
  while (!rest.empty()) {
    int k = -1;
    const auto col = [&](std::string_view name) {
      if (rest.substr(0, name.size()) != name) throw std::runtime_error("lines.csv: bad class columns in the header");
      rest.remove_prefix(name.size());
      int v = -1;
      const auto [p, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), v);
      if (ec != std::errc() || v < 0 || v >= kUnsplitClasses || (k >= 0 && v != k))
        throw std::runtime_error("lines.csv: bad class columns in the header");
      rest.remove_prefix(static_cast<std::size_t>(p - rest.data()));
      k = v;
    };
    col(",lines_c");
    col(",P_c");
    col(",var_c");
    if (!classes.empty() && k <= classes.back())
      throw std::runtime_error("lines.csv: the classes must be distinct and increasing");
    classes.push_back(k);
  }
  return classes;
}

}  // namespace

void read_lines_csv(const std::string& text, const Scene& scene, SurvivalCurve& c) {
  if (!c.lines) throw std::runtime_error("lines.csv: the run is not split (run.splitting = false)");
  const std::size_t eol = text.find('\n');
  if (eol == std::string::npos || text.back() != '\n') throw std::runtime_error("lines.csv: truncated");
  const std::vector<int> classes = lines_classes(std::string_view(text).substr(0, eol));
  const std::size_t fields = 6 + 3 * classes.size(), points = c.t.size();
  c.unsplit_classes.assign(classes.size(), {});
  for (std::size_t q = 0; q < classes.size(); ++q) c.unsplit_classes[q].classes = {classes[q]};
  c.unsplit_lines.clear();
  c.unsplit_P.clear();
  std::size_t line = 1, row = 0;
  std::vector<std::string_view> f(fields);
  for (std::size_t pos = eol + 1; pos < text.size(); ++row) {
    const std::size_t end = text.find('\n', pos);
    const std::string_view r(text.data() + pos, end - pos);
    pos = end + 1;
    ++line;
    const std::string where = "lines.csv line " + std::to_string(line) + ": ";
    if (split_fields(r, f) != fields || row >= points)
      throw std::runtime_error(where + "expected " + std::to_string(fields) + " fields on a grid row");
    const auto number = [&](std::size_t i) {
      if (!decimal_field(f[i], false))
        throw std::runtime_error(where + "field " + std::to_string(i + 1) + " is not a number");
      return field_value(f[i]);
    };
    const auto count_of = [&](std::size_t i) {
      std::uint64_t k = 0;
      if (!decimal_field(f[i], true) || std::from_chars(f[i].data(), f[i].data() + f[i].size(), k).ec != std::errc())
        throw std::runtime_error(where + "field " + std::to_string(i + 1) + " is not a count");
      return k;
    };
    // survival.csv's t and P, written from the same doubles: any difference is another run's file
    if (number(0) != c.t[row] || number(1) != c.P_w[row])
      throw std::runtime_error(where + "t or P differs from survival.csv");
    c.R[row] = number(2);
    c.lines_alive[row] = count_of(3);
    c.unsplit_lines.push_back(count_of(4));
    c.unsplit_P.push_back(number(5));
    for (std::size_t q = 0; q < classes.size(); ++q) {
      c.unsplit_classes[q].lines.push_back(count_of(6 + 3 * q));
      c.unsplit_classes[q].P.push_back(number(7 + 3 * q));
      c.unsplit_classes[q].var.push_back(number(8 + 3 * q));
    }
  }
  if (row != points)
    throw std::runtime_error("lines.csv: " + std::to_string(row) + " rows where the grid has " +
                             std::to_string(points));
  finish_lines_curve(scene, c);
}

SurvivalCurve read_run_curve(const std::filesystem::path& dir, const Scene& scene) {
  SurvivalCurve c = read_survival_csv(read_file(dir / "survival.csv"), scene);
  if (c.lines && std::filesystem::exists(dir / "lines.csv")) read_lines_csv(read_file(dir / "lines.csv"), scene, c);
  return c;
}

}  // namespace rotleak
