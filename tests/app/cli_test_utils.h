// Helpers shared by the in-process CLI tests of tests/app: run `predvs` through runCli() and
// capture its streams, a fresh scratch directory per test, and the failure contract of every
// subcommand (exit status 2, exactly one "predvs: error: " line, no output left behind).
#pragma once

#include "cli.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <unistd.h>
#include <utility>
#include <vector>

namespace predvs::apptest {

/// Exit status and the two streams of one in-process `predvs` run.
struct CliRun {
  int code = -1;
  std::string out, err;
};

/// Runs the command line `args` (without the program name) through runCli().
inline CliRun run(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  CliRun r;
  r.code = runCli(args, out, err);
  r.out = out.str();
  r.err = err.str();
  return r;
}

/// Runs `args` followed by `extra` (a command's fixed arguments and the ones a case adds).
inline CliRun run(std::vector<std::string> args, const std::vector<std::string>& extra) {
  args.insert(args.end(), extra.begin(), extra.end());
  return run(args);
}

/// Number of '\n' in s.
inline int lineCount(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

/// Whole content of the file at `path` ("" if it cannot be opened).
inline std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The data rows of a CSV text (the header row skipped), each split at its commas.
inline std::vector<std::vector<std::string>> csvRows(const std::string& csv) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

/// The mean column of a `predvs compare` leaderboard.csv, keyed "variant/predictor/metric" (rows
/// without a mean left out).
inline std::map<std::string, double> leaderboardMeans(const std::string& csv_path) {
  std::map<std::string, double> out;
  for (const auto& f : csvRows(slurp(csv_path)))
    if (f.size() >= 6 && !f[5].empty()) out[f[1] + "/" + f[2] + "/" + f[3]] = std::stod(f[5]);
  return out;
}

/// The JSON document in the file at `path` (throws if it is missing or malformed).
inline nlohmann::json readJson(const std::filesystem::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

/// Fixture with an empty scratch directory per test, <temp>/<prefix>_<pid>_<suite>_<test>
/// (the pid keeps parallel ctest processes apart), removed after the test.
class ScratchDirTest : public ::testing::Test {
 protected:
  explicit ScratchDirTest(std::string prefix) : prefix_(std::move(prefix)) {}
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() / (prefix_ + "_" + std::to_string(::getpid()) + "_" +
                                                     info->test_suite_name() + "_" + info->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  /// Path of `name` inside the scratch directory.
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  /// Writes `text` to `name` in the scratch directory and returns its path.
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
    return path(name);
  }
  /// The failure contract: status 2, one line starting "predvs: error: " that contains `needle`,
  /// no output directory `out_dir` (when given) and no staging directory (".tmp-") left behind.
  void expectError(const CliRun& r, const std::string& needle, const std::string& out_dir = "") const {
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(lineCount(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind("predvs: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << "expected '" << needle << "' in: " << r.err;
    if (!out_dir.empty()) {
      EXPECT_FALSE(std::filesystem::exists(out_dir)) << out_dir;
    }
    for (const auto& e : std::filesystem::directory_iterator(dir_))
      EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
  }

  std::filesystem::path dir_;

 private:
  std::string prefix_;
};

}  // namespace predvs::apptest
