// Issue 11 item 8: the fast paths of `predvs predict` (app/track_csv.cpp, app/predict_command.cpp)
// keep the old behaviour: cells parse to the values strtod gives (and are rejected with the same
// messages), the plot data is thinned by the documented rule, and the summary table stays aligned
// for counts of seven digits and more. The speed itself is measured by bench/predict_io_bench.cpp.
#include "cli.h"
#include "large_buffer.h"
#include "number_text.h"
#include "output_dir.h"
#include "predict_command.h"
#include "track_csv.h"

#include "predvs/predictors/predictor.h"
#include "predvs/servo/sampled_signal.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
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
  const std::vector<std::string> cells{"1.5", "+1.5", "-0.25", ".5", "5.", "1e3", " 2 ", "318.5719833",
                                       "1.7976931348623157e308", "2.2250738585072014e-308", "1e-310", "0", "-0"};
  std::string csv = "t,u,v\n";
  for (size_t i = 0; i < cells.size(); ++i) csv += std::to_string(i) + "," + cells[i] + "," + cells[i] + "\n";
  const predvs::FeatureTrack track = predvs::readFeatureTrack(writeTemp("cells.csv", csv));
  ASSERT_EQ(track.size(), cells.size());
  for (size_t i = 0; i < cells.size(); ++i) {
    EXPECT_EQ(track.u_px[0][i], std::strtod(cells[i].c_str(), nullptr)) << cells[i];
    EXPECT_EQ(track.v_px[0][i], std::strtod(cells[i].c_str(), nullptr)) << cells[i];
  }
}

// strtod's, but for hexadecimal (a CSV of decimals does not mean "0x10" as 16) and subnormals (finite,
// taken above).
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
  EXPECT_NE(message("hex.csv", "0x10").find(":3: column 'u': expected a number, got '0x10'"), std::string::npos);
  EXPECT_NE(message("hexf.csv", "0x1p3").find(":3: column 'u': expected a number, got '0x1p3'"), std::string::npos);
  EXPECT_NE(message("junk.csv", "1.5x").find(":3: column 'u': expected a number, got '1.5x'"), std::string::npos);
  EXPECT_NE(message("two.csv", "1 2").find(":3: column 'u': expected a number, got '1 2'"), std::string::npos);
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

/// A generated track: `points` points moving on curves with 1.5 px noise, 2 % of cells empty (the
/// whole frame for point 0 every 97th frame), with truth; 30 Hz with a little jitter.
predvs::FeatureTrack syntheticTrack(size_t rows, int points) {
  predvs::FeatureTrack track;
  track.path = "synthetic";
  track.format = points == 1 ? "wide" : "long";
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 1.5);
  for (int p = 0; p < points; ++p) track.point_names.push_back(std::to_string(p));
  const size_t np = static_cast<size_t>(points);
  track.u_px.assign(np, {});
  track.v_px.assign(np, {});
  track.u_true_px.assign(np, {});
  track.v_true_px.assign(np, {});
  double t = 0.0;
  for (size_t i = 0; i < rows; ++i) {
    track.t_s.push_back(t);
    for (size_t p = 0; p < np; ++p) {
      const double u = 320.0 + 150.0 * std::sin(0.3 * t + p) + 20.0 * std::sin(2.0 * t);
      const double v = 240.0 + 100.0 * std::cos(0.21 * t + p);
      const bool drop = uni(rng) < 0.02 || (p == 0 && i % 97 == 50);
      track.u_px[p].push_back(drop ? std::nan("") : u + noise(rng));
      track.v_px[p].push_back(drop ? std::nan("") : v + noise(rng));
      track.u_true_px[p].push_back(u);
      track.v_true_px[p].push_back(v);
    }
    t += (1.0 + 0.1 * (uni(rng) - 0.5)) / 30.0;
  }
  return track;
}

bool sameBits(double a, double b) { return (std::isnan(a) && std::isnan(b)) || std::memcmp(&a, &b, sizeof a) == 0; }

