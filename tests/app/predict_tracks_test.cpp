// `predvs predict` on N-point tracks (issue 9 item 5): the long (t,point,u,v) and wide
// (t,u0,v0,u1,v1,...) formats give identical results on the same data; what spreadsheets write
// (UTF-8 BOM, CRLF, extra columns) is read and the extra columns are named in summary.json; the
// file `predvs track` writes (long, integer ids, empty cells when lost) is read; --predictor takes
// a comma list; errors stay FILE:LINE one-liners. Also the lost-feature policy's scenario key
// (lost:) where only the app can check it: drop refused for a law or an open loop that cannot.
#include "cli_test_utils.h"
#include "scenario.h"
#include "scenario_file.h"
#include "track_csv.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>

namespace fs = std::filesystem;
using namespace predvs::apptest;

namespace {

class PredictTracksTest : public ScratchDirTest {
 protected:
  PredictTracksTest() : ScratchDirTest("predvs_predict_tracks") {}

  /// Three points on constant-velocity lines, T = 0.04 s, 60 frames, seeded 0.5 px noise; point
  /// 1 not measured on every 7th frame, point 2 lost from frame 30 to 35; with truth.
  struct Sample {
    double t;
    int point;
    double u, v, ut, vt;
    bool measured;
  };
  static std::vector<Sample> samples() {
    std::mt19937 rng(11);
    std::normal_distribution<double> noise(0.0, 0.5);
    std::vector<Sample> s;
    for (int i = 0; i < 60; ++i)
      for (int p = 0; p < 3; ++p) {
        const double t = 0.04 * i;
        const double u = 100 + 40 * p + (30 - 10 * p) * t, v = 50 + 25 * p - (20 + 5 * p) * t;
        const bool measured = !(p == 1 && i % 7 == 3) && !(p == 2 && i >= 30 && i <= 35);
        s.push_back({t, p, u + noise(rng), v + noise(rng), u, v, measured});
      }
    return s;
  }
  static std::string num(double x) {
    std::ostringstream o;
    o.precision(12);
    o << x;
    return o.str();
  }
  /// Long format; `eol` the line end; a lost point as a row with empty cells (as `predvs track`
  /// writes it) when `empty_rows`, else left out of its frame.
  std::string longCsv(const std::string& eol = "\n", bool empty_rows = true, bool truth = true) const {
    std::ostringstream csv;
    csv << "t,point,u,v" << (truth ? ",u_true,v_true" : "") << eol;
    for (const auto& x : samples()) {
      if (!x.measured && !empty_rows) continue;
      csv << num(x.t) << "," << x.point << "," << (x.measured ? num(x.u) : "") << "," << (x.measured ? num(x.v) : "");
      if (truth) csv << "," << num(x.ut) << "," << num(x.vt);
      csv << eol;
    }
    return csv.str();
  }
  std::string wideCsv() const {
    std::ostringstream csv;
    csv << "t,u0,v0,u1,v1,u2,v2,u0_true,v0_true,u1_true,v1_true,u2_true,v2_true\n";
    const auto s = samples();
    for (size_t f = 0; f < s.size(); f += 3) {
      csv << num(s[f].t);
      for (size_t p = 0; p < 3; ++p)
        csv << "," << (s[f + p].measured ? num(s[f + p].u) : "") << "," << (s[f + p].measured ? num(s[f + p].v) : "");
      for (size_t p = 0; p < 3; ++p) csv << "," << num(s[f + p].ut) << "," << num(s[f + p].vt);
      csv << "\n";
    }
    return csv.str();
  }
  CliRun predict(const std::string& input, const std::string& out, const std::string& predictors = "kf-cv,stkf",
                 const std::vector<std::string>& extra = {}) const {
    return run({"predict", "--input", input, "--predictor", predictors, "--delay-frames", "2", "--out", out, "--no-plots"},
               extra);
  }
};

TEST_F(PredictTracksTest, LongAndWideGiveIdenticalResults) {
  // GIVEN the same three-point track in the long format (lost points as empty rows, and left out)
  // and in the wide format
  const std::string a = path("a"), b = path("b"), c = path("c");
  // WHEN kf-cv (tuned for these slow lines: q 100 px^2/s^3, r 0.25 px^2; its defaults are sized
  // for targets of 50-400 px/s; no coasting decay, coast_tau_s = 0: these lines are exactly
  // constant-velocity through the lost frames, measured 1.05 px with the default 0.2 s) and stkf
  // predict 2 frames ahead on each
  // (and the plain forecast, hold_blend_tau_s = 0: on these 2.4 s lines the one-frame step, 0.4-1.2
  // px, is near the noise and the default blend with hold gives 1.01 px)
  const std::vector<std::string> slow{"--param", "kf-cv.q=100", "--param", "kf-cv.r=0.25", "--param",
                                      "kf-cv.coast_tau_s=0", "--param", "kf-cv.hold_blend_tau_s=0"};
  ASSERT_EQ(predict(write("long.csv", longCsv()), a, "kf-cv,stkf", slow).code, 0);
  ASSERT_EQ(predict(write("long_sparse.csv", longCsv("\n", false)), b, "kf-cv,stkf", slow).code, 0);
  const CliRun w = predict(write("wide.csv", wideCsv()), c, "kf-cv,stkf", slow);
  ASSERT_EQ(w.code, 0) << w.err;
  // THEN the predictions and every error figure are the same
  const auto ja = readJson(a + "/summary.json"), jb = readJson(b + "/summary.json"), jc = readJson(c + "/summary.json");
  EXPECT_EQ(ja["format"], "long");
  EXPECT_EQ(jc["format"], "wide");
  EXPECT_EQ(ja["points"], nlohmann::json({"0", "1", "2"}));
  EXPECT_EQ(jc["points"], ja["points"]);
  EXPECT_EQ(ja["rows"], 60);
  EXPECT_EQ(ja["predictors"], jc["predictors"]);
  EXPECT_EQ(slurp(a + "/predictions.csv"), slurp(c + "/predictions.csv"));
  // (the file that leaves the lost points out also leaves out their truth: the same predictions
  // and errors against the measurement, the truth scored on fewer frames)
  for (size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(ja["predictors"][k]["vs_measurement"], jb["predictors"][k]["vs_measurement"]);
    for (size_t q = 0; q < 3; ++q)
      EXPECT_EQ(ja["predictors"][k]["per_point"][q]["vs_measurement"], jb["predictors"][k]["per_point"][q]["vs_measurement"]);
  }
  EXPECT_LT(jb["predictors"][0]["vs_truth"]["n"].get<int>(), ja["predictors"][0]["vs_truth"]["n"].get<int>());
  // AND the figures are per point and overall: point 1, not measured on every 7th frame, is
  // scored on fewer predictions; the overall n is the sum
  for (const auto& p : ja["predictors"]) {
    ASSERT_EQ(p["per_point"].size(), 3u);
    int n = 0;
    for (const auto& q : p["per_point"]) n += q["vs_measurement"]["n"].get<int>();
    EXPECT_EQ(p["vs_measurement"]["n"].get<int>(), n);
    EXPECT_LT(p["per_point"][1]["vs_measurement"]["n"].get<int>(), p["per_point"][0]["vs_measurement"]["n"].get<int>());
  }
  // AND kf-cv on these lines is within the 0.5 px noise of the truth, overall (measured 0.81 px)
  constexpr double kCvOnLinesPx = 1.0;
  EXPECT_LT(ja["predictors"][0]["vs_truth"]["rmse_px"].get<double>(), kCvOnLinesPx);
  // AND the table names every point
  EXPECT_NE(w.out.find("RMSE vs measurement per point"), std::string::npos) << w.out;
  EXPECT_NE(w.out.find("stkf"), std::string::npos);
}

TEST_F(PredictTracksTest, OnePointWideEqualsTheSingleColumnsAndKeepsTheOldOutputs) {
  // GIVEN point 0 alone as t,u,v,u_true,v_true and as t,u0,v0,u0_true,v0_true
  std::ostringstream single, indexed;
  single << "t,u,v,u_true,v_true\n";
  indexed << "t,u0,v0,u0_true,v0_true\n";
  for (const auto& x : samples()) {
    if (x.point != 0) continue;
    const std::string row = num(x.t) + "," + num(x.u) + "," + num(x.v) + "," + num(x.ut) + "," + num(x.vt) + "\n";
    single << row;
    indexed << row;
  }
  const std::string a = path("a"), b = path("b");
  ASSERT_EQ(predict(write("single.csv", single.str()), a, "kf-cv").code, 0);
  ASSERT_EQ(predict(write("indexed.csv", indexed.str()), b, "kf-cv").code, 0);
  const auto ja = readJson(a + "/summary.json"), jb = readJson(b + "/summary.json");
  EXPECT_EQ(ja["predictors"], jb["predictors"]);
  // THEN predictions.csv keeps the one-point layout, and overall = the point's figures
  const std::string header = "t,u,v,t_target,kf-cv.u_pred,kf-cv.v_pred\n";
  EXPECT_EQ(slurp(a + "/predictions.csv").substr(0, header.size()), header);
  EXPECT_EQ(ja["predictors"][0]["vs_measurement"], ja["predictors"][0]["per_point"][0]["vs_measurement"]);
}

TEST_F(PredictTracksTest, ReadsBomCrlfAndExtraColumnsAndNamesThem) {
  // GIVEN the long track as a spreadsheet writes it: a BOM, CRLF line ends, two extra columns
  std::string text = longCsv("\r\n");
  std::istringstream in(text);
  std::ostringstream out;
  bool header = true;
  for (std::string line; std::getline(in, line);) {
    line.pop_back();  // the '\r'
    out << line << (header ? ",score,comment" : ",0.9,ok") << "\r\n";
    header = false;
  }
  const std::string dirty = write("dirty.csv", "\xEF\xBB\xBF" + out.str());
  const std::string clean = write("clean.csv", longCsv());
  const std::string a = path("a"), b = path("b");
  // WHEN predicting on both
  const CliRun r = predict(dirty, a);
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(predict(clean, b).code, 0);
  // THEN the results are those of the clean file and the extra columns are named
  const auto ja = readJson(a + "/summary.json"), jb = readJson(b + "/summary.json");
  EXPECT_EQ(ja["predictors"], jb["predictors"]);
  EXPECT_EQ(ja["ignored_columns"], nlohmann::json({"score", "comment"}));
  EXPECT_EQ(jb["ignored_columns"], nlohmann::json::array());
}

TEST_F(PredictTracksTest, ReadsTheTrackCommandsFileWithNamedOrIntegerIds) {
  // GIVEN a file as `predvs track` writes it (t,point,u,v, integer ids 0..N-1, empty cells when a
  // dot is lost, no truth), its ids out of order within a frame
  std::ostringstream csv;
  csv << "t,point,u,v\n";
  for (int i = 0; i < 20; ++i)
    for (int p : {4, 0, 3, 1, 2}) {
      const double t = 0.04 * i;
      csv << num(t) << "," << p << ",";
      if (p == 3 && i > 10)
        csv << ",\n";  // lost
      else
        csv << num(50.0 * p + 10 * t) << "," << num(20.0 + p - 5 * t) << "\n";
    }
  const std::string out = path("out");
  const CliRun r = predict(write("tracks.csv", csv.str()), out, "hold,kf-cv");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = readJson(out + "/summary.json");
  // THEN the five points are sorted by id, the lost one is scored on its measured frames only
  EXPECT_EQ(j["points"], nlohmann::json({"0", "1", "2", "3", "4"}));
  EXPECT_EQ(j["predictors"][1]["name"], "kf-cv");
  EXPECT_TRUE(j["predictors"][1]["vs_truth"].is_null());
  EXPECT_EQ(j["predictors"][1]["per_point"][3]["vs_measurement"]["n"].get<int>(), 9);   // frames 0..8 + 2 ahead <= 10
  EXPECT_EQ(j["predictors"][1]["per_point"][0]["vs_measurement"]["n"].get<int>(), 18);  // 20 - 2
  // AND a noise-free line is predicted exactly by kf-cv once it has its velocity
  EXPECT_LT(j["predictors"][1]["per_point"][0]["vs_measurement"]["rmse_px"].get<double>(), 1.0);
  // AND names work as ids too, in order of first appearance
  const predvs::FeatureTrack named =
      predvs::readFeatureTrack(write("named.csv", "t,point,u,v\n0,left,1,2\n0,right,3,4\n0.1,right,5,6\n"));
  EXPECT_EQ(named.point_names, (std::vector<std::string>{"left", "right"}));
  EXPECT_TRUE(std::isnan(named.u_px[0][1]));
  EXPECT_EQ(named.u_px[1][1], 5.0);
}

TEST_F(PredictTracksTest, PredictorCommaList) {
  const std::string in = write("long.csv", longCsv()), out = path("out");
  const CliRun r = predict(in, out, "hold,kf-cv,stkf");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto j = readJson(out + "/summary.json");
  ASSERT_EQ(j["predictors"].size(), 3u);
  EXPECT_EQ(j["predictors"][2]["name"], "stkf");
  const std::string none = path("none");
  expectError(predict(in, none, "kf-cv,nope"), "--predictor: unknown predictor 'nope'", none);
  expectError(predict(in, none, "kf-cv,kf-cv"), "--predictor: 'kf-cv' is listed twice", none);
  expectError(predict(in, none, "all,kf-cv"), "--predictor: 'all' stands alone", none);
  expectError(predict(in, none, ","), "--predictor: an empty element in ','", none);
  expectError(predict(in, none, "kf-cv,"), "--predictor: an empty element in 'kf-cv,'", none);
}

/// The u_pred column of `name` in predictions.csv (its text per row).
std::vector<std::string> predColumn(const std::string& csv_path, const std::string& name) {
  std::istringstream in(slurp(csv_path));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) header.push_back(cell);
  const auto it = std::find(header.begin(), header.end(), name + ".u_pred");
  EXPECT_NE(it, header.end()) << name << " not in " << line;
  const auto col = static_cast<size_t>(it - header.begin());
  std::vector<std::string> out;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');) cells.push_back(cell);
    out.push_back(col < cells.size() ? cells[col] : "");
  }
  return out;
}

