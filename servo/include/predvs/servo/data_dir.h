#pragma once
/// \file data_dir.h
/// Where predvs finds its data (scenarios/, textures/, params/): one run-time lookup, no source
/// path compiled in. dataDir() tries, in this order, and returns the first that applies:
///   (a) the environment variable PREDVS_DATA_DIR, if set and non-empty; if it is set but is not
///       a directory, dataDir() throws std::runtime_error naming PREDVS_DATA_DIR (no fallback, so
///       a typo is never silently ignored);
///   (b) `<directory of the running executable>/../share/predvs`, if it is a directory: the
///       installed layout (`cmake --install` puts predvs in bin/ and data/ in share/predvs/); the
///       executable is found through /proc/self/exe (Linux);
///   (c) the build tree: at configure time CMake creates `<build>/share/predvs`, a symbolic link
///       to the source tree's data/, so an executable one level below the build directory
///       (build/app/predvs, build/tests/*_tests, build/bench/...) finds it through the same rule
///       (b). Nothing of the build or source tree is compiled into any binary: an installed copy
///       only ever looks at its own prefix.
/// If none applies, dataDir() throws std::runtime_error listing what it tried and telling the
/// user to set PREDVS_DATA_DIR (e.g. a program linking predvs::servo from elsewhere).
/// The result is an absolute or executable-relative directory path, without a trailing '/'.

#include <string>

namespace predvs {

/// The predvs data directory (see the file comment for the lookup order). Throws
/// std::runtime_error naming PREDVS_DATA_DIR when it cannot be found.
std::string dataDir();

}  // namespace predvs