std::string readAll(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

std::vector<predvs::PredictorSpec> everyPredictor() {
  std::vector<predvs::PredictorSpec> specs;
  for (const auto& info : predvs::predictorRegistry()) specs.push_back({info.name, {}});
  return specs;
}

/// predictToFiles of `specs` into a fresh temporary directory; returns the directory.
std::filesystem::path filesOf(const predvs::FeatureTrack& track, const std::vector<predvs::PredictorSpec>& specs,
                              int jobs, const std::string& name, predvs::PredictionFiles files = {},
                              predvs::PredictionReport* report = nullptr) {
  const auto out = std::filesystem::temp_directory_path() / ("predvs_throughput_" + name);
  std::filesystem::remove_all(out);
  files.delay_frames = 2;
  files.command_line = "predvs predict (test)";
  predvs::StagedOutputDir dir(out);
  const predvs::PredictionReport r = predvs::predictToFiles(track, specs, 2.0 / 30.0, files, dir, jobs);
  dir.commit();
  if (report) *report = r;
  return out;
}

/// predictTrack (the report) and predictToFiles without the plot (the files) with `jobs` threads;
/// returns the output directory.
std::filesystem::path predictWith(const predvs::FeatureTrack& track, int jobs, const std::string& name,
                                  predvs::PredictionReport& report) {
  report = predvs::predictTrack(track, everyPredictor(), 2.0 / 30.0, jobs);
  predvs::PredictionFiles files;
  files.plots = false;
  return filesOf(track, everyPredictor(), jobs, "jobs_" + name, files);
}

TEST(PredictThroughput, ParallelRunGivesTheSameOutputsAsOneThread) {
  // GIVEN a one-point track long enough for the longest-first ordering and several CSV chunks,
  // and a three-point track (long layout)
  for (const auto& [rows, points] : {std::pair<size_t, int>{40000, 1}, std::pair<size_t, int>{3000, 3}}) {
    const predvs::FeatureTrack track = syntheticTrack(rows, points);
    const std::string tag = std::to_string(points);
    // WHEN every predictor runs on 1 thread and on 3
    predvs::PredictionReport one, three;
    const auto dir1 = predictWith(track, 1, tag + "_1", one);
    const auto dir3 = predictWith(track, 3, tag + "_3", three);
    // THEN every prediction and every error has the same bits, in registry order
    ASSERT_EQ(one.runs.size(), predvs::predictorRegistry().size());
    ASSERT_EQ(three.runs.size(), one.runs.size());
    for (size_t k = 0; k < one.runs.size(); ++k) {
      EXPECT_EQ(three.runs[k].spec.name, predvs::predictorRegistry()[k].name);
      EXPECT_TRUE(sameBits(three.runs[k].vs_truth.rmse_px, one.runs[k].vs_truth.rmse_px)) << one.runs[k].spec.name;
      EXPECT_EQ(three.runs[k].vs_measurement.n, one.runs[k].vs_measurement.n);
      EXPECT_GT(one.runs[k].vs_measurement.n, static_cast<int>(rows) / 2) << one.runs[k].spec.name;
      for (size_t p = 0; p < static_cast<size_t>(points); ++p)
        for (size_t i = 0; i < rows; ++i) {
          ASSERT_TRUE(sameBits(three.runs[k].points[p].u_pred_px[i], one.runs[k].points[p].u_pred_px[i]))
              << one.runs[k].spec.name << " row " << i;
          ASSERT_TRUE(sameBits(three.runs[k].points[p].v_pred_px[i], one.runs[k].points[p].v_pred_px[i]))
              << one.runs[k].spec.name << " row " << i;
        }
    }
    // ... and the files are byte for byte the same
    const std::string csv1 = readAll(dir1 / "predictions.csv");
    EXPECT_GT(csv1.size(), rows * 100 * static_cast<size_t>(points));
    EXPECT_TRUE(csv1 == readAll(dir3 / "predictions.csv")) << tag;
    EXPECT_EQ(readAll(dir1 / "summary.json"), readAll(dir3 / "summary.json"));
    std::filesystem::remove_all(dir1);
    std::filesystem::remove_all(dir3);
  }
}

/// The message of the exception `run` throws ("" when it throws none, "?" for one not derived
/// from std::exception).
template <class Run>
std::string thrownMessage(Run&& run) {
  try {
    run();
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
    return "?";
  }
  return "";
}

TEST(PredictThroughput, APredictorThrowingMidTrackGivesOneThreadsErrorAndNoFiles) {
  // GIVEN a two-point track (in memory: the CSV reader would refuse it) whose time goes back at
  // row 1234, i.e. in the third block of 500 rows: every channel of every predictor throws there
  const size_t rows = 3000;
  predvs::FeatureTrack track = syntheticTrack(rows, 2);
  track.t_s[1234] = track.t_s[1233] - 0.01;
  const auto specs = everyPredictor();
  // WHEN the predictions run on 1 thread in one block, and on 3 threads in blocks of 500 rows
  const std::string one = thrownMessage([&] { predvs::predictTrack(track, specs, 2.0 / 30.0, 1, rows); });
  const std::string three = thrownMessage([&] { predvs::predictTrack(track, specs, 2.0 / 30.0, 3, 500); });
  // THEN both report the error a serial run meets first: the first predictor's, at that update
  EXPECT_EQ(three, one);
  EXPECT_EQ(one.rfind(specs.front().name + ": update time ", 0), 0u) << one;
  EXPECT_NE(one.find("is not after the previous one"), std::string::npos) << one;
  // ... and predictToFiles throws it too and leaves no output directory behind
  const auto out = std::filesystem::temp_directory_path() / "predvs_throughput_throws";
  std::filesystem::remove_all(out);
  predvs::PredictionFiles files;
  files.block_rows = 500;
  files.delay_frames = 2;
  const std::string written = thrownMessage([&] {
    predvs::StagedOutputDir dir(out);
    predvs::predictToFiles(track, specs, 2.0 / 30.0, files, dir, 3);
    dir.commit();
  });
  EXPECT_EQ(written, one);
  EXPECT_FALSE(std::filesystem::exists(out));
  for (const auto& entry : std::filesystem::directory_iterator(out.parent_path()))
    EXPECT_EQ(entry.path().filename().string().find(".predvs_throughput_throws"), std::string::npos) << entry.path();
}

TEST(PredictThroughput, PlotBinaryHoldsTheNumbersOfThePlotText) {
  // GIVEN a one-point track with empty cells, thinned for the plot (its envelope), and three predictors
  // (and no measurement for 100 rows: slices with no number, NaN in the plot)
  predvs::FeatureTrack track = syntheticTrack(predvs::kMaxPlotRows + 3001, 1);
  std::fill(track.u_px[0].begin() + 5000, track.u_px[0].begin() + 5100, std::nan(""));
  std::fill(track.v_px[0].begin() + 5000, track.v_px[0].begin() + 5100, std::nan(""));
  const std::vector<predvs::PredictorSpec> specs{{"hold", {}}, {"kf-cv", {}}, {"fakf", {}}};
  // WHEN the outputs are written with the plot
  const auto out = filesOf(track, specs, 2, "plot_bin");
  // THEN predictions_plot.bin holds, row by row, the doubles the text of predictions_plot.dat reads
  // as (NaN for "NaN"), and predictions.gp reads it with that many columns
  const size_t columns = 6 + 2 * specs.size();
  const std::string bin = readAll(out / "predictions_plot.bin");
  std::ifstream dat(out / "predictions_plot.dat");
  std::string line;
  size_t rows = 0, nans = 0, at = 0;
  while (std::getline(dat, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream cells(line);
    std::string cell;
    size_t c = 0;
    for (; cells >> cell; ++c) {
      ASSERT_LE(at + sizeof(double), bin.size()) << "row " << rows;
      double value;
      std::memcpy(&value, bin.data() + at, sizeof value);
      at += sizeof value;
      if (cell == "NaN") {
        EXPECT_TRUE(std::isnan(value)) << "row " << rows << " column " << c;
        ++nans;
      } else {
        EXPECT_TRUE(sameBits(value, std::strtod(cell.c_str(), nullptr))) << cell << " row " << rows << " column " << c;
      }
    }
    ASSERT_EQ(c, columns) << "row " << rows;
    ++rows;
  }
  EXPECT_GT(rows, predvs::kPlotSlices);  // two rows per slice of about 19 rows
  EXPECT_LE(rows, 2 * predvs::kPlotSlices);
  EXPECT_EQ(at, bin.size());
  EXPECT_GT(nans, 0u);
  const std::string gp = readAll(out / "predictions.gp");
  EXPECT_NE(gp.find("data = 'predictions_plot.bin'"), std::string::npos) << gp;
  EXPECT_NE(gp.find("binary format='%" + std::to_string(columns) + "float64'"), std::string::npos) << gp;
  EXPECT_TRUE(std::filesystem::exists(out / "predictions.png"));
  std::filesystem::remove_all(out);
}

TEST(PredictThroughput, PlotDataOfATrackUpToTheLimitHasEveryRow) {
  // GIVEN a one-point track of kMaxPlotRows rows and one predictor
  const predvs::FeatureTrack track = syntheticTrack(predvs::kMaxPlotRows, 1);
  // WHEN the outputs are written with the plot
  const auto out = filesOf(track, {{"hold", {}}}, 2, "plot_whole");
  // THEN predictions_plot.dat has every row, each row's time the track's, and the title no thinning
  std::ifstream dat(out / "predictions_plot.dat");
  std::string line;
  size_t rows = 0, comments = 0;
  while (std::getline(dat, line)) {
    if (line.empty() || line[0] == '#') {
      ++comments;
      continue;
    }
    ASSERT_LT(rows, track.size());
    EXPECT_NEAR(std::strtod(line.c_str(), nullptr), track.t_s[rows], 1e-7 * (1.0 + track.t_s[rows])) << rows;
    ++rows;
  }
  EXPECT_EQ(rows, track.size());
  EXPECT_EQ(comments, 1u);
  EXPECT_EQ(readAll(out / "predictions.gp").find("slices"), std::string::npos);
  std::filesystem::remove_all(out);
}

TEST(PredictThroughput, StreamedFilesAreTheSameForAnyBlockSizeAndHoldPredictTracksColumns) {
  // GIVEN a one-point track past the plot's limit (its envelope) with a stretch of empty cells, and
  // a three-point track (long layout), every predictor
  for (const auto& [rows, points] : {std::pair<size_t, int>{predvs::kMaxPlotRows + 5003, 1}, std::pair<size_t, int>{3001, 3}}) {
    predvs::FeatureTrack track = syntheticTrack(rows, points);
    std::fill(track.u_px[0].begin() + 2000, track.u_px[0].begin() + 2100, std::nan(""));
    std::fill(track.v_px[0].begin() + 2000, track.v_px[0].begin() + 2100, std::nan(""));
    const std::string tag = std::to_string(points);
    const auto specs = everyPredictor();
    // WHEN the files are written in one block, in blocks of 777 rows (not a multiple of the CSV's
    // chunks) on 2 threads and of 1000 rows on 1, and the report is made by predictTrack
    predvs::PredictionFiles whole, small, other;
    whole.block_rows = rows;
    small.block_rows = 777;
    other.block_rows = 1000;
    predvs::PredictionReport streamed;
    const auto dir_whole = filesOf(track, specs, 2, "blocks_whole_" + tag, whole, &streamed);
    const auto dir_small = filesOf(track, specs, 2, "blocks_777_" + tag, small);
    const auto dir_other = filesOf(track, specs, 1, "blocks_1000_" + tag, other);
    const predvs::PredictionReport report = predvs::predictTrack(track, specs, 2.0 / 30.0, 2, 4096);
    // THEN every file is byte for byte the same
    for (const char* f : {"predictions.csv", "summary.json", "predictions_plot.dat", "predictions_plot.bin",
                          "predictions_errors.dat"}) {
      const std::string text = readAll(dir_whole / f);
      EXPECT_GT(text.size(), 1000u) << f;
      EXPECT_TRUE(text == readAll(dir_small / f)) << f << " " << tag;
      EXPECT_TRUE(text == readAll(dir_other / f)) << f << " " << tag;
    }
    // ... predictions.csv holds predictTrack's columns, in csvNumber's 10 digits, row by row
    std::istringstream csv(readAll(dir_whole / "predictions.csv"));
    std::string line;
    std::getline(csv, line);  // the header
    for (size_t i = 0; i < rows; ++i)
      for (size_t p = 0; p < static_cast<size_t>(points); ++p) {
        ASSERT_TRUE(std::getline(csv, line)) << i;
        std::string expected = predvs::csvNumber(track.t_s[i], 10) + "," +
                               (points > 1 ? track.point_names[p] + "," : std::string()) +
                               predvs::csvNumber(track.u_px[p][i], 10) + "," + predvs::csvNumber(track.v_px[p][i], 10) +
                               "," + predvs::csvNumber(track.t_s[i] + 2.0 / 30.0, 10);
        for (const auto& run : report.runs)
          expected += "," + predvs::csvNumber(run.points[p].u_pred_px[i], 10) + "," +
                      predvs::csvNumber(run.points[p].v_pred_px[i], 10);
        ASSERT_EQ(line, expected) << "row " << i << " point " << p;
      }
    EXPECT_FALSE(std::getline(csv, line));
    // ... and the streamed errors are predictTrack's, and predictionErrors' on its columns, bit for bit
    for (size_t k = 0; k < report.runs.size(); ++k) {
      EXPECT_TRUE(sameBits(streamed.runs[k].vs_truth.rmse_px, report.runs[k].vs_truth.rmse_px)) << k;
      EXPECT_TRUE(sameBits(streamed.runs[k].vs_measurement.rmse_u_px, report.runs[k].vs_measurement.rmse_u_px)) << k;
      EXPECT_EQ(streamed.runs[k].vs_measurement.n, report.runs[k].vs_measurement.n);
      const auto& pt = report.runs[k].points[0];
      const predvs::PredictionErrors direct =
          predvs::predictionErrors(track.t_s, pt.u_pred_px, pt.v_pred_px, 2.0 / 30.0, track.u_true_px[0], track.v_true_px[0]);
      EXPECT_TRUE(sameBits(direct.rmse_px, report.runs[k].points[0].vs_truth.rmse_px)) << k;
      EXPECT_TRUE(streamed.runs[k].points[0].u_pred_px.empty());  // no column of the track's size kept
    }
    for (const auto& d : {dir_whole, dir_small, dir_other}) std::filesystem::remove_all(d);
  }
}

TEST(PredictThroughput, ScoringFromARowIsTheErrorOfTheRowsAfterIt) {
  // GIVEN a track and two predictors, scored from row 1234 on (predict --fit-split), in blocks of 500
  const predvs::FeatureTrack track = syntheticTrack(5000, 2);
  const std::vector<predvs::PredictorSpec> specs{{"kf-cv", {}}, {"imm", {}}};
  predvs::PredictionFiles files;
  files.plots = false;
  files.score_from = 1234;
  files.block_rows = 500;
  predvs::PredictionReport streamed;
  const auto dir = filesOf(track, specs, 2, "score_from", files, &streamed);
  // THEN each point's errors are those of its predictions with the first 1234 rows blanked
  const predvs::PredictionReport report = predvs::predictTrack(track, specs, 2.0 / 30.0, 1);
  for (size_t k = 0; k < specs.size(); ++k)
    for (size_t p = 0; p < 2; ++p) {
      std::vector<double> u = report.runs[k].points[p].u_pred_px, v = report.runs[k].points[p].v_pred_px;
      std::fill(u.begin(), u.begin() + 1234, std::nan(""));
      std::fill(v.begin(), v.begin() + 1234, std::nan(""));
      const predvs::PredictionErrors meas = predvs::predictionErrors(track.t_s, u, v, 2.0 / 30.0, track.u_px[p], track.v_px[p]);
      const predvs::PredictionErrors truth =
          predvs::predictionErrors(track.t_s, u, v, 2.0 / 30.0, track.u_true_px[p], track.v_true_px[p]);
      const auto& got = streamed.runs[k].points[p];
      EXPECT_TRUE(sameBits(got.vs_measurement.rmse_px, meas.rmse_px)) << k << " " << p;
      EXPECT_TRUE(sameBits(got.vs_truth.rmse_v_px, truth.rmse_v_px)) << k << " " << p;
      EXPECT_EQ(got.vs_truth.n, truth.n);
      EXPECT_LT(got.vs_truth.n, 5000 - 1234 + 1);
      EXPECT_GT(got.vs_truth.n, 5000 - 1234 - 10);
    }
  std::filesystem::remove_all(dir);
}

TEST(PredictErrorPanel, EachSliceIsTheRmsOfItsScoredRowsAgainstTheTruth) {
  // GIVEN a two-point track with truth and dropped frames, two predictors, scored from row 700
  // (predict --fit-split), in blocks of 333 rows
  const size_t rows = 2000, score_from = 700;
  const predvs::FeatureTrack track = syntheticTrack(rows, 2);
  const std::vector<predvs::PredictorSpec> specs{{"hold", {}}, {"kf-cv", {}}};
  predvs::PredictionFiles files;
  files.score_from = score_from;
  files.block_rows = 333;
  const auto dir = filesOf(track, specs, 2, "error_panel", files);
  // WHEN predictions_errors.dat (the third panel of predictions.png) is read
  std::ifstream dat(dir / "predictions_errors.dat");
  std::vector<std::vector<double>> table;
  for (std::string line; std::getline(dat, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream in(line);
    std::vector<double> row;
    for (std::string cell; in >> cell;) row.push_back(cell == "NaN" ? std::nan("") : std::stod(cell));
    ASSERT_EQ(row.size(), 3u) << line;
    table.push_back(row);
  }
  // THEN it has 200 slices (2000 rows / 8, at most 200), and each is the RMS over the slice's rows
  // from row 700 on of every point's error against the truth at t + horizon, pooled; slices before
  // row 700 are empty
  ASSERT_EQ(table.size(), 200u);
  const double h = 2.0 / 30.0, t0 = track.t_s.front(), span = track.t_s.back() - t0;
  const predvs::PredictionReport report = predvs::predictTrack(track, specs, h, 1);
  std::vector<std::vector<double>> sq(2, std::vector<double>(200, 0.0));
  std::vector<std::vector<int>> n(2, std::vector<int>(200, 0));
  for (size_t p = 0; p < 2; ++p) {
    const std::vector<double> ut = predvs::interpolateShifted(track.t_s, track.u_true_px[p], h);
    const std::vector<double> vt = predvs::interpolateShifted(track.t_s, track.v_true_px[p], h);
    for (size_t k = 0; k < 2; ++k)
      for (size_t i = score_from; i < rows; ++i) {
        const double du = report.runs[k].points[p].u_pred_px[i] - ut[i], dv = report.runs[k].points[p].v_pred_px[i] - vt[i];
        if (!std::isfinite(du) || !std::isfinite(dv)) continue;
        const size_t j = std::min<size_t>(199, static_cast<size_t>((track.t_s[i] - t0) / span * 200.0));
        sq[k][j] += du * du + dv * dv;
        ++n[k][j];
      }
  }
  size_t empty = 0;
  for (size_t j = 0; j < 200; ++j) {
    EXPECT_NEAR(table[j][0], t0 + span * (j + 0.5) / 200.0 + h, 1e-6) << j;
    for (size_t k = 0; k < 2; ++k) {
      if (n[k][j] == 0) {
        EXPECT_TRUE(std::isnan(table[j][1 + k])) << j;
        empty += k;
        continue;
      }
      const double want = std::sqrt(sq[k][j] / n[k][j]);
      EXPECT_NEAR(table[j][1 + k], want, 1e-7 * want) << "slice " << j << " predictor " << k;
    }
  }
  EXPECT_GE(empty, 69u);  // the slices of rows 0-699 (each slice holds about 10 rows)
  EXPECT_LE(empty, 71u);
  // ... and hold's error, the motion over the horizon, is above kf-cv's in most slices
  size_t hold_worse = 0;
  for (size_t j = 70; j < 200; ++j) hold_worse += table[j][1] > table[j][2];
  EXPECT_GT(hold_worse, 100u);
  // ... and predictions.gp draws it as a third panel on a log axis
  const std::string gp = readAll(dir / "predictions.gp");
  EXPECT_NE(gp.find("multiplot layout 3,1"), std::string::npos);
  EXPECT_NE(gp.find("set logscale y"), std::string::npos);
  EXPECT_NE(gp.find("'predictions_errors.dat' using 1:3"), std::string::npos);
  EXPECT_NE(gp.find("RMS prediction error vs truth"), std::string::npos);
  EXPECT_NE(gp.find("the rows scored (from t = "), std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST(PredictErrorPanel, AnExactForecastEverywhereKeepsALinearAxis) {
  // GIVEN a still target without noise at (0, 0), where the interpolated reference is exact: hold's
  // error is 0 on every row
  predvs::FeatureTrack track;
  track.path = "still";
  track.format = "wide";
  track.point_names = {"0"};
  for (int i = 0; i < 100; ++i) track.t_s.push_back(i / 30.0);
  track.u_px = {std::vector<double>(100, 0.0)};
  track.v_px = {std::vector<double>(100, 0.0)};
  // WHEN hold's outputs are written with the plot
  const auto dir = filesOf(track, {{"hold", {}}}, 1, "error_panel_still");
  // THEN every slice is 0 vs the measurement, the axis is linear (a log axis has no 0) and the PNG is drawn
  const std::string gp = readAll(dir / "predictions.gp");
  EXPECT_EQ(gp.find("set logscale y"), std::string::npos);
  EXPECT_NE(gp.find("RMS prediction error vs measurement"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir / "predictions.png"));
  std::ifstream dat(dir / "predictions_errors.dat");
  size_t slices = 0;
  for (std::string line; std::getline(dat, line);) {
    if (line.empty() || line[0] == '#') continue;
    EXPECT_EQ(line.substr(line.find(' ') + 1), "0") << line;
    ++slices;
  }
  EXPECT_EQ(slices, 12u);  // 100 rows / 8
  std::filesystem::remove_all(dir);
}

TEST(PredictThroughput, InterpolatedRangesAreTheWholePassesRows) {
  // GIVEN a signal with gaps at jittered times
  const predvs::FeatureTrack track = syntheticTrack(3000, 1);
  std::vector<double> y = track.u_px[0];
  std::fill(y.begin() + 100, y.begin() + 180, std::nan(""));
  const std::vector<double> whole = predvs::interpolateShifted(track.t_s, y, 0.07);
  // WHEN it is interpolated in ranges of 1, 7 and 500 rows
  for (size_t step : {size_t{1}, size_t{7}, size_t{500}}) {
    std::vector<double> pieces(y.size());
    for (size_t i0 = 0; i0 < y.size(); i0 += step)
      predvs::interpolateShifted(track.t_s, y, 0.07, i0, std::min(y.size(), i0 + step), pieces.data() + i0);
    // THEN every row has the whole pass's bits
    for (size_t i = 0; i < y.size(); ++i) ASSERT_TRUE(sameBits(pieces[i], whole[i])) << step << " row " << i;
  }
}

/// A wide track's text: 3 points (truth for points 0 and 2 only), an ignored column, empty cells,
/// a blank line now and then, CRLF line ends on some rows; `rows` data rows at 30 Hz.
std::string wideTrackText(size_t rows) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::string text = "t,u0,v0,u1,v1,u2,v2,note,u0_true,v0_true,u2_true,v2_true\n";
  char cell[64];
  auto num = [&](double x) {
    std::snprintf(cell, sizeof cell, "%.10g", x);
    return std::string(cell);
  };
  for (size_t i = 0; i < rows; ++i) {
    const double t = i / 30.0;
    std::string row = num(t);
    for (int p = 0; p < 3; ++p)
      for (int axis = 0; axis < 2; ++axis) row += "," + (uni(rng) < 0.03 ? std::string() : num(300.0 * uni(rng) + p));
    row += ",x" + std::to_string(i % 7);
    for (int k = 0; k < 4; ++k) row += "," + num(200.0 + 100.0 * uni(rng));
    text += row + (i % 5 == 0 ? "\r\n" : "\n");
    if (i % 211 == 0) text += "\n";
  }
  return text;
}

TEST(PredictThroughput, ParallelParseGivesTheSameTrackAsOneThread) {
  // GIVEN a wide track (and a long one)
  const std::string wide = writeTemp("parallel_wide.csv", wideTrackText(3000));
  const std::string long_csv =
      writeTemp("parallel_long.csv", "t,point,u,v\n0,a,1,2\n0,b,3,4\n0.1,b,5,6\n0.2,a,7,8\n0.2,b,9,10\n");
  for (const std::string& path : {wide, long_csv}) {
    // WHEN it is read on one thread and, cut into pieces (no size threshold), on 1 to 4 threads
    const predvs::FeatureTrack one = predvs::readFeatureTrack(path, 1);
    for (int jobs : {2, 3, 4}) {
      const predvs::FeatureTrack many = predvs::readFeatureTrack(path, jobs, 1);
      // THEN the tracks are the same, value for value
      EXPECT_EQ(many.format, one.format);
      EXPECT_EQ(many.point_names, one.point_names);
      EXPECT_EQ(many.ignored_columns, one.ignored_columns);
      ASSERT_EQ(many.size(), one.size()) << jobs;
      auto same = [&](const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>& b) {
        ASSERT_EQ(a.size(), b.size());
        for (size_t p = 0; p < a.size(); ++p) {
          ASSERT_EQ(a[p].size(), b[p].size());
          for (size_t i = 0; i < a[p].size(); ++i) ASSERT_TRUE(sameBits(a[p][i], b[p][i])) << "point " << p << " row " << i;
        }
      };
      same({many.t_s}, {one.t_s});
      same(many.u_px, one.u_px);
      same(many.v_px, one.v_px);
      same(many.u_true_px, one.u_true_px);
      same(many.v_true_px, one.v_true_px);
    }
  }
  const predvs::FeatureTrack track = predvs::readFeatureTrack(wide, 3, 1);
  EXPECT_EQ(track.size(), 3000u);
  EXPECT_EQ(track.points(), 3);
  EXPECT_TRUE(std::isnan(track.u_true_px[1][7]));
  EXPECT_EQ(track.ignored_columns, std::vector<std::string>{"note"});
}

TEST(PredictThroughput, ParallelParseGivesTheSameErrorLineAsOneThread) {
  // GIVEN a wide track of 2000 rows with one defect, at lines spread over the file (so at the start,
  // inside and at the ends of the pieces)
  const std::string good = wideTrackText(2000);
  std::vector<size_t> line_start{0};
  for (size_t i = 0; i < good.size(); ++i)
    if (good[i] == '\n') line_start.push_back(i + 1);
  const size_t lines = line_start.size() - 1;
  int checked = 0;
  for (size_t line = 2; line <= lines; line += 97) {
    const size_t b = line_start[line - 1], e = line_start[line];
    const std::string row = good.substr(b, e - b);
    if (row == "\n") continue;  // a blank line
    const size_t comma = row.find(',');
    for (int defect = 0; defect < 3; ++defect) {
      std::string bad_row;
      if (defect == 0) bad_row = row.substr(0, comma) + ",1.5x" + row.substr(row.find(',', comma + 1));  // a bad cell
      if (defect == 1) bad_row = row.substr(0, comma) + ",1" + row.substr(comma);                       // a cell too many
      if (defect == 2) bad_row = "-1" + row.substr(comma);  // a time that goes back (but on line 2)
      const std::string path = writeTemp("parallel_bad.csv", good.substr(0, b) + bad_row + good.substr(e));
      auto message = [&](int jobs) {
        try {
          predvs::readFeatureTrack(path, jobs, 1);
        } catch (const std::invalid_argument& ex) {
          return std::string(ex.what());
        }
        return std::string("no error");
      };
      // WHEN it is read on one thread and on three
      const std::string one = message(1);
      // THEN both give the same message, naming the line
      EXPECT_EQ(message(3), one);
      if (!(defect == 2 && line == 2)) {
        EXPECT_NE(one.find(":" + std::to_string(line) + ": "), std::string::npos) << one;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 50);
  // ... and a time that goes back on every line of a short track, so also on the first row of each
  // piece (where only the check across pieces can see it)
  const std::string small = wideTrackText(150);
  size_t b = small.find('\n') + 1;
  for (int line = 2; b < small.size(); ++line) {
    const size_t e = small.find('\n', b) + 1;
    if (e - b > 1 && line > 2) {
      const std::string path = writeTemp("parallel_back.csv", small.substr(0, b) + "-1" +
                                                                 small.substr(small.find(',', b), std::string::npos));
      std::string one, three;
      try {
        predvs::readFeatureTrack(path, 1);
      } catch (const std::invalid_argument& ex) {
        one = ex.what();
      }
      try {
        predvs::readFeatureTrack(path, 3, 1);
      } catch (const std::invalid_argument& ex) {
        three = ex.what();
      }
      EXPECT_NE(one.find(":" + std::to_string(line) + ": column 't'"), std::string::npos) << one;
      EXPECT_EQ(three, one);
    }
    b = e;
  }
}

TEST(PredictThroughput, BadJobsIsAOneLineErrorWithNoOutput) {
  const std::string input = writeTemp("jobs.csv", "t,u,v\n0,1,2\n0.1,2,3\n0.2,3,4\n");
  const auto out = std::filesystem::temp_directory_path() / "predvs_throughput_bad_jobs";
  std::filesystem::remove_all(out);
  for (const char* jobs : {"0", "x", "-2"}) {
    std::ostringstream o, e;
    const int rc = predvs::runCli({"predict", "--input", input, "--predictor", "kf-cv", "--delay-frames", "1", "--no-plots",
                                   "--jobs", jobs, "--out", out.string()},
                                  o, e);
    const std::string err = e.str();
    EXPECT_EQ(rc, 2) << jobs;
    EXPECT_NE(err.find("--jobs"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_FALSE(std::filesystem::exists(out)) << jobs;
  }
}

TEST(PredictThroughput, ReserveLargeReservesAndKeepsTheElements) {
  // Speed only (large_buffer.h): what the vector holds and can hold is what reserve() gives.
  std::vector<double> big;
  const size_t n = 3 * (predvs::kLargeBufferMinBytes / sizeof(double)) + 12345;  // spans whole 2 MB pages
  predvs::reserveLarge(big, n);
  EXPECT_TRUE(big.empty());
  ASSERT_GE(big.capacity(), n);
  const double* data = big.data();
  for (size_t i = 0; i < n; ++i) big.push_back(static_cast<double>(i));
  EXPECT_EQ(big.data(), data);  // no reallocation on the way
  EXPECT_EQ(big[n - 1], static_cast<double>(n - 1));

  std::vector<double> small{1.0, 2.0, 3.0};
  predvs::reserveLarge(small, 10);  // below the threshold: a plain reserve
  EXPECT_GE(small.capacity(), 10u);
  EXPECT_EQ(small, (std::vector<double>{1.0, 2.0, 3.0}));
  predvs::reserveLarge(small, 2);  // less than held: nothing changes
  EXPECT_EQ(small, (std::vector<double>{1.0, 2.0, 3.0}));
  predvs::reserveLarge(small, n);  // grows with its elements copied
  EXPECT_GE(small.capacity(), n);
  EXPECT_EQ(small, (std::vector<double>{1.0, 2.0, 3.0}));
}

}  // namespace