TEST_F(PredictTracksTest, OnePredictorUnderTwoLabelsWithItsOwnParameters) {
  // GIVEN kf-cv twice, once as itself and once labelled with r = 9 (compare's [LABEL=]TYPE:KEY=VALUE),
  // and imm as itself and labelled, with a --param addressed to a label and a --params file naming
  // imm (a file names registry predictors: it sets the entry shown as imm, not the labelled one)
  const std::string in = write("long.csv", longCsv()), out = path("out"), ref = path("ref");
  const std::string file = write("p.yaml", "predictors:\n  - name: imm\n    params: {q_cv: 300}\n");
  const CliRun r = predict(in, out, "kf-cv,kf-cv-r9=kf-cv:r=9,imm,imm-cp1=imm:coast_cp=1",
                           {"--param", "kf-cv-r9.q=3000", "--params", file});
  ASSERT_EQ(r.code, 0) << r.err;
  // THEN each label is a predictor of its own in every output, the labelled ones naming their type
  const auto j = readJson(out + "/summary.json");
  ASSERT_EQ(j["predictors"].size(), 4u);
  EXPECT_EQ(j["predictors"][0]["name"], "kf-cv");
  EXPECT_FALSE(j["predictors"][0].contains("type"));
  EXPECT_EQ(j["predictors"][1]["name"], "kf-cv-r9");
  EXPECT_EQ(j["predictors"][1]["type"], "kf-cv");
  EXPECT_EQ(j["predictors"][1]["params"]["r"], 9.0);
  EXPECT_EQ(j["predictors"][1]["params"]["q"], 3000.0);
  EXPECT_EQ(j["predictors"][2]["name"], "imm");
  EXPECT_EQ(j["predictors"][2]["params"]["q_cv"], 300.0);
  EXPECT_EQ(j["predictors"][3]["type"], "imm");
  EXPECT_EQ(j["predictors"][3]["params"]["coast_cp"], 1.0);
  EXPECT_FALSE(j["predictors"][3]["params"].contains("q_cv"));
  EXPECT_NE(r.out.find("kf-cv-r9"), std::string::npos) << r.out;
  // AND a labelled entry predicts exactly as its type run alone with those parameters
  ASSERT_EQ(predict(in, ref, "kf-cv", {"--param", "r=9", "--param", "q=3000"}).code, 0);
  EXPECT_EQ(predColumn(out + "/predictions.csv", "kf-cv-r9"), predColumn(ref + "/predictions.csv", "kf-cv"));
  EXPECT_NE(predColumn(out + "/predictions.csv", "kf-cv-r9"), predColumn(out + "/predictions.csv", "kf-cv"));
  // AND what cannot be run is refused, naming the element, with no output directory
  const std::string none = path("none");
  expectError(predict(in, none, "kf-cv,kf-cv=kf-cv:r=2"), "--predictor: 'kf-cv' is listed twice", none);
  expectError(predict(in, none, "kf-cv,x=nope"), "--predictor 'x=nope': unknown predictor 'nope'", none);
  expectError(predict(in, none, "kf-cv,a b=kf-cv"), "predictor label 'a b'", none);
  expectError(predict(in, none, "kf-cv,k2=kf-cv:r"), "expected KEY=VALUE after ':'", none);
  expectError(predict(in, none, "kf-cv,k2=kf-cv:nokey=1"), "nokey", none);
  expectError(predict(in, none, "kf-cv,k2=kf-cv", {"--param", "stkf.r=2"}), "'stkf' is not being run", none);
}

