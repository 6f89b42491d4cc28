// Writing a scene: scene_json (summary.json's "scene"), its TOML rendering (scene.toml, which
// parse_scene reads back to the same scene), and the simulation's inputs text the tally files carry.
#include <sstream>

#include "io/scene_file.hpp"

namespace rotleak {

namespace {

/// [start_splitting]'s keys, written only when on (as run.splitting's are).
json start_splitting_inputs(const StartSplitSpec& g) {
  return {{"on", true},
          {"replicates", g.replicates},
          {"factor", g.factor},
          {"moves", g.moves},
          {"halvings", g.halvings},
          {"window", g.window},
          {"deep_tier", Tier{g.deep_tier, 0}.name()},
          {"handover_bits", g.handover_bits},
          {"p", {g.p_lo, g.p_hi}},
          {"edges", g.edges}};
}

}  // namespace

json scene_json(const Scene& s) {
  json j;
  j["source"] = s.source;
  if (s.table) {  // any other table: its kind and parameters as written
    json t = {{"kind", s.table->kind}};
    const TableKind& kind = *find_table_kind(s.table->kind);
    for (std::size_t i = 0; i < s.table->params.size(); ++i) t[kind.params[i]] = s.table->params[i].text;
    if (!s.table->vertices.empty()) {
      t["vertices"] = json::array();
      for (const auto& [x, y] : s.table->vertices) t["vertices"].push_back({x.text, y.text});
    }
    j["table"] = t;
  } else {
    j["stadium"] = {{"d", s.d_text}, {"r", s.r_text}};
  }
  if (s.leaks.empty()) {
    j["leak"] = {{"width", s.width_text}, {"start", s.start_text}, {"omega", s.omega_text}};
  } else {  // a list: [[leaks]]
    j["leaks"] = json::array();
    for (const LeakInput& l : s.leaks)
      j["leaks"].push_back(
          {{"loop", l.loop}, {"width", l.width.text}, {"start", l.start.text}, {"omega", l.omega.text}});
  }
  j["ensemble"] = {{"particles", s.particles},
                   {"seed", s.seed},
                   {"init", to_string(s.init)},
                   {"creation_window", s.creation_window}};
  if (s.sampling.weighted()) {
    j["ensemble"]["sampling"] = to_string(s.sampling.kind);
    j["ensemble"]["sampling_eps"] = s.sampling.eps;
    j["ensemble"]["sampling_p"] = {s.sampling.p_min, s.sampling.p_max};
    if (s.sampling.ride > 0) j["ensemble"]["sampling_ride"] = s.sampling.ride;  // 0: the inputs as before
  }
  if (s.enter_through >= 0) j["ensemble"]["enter_through"] = s.enter_through;  // absent: the inputs as before
  j["run"] = {{"t_max", s.t_max},
              {"tier", to_string(s.tier)},
              {"fast_forward", s.fast_forward},
              {"checkpoint_seconds", s.checkpoint_seconds}};
  if (s.start_splitting.on) j["start_splitting"] = start_splitting_inputs(s.start_splitting);  // only when on
  if (s.splitting.on) {  // written only when on: the inputs of every other run stay as they were
    j["run"]["splitting"] = true;
    j["run"]["split_every"] = s.splitting.every;
    j["run"]["split_delta"] = s.splitting.delta;
    j["run"]["split_cap"] = s.splitting.cap;
  }
  json obs = {{"survival_dt", s.survival_dt}, {"escapes", s.escape_records}};
  if (s.collision_density) {
    json w = json::array();
    for (const auto& win : s.collision_density->windows) w.push_back({win.from, win.to});
    obs["collision_density"] = {{"bins", s.collision_density->bins}, {"windows", w}};
  }
  j["observe"] = obs;
  j["fit"] = {{"kappa_window", {s.kappa_window.from, s.kappa_window.to}},
              {"alpha_factor", s.alpha_factor},
              {"alpha_sigma", s.alpha_sigma},
              {"min_survivors", s.min_survivors},
              {"tail_floor", s.tail_floor}};
  return j;
}

namespace {

/// A JSON value as a TOML value: strings in JSON's escapes (valid TOML basic strings), floats with
/// a decimal point so they read back as floats, arrays and objects inline.
std::string toml_value(const json& v) {
  switch (v.type()) {
    case json::value_t::number_float:
      return toml_float(v.get<double>());
    case json::value_t::array: {
      std::string out = "[";
      for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + toml_value(v[i]);
      return out + "]";
    }
    case json::value_t::object: {
      std::string out = "{ ";
      bool first = true;
      for (const auto& [k, x] : v.items()) {
        out += (first ? "" : ", ") + k + " = " + toml_value(x);
        first = false;
      }
      return out + " }";
    }
    default:
      return v.dump();  // strings, integers, booleans: JSON's text is TOML's
  }
}

}  // namespace

std::string scene_to_toml(const Scene& s) { return scene_to_toml(scene_json(s)); }

std::string simulation_inputs(const Scene& scene, const std::string& engine) {
  Scene physics = scene;
  physics.kappa_window = {0, 0};
  physics.alpha_factor = physics.alpha_sigma = 0;
  physics.min_survivors = 0;
  json doc = scene_json(physics);
  doc["run"].erase("checkpoint_seconds");
  doc["fit"].erase("tail_floor");  // added after the others: the inputs of earlier runs and scans stay as they were
  return scene_to_toml(doc) + "# engine = " + engine + "\n";
}

std::string scene_to_toml(const json& doc) {
  std::string out;
  const auto section_text = [&out](const std::string& header, const json& keys) {
    out += (out.empty() ? "" : "\n") + header + "\n";
    for (const auto& [k, v] : keys.items()) out += k + " = " + toml_value(v) + "\n";
  };
  for (const auto& [section, keys] : doc.items()) {
    if (keys.is_object()) section_text("[" + section + "]", keys);
    if (keys.is_array())  // a list of tables: [[leaks]]
      for (const json& item : keys) section_text("[[" + section + "]]", item);
    // anything else ("source": where it came from) is not part of the scene
  }
  return out;
}

}  // namespace rotleak
