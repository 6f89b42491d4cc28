// libFuzzer target: the scene reader with --set overrides (io/scene_file.hpp). The input is a TOML text,
// then, after a line "#--set", one override per line. Bad input must be an InputError with a one-line
// message (the command line prints it and exits 2); a scene that is read must write back to a TOML text
// that reads to the same text again (scene_to_toml is what run directories keep as scene.toml).
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "io/scene_file.hpp"
#include "numeric/input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string in(reinterpret_cast<const char*>(data), size);
  std::string toml = in;
  std::vector<std::string> sets;
  const std::string mark = "\n#--set\n";
  if (const auto cut = in.find(mark); cut != std::string::npos) {
    toml = in.substr(0, cut);
    std::istringstream rest(in.substr(cut + mark.size()));
    for (std::string line; std::getline(rest, line);)
      if (!line.empty()) sets.push_back(line);
  }
  try {
    const rotleak::Scene scene = rotleak::parse_scene(toml, sets, "fuzz.toml");
    const std::string back = rotleak::scene_to_toml(scene);
    if (rotleak::scene_to_toml(rotleak::parse_scene(back, {}, "scene.toml")) != back) __builtin_trap();
  } catch (const rotleak::InputError& e) {
    if (std::string(e.what()).find('\n') != std::string::npos) __builtin_trap();  // one line, always
  }
  return 0;
}