TEST_F(PredictTracksTest, ErrorsAreFileLineOneLiners) {
  const std::string out = path("out");
  auto bad = [&](const std::string& name, const std::string& text, const std::string& needle) {
    expectError(predict(write(name, text), out), needle, out);
  };
  // bad cells
  bad("a.csv", "t,point,u,v\n0,0,1,2\n0,1,x,2\n", "a.csv:3: column 'u': expected a number, got 'x'");
  bad("b.csv", "t,u0,v0,u1,v1\n0,1,2,3,4\n0.04,1,2,3,inf\n", "b.csv:3: column 'v1': expected a finite number");
  bad("c.csv", "t,point,u,v\n0,,1,2\n", "c.csv:2: column 'point': expected a point id");
  // inconsistent point sets
  bad("d.csv", "t,u0,v0,u1\n0,1,2,3\n", "d.csv:1: missing required column 'v1' (given 'u1')");
  bad("e.csv", "t,u0,v0,u2,v2\n0,1,2,3,4\n", "e.csv:1: point indices must run 0..1 without a gap");
  bad("f.csv", "t,u,v,u0,v0\n0,1,2,3,4\n", "f.csv:1: both the single-point columns");
  bad("g.csv", "t,u0,v0,u1_true,v1_true\n0,1,2,3,4\n", "g.csv:1: column 'u1_true' has no measured point");
  bad("h.csv", "t,u0,v0,u0_true\n0,1,2,3\n", "h.csv:1: columns 'u0_true' and 'v0_true' must be given together");
  bad("i.csv", "t,point,u,v\n0,0,1,2\n0,0,1,2\n", "i.csv:3: column 'point': point '0' appears twice in the frame");
  bad("j.csv", "t,point,u,v\n0,0,1,2\n0.04,0,1,2\n0,1,1,2\n", "j.csv:4: column 't': expected the rows of a frame together");
  // a repeated column is still an error, even an extra one
  bad("k.csv", "t,u,v,x,x\n0,1,2,3,4\n", "k.csv:1: column 'x' appears twice");
  bad("l.csv", "t,point,u\n0,0,1\n", "l.csv:1: missing required column 'v'");
}

