// Files are written whole or not at all: to a temporary name, then renamed.
#pragma once

#include <filesystem>
#include <string>

namespace rotleak {

/// Writes content to path via path.tmp-<pid> and rename(2). Throws std::runtime_error on failure.
void write_file_atomic(const std::filesystem::path& path, const std::string& content);

/// Shortest decimal that reads back to the same double (std::to_chars).
std::string shortest(double x);

/// A run directory built under a staging name and renamed into place when complete, so an
/// interrupted run never leaves a directory that looks finished.
class RunDirectory {
 public:
  /// Throws InputError (key --out) if `final` exists and force is false, or exists with force but
  /// is neither empty nor a rotleak run directory (has summary.json).
  RunDirectory(std::filesystem::path final, bool force);
  ~RunDirectory();  ///< removes the staging directory unless commit() ran
  RunDirectory(const RunDirectory&) = delete;
  RunDirectory& operator=(const RunDirectory&) = delete;

  std::filesystem::path file(const std::string& name) const { return staging_ / name; }
  const std::filesystem::path& final_path() const { return final_; }
  /// Moves the staging directory to its final name (replacing an old run with --force).
  void commit();

 private:
  std::filesystem::path final_, staging_;
  bool committed_ = false;
};

}  // namespace rotleak
