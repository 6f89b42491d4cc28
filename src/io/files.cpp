#include "io/files.hpp"

#include <unistd.h>

#include <charconv>
#include <fstream>
#include <stdexcept>

#include "numeric/input.hpp"

namespace rotleak {

namespace fs = std::filesystem;

void write_file_atomic(const fs::path& path, const std::string& content) {
  const fs::path tmp = path.string() + ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) throw std::runtime_error("cannot write " + tmp.string());
    f.write(content.data(), static_cast<std::streamsize>(content.size()));
    f.flush();
    if (!f) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error("write failed: " + tmp.string());
    }
  }
  fs::rename(tmp, path);
}

std::string shortest(double x) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

RunDirectory::RunDirectory(fs::path final, bool force) : final_(std::move(final)) {
  if (final_.empty()) throw InputError("--out", "\"\"", "must name a directory");
  std::error_code ec;
  if (fs::exists(final_, ec)) {
    if (!force) throw InputError("--out", "\"" + final_.string() + "\"", "already exists; pass --force to replace it");
    if (!fs::is_directory(final_) || (!fs::is_empty(final_) && !fs::exists(final_ / "summary.json")))
      throw InputError("--out", "\"" + final_.string() + "\"",
                       "exists and is not a rotleak run directory (no summary.json); refusing to replace it");
  }
  fs::path parent = final_.parent_path();
  if (!parent.empty()) fs::create_directories(parent, ec);
  staging_ = final_.string() + ".partial-" + std::to_string(::getpid());
  fs::remove_all(staging_, ec);
  if (!fs::create_directory(staging_, ec))
    throw InputError("--out", "\"" + final_.string() + "\"", "cannot create a directory there (" + ec.message() + ")");
}

RunDirectory::~RunDirectory() {
  if (!committed_) {
    std::error_code ec;
    fs::remove_all(staging_, ec);
  }
}

void RunDirectory::commit() {
  std::error_code ec;
  if (fs::exists(final_, ec)) fs::remove_all(final_);
  fs::rename(staging_, final_);
  committed_ = true;
}

}  // namespace rotleak
