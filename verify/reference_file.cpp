// The reference set on disk: data/trajectories (reference.json, cases, one steps CSV per case), read
// and written whole, and two sets compared (what --regenerate changed).
#include "verify/reference.hpp"

#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>

#include "io/files.hpp"
#include "io/scene_file.hpp"
#include "verify/reference_detail.hpp"

namespace rotleak {

using namespace reference_detail;

namespace {

// ---- reading and writing ----

std::string steps_csv(const RefCase& c) {
  std::string out = "k,piece,t,s,p,phase,in_leak,margin,radius,gain\n";
  char buf[200];
  for (const RefStep& st : c.steps) {
    std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g\n", st.margin, st.radius, st.gain);
    out += std::to_string(st.k) + "," + piece_name(st.piece) + "," + st.t + "," + st.s + "," + st.p + "," + st.phase +
           "," + (st.in_leak ? "1" : "0") + "," + buf;
  }
  return out;
}

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char ch : line) {
    if (ch == sep) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += ch;
    }
  }
  out.push_back(cur);
  return out;
}

std::vector<RefStep> read_steps(const std::filesystem::path& path) {
  // strtod, not stod: a radius of 1e-310 is a fine (subnormal) number, which stod refuses
  auto number = [&](const std::string& text) { return from_hex(text, path.string()); };
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  std::string line;
  std::getline(in, line);
  if (line != "k,piece,t,s,p,phase,in_leak,margin,radius,gain")
    throw std::runtime_error(path.string() + ": unexpected header");
  std::vector<RefStep> out;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const auto f = split(line, ',');
    if (f.size() != 10) throw std::runtime_error(path.string() + ": a line without 10 fields: " + line.substr(0, 80));
    RefStep st;
    st.k = std::stoul(f[0]);
    st.piece = piece_of(f[1]);
    st.t = f[2];
    st.s = f[3];
    st.p = f[4];
    st.phase = f[5];
    st.in_leak = f[6] == "1";
    st.margin = number(f[7]);
    st.radius = number(f[8]);
    st.gain = number(f[9]);
    if (st.k != out.size() + 1) throw std::runtime_error(path.string() + ": collisions out of order at " + f[0]);
    out.push_back(std::move(st));
  }
  return out;
}

}  // namespace

std::optional<std::size_t> RefCase::escape() const {
  for (const RefStep& st : steps)
    if (st.in_leak) return st.k;
  return std::nullopt;
}

std::vector<std::string> reference_tiers() { return {"float", "double", "long_double", "dd", "float128", "mpfr:256"}; }

void write_reference(const std::string& dir, const ReferenceSet& set) {
  namespace fs = std::filesystem;
  fs::create_directories(fs::path(dir) / "steps");
  json doc;
  doc["format"] = 1;
  doc["provenance"] = json::parse(set.provenance_json);
  doc["error_model"] = error_model_json();
  json cases = json::array();
  for (const RefCase& c : set.cases) {
    const std::string file = "steps/" + c.name + ".csv";
    write_file_atomic(fs::path(dir) / file, steps_csv(c));
    json j;
    j["name"] = c.name;
    j["kind"] = c.kind;
    j["note"] = c.note;
    j["particle"] = nullable(c.id);
    j["draw"] = {{"s", hex_exact(c.draw.s)}, {"p", hex_exact(c.draw.p)}, {"x", hex_exact(c.draw.x)},
                 {"y", hex_exact(c.draw.y)}, {"u", hex_exact(c.draw.u)}, {"tau", hex_exact(c.draw.tau)},
                 {"flow", c.draw.flow}};
    j["bits"] = c.bits;
    j["collisions_requested"] = c.requested;
    j["collisions"] = c.steps.size();
    j["escape"] = nullable(c.escape());
    j["steps"] = file;
    json fp = json::object();
    for (const auto& [tier, list] : c.fingerprints) {
      json a = json::array();
      for (const auto& [k, h] : list) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
        a.push_back({k, buf});
      }
      fp[tier] = a;
    }
    j["fingerprints"] = fp;
    j["scene"] = c.scene_toml;
    cases.push_back(j);
  }
  doc["cases"] = cases;
  write_file_atomic(fs::path(dir) / "reference.json", doc.dump(1) + "\n");
  // step files of cases no longer in the set go (after the new index no longer names them)
  std::set<std::string> keep;
  for (const RefCase& c : set.cases) keep.insert(c.name + ".csv");
  for (const auto& entry : fs::directory_iterator(fs::path(dir) / "steps"))
    if (entry.path().extension() == ".csv" && !keep.count(entry.path().filename().string())) fs::remove(entry.path());
}

