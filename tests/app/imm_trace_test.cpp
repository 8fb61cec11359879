// imm's mode probabilities and forecast weights in the trace: `predvs servo` writes each predictor's
// diagnostics() as trailing log.csv columns (app/servo_report.cpp), and `compare` prints the
// imm / best of kf-cv, kf-ca line under a table that has all three (app/report.h).
#include "app/cli_test_utils.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

namespace predvs {
namespace {

using apptest::CliRun;
using apptest::run;
using apptest::slurp;

class ImmTrace : public apptest::ScratchDirTest {
 protected:
  ImmTrace() : ScratchDirTest("predvs_imm_trace_test") {}
};

TEST_F(ImmTrace, ServoLogHasTheModeProbabilitiesAndTheyFollowTheAccelerationJump) {
  // GIVEN E2 (the acceleration jumps from 1 to 30 px/s^2 at 14 s) with hold and imm;
  // THEN log.csv has mu_cp_0 .. mu_ca_1 and fw_cp_0 .. fw_ca_1, empty on hold's rows, each summing
  // to one per channel on imm's, and the CA mode holds most of the probability at the end
  // (t > 18 s) but not before the jump; its forecast weight is larger after the jump than before.
  const CliRun r = run({"servo", "--scenario", "e2-accel-jump", "--predictors", "hold,imm", "--no-plots", "--out",
                        path("run")});
  ASSERT_EQ(r.code, 0) << r.err;
  // Every line of log.csv split at every comma (an empty last cell kept), the header first.
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(slurp(path("run") + "/log.csv"));
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells(1);
    for (char c : line)
      if (c == ',')
        cells.emplace_back();
      else
        cells.back().push_back(c);
    rows.push_back(std::move(cells));
  }
  ASSERT_GT(rows.size(), 10u);
  const auto& head = rows.front();
  const auto col = [&](const std::string& name) {
    const auto it = std::find(head.begin(), head.end(), name);
    EXPECT_NE(it, head.end()) << name;
    return static_cast<size_t>(it - head.begin());
  };
  const size_t t = col("t_s"), cp = col("mu_cp_0"), cv = col("mu_cv_0"), ca = col("mu_ca_0"), ca1 = col("mu_ca_1");
  const size_t fcp = col("fw_cp_0"), fcv = col("fw_cv_0"), fca = col("fw_ca_0");
  double fw_ca_late = 0.0, fw_ca_early = 0.0;
  int hold_rows = 0, late = 0, early = 0;
  double ca_late = 0.0, ca_early = 0.0;
  for (size_t i = 1; i < rows.size(); ++i) {
    const auto& row = rows[i];
    ASSERT_EQ(row.size(), head.size()) << "row " << i;
    if (row[0] == "hold") {
      EXPECT_TRUE(row[cp].empty() && row[ca1].empty());
      ++hold_rows;
      continue;
    }
    const double sum = std::stod(row[cp]) + std::stod(row[cv]) + std::stod(row[ca]);
    EXPECT_NEAR(sum, 1.0, 1e-9) << "row " << i;
    const double fw_sum = std::stod(row[fcp]) + std::stod(row[fcv]) + std::stod(row[fca]);
    EXPECT_NEAR(fw_sum, 1.0, 1e-9) << "row " << i;
    const double ts = std::stod(row[t]);
    if (ts > 18.0) ca_late += std::stod(row[ca]), fw_ca_late += std::stod(row[fca]), ++late;
    if (ts > 8.0 && ts < 14.0) ca_early += std::stod(row[ca]), fw_ca_early += std::stod(row[fca]), ++early;
  }
  EXPECT_GT(hold_rows, 0);
  ASSERT_GT(late, 0);
  ASSERT_GT(early, 0);
  EXPECT_GT(ca_late / late, 0.7);
  EXPECT_LT(ca_early / early, ca_late / late);
  // The forecast weights follow the jump too.
  EXPECT_LT(fw_ca_early / early, fw_ca_late / late);
}

TEST_F(ImmTrace, ClosedLoopServoLogHasTheModeProbabilitiesToo) {
  // GIVEN the closed loop ibvs-moving-target with kf-cv and imm
  const CliRun r = run({"servo", "--scenario", "ibvs-moving-target", "--predictors", "kf-cv,imm", "--set",
                        "duration_s=4", "--no-plots", "--out", path("loop")});
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream in(slurp(path("loop") + "/log.csv"));
  std::string header;
  ASSERT_TRUE(static_cast<bool>(std::getline(in, header)));
  // THEN log.csv ends with imm's diagnostics for each of the 8 feature channels, empty on kf-cv's
  // rows and filled on imm's once a frame has arrived (its CV and CA modes: in a closed loop imm
  // leaves its CP mode out, imm.h)
  const std::string tail = ",fw_cv_7,fw_ca_7,ff_cv_0,ff_ca_0,ff_cv_1,ff_ca_1,ff_cv_2,ff_ca_2,ff_cv_3,ff_ca_3,ff_cv_4,ff_ca_4,ff_cv_5,"
                           "ff_ca_5,ff_cv_6,ff_ca_6,ff_cv_7,ff_ca_7";
  ASSERT_GE(header.size(), tail.size());
  EXPECT_EQ(header.substr(header.size() - tail.size()), tail) << header;
  EXPECT_NE(header.find(",wz,mu_cv_0,mu_ca_0,mu_cv_1,"), std::string::npos) << header;
  EXPECT_EQ(header.find("mu_cp_"), std::string::npos) << header;
  int kf_rows = 0, imm_filled = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("kf-cv,", 0) == 0) {
      EXPECT_EQ(line.substr(line.size() - 3), ",,,") << line;
      ++kf_rows;
    } else if (line.rfind("imm,", 0) == 0 && line.back() != ',') {
      ++imm_filled;
    }
  }
  EXPECT_GT(kf_rows, 10);
  EXPECT_GT(imm_filled, 10);
}

TEST_F(ImmTrace, CompareSaysHowImmStandsAgainstItsSingleModels) {
  const CliRun r = run({"compare", "--scenarios", "e1-line", "--predictors", "hold,kf-cv,kf-ca,imm", "--runs", "2",
                        "--no-plots", "--out", path("cmp")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("imm / best of kf-cv, kf-ca (rmse): "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("; imm / hold: "), std::string::npos) << r.out;
  EXPECT_NE(slurp(path("cmp") + "/leaderboard.md").find("imm / best of kf-cv, kf-ca (rmse): "), std::string::npos);
  // Without kf-ca in the table: no line.
  const CliRun two = run({"compare", "--scenarios", "e1-line", "--predictors", "hold,kf-cv,imm", "--runs", "1",
                          "--no-plots", "--out", path("cmp2")});
  ASSERT_EQ(two.code, 0) << two.err;
  EXPECT_EQ(two.out.find("imm / best of"), std::string::npos);
}

}  // namespace
}  // namespace predvs
