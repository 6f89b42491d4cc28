// A test's scratch folder under the system's temporary directory, named for the process (each test runs
// in its own process under CTest): emptied when made, and removed when the test ends, pass or fail, so no
// run of the suite leaves anything behind.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace rotleak::test {

struct ScratchDir {
  std::filesystem::path path;
  explicit ScratchDir(const std::string& prefix)
      : path(std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  ~ScratchDir() {
    std::error_code ec;  // never throw from here
    std::filesystem::remove_all(path, ec);
  }
};

}  // namespace rotleak::test
