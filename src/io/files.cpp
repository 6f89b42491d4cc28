#include "io/files.hpp"

#include <fcntl.h>
#include <stdio.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "numeric/input.hpp"

namespace rotleak {

namespace fs = std::filesystem;

void write_file_atomic(const fs::path& path, const std::string& content, bool durable) {
  const fs::path tmp = path.string() + ".tmp-" + std::to_string(::getpid());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error("cannot write " + tmp.string() + ": " + std::strerror(errno));
  std::size_t at = 0;
  bool ok = true;
  while (ok && at < content.size()) {
    const ssize_t w = ::write(fd, content.data() + at, content.size() - at);
    if (w < 0 && errno == EINTR) continue;
    ok = w > 0;
    if (ok) at += static_cast<std::size_t>(w);
  }
  const int err = ok ? 0 : errno;
  if (ok && durable) ok = ::fsync(fd) == 0;
  ok = (::close(fd) == 0) && ok;
  if (!ok) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw std::runtime_error("write failed: " + tmp.string() + (err ? std::string(": ") + std::strerror(err) : ""));
  }
  fs::rename(tmp, path);
  if (durable) {  // the rename itself reaches the disk with the directory
    const fs::path parent = path.has_parent_path() ? path.parent_path() : fs::path(".");
    const int dfd = ::open(parent.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
      ::fsync(dfd);
      ::close(dfd);
    }
  }
}

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + p.string());
  std::ostringstream ss;
  ss << in.rdbuf();
  if (!in && !in.eof()) throw std::runtime_error("cannot read " + p.string());
  return ss.str();
}

std::string shortest(double x) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

std::string hex_exact(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", x);
  return buf;
}

fs::path RunDirectory::normalise(const fs::path& out) {
  fs::path p = out.lexically_normal();
  if (!p.empty() && p.filename().empty()) p = p.parent_path();  // "o/" -> "o"
  return p;
}

RunDirectory::RunDirectory(fs::path final, bool force)
    : final_(normalise(final)), shown_("\"" + final.string() + "\"") {
  if (final_.empty() || final_.filename() == "." || final_.filename() == ".." || final_ == final_.root_path())
    throw InputError("--out", shown_, "must name a directory to create (not empty, '.', '..' or '/')");
  std::error_code ec;
  // refuse what cannot be replaced before creating anything
  if (fs::exists(final_, ec)) {
    // what --force cannot replace is said first: "pass --force" and then a refusal was a runaround
    if (!fs::is_directory(final_))
      throw InputError("--out", shown_, "exists and is a file, not a run directory; choose another --out");
    if (!fs::is_empty(final_) && !fs::exists(final_ / "summary.json"))
      throw InputError("--out", shown_,
                       "exists and is not a rotleak run directory (no summary.json); choose another --out (--force "
                       "replaces run directories only)");
    if (!force) throw InputError("--out", shown_, "already exists; pass --force to replace it");
    // the earlier run goes after the new one is in place: a directory of it we cannot write would stay behind
    // (a read-only run was once "replaced" with rc 0, the old one left as .NAME.partial-N without a word)
    const auto require_writable = [&](const fs::path& d) {
      if (::access(d.c_str(), W_OK | X_OK) != 0)
        throw InputError("--out", shown_,
                         "holds a run --force cannot replace: " + d.string() + " is not writable (" +
                             std::strerror(errno) + "); make it writable (chmod -R u+w) or choose another --out");
    };
    require_writable(final_);
    for (auto it = fs::recursive_directory_iterator(final_, ec); !ec && it != fs::recursive_directory_iterator();
         it.increment(ec))
      if (it->is_directory()) require_writable(it->path());
  }
  // parents: remember the ones this run creates, to remove them if it fails
  fs::path parent = final_.parent_path();
  std::vector<fs::path> missing;
  for (fs::path p = parent; !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
    missing.push_back(p);
    if (p == p.parent_path()) break;
  }
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    if (!fs::create_directory(*it, ec) && ec)
      throw InputError("--out", shown_, "cannot create " + it->string() + " (" + ec.message() + ")");
    created_parents_.push_back(*it);
  }
  const fs::path dir = parent.empty() ? fs::path(".") : parent;
  const std::string name = final_.filename().string();
  staging_ = dir / ("." + name + ".partial-" + std::to_string(::getpid()));
  try {
    lock_ = std::make_unique<DirectoryLock>(final_, "--out", shown_);
    remove_stale_staging();
    if (!fs::create_directory(staging_, ec))
      throw InputError("--out", shown_, "cannot create a directory there (" + ec.message() + ")");
  } catch (...) {
    release();  // a throwing constructor runs no destructor: undo what was made (lock, parents) here
    throw;
  }
}

