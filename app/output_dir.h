// predvs app — an output directory that appears only when the run succeeded.
//
// Files are written into a temporary sibling ".NAME.tmp-PID-N" of the target directory. commit()
// renames it into place (replacing an existing directory only at that moment); if the object is
// destroyed without commit() (an error was thrown), the temporary directory, and any parent
// directories this object had to create, are removed. A failed run therefore never leaves a
// partial output directory behind and never clobbers a previous good one.
//
// Only what predvs wrote is ever replaced: every output directory carries the file
// kOutputMarker, and an existing target must be empty or carry it. A target that holds the
// working directory, or one of the run's inputs (checkReplaceable), is refused too, so a run
// never deletes its own input or the user's files.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace predvs {

/// The file in every output directory that marks it as predvs's, so that a later run may replace it.
inline constexpr const char* kOutputMarker = ".predvs-output";

class StagedOutputDir {
 public:
  /// Creates the staging directory next to `target` (a symbolic link is followed: the directory it
  /// points to is replaced). Throws std::invalid_argument if `target` exists and is not a
  /// directory, or may not be replaced (checkReplaceable);
  /// std::runtime_error if the directory cannot be created.
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

  /// Throws std::invalid_argument, with a one-line reason, unless `target` may be replaced: it
  /// must not exist, or be an empty directory, or one with kOutputMarker; and it must hold neither
  /// the working directory nor one of `inputs` (files or directories the run reads; empty paths
  /// are skipped). The constructor checks the same without inputs; commands call this before
  /// their work, so that a bad --out is the first error, not one after the run.
  static void checkReplaceable(const std::filesystem::path& target, const std::vector<std::string>& inputs);

 private:
  std::filesystem::path target_;
  std::filesystem::path staging_;
  std::filesystem::path created_root_;  ///< topmost parent we created (removed on failure), or empty
  bool committed_ = false;
};

}  // namespace predvs
