#include "predvs/servo/data_dir.h"

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace predvs {
namespace fs = std::filesystem;

std::string dataDir() {
  std::error_code ec;
  if (const char* env = std::getenv("PREDVS_DATA_DIR"); env != nullptr && *env != '\0') {
    if (!fs::is_directory(env, ec))
      throw std::runtime_error(std::string("PREDVS_DATA_DIR=") + env + ": not a directory");
    return fs::path(env).lexically_normal().string();
  }
  std::string tried;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec && !exe.empty()) {
    const fs::path share = (exe.parent_path() / ".." / "share" / "predvs").lexically_normal();
    if (fs::is_directory(share, ec)) return share.string();
    tried = share.string();
  } else {
    tried = "(/proc/self/exe unreadable)";
  }
  throw std::runtime_error("predvs data directory not found (tried " + tried +
                           "): set PREDVS_DATA_DIR to the folder holding scenarios/ and textures/");
}

}  // namespace predvs