fs::path DirectoryLock::path_for(const fs::path& target) {
  const fs::path final = RunDirectory::normalise(target);
  const fs::path dir = final.parent_path().empty() ? fs::path(".") : final.parent_path();
  return dir / ("." + final.filename().string() + ".lock");
}

DirectoryLock::DirectoryLock(const fs::path& target, const std::string& key, const std::string& shown)
    : path_(path_for(target)) {
  // flock on a file beside the target; after taking it, make sure the file is still the one at the
  // path (a finishing process unlinks it), else take the new one.
  for (int attempt = 0; attempt < 100; ++attempt) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0)
      throw InputError(key, shown, "cannot create the lock file " + path_.string() + " (" + std::strerror(errno) + ")");
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      ::close(fd_);
      fd_ = -1;
      throw InputError(key, shown,
                       "another rotleak run is writing this directory now; wait for it or choose another "
                       "directory");
    }
    struct stat held {
    }, at_path{};
    if (::fstat(fd_, &held) == 0 && ::stat(path_.c_str(), &at_path) == 0 && held.st_ino == at_path.st_ino &&
        held.st_dev == at_path.st_dev)
      return;
    ::close(fd_);  // unlinked under us: try the file now at the path
    fd_ = -1;
  }
  throw InputError(key, shown, "cannot take the lock " + path_.string());
}

DirectoryLock::~DirectoryLock() {
  if (fd_ < 0) return;
  ::unlink(path_.c_str());  // before the unlock: a process that opened it then re-checks the path
  ::close(fd_);
}

void RunDirectory::remove_stale_staging() const {
  // Holding the lock, no live run is writing this target: any staging directory of it is left over
  // from a run that was killed, and so is a swapped-out old run that was not removed.
  const fs::path dir = staging_.parent_path();
  const std::string prefix = "." + final_.filename().string() + ".partial-";
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().filename().string().rfind(prefix, 0) == 0) fs::remove_all(e.path(), ec);
}

RunDirectory::~RunDirectory() { release(); }

void RunDirectory::release() {
  std::error_code ec;
  if (!committed_) fs::remove_all(staging_, ec);
  lock_.reset();
  if (!committed_)
    for (auto it = created_parents_.rbegin(); it != created_parents_.rend(); ++it)
      fs::remove(*it, ec);  // only if empty
  created_parents_.clear();
}

namespace {

/// Removes the run a --force commit replaced (moved to `old`). The constructor checked it writable; where that
/// changed since, the new run stands and the old one is said, not left without a word.
void remove_replaced(const fs::path& old) {
  std::error_code ec;
  fs::remove_all(old, ec);
  if (ec)
    std::fprintf(stderr, "rotleak: warning: the replaced run, now %s, could not be removed (%s): remove it by hand\n",
                 old.c_str(), ec.message().c_str());
}

}  // namespace

void RunDirectory::commit() {
  std::error_code ec;
  if (fs::exists(final_, ec)) {
    // atomic swap: the target holds the new run, the staging name the old one, which then goes
    if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, final_.c_str(), RENAME_EXCHANGE) == 0) {
      committed_ = true;
      remove_replaced(staging_);
      return;
    }
    // a file system without RENAME_EXCHANGE: move the old run aside first, never delete it first
    const fs::path old = staging_.string() + "-old";
    fs::rename(final_, old);
    fs::rename(staging_, final_);
    remove_replaced(old);
  } else {
    fs::rename(staging_, final_);
  }
  committed_ = true;
}

}  // namespace rotleak
