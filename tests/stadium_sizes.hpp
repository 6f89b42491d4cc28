// The four stadiums of the bit-identity tests (tests/test_stadiums.cpp, tests/test_kernel_probe.cpp): d = 2,
// r = 1; d = 1, r = 1; d = 2, r = 2; d = 3, r = 0.7, and a scene on each.
#pragma once

#include <string>
#include <vector>

#include "io/scene_file.hpp"
#include "paths.hpp"

namespace rotleak::test {

struct Size {
  const char* d;
  const char* r;
  const char* name;
};
const Size kSizes[] = {{"2", "1", "d2_r1"}, {"1", "1", "d1_r1"}, {"2", "2", "d2_r2"}, {"3", "0.7", "d3_r07"}};

inline Scene scene_of(const Size& z, std::vector<std::string> sets) {
  sets.push_back(std::string("stadium.d=") + z.d);
  sets.push_back(std::string("stadium.r=") + z.r);
  return load_scene(std::string(rotleak::test::source_dir()) + "/data/scenes/stationary_sL_0.toml", sets);
}

}  // namespace rotleak::test