ReferenceSet read_reference(const std::string& dir) {
  namespace fs = std::filesystem;
  const fs::path index = fs::path(dir) / "reference.json";
  std::ifstream in(index);
  if (!in) throw std::runtime_error("cannot read " + index.string() + " (regenerate with rotleak verify --regenerate)");
  ReferenceSet set;
  try {
    const json doc = json::parse(in);
    if (doc.at("format").get<int>() != 1) throw std::runtime_error("unknown format");
    set.provenance_json = doc.at("provenance").dump();
    for (const json& j : doc.at("cases")) {
      RefCase c;
      c.name = j.at("name").get<std::string>();
      c.kind = j.at("kind").get<std::string>();
      c.note = j.at("note").get<std::string>();
      if (!j.at("particle").is_null()) c.id = j.at("particle").get<std::uint64_t>();
      const json& d = j.at("draw");
      const std::string what = c.name + ".draw";
      c.draw = {from_hex(d.at("s"), what), from_hex(d.at("p"), what), from_hex(d.at("x"), what),
                from_hex(d.at("y"), what), from_hex(d.at("u"), what), from_hex(d.at("tau"), what),
                d.at("flow").get<bool>()};
      c.bits = j.at("bits").get<long>();
      c.requested = j.at("collisions_requested").get<std::size_t>();
      c.scene_toml = j.at("scene").get<std::string>();
      c.scene = parse_scene(c.scene_toml, {}, "reference case " + c.name);
      c.steps = read_steps(fs::path(dir) / j.at("steps").get<std::string>());
      if (c.steps.size() != j.at("collisions").get<std::size_t>())
        throw std::runtime_error(c.name + ": the step file does not hold the collisions the index says");
      for (const auto& [tier, list] : j.at("fingerprints").items())
        for (const json& e : list)
          c.fingerprints[tier].emplace_back(e.at(0).get<std::size_t>(),
                                            std::stoull(e.at(1).get<std::string>(), nullptr, 16));
      set.cases.push_back(std::move(c));
    }
  } catch (const json::exception& e) {
    throw std::runtime_error(index.string() + ": " + e.what());
  }
  return set;
}

std::vector<std::string> compare_references(const ReferenceSet& before, const ReferenceSet& after) {
  std::vector<std::string> lines;
  std::map<std::string, const RefCase*> old;
  for (const RefCase& c : before.cases) old[c.name] = &c;
  for (const RefCase& c : after.cases) {
    const auto it = old.find(c.name);
    if (it == old.end()) {
      lines.push_back(c.name + ": new (" + std::to_string(c.steps.size()) + " collisions)");
      continue;
    }
    const RefCase& o = *it->second;
    old.erase(it);
    const double L = perimeter(c.scene);
    if (o.scene_toml != c.scene_toml || o.draw.s != c.draw.s || o.draw.p != c.draw.p || o.draw.x != c.draw.x ||
        o.draw.y != c.draw.y || o.draw.u != c.draw.u || o.draw.tau != c.draw.tau) {
      lines.push_back(c.name + ": another particle or scene");
      continue;
    }
    const auto a = parse_steps(o, L), b = parse_steps(c, L);
    std::optional<std::size_t> moved;
    double by = 0;
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
      const double d =
          std::max({distance(a[i].t, b[i].t), L * distance(a[i].s, b[i].s, true), distance(a[i].p, b[i].p)});
      const double allowed = o.steps[i].radius + c.steps[i].radius + a[i].resolution + b[i].resolution;
      if (o.steps[i].piece != c.steps[i].piece || o.steps[i].in_leak != c.steps[i].in_leak || d > allowed) {
        moved = i + 1;
        by = d;
        break;
      }
    }
    if (moved) {
      char buf[160];
      std::snprintf(buf, sizeof buf, ": trajectory differs from collision %zu (by %.3g)", *moved, by);
      lines.push_back(c.name + buf);
    } else if (a.size() != b.size()) {
      lines.push_back(c.name + ": certified through " + std::to_string(b.size()) + " collisions (was " +
                      std::to_string(a.size()) + ")");
    }
    for (const auto& [tier, list] : c.fingerprints) {
      const auto f = o.fingerprints.find(tier);
      if (f == o.fingerprints.end() || f->second != list) {
        std::size_t k = 0;
        if (f != o.fingerprints.end())
          for (std::size_t i = 0; i < std::min(list.size(), f->second.size()); ++i)
            if (list[i] != f->second[i]) {
              k = list[i].first;
              break;
            }
        lines.push_back(c.name + ": " + tier + " bits differ" + (k ? " by collision " + std::to_string(k) : ""));
      }
    }
  }
  for (const auto& [name, c] : old) lines.push_back(name + ": removed");
  return lines;
}

}  // namespace rotleak