// The lost-feature policy's key, checked where the scenario is read (file:line).
TEST_F(PredictTracksTest, LostKeyIsValidatedWithItsLine) {
  using predvs::loadScenario;
  using predvs::parseScenarioOverride;
  using predvs::resolveScenario;
  const std::string e8 = resolveScenario("e8-vtc"), e7 = resolveScenario("e7-occlusion");
  auto message = [](const std::string& file, const std::string& set) {
    try {
      loadScenario(file, {parseScenarioOverride(set)});
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  // the tracking law needs all four corners: drop is refused, naming the key
  EXPECT_NE(message(e8, "lost.action=drop").find("lost.action: 'drop' needs a law"), std::string::npos);
  // the open loop has no task to drop from
  EXPECT_NE(message(e7, "lost.action=drop").find("'drop' needs a closed loop"), std::string::npos);
  EXPECT_NE(message(e7, "lost.action=freeze").find("lost.action must be 'hold', 'drop' or 'extrapolate'"),
            std::string::npos);
  EXPECT_NE(message(e7, "lost.timeout_s=0").find("timeout_s"), std::string::npos);
  // and the values are read
  const auto sc = loadScenario(e7, {parseScenarioOverride("lost.timeout_s=0.5"), parseScenarioOverride("lost.action=extrapolate")});
  EXPECT_EQ(sc.open_loop.lost.timeout_s, 0.5);
  EXPECT_EQ(sc.open_loop.lost.action, predvs::LostAction::Extrapolate);
}

}  // namespace
