#include "output_dir.h"

#include <atomic>
#include <stdexcept>
#include <system_error>
#include <unistd.h>

namespace predvs {
namespace fs = std::filesystem;

namespace {
std::string uniqueSuffix() {
  static std::atomic<int> counter{0};
  return std::to_string(::getpid()) + "-" + std::to_string(counter++);
}
}  // namespace

StagedOutputDir::StagedOutputDir(const fs::path& target) : target_(target) {
  if (target_.empty()) throw std::invalid_argument("--out: expected a directory path, got an empty string");
  if (target_.filename().empty()) target_ = target_.parent_path();  // "dir/" -> "dir"
  std::error_code ec;
  if (fs::exists(target_, ec) && !fs::is_directory(target_, ec))
    throw std::invalid_argument("--out: '" + target_.string() + "' exists and is not a directory");

  fs::path parent = target_.parent_path();
  if (parent.empty()) parent = ".";
  // Remember the topmost missing ancestor so a failed run can remove what it created.
  for (fs::path p = parent; !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
    created_root_ = p;
    if (p == p.parent_path()) break;
  }
  fs::create_directories(parent, ec);
  if (ec) throw std::runtime_error("--out: cannot create directory '" + parent.string() + "': " + ec.message());
  staging_ = parent / ("." + target_.filename().string() + ".tmp-" + uniqueSuffix());
  fs::create_directory(staging_, ec);
  if (ec) throw std::runtime_error("--out: cannot create directory '" + staging_.string() + "': " + ec.message());
}

StagedOutputDir::~StagedOutputDir() {
  if (committed_) return;
  std::error_code ec;
  fs::remove_all(staging_, ec);
  if (!created_root_.empty()) fs::remove_all(created_root_, ec);
}

void StagedOutputDir::commit() {
  std::error_code ec;
  fs::path old;
  if (fs::exists(target_, ec)) {
    old = target_.parent_path() / ("." + target_.filename().string() + ".old-" + uniqueSuffix());
    fs::rename(target_, old, ec);
    if (ec) throw std::runtime_error("--out: cannot move the previous '" + target_.string() + "' aside: " + ec.message());
  }
  fs::rename(staging_, target_, ec);
  if (ec) {
    std::error_code ignored;
    if (!old.empty()) fs::rename(old, target_, ignored);
    throw std::runtime_error("--out: cannot move results into '" + target_.string() + "': " + ec.message());
  }
  committed_ = true;
  if (!old.empty()) fs::remove_all(old, ec);
}

}  // namespace predvs
