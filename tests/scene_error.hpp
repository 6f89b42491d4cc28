// The one-line message a scene's reader gives for bad input, or "" when it accepts it: what the scene tests check.
#pragma once

#include <string>
#include <vector>

#include "io/scene_file.hpp"

namespace rotleak {

inline std::string error_of(const std::string& toml, const std::vector<std::string>& sets = {}) {
  try {
    parse_scene(toml, sets);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace rotleak
