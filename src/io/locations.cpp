#include "io/locations.hpp"

#include <cstdlib>
#include <string>
#include <system_error>
#include <vector>

#include "numeric/input.hpp"

#ifndef ROTLEAK_DATA_RELATIVE
#define ROTLEAK_DATA_RELATIVE "share/rotleak/data"
#endif
#ifndef ROTLEAK_PYTHON_RELATIVE
#define ROTLEAK_PYTHON_RELATIVE "lib/python3/dist-packages"
#endif

namespace rotleak {

namespace fs = std::filesystem;

fs::path program_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path();
}

namespace {

/// $VAR when set (it must be a directory); else the first candidate holding `marker`.
fs::path locate(const char* var, const std::vector<fs::path>& candidates, const char* marker, const std::string& what) {
  if (const char* v = std::getenv(var); v && *v) {
    if (!fs::is_directory(v)) throw InputError(var, "\"" + std::string(v) + "\"", "must be a directory (" + what + ")");
    return v;
  }
  std::string tried;
  for (const fs::path& c : candidates) {
    if (c.empty()) continue;
    if (fs::exists(c / marker)) return c;
    tried += (tried.empty() ? "" : ", ") + c.string();
  }
  throw InputError(
      var, "(not set)",
      "rotleak cannot find " + what + " (looked in " + tried + "); set " + var + " to the directory that holds it");
}

}  // namespace

fs::path data_dir() {
  const fs::path bin = program_dir();
  // the source tree only for a binary in its build tree (the directory CMake configured), never for
  // an installed one
  const bool build_tree = !bin.empty() && fs::exists(bin / "CMakeCache.txt");
  return locate("ROTLEAK_DATA",
                {bin.empty() ? fs::path() : bin.parent_path() / ROTLEAK_DATA_RELATIVE,
                 build_tree ? fs::path(ROTLEAK_BUILD_SOURCE_DIR) / "data" : fs::path()},
                "scenes", "its data: scenes, study inputs, reference trajectories");
}

fs::path python_dir() {
  const fs::path bin = program_dir();
  return locate("ROTLEAK_PYTHONPATH",
                {bin.empty() ? fs::path() : bin.parent_path() / ROTLEAK_PYTHON_RELATIVE,
                 bin.empty() ? fs::path() : bin / "python"},
                "rotleak/__init__.py", "its Python package (rotleak.plot)");
}

}  // namespace rotleak
