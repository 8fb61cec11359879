// predvs app — an output directory that appears only when the run succeeded.
//
// Files are written into a temporary sibling ".NAME.tmp-PID-N" of the target directory. commit()
// renames it into place (replacing an existing directory only at that moment); if the object is
// destroyed without commit() (an error was thrown), the temporary directory, and any parent
// directories this object had to create, are removed. A failed run therefore never leaves a
// partial output directory behind and never clobbers a previous good one.
#pragma once

#include <filesystem>
#include <string>

namespace predvs {

class StagedOutputDir {
 public:
  /// Creates the staging directory next to `target`. Throws std::invalid_argument if `target`
  /// exists and is not a directory, std::runtime_error if the directory cannot be created.
  explicit StagedOutputDir(const std::filesystem::path& target);
  ~StagedOutputDir();
  StagedOutputDir(const StagedOutputDir&) = delete;
  StagedOutputDir& operator=(const StagedOutputDir&) = delete;

  /// Where to write files now (the staging directory).
  const std::filesystem::path& staging() const { return staging_; }
  /// Where the files will be after commit().
  const std::filesystem::path& target() const { return target_; }
  /// staging() / name, as a string.
  std::string file(const std::string& name) const { return (staging_ / name).string(); }
  /// Moves the staging directory to the target (replacing an existing target directory).
  void commit();

 private:
  std::filesystem::path target_;
  std::filesystem::path staging_;
  std::filesystem::path created_root_;  ///< topmost parent we created (removed on failure), or empty
  bool committed_ = false;
};

}  // namespace predvs
