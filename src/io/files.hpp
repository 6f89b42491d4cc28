// Files are written whole or not at all: to a temporary name, then renamed.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace rotleak {

/// Writes content to path via path.tmp-<pid> and rename(2). Throws std::runtime_error on failure.
/// durable: the data and the rename are flushed to the disk (fsync) before returning, so a power
/// loss leaves the old file or the new one (checkpoints).
void write_file_atomic(const std::filesystem::path& path, const std::string& content, bool durable = false);
/// The whole file. Throws std::runtime_error naming it if it cannot be read.
std::string read_file(const std::filesystem::path& path);

/// Shortest decimal that reads back to the same double (std::to_chars).
std::string shortest(double x);
/// The double exactly, in C's hexadecimal (%a); strtod reads it back bit for bit.
std::string hex_exact(double x);

/// An exclusive lock on a directory's path, held from construction to destruction: flock on
/// `.<name>.lock` beside it (the parent must exist), so that a second rotleak process that writes the
/// same directory -- a run, a scan, a refit -- is refused instead of racing it. The lock file is
/// unlinked before it is released; a process that opened it in between re-checks the path.
class DirectoryLock {
 public:
  /// Throws InputError (key `key`, value `shown`) when another process holds the lock or the lock file
  /// cannot be created (with the reason).
  DirectoryLock(const std::filesystem::path& target, const std::string& key, const std::string& shown);
  ~DirectoryLock();
  DirectoryLock(const DirectoryLock&) = delete;
  DirectoryLock& operator=(const DirectoryLock&) = delete;

  /// `.<name>.lock` beside the (normalised) target.
  static std::filesystem::path path_for(const std::filesystem::path& target);

 private:
  std::filesystem::path path_;
  int fd_ = -1;
};

/// A run directory as a transaction. The target path is normalised (a trailing slash names the same
/// directory); an exclusive lock (flock on `.<name>.lock` beside it) is held from construction to
/// the end, so a second run into the same target is refused; the run is built in a staging
/// directory beside the target (`.<name>.partial-<pid>`), where stale staging left by killed runs is
/// removed first; commit() swaps the staging directory into place atomically (renameat2
/// RENAME_EXCHANGE), so the target is at every moment either the old complete run or the new one.
/// Without commit() the destructor removes the staging directory and any parent directories it
/// created.
class RunDirectory {
 public:
  /// Throws InputError (key --out) if `final` exists and force is false; if it exists with force but
  /// is neither empty nor a rotleak run directory (has summary.json); if another run holds it.
  RunDirectory(std::filesystem::path final, bool force);
  ~RunDirectory();
  RunDirectory(const RunDirectory&) = delete;
  RunDirectory& operator=(const RunDirectory&) = delete;

  std::filesystem::path file(const std::string& name) const { return staging_ / name; }
  const std::filesystem::path& final_path() const { return final_; }
  /// Puts the staging directory in the target's place (replacing an old run with --force).
  void commit();

  /// The target as the user meant it: lexically normal, without a trailing separator.
  static std::filesystem::path normalise(const std::filesystem::path& out);

 private:
  void remove_stale_staging() const;
  /// Unless committed: the staging directory and the parents this run created go; the lock is released.
  void release();

  std::filesystem::path final_, staging_;
  std::unique_ptr<DirectoryLock> lock_;
  std::string shown_;                                   ///< the target as the user wrote it, quoted, for messages
  std::vector<std::filesystem::path> created_parents_;  ///< made by this run, removed if it fails
  bool committed_ = false;
};

}  // namespace rotleak
