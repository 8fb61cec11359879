#include "output_dir.h"

#include <atomic>
#include <fstream>
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

/// Whether `p` is `dir` or below it (both made absolute and normal, links resolved where they exist).
bool isAtOrBelow(const fs::path& p, const fs::path& dir) {
  std::error_code ec;
  const fs::path a = fs::weakly_canonical(fs::absolute(p), ec);
  const fs::path d = fs::weakly_canonical(fs::absolute(dir), ec);
  auto ai = a.begin();
  for (auto di = d.begin(); di != d.end(); ++di, ++ai) {
    if (di->empty()) continue;  // a trailing separator
    if (ai == a.end() || *ai != *di) return false;
  }
  return true;
}

fs::path outTarget(fs::path target) {
  if (target.empty()) throw std::invalid_argument("--out: expected a directory path, got an empty string");
  if (target.filename().empty()) target = target.parent_path();  // "dir/" -> "dir"
  return target;
}

/// The directory a link to one names (replacing the link would lose it), else `target` itself.
fs::path followDirectoryLink(const fs::path& target) {
  std::error_code ec;
  return fs::is_symlink(target, ec) && fs::is_directory(target, ec) ? fs::canonical(target, ec) : target;
}
}  // namespace

void StagedOutputDir::checkReplaceable(const fs::path& target, const std::vector<std::string>& inputs) {
  const fs::path given = outTarget(target);
  const fs::path t = followDirectoryLink(given);
  std::error_code ec;
  if (fs::exists(t, ec) && !fs::is_directory(t, ec))
    throw std::invalid_argument("--out: '" + given.string() + "' exists and is not a directory");
  const auto refuse = [&](const std::string& what) {
    throw std::invalid_argument("--out: '" + given.string() + "' " + what +
                                ", which replacing it would delete: choose another --out");
  };
  if (fs::is_directory(t, ec)) {
    if (!fs::is_empty(t, ec) && !fs::exists(t / kOutputMarker, ec))
      refuse(std::string("is a directory predvs did not write (no ") + kOutputMarker + " in it)");
    if (isAtOrBelow(fs::current_path(ec), t)) refuse("holds the working directory");
  }
  for (const std::string& in : inputs)
    if (!in.empty() && isAtOrBelow(in, t)) refuse("holds the input '" + in + "'");
}

StagedOutputDir::StagedOutputDir(const fs::path& target) : target_(followDirectoryLink(outTarget(target))) {
  checkReplaceable(target, {});
  std::error_code ec;

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
  if (ec) throw std::runtime_error("--out: cannot create directory '" + target_.string() + "' (staged in '" +
                                   staging_.string() + "'): " + ec.message());
  std::ofstream marker(staging_ / kOutputMarker);
  marker << "written by predvs; a later predvs run may replace this directory\n";
  if (!marker) {
    fs::remove_all(staging_, ec);
    if (!created_root_.empty()) fs::remove_all(created_root_, ec);
    throw std::runtime_error("--out: cannot write in '" + staging_.string() + "'");
  }
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
