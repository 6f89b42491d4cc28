// Scene files: TOML in, validated Scene out (every error names the key, the value and what is
// allowed); and the one serialiser of a Scene, as JSON (summary.json) and as TOML (scene.toml).
#pragma once

#include <string>
#include <vector>

#include "io/json.hpp"
#include "sim/model/scene.hpp"

namespace rotleak {

/// Reads and validates a TOML scene. `overrides` are "section.key=value" strings applied on top of
/// the file before validation (values for exact keys are taken verbatim as text).
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});
/// Same from TOML text (for tests and for scenes built in memory).
Scene parse_scene(const std::string& toml_text, const std::vector<std::string>& overrides = {},
                  const std::string& source = "<string>");

/// Refuses a scene on another table or with a list of leaks (Scene::on_table) for a command that runs the stadium
/// with one leak only so far (`command`: "rotleak audit"): an InputError naming SCENE and what it has.
void require_stadium(const Scene& scene, const std::string& command);

/// The scene as a JSON object: "source", then one object per TOML section, exact keys as their text.
json scene_json(const Scene& s);
/// A float as TOML writes it: the shortest decimal that reads back, with a point (1000.0, not 1000).
std::string toml_float(double x);
/// The scene as TOML text that parse_scene reads back to the same scene (scene_json, rendered as TOML).
std::string scene_to_toml(const Scene& s);
/// A scene_json document rendered as TOML.
std::string scene_to_toml(const json& doc);
/// What decides a run's numbers, as text: the scene without its fit keys (those only re-analyse)
/// and without run.checkpoint_seconds, plus the engine asked for. Two runs with equal inputs give
/// the same survival.csv; scans compare it to skip done points, checkpoints and shards to refuse a
/// resume or merge of a different run.
std::string simulation_inputs(const Scene& scene, const std::string& engine);

}  // namespace rotleak
