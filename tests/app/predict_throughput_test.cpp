// Issue 11 item 8: the fast paths of `predvs predict` (app/track_csv.cpp, app/predict_command.cpp)
// keep the old behaviour: cells parse to the values strtod gives (and are rejected with the same
// messages), the plot data is thinned by the documented rule, and the summary table stays aligned
// for counts of seven digits and more. The speed itself is measured by bench/predict_io_bench.cpp.
#include "predict_command.h"
#include "track_csv.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

std::string writeTemp(const std::string& name, const std::string& text) {
  const auto p = std::filesystem::temp_directory_path() / ("predvs_throughput_" + name);
  std::ofstream(p) << text;
  return p.string();
}

TEST(PredictThroughput, CellsParseToTheValuesStrtodGives) {
  const std::vector<std::string> cells{"1.5", "+1.5", "-0.25", ".5", "5.", "1e3", "0x10", " 2 ", "318.5719833",
                                       "1.7976931348623157e308", "2.2250738585072014e-308", "0", "-0"};
  std::string csv = "t,u,v\n";
  for (size_t i = 0; i < cells.size(); ++i) csv += std::to_string(i) + "," + cells[i] + "," + cells[i] + "\n";
  const predvs::FeatureTrack track = predvs::readFeatureTrack(writeTemp("cells.csv", csv));
  ASSERT_EQ(track.size(), cells.size());
  for (size_t i = 0; i < cells.size(); ++i) {
    EXPECT_EQ(track.u_px[0][i], std::strtod(cells[i].c_str(), nullptr)) << cells[i];
    EXPECT_EQ(track.v_px[0][i], std::strtod(cells[i].c_str(), nullptr)) << cells[i];
  }
}

TEST(PredictThroughput, RejectsWhatStrtodRejectsWithTheSameMessages) {
  auto message = [](const std::string& name, const std::string& cell) {
    try {
      predvs::readFeatureTrack(writeTemp(name, "t,u,v\n0,1,2\n1," + cell + ",2\n"));
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("nan.csv", "nan").find(":3: column 'u': expected a finite number, got 'nan'"), std::string::npos);
  EXPECT_NE(message("inf.csv", "-inf").find(":3: column 'u': expected a finite number, got '-inf'"), std::string::npos);
  EXPECT_NE(message("big.csv", "1e999").find(":3: column 'u': expected a finite number"), std::string::npos);
  EXPECT_NE(message("sub.csv", "1e-310").find(":3: column 'u': expected a finite number"), std::string::npos);
  EXPECT_NE(message("junk.csv", "1.5x").find(":3: column 'u': expected a number, got '1.5x'"), std::string::npos);
  EXPECT_NE(message("two.csv", "1 2").find(":3: column 'u': expected a number, got '1 2'"), std::string::npos);
}

TEST(PredictThroughput, PlotDataIsThinnedBeyondTheLimitOnly) {
  EXPECT_EQ(predvs::plotStride(1), 1u);
  EXPECT_EQ(predvs::plotStride(predvs::kMaxPlotRows), 1u);
  EXPECT_EQ(predvs::plotStride(predvs::kMaxPlotRows + 1), 2u);
  EXPECT_EQ(predvs::plotStride(2000011), 101u);
  for (size_t rows : {20001u, 123457u, 2000011u})
    EXPECT_LE((rows + predvs::plotStride(rows) - 1) / predvs::plotStride(rows), predvs::kMaxPlotRows) << rows;
}

TEST(PredictThroughput, SummaryTableStaysAlignedForSevenDigitCounts) {
  predvs::FeatureTrack track;
  track.point_names = {"0"};
  track.t_s = {0.0};
  track.u_px = track.v_px = track.u_true_px = track.v_true_px = {{1.0}};
  predvs::PredictionReport report;
  for (int n : {2000008, 12, 123456789}) {
    predvs::PredictionRun run;
    run.spec.name = "kf-cv" + std::to_string(n % 10);
    run.vs_measurement = {3.658, 2.5, 2.6, n};
    run.vs_truth = {2.996, 2.1, 2.2, n};
    report.runs.push_back(run);
  }
  std::ostringstream out;
  predvs::printPredictionTable(report, track, out);
  std::istringstream lines(out.str());
  std::string line;
  std::vector<std::string> rows;
  while (std::getline(lines, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 4u) << out.str();
  for (const auto& r : rows) EXPECT_EQ(r.size(), rows[0].size()) << out.str();
  // The count is separated from the RMSE before it, and right-aligned under "n".
  EXPECT_NE(rows[1].find("2.996  "), std::string::npos) << out.str();
  EXPECT_NE(rows[3].find("2.996  123456789"), std::string::npos) << out.str();
  EXPECT_EQ(rows[0].back(), 'n');
}

}  // namespace
