// CLI tests of `predvs`, run in-process through runCli(): every bad input gives exit status 2,
// exactly one "predvs: error:" line naming the file:line, key or option, and no output directory;
// the happy paths write every promised file.
#include "cli.h"
#include "cli_test_utils.h"
#include "output_dir.h"
#include "scenario.h"
#include "scenario_file.h"
#include "track_csv.h"

#include "predvs/predictors/predictor.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <sys/stat.h>

namespace fs = std::filesystem;
using namespace predvs::apptest;  // run(), CliRun, slurp(), ScratchDirTest (cli_test_utils.h)

namespace {

class CliTest : public ScratchDirTest {
 protected:
  CliTest() : ScratchDirTest("predvs_app_test") {}

  /// A target on a constant-velocity line (u = 100 + 30 t, v = 50 - 20 t), T = 0.04 s, seeded
  /// Gaussian noise of 0.5 px, with a dropped frame every 13th row and the truth columns.
  std::string lineTrack(int rows = 100) const {
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, 0.5);
    std::ostringstream csv;
    csv << "t,u,v,u_true,v_true\n";
    for (int i = 0; i < rows; ++i) {
      const double t = 0.04 * i, u = 100 + 30 * t, v = 50 - 20 * t;
      if (i % 13 == 7)
        csv << t << ",,," << u << "," << v << "\n";
      else
        csv << t << "," << u + noise(rng) << "," << v + noise(rng) << "," << u << "," << v << "\n";
    }
    return write("track.csv", csv.str());
  }
  std::vector<std::string> predictArgs(const std::string& input, const std::string& out) const {
    return {"predict", "--input", input, "--predictor", "kf-cv", "--delay-frames", "2", "--out", out, "--no-plots"};
  }
  /// A short closed-loop scenario (1 s) for the happy path.
  std::string shortClosedLoop(const std::string& extra = "") const {
    return write("short.yaml",
                 "description: short closed loop for the tests\n"
                 "kind: closed-loop\n"
                 "seed: 5\n"
                 "duration_s: 1.0\n"
                 "timing: {base_period_s: 0.04, frame_period_n: 1, delay_frames: 2}\n"
                 "noise: {model: gaussian, sigma: 0.5}\n"
                 "predictors: [hold, kf-cv]\n" +
                     extra);
  }
};

// --------------------------------------------------------------------------------------------
// predict: bad inputs

TEST_F(CliTest, PredictRejectsMissingFile) {
  // GIVEN no input file WHEN predicting THEN the error names the file
  const std::string out = path("out");
  expectError(run(predictArgs(path("nope.csv"), out)), "nope.csv: cannot open", out);
}

TEST_F(CliTest, PredictRejectsEmptyFile) {
  const std::string out = path("out");
  expectError(run(predictArgs(write("empty.csv", ""), out)), "empty.csv: the file is empty", out);
}

TEST_F(CliTest, PredictRejectsHeaderOnly) {
  const std::string out = path("out");
  expectError(run(predictArgs(write("h.csv", "t,u,v\n"), out)), "h.csv:1: no data rows", out);
}

TEST_F(CliTest, PredictIgnoresAnUnknownColumnButNeedsItsPoints) {
  // An unknown column is ignored (issue 9: spreadsheets add columns), so t,u,w lacks v
  const std::string out = path("out");
  expectError(run(predictArgs(write("c.csv", "t,u,w\n0,1,2\n"), out)), "c.csv:1: missing required column 'v'", out);
  expectError(run(predictArgs(write("d.csv", "t,w\n0,1\n"), out)), "d.csv:1: no point columns", out);
}

TEST_F(CliTest, PredictRejectsMissingColumn) {
  const std::string out = path("out");
  expectError(run(predictArgs(write("c.csv", "t,u\n0,1\n"), out)), "c.csv:1: missing required column 'v'", out);
}

TEST_F(CliTest, PredictRejectsNonNumericCell) {
  const std::string out = path("out");
  expectError(run(predictArgs(write("c.csv", "t,u,v\n0,1,2\n0.04,abc,2\n"), out)),
              "c.csv:3: column 'u': expected a number, got 'abc'", out);
}

TEST_F(CliTest, PredictRejectsNonFiniteCells) {
  const std::string out = path("out");
  expectError(run(predictArgs(write("c.csv", "t,u,v\n0,1,2\n0.04,1,inf\n"), out)),
              "c.csv:3: column 'v': expected a finite number, got 'inf'", out);
  expectError(run(predictArgs(write("d.csv", "t,u,v\n0,nan,2\n"), out)), "d.csv:2: column 'u': expected a finite", out);
}

TEST_F(CliTest, PredictRejectsNonIncreasingTime) {
  const std::string out = path("out");
  expectError(run(predictArgs(write("c.csv", "t,u,v\n0,1,2\n0.04,1,2\n0.04,1,2\n"), out)),
              "c.csv:4: column 't': expected a time after the previous row's", out);
}

TEST_F(CliTest, PredictRejectsEmptyTimeAndWrongCellCount) {
  const std::string out = path("out");
  expectError(run(predictArgs(write("c.csv", "t,u,v\n0,1,2\n,1,2\n"), out)), "c.csv:3: column 't'", out);
  expectError(run(predictArgs(write("d.csv", "t,u,v\n0,1,2\n0.04,1\n"), out)), "d.csv:3: expected 3 cells, got 2", out);
}

TEST_F(CliTest, PredictRejectsUnknownPredictor) {
  const std::string out = path("out");
  auto args = predictArgs(lineTrack(), out);
  args[4] = "nope";
  expectError(run(args), "--predictor: unknown predictor 'nope'", out);
}

TEST_F(CliTest, PredictRejectsBadHorizon) {
  const std::string out = path("out"), in = lineTrack();
  const std::vector<std::string> base = {"predict", "--input", in, "--predictor", "kf-cv", "--out", out, "--no-plots"};
  auto with = [&](const std::vector<std::string>& extra) { return run(base, extra); };
  expectError(with({"--horizon-s", "abc"}), "--horizon-s: expected a number, got 'abc'", out);
  expectError(with({"--horizon-s", "nan"}), "--horizon-s: expected a finite number", out);
  expectError(with({"--horizon-s", "-0.1"}), "--horizon-s: expected a number >= 0", out);
  expectError(with({"--delay-frames", "1.5"}), "--delay-frames: expected an integer", out);
  expectError(with({}), "expected exactly one of them", out);
  expectError(with({"--horizon-s", "0.1", "--delay-frames", "2"}), "--horizon-s", out);
}

TEST_F(CliTest, PredictRejectsBadParams) {
  const std::string out = path("out"), in = lineTrack();
  auto with = [&](const std::string& predictor, const std::string& param) {
    return run({"predict", "--input", in, "--predictor", predictor, "--horizon-s", "0.08", "--out", out,
                "--no-plots", "--param", param});
  };
  expectError(with("kf-cv", "q"), "--param: expected [PREDICTOR.]KEY=VALUE, got 'q'", out);
  expectError(with("kf-cv", "q=abc"), "--param: parameter 'q' expects a number or 'auto', got 'abc'", out);
  expectError(with("kf-cv", "q=1x"), "--param q: expected a number, got '1x'", out);
  expectError(with("kf-cv", "zz=1"), "unknown parameter 'zz'", out);
  expectError(with("kf-cv", "q=-5"), "'q'", out);
  expectError(with("all", "q=5"), "with --predictor all or several predictors, scope each parameter", out);
  expectError(with("kf-cv,stkf", "q=5"), "scope each parameter", out);
  expectError(with("all", "nope.q=5"), "unknown predictor 'nope'", out);
}

TEST_F(CliTest, RejectsUnknownOptionAndMissingRequired) {
  const std::string out = path("out");
  expectError(run({"predict", "--input", lineTrack(), "--predictor", "kf-cv", "--horizon-s", "0.1", "--out", out,
                   "--bogus"}),
              "--bogus", out);
  expectError(run({"predict", "--predictor", "kf-cv", "--horizon-s", "0.1", "--out", out}), "--input", out);
  expectError(run({}), "subcommand", out);
  expectError(run({"frobnicate"}), "frobnicate", out);
}

TEST_F(CliTest, FailureKeepsAnExistingGoodDirectory) {
  // GIVEN a previous good output directory WHEN a run fails THEN it is untouched
  const std::string out = path("out");
  ASSERT_EQ(run(predictArgs(lineTrack(), out)).code, 0);
  const std::string before = slurp(out + "/predictions.csv");
  const CliRun r = run(predictArgs(write("c.csv", "t,u,v\n0,1,x\n"), out));
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(slurp(out + "/predictions.csv"), before);
}

// The rules of StagedOutputDir::checkReplaceable (app/output_dir.h): only what predvs wrote is
// replaced, never a directory that holds the run's input or the working directory.
TEST_F(CliTest, RefusesToReplaceADirectoryItDidNotWrite) {
  const std::string out = path("mine");
  fs::create_directories(out);
  std::ofstream(out + "/notes.txt") << "the user's\n";
  const CliRun r = run(predictArgs(lineTrack(), out));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--out: '" + out + "' is a directory predvs did not write (no .predvs-output in it)"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(slurp(out + "/notes.txt"), "the user's\n");
  EXPECT_FALSE(fs::exists(out + "/predictions.csv"));
  // AND an empty directory is taken
  fs::create_directories(path("empty"));
  EXPECT_EQ(run(predictArgs(lineTrack(), path("empty"))).code, 0);
  EXPECT_TRUE(fs::exists(path("empty") + "/.predvs-output"));
}

TEST_F(CliTest, RefusesAnOutThatHoldsTheInput) {
  // GIVEN an output directory of predvs's that the user put a track in
  const std::string out = path("out");
  ASSERT_EQ(run(predictArgs(lineTrack(), out)).code, 0);
  fs::copy_file(lineTrack(), out + "/track.csv");
  // WHEN it is both the input's directory and --out THEN the run is refused before it starts
  const CliRun r = run(predictArgs(out + "/track.csv", out));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("holds the input '" + out + "/track.csv'"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(out + "/track.csv"));
  // AND merge may not write over one of its shards
  const CliRun m = run({"merge", "--out", out, out});
  EXPECT_EQ(m.code, 2);
  EXPECT_NE(m.err.find("holds the input '" + out + "'"), std::string::npos) << m.err;
  EXPECT_TRUE(fs::exists(out + "/track.csv"));
}

TEST_F(CliTest, RefusesAnOutThatHoldsTheWorkingDirectory) {
  const std::string out = path("out");
  ASSERT_EQ(run(predictArgs(lineTrack(), out)).code, 0);
  fs::create_directories(out + "/sub");
  const fs::path cwd = fs::current_path();
  fs::current_path(out + "/sub");
  const CliRun r = run(predictArgs(path("track.csv"), out));
  fs::current_path(cwd);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("holds the working directory"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_directory(out + "/sub"));
}

TEST_F(CliTest, OutThroughALinkReplacesTheDirectoryItNames) {
  const std::string real = path("real"), link = path("link");
  ASSERT_EQ(run(predictArgs(lineTrack(), real)).code, 0);
  fs::create_directory_symlink(real, link);
  ASSERT_EQ(run(predictArgs(lineTrack(), link)).code, 0);
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_TRUE(fs::exists(real + "/predictions.csv"));
}

TEST_F(CliTest, MakeTrackWritesThroughALinkAndRefusesAPipe) {
  // GIVEN a link to a file WHEN make-track writes to the link THEN the file it names holds the track
  const std::string real = write("real.csv", "old\n"), link = path("link.csv");
  fs::create_symlink(real, link);
  ASSERT_EQ(run({"make-track", "--duration-s", "1", "--out", link}).code, 0);
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(slurp(real).rfind("t,u,v,u_true,v_true\n", 0), 0u);
  // AND a pipe (like a device) is refused and left as it is, not replaced by a file
  const std::string fifo = path("fifo.csv");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const CliRun r = run({"make-track", "--duration-s", "1", "--out", fifo});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--out: '" + fifo + "' exists and is not a regular file"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_fifo(fifo));
}

TEST_F(CliTest, FailureBeforeStagingCreatesNoParents) {
  const std::string out = path("a/b/out");
  const CliRun r = run(predictArgs(write("one.csv", "t,u,v\n0,1,2\n"), out));
  expectError(r, "one.csv: --delay-frames needs at least two data rows", out);
  EXPECT_FALSE(fs::exists(path("a")));
}

TEST_F(CliTest, StagedDirectoryIsRemovedWithTheParentsItCreated) {
  // GIVEN a staged output under missing parents WHEN an error unwinds before commit()
  const std::string out = path("a/b/out");
  try {
    predvs::StagedOutputDir dir(out);
    std::ofstream(dir.file("partial.csv")) << "t\n";
    EXPECT_TRUE(fs::exists(dir.staging()));
    throw std::runtime_error("simulated failure in the middle of writing");
  } catch (const std::runtime_error&) {
  }
  // THEN neither the staging directory nor the parents it created remain
  EXPECT_FALSE(fs::exists(path("a")));
  // AND a committed one appears under the target name with its files
  {
    predvs::StagedOutputDir dir(out);
    std::ofstream(dir.file("done.csv")) << "t\n";
    dir.commit();
  }
  EXPECT_TRUE(fs::exists(out + "/done.csv"));
  for (const auto& e : fs::directory_iterator(path("a/b"))) EXPECT_EQ(e.path().filename(), "out");
}

TEST_F(CliTest, OutPathThatIsAFileIsAnError) {
  const std::string out = write("file.txt", "x");
  const CliRun r = run(predictArgs(lineTrack(), out));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("exists and is not a directory"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_regular_file(out));
}

TEST_F(CliTest, MissingGnuplotIsOneLineError) {
  // GIVEN no gnuplot on PATH WHEN plots are requested THEN one line naming gnuplot, exit 2
  const std::string out = path("out"), in = lineTrack();
  const char* old = std::getenv("PATH");
  const std::string saved = old ? old : "";
  ::setenv("PATH", "/nonexistent-predvs-test", 1);
  const CliRun r = run({"predict", "--input", in, "--predictor", "kf-cv", "--horizon-s", "0.1", "--out", out});
  ::setenv("PATH", saved.c_str(), 1);
  expectError(r, "gnuplot not found", out);
}

// --------------------------------------------------------------------------------------------
// predict: happy paths

TEST_F(CliTest, PredictWritesPredictionsAndSummary) {
  // GIVEN a noisy constant-velocity track WHEN kf-cv predicts 2 frames ahead (without the
  // coasting decay on the dropped frames, coast_tau_s = 0: the line is exactly constant-velocity
  // through them; with the default 0.2 s the error below is 0.79 px; and the blend with hold's one
  // weight, hold_blend_split = 0: on this 4 s track the two weights are still fitting the filter's
  // start-up, 0.72 px; and without the blend's start-up prior, hold_blend_prior = 0: with it the first
  // forecasts of the track are hold's, 0.83 px)
  const std::string out = path("out");
  const CliRun r = run({"predict", "--input", lineTrack(), "--predictor", "kf-cv", "--delay-frames", "2", "--out", out,
                        "--param", "q=50", "--param", "coast_tau_s=0", "--param", "hold_blend_split=0",
                        "--param", "hold_blend_prior=0"});
  ASSERT_EQ(r.code, 0) << r.err;
  // THEN every file is there and the summary holds one entry with the documented horizon
  for (const char* f : {"predictions.csv", "summary.json", "predictions.png", "predictions.gp"})
    EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
  EXPECT_GT(fs::file_size(out + "/predictions.png"), 1000u);
  std::ifstream js(out + "/summary.json");
  const auto j = nlohmann::json::parse(js);
  constexpr double kTimeTol = 1e-9;  // sums of 0.04 s steps in binary floating point
  EXPECT_NEAR(j["horizon_s"].get<double>(), 0.08, kTimeTol);
  EXPECT_EQ(j["delay_frames"].get<int>(), 2);
  // the frame period the horizon was measured with (medianPeriod, once per run)
  EXPECT_NEAR(j["frame_period_s"].get<double>(), 0.04, kTimeTol);
  ASSERT_EQ(j["predictors"].size(), 1u);
  EXPECT_EQ(j["predictors"][0]["name"], "kf-cv");
  EXPECT_EQ(j["predictors"][0]["params"]["q"].get<double>(), 50.0);
  EXPECT_EQ(j["predictors"][0]["params"]["hold_blend_split"].get<double>(), 0.0);
  // Predictions start at row 0 and are scored wherever t + 0.08 s has a measurement (98 rows
  // minus the dropped frames that fall exactly there).
  EXPECT_GT(j["predictors"][0]["vs_measurement"]["n"].get<int>(), 80);
  // On a constant-velocity target the KF forecast beats the raw noise level (sigma 0.5 px per
  // axis, i.e. 0.71 px as a 2D RMS) against the truth.
  EXPECT_LT(j["predictors"][0]["vs_truth"]["rmse_px"].get<double>(), 0.71);
  std::ifstream csv(out + "/predictions.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "t,u,v,t_target,kf-cv.u_pred,kf-cv.v_pred");
  int rows = 0;
  for (std::string line; std::getline(csv, line);) ++rows;
  EXPECT_EQ(rows, 100);
  EXPECT_NE(r.out.find("kf-cv"), std::string::npos);
}

TEST_F(CliTest, PredictAllComparesEveryPredictor) {
  const std::string out = path("out");
  const CliRun r = run({"predict", "--input", lineTrack(), "--predictor", "all", "--horizon-s", "0.08", "--out", out,
                        "--no-plots", "--param", "kf-cv.q=20"});
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream js(out + "/summary.json");
  const auto j = nlohmann::json::parse(js);
  const auto& reg = predvs::predictorRegistry();
  ASSERT_EQ(j["predictors"].size(), reg.size());
  // --horizon-s: no frame period was needed for the horizon; the summary measures it itself
  EXPECT_NEAR(j["frame_period_s"].get<double>(), 0.04, 1e-9);
  EXPECT_TRUE(j["delay_frames"].is_null());
  double hold = NAN, kfcv = NAN;
  for (size_t i = 0; i < reg.size(); ++i) {
    EXPECT_EQ(j["predictors"][i]["name"], reg[i].name);
    EXPECT_NE(r.out.find(reg[i].name), std::string::npos) << "table misses " << reg[i].name;
    if (reg[i].name == "hold") hold = j["predictors"][i]["vs_truth"]["rmse_px"].get<double>();
    if (reg[i].name == "kf-cv") kfcv = j["predictors"][i]["vs_truth"]["rmse_px"].get<double>();
  }
  // The target moves 36 px/s, so holding the last frame for 0.08 s is ~2.9 px behind: the CV
  // filter must do clearly better (a regression check that the horizon is really applied).
  EXPECT_GT(hold, 2.0);
  EXPECT_LT(kfcv, 1.0);
  EXPECT_FALSE(fs::exists(out + "/predictions.png"));
}

TEST_F(CliTest, ADirectoryWhereAFileIsExpectedIsNamed) {
  const std::string dir = path("dir"), out = path("out"), track = lineTrack();
  fs::create_directories(dir);
  const std::vector<std::vector<std::string>> commands = {
      {"predict", "--input", dir, "--predictor", "hold", "--delay-frames", "1", "--out", out},
      {"predict", "--input", track, "--predictor", "hold", "--delay-frames", "1", "--params", dir, "--out", out},
      {"servo", "--scenario", dir + "/", "--out", out},
      {"servo", "--set-file", dir, "--out", out},
      {"servo", "--camera", dir, "--out", out},
      {"calibrate", "latency", "--log", dir, "--out", out}};
  for (const auto& c : commands) {
    const CliRun r = run(c);
    EXPECT_EQ(r.code, 2) << c[0] << " " << c[1];
    EXPECT_NE(r.err.find(dir), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("is a directory, expected a"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
}

TEST_F(CliTest, NothingToScoreIsAnError) {
  // predict: a horizon past the track's end
  const CliRun p = run({"predict", "--input", lineTrack(20), "--predictor", "kf-cv", "--delay-frames", "25", "--no-plots",
                        "--out", path("out")});
  EXPECT_EQ(p.code, 2);
  EXPECT_NE(p.err.find("no prediction 1 s ahead can be scored on its 20 rows"), std::string::npos) << p.err;
  EXPECT_FALSE(fs::exists(path("out")));
  // track-study: a track shorter than the horizon, and one that hold predicts exactly
  const std::vector<std::string> one = {"track-study", "--kinds", "turns", "--rates", "30", "--seeds", "1",
                                        "--predictors", "hold,kf-cv"};
  auto with = [&](const std::vector<std::string>& extra) { return run(one, extra); };
  const CliRun s = with({"--noise", "1", "--duration-s", "0.05"});
  EXPECT_EQ(s.code, 2);
  EXPECT_NE(s.err.find("track turns 30 Hz 1 px #1: no prediction 2 frames ahead is scored"), std::string::npos) << s.err;
  const CliRun z = with({"--noise", "0", "--drop", "0", "--delay-frames", "0"});
  EXPECT_EQ(z.code, 2);
  EXPECT_NE(z.err.find("hold predicts the truth exactly"), std::string::npos) << z.err;
}

TEST_F(CliTest, ALabelMayNotBeAnotherPredictorsName) {
  // `hold=kf-cv` would print kf-cv's figures as hold's, and "vs hold" against them
  const std::string out = path("out");
  expectError(run({"servo", "--scenario", shortClosedLoop(), "--predictors", "hold=kf-cv,kf-ca", "--no-plots", "--out", out}),
              "--predictors 'hold=kf-cv': predictor label 'hold' is the name of another predictor", out);
  expectError(run({"predict", "--input", lineTrack(), "--predictor", "kf-cv=hold", "--delay-frames", "1", "--out", out}),
              "predictor label 'kf-cv' is the name of another predictor", out);
  expectError(run({"servo", "--scenario", write("l.yaml", "kind: closed-loop\npredictors: [hold, {name: kf-ca, type: kf-cv}]\n"),
                   "--out", out}),
              "l.yaml:2: 'predictors': predictor label 'kf-ca' is the name of another predictor", out);
  // AND a predictor labelled with its own name is that predictor
  EXPECT_EQ(run({"predict", "--input", lineTrack(), "--predictor", "kf-cv=kf-cv:r=3", "--delay-frames", "1", "--no-plots",
                 "--out", out})
                .code,
            0);
}

TEST_F(CliTest, AMisspelledOptionOrSubcommandIsNamed) {
  // CLI11 reports a missing required option first: "--input is required" for a misspelt --input
  const CliRun r = run({"predict", "--inptu", lineTrack(), "--predictor", "hold", "--delay-frames", "1", "--out", path("o")});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("unknown option '--inptu'"), std::string::npos) << r.err;
  const CliRun c = run({"calibrate", "bogus"});
  EXPECT_EQ(c.code, 2);
  EXPECT_NE(c.err.find("unknown subcommand 'bogus' of calibrate (expected camera, latency)"), std::string::npos) << c.err;
  // AND a required option really missing is still named as such
  const CliRun m = run({"predict", "--predictor", "hold", "--delay-frames", "1", "--out", path("o")});
  EXPECT_NE(m.err.find("--input is required"), std::string::npos) << m.err;
}

TEST_F(CliTest, AParameterFileOfPredvsIsGivenByName) {
  // data/params/pre-issue-11.yaml, found in the data directory wherever predvs is installed
  const CliRun r = run({"predict", "--input", lineTrack(), "--predictor", "kf-ca", "--delay-frames", "1", "--params",
                        "pre-issue-11", "--no-plots", "--out", path("out")});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(slurp(path("out") + "/summary.json").find("\"shrink_sigmas\""), std::string::npos);
  expectError(run({"predict", "--input", lineTrack(), "--predictor", "kf-cv", "--delay-frames", "1", "--params", "nope",
                   "--out", path("o2")}),
              "nope: cannot open the parameter file", path("o2"));
}

TEST_F(CliTest, SuccessfulRunReplacesPreviousDirectory) {
  // GIVEN a directory an earlier run wrote, with a file added since
  const std::string out = path("out");
  ASSERT_EQ(run(predictArgs(lineTrack(), out)).code, 0);
  std::ofstream(out + "/stale.txt") << "old\n";
  // WHEN a run succeeds into it THEN it holds that run's files only
  ASSERT_EQ(run(predictArgs(lineTrack(), out)).code, 0);
  EXPECT_FALSE(fs::exists(out + "/stale.txt"));
  EXPECT_TRUE(fs::exists(out + "/predictions.csv"));
}

// --------------------------------------------------------------------------------------------
// servo / scenarios: bad inputs

TEST_F(CliTest, ServoRejectsUnknownScenario) {
  const std::string out = path("out");
  expectError(run({"servo", "--scenario", "no-such-scenario", "--out", out}),
              "--scenario: unknown scenario 'no-such-scenario'", out);
  expectError(run({"servo", "--scenario", path("missing.yaml"), "--out", out}), "--scenario: no such file", out);
}

TEST_F(CliTest, ServoRejectsYamlSyntaxError) {
  const std::string out = path("out");
  const std::string f = write("bad.yaml", "kind: closed-loop\npredictors: [hold\nseed: 1\n");
  expectError(run({"servo", "--scenario", f, "--out", out}), "bad.yaml:", out);
}

TEST_F(CliTest, ServoRejectsUnknownKeysWithTheirLine) {
  const std::string out = path("out");
  // top level (line 8, after the 7 lines of the short scenario)
  expectError(run({"servo", "--scenario", shortClosedLoop("colour: blue\n"), "--out", out}),
              "short.yaml:8: unknown key 'colour'", out);
  // nested
  expectError(run({"servo", "--scenario", shortClosedLoop("task:\n  lambda: 1\n  gain_typo: 2\n"), "--out", out}),
              "short.yaml:10: unknown parameter 'gain_typo' for task 'ibvs'", out);
  // a trajectory parameter (checked by the servo layer, located by the app)
  expectError(run({"servo", "--scenario",
                   shortClosedLoop("target:\n  trajectory:\n    type: circle\n    radius: 0.05\n    radiuss: 1\n"), "--out",
                   out}),
              "short.yaml:12: unknown parameter 'radiuss'", out);
  // open-loop keys in a closed-loop file
  expectError(run({"servo", "--scenario", shortClosedLoop("trajectory: {type: line}\n"), "--out", out}),
              "short.yaml:8: unknown key 'trajectory' for a closed-loop scenario", out);
  // a task's own check of a value (its message names task.KEY, unquoted) points at that key's line
  expectError(run({"servo", "--scenario", shortClosedLoop("task:\n  interaction: current\n  lambda: -1\n"), "--out", out}),
              "short.yaml:10: task.lambda must be > 0", out);
  expectError(run({"servo", "--scenario", shortClosedLoop("task:\n  lambda: 1\n  interaction: bogus\n"), "--out", out}),
              "short.yaml:10: task.interaction must be", out);
}

TEST_F(CliTest, AKeyOrParameterGivenTwiceIsRefused) {
  // YAML leaves a key given twice to the reader; yaml-cpp would keep the first silently
  const std::string out = path("out");
  expectError(run({"servo", "--scenario", shortClosedLoop("duration_s: 3\n"), "--out", out}),
              "short.yaml:8: 'duration_s' given twice", out);
  expectError(run({"servo", "--scenario", shortClosedLoop("task: {lambda: 1, lambda: 2}\n"), "--out", out}),
              "short.yaml:8: 'task.lambda' given twice", out);
  // and on the command line
  const std::string t = lineTrack();
  expectError(run({"predict", "--input", t, "--predictor", "kf-cv", "--delay-frames", "1", "--param", "q=5", "--param",
                   "kf-cv.q=6", "--out", out}),
              "--param kf-cv.q: given twice", out);
  expectError(run({"track-study", "--predictors", "hold,kf-cv", "--param", "kf-cv.q=5", "--param", "kf-cv.q=6", "--out", out}),
              "--param kf-cv.q: given twice", out);
  expectError(run({"fit-noise", "--input", t, "--predictor", "kf-cv", "--param", "r=1", "--param", "r=2", "--out", out}),
              "--param r: given twice", out);
}

TEST_F(CliTest, ServoRejectsBadValues) {
  const std::string out = path("out");
  const std::string f1 = write("a.yaml", "kind: closed-loop\nduration_s: abc\npredictors: [hold]\n");
  expectError(run({"servo", "--scenario", f1, "--out", out}), "a.yaml:2: 'duration_s': expected a number, got 'abc'", out);
  const std::string f2 = write("b.yaml", "kind: closed-loop\nduration_s: .inf\npredictors: [hold]\n");
  expectError(run({"servo", "--scenario", f2, "--out", out}), "b.yaml:2: 'duration_s': expected a finite number", out);
  const std::string f3 = write("c.yaml", "kind: closed-loop\npredictors: [hold, nope]\n");
  expectError(run({"servo", "--scenario", f3, "--out", out}), "c.yaml:2: unknown predictor 'nope'", out);
  const std::string f4 = write("d.yaml", "duration_s: 1\npredictors: [hold]\n");
  expectError(run({"servo", "--scenario", f4, "--out", out}), "d.yaml:1: missing required key 'kind'", out);
  const std::string f5 = write("e.yaml", "kind: sideways\npredictors: [hold]\n");
  expectError(run({"servo", "--scenario", f5, "--out", out}), "e.yaml:1: 'kind': expected open-loop or closed-loop", out);
  const std::string f6 =
      write("f.yaml", "kind: closed-loop\npredictors:\n  - name: kf-cv\n    params: {q: 1, qq: 2}\n");
  expectError(run({"servo", "--scenario", f6, "--out", out}), "f.yaml:4: unknown parameter 'qq'", out);
  const std::string f7 = write("g.yaml", "kind: closed-loop\ntiming: {frame_period_n: 0}\npredictors: [hold]\n");
  expectError(run({"servo", "--scenario", f7, "--out", out}), "g.yaml:2: 'timing.frame_period_n'", out);
}

TEST_F(CliTest, ServoRejectsBadArguments) {
  const std::string out = path("out"), f = shortClosedLoop();
  expectError(run({"servo", "--scenario", f, "--predictors", "hold,nope", "--out", out}),
              "--predictors: unknown predictor 'nope'", out);
  expectError(run({"servo", "--scenario", f, "--seed", "abc", "--out", out}), "--seed: expected an integer", out);
  expectError(run({"servo", "--scenario", f, "--seed", "-1", "--out", out}), "--seed: expected an integer", out);
}

// --------------------------------------------------------------------------------------------
// servo / scenarios: happy paths

TEST_F(CliTest, ServoShortClosedLoopWritesAllFiles) {
  // GIVEN a 1 s closed-loop scenario WHEN run with the seed overridden
  const std::string out = path("out");
  const CliRun r = run({"servo", "--scenario", shortClosedLoop(), "--seed", "9", "--out", out});
  ASSERT_EQ(r.code, 0) << r.err;
  // THEN log, summary and the plots exist (ibvs has no diagnostics: no diagnostics.png), and the
  // summary records what was run
  for (const char* f : {"log.csv", "summary.json", "error.png", "trajectories.png", "features.png", "command.png",
                        "error.gp", "trajectories.gp"})
    EXPECT_TRUE(fs::exists(out + "/" + f)) << f;
  EXPECT_FALSE(fs::exists(out + "/diagnostics.png"));
  EXPECT_GT(fs::file_size(out + "/error.png"), 1000u);
  EXPECT_GT(fs::file_size(out + "/trajectories.png"), 1000u);
  std::ifstream js(out + "/summary.json");
  const auto j = nlohmann::json::parse(js);
  EXPECT_EQ(j["scenario"], "short");
  EXPECT_EQ(j["seed"].get<int>(), 9);
  EXPECT_EQ(j["kind"], "closed-loop");
  EXPECT_NE(j["command"].get<std::string>().find("--seed 9"), std::string::npos);
  ASSERT_EQ(j["predictors"].size(), 2u);
  for (const auto& p : j["predictors"]) {
    EXPECT_TRUE(p["metrics"]["rmse"].is_number());
    EXPECT_TRUE(p["metrics"]["effort"].is_number());
  }
  // log.csv: header + one row per (predictor, tick); 1 s at 40 ms is 25 or 26 ticks.
  std::ifstream csv(out + "/log.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("predictor,t_s,", 0), 0u) << header;
  EXPECT_NE(header.find("error_px"), std::string::npos);
  EXPECT_NE(header.find("vx"), std::string::npos);
  int rows = 0;
  for (std::string line; std::getline(csv, line);) ++rows;
  const int steps = j["predictors"][0]["steps"].get<int>();
  EXPECT_GE(steps, 25);
  EXPECT_EQ(rows, steps + j["predictors"][1]["steps"].get<int>());
  // The table names every predictor, with hold in the run it has the factor against hold (1.0x
  // for hold itself); progress went to stderr.
  EXPECT_NE(r.out.find("kf-cv"), std::string::npos);
  EXPECT_NE(r.out.find("vs hold"), std::string::npos) << r.out;
  const size_t hold_row = r.out.find("\nhold ");
  ASSERT_NE(hold_row, std::string::npos) << r.out;
  const std::string row = r.out.substr(hold_row + 1, r.out.find('\n', hold_row + 1) - hold_row - 1);
  EXPECT_EQ(row.substr(row.size() - 4), "1.0x") << row;
  EXPECT_NE(r.err.find("[2/2]"), std::string::npos);
}

TEST_F(CliTest, ServoSameSeedIsReproducible) {
  const std::string f = shortClosedLoop();
  ASSERT_EQ(run({"servo", "--scenario", f, "--out", path("a"), "--no-plots"}).code, 0);
  ASSERT_EQ(run({"servo", "--scenario", f, "--out", path("b"), "--no-plots"}).code, 0);
  EXPECT_EQ(slurp(path("a/log.csv")), slurp(path("b/log.csv")));
  EXPECT_FALSE(fs::exists(path("a/error.png")));
}

TEST_F(CliTest, ServoRunsAnOpenLoopScenario) {
  const std::string out = path("out");
  const std::string f = write("open.yaml",
                              "kind: open-loop\nduration_s: 3\n"
                              "timing: {base_period_s: 0.1, delay_frames: 2}\n"
                              "trajectory: {type: line, vx: 10, vy: 10}\n"
                              "predictors: [hold, {name: kf-cv, params: {q: 10}}]\n");
  const CliRun r = run({"servo", "--scenario", f, "--out", out});
  ASSERT_EQ(r.code, 0) << r.err;
  for (const char* f2 : {"log.csv", "summary.json", "error.png", "trajectories.png"})
    EXPECT_TRUE(fs::exists(out + "/" + f2)) << f2;
  std::ifstream js(out + "/summary.json");
  const auto j = nlohmann::json::parse(js);
  EXPECT_EQ(j["kind"], "open-loop");
  EXPECT_EQ(j["predictors"][1]["params"]["q"].get<double>(), 10.0);
  EXPECT_TRUE(j["predictors"][0]["metrics"]["rmse"].is_number());
  EXPECT_FALSE(j["predictors"][0]["metrics"].contains("effort"));  // no command in open loop
}

TEST_F(CliTest, ListShowsPredictorsAndScenarios) {
  const CliRun r = run({"list"});
  ASSERT_EQ(r.code, 0) << r.err;
  for (const auto& p : predvs::predictorRegistry()) EXPECT_NE(r.out.find(p.name), std::string::npos) << p.name;
  for (const char* s : {"ibvs-moving-target", "e1-line", "e2-accel-jump", "e3-zigzag", "e4-circle"})
    EXPECT_NE(r.out.find(s), std::string::npos) << s;
  EXPECT_EQ(r.out.find("unreadable"), std::string::npos) << r.out;
}

TEST_F(CliTest, HelpOfEverySubcommandShowsItsOptions) {
  const CliRun p = run({"predict", "--help"});
  EXPECT_EQ(p.code, 0);
  for (const char* o : {"--input", "--predictor", "--horizon-s", "--delay-frames", "--out", "--param"})
    EXPECT_NE(p.out.find(o), std::string::npos) << o;
  const CliRun s = run({"servo", "--help"});
  EXPECT_EQ(s.code, 0);
  EXPECT_NE(s.out.find("ibvs-moving-target"), std::string::npos);  // the shown default
  EXPECT_NE(s.out.find("open-loop"), std::string::npos);
}

// --------------------------------------------------------------------------------------------
// scenario files

TEST(Scenarios, EveryScenarioFileParses) {
  // GIVEN every YAML in data/scenarios WHEN loaded THEN it validates, with predictors to compare
  int count = 0;
  for (const auto& e : fs::directory_iterator(predvs::scenariosDir())) {
    if (e.path().extension() != ".yaml") continue;
    ++count;
    SCOPED_TRACE(e.path().string());
    predvs::Scenario sc;
    ASSERT_NO_THROW(sc = predvs::loadScenario(e.path().string()));
    EXPECT_FALSE(sc.description.empty());
    EXPECT_FALSE(sc.predictors.empty());
  }
  EXPECT_GE(count, 5);
}

TEST(Scenarios, DefaultScenarioIsTheDocumentedOne) {
  const auto sc = predvs::loadScenario(predvs::resolveScenario("ibvs-moving-target"));
  EXPECT_EQ(sc.kind, predvs::ScenarioKind::ClosedLoop);
  std::vector<std::string> names;
  for (const auto& p : sc.predictors) names.push_back(p.name);
  EXPECT_EQ(names, (std::vector<std::string>{"hold", "kf-cv", "cs-akf-adaptive"}));
  // 2-frame vision delay: t_ac + t_p = 2 T.
  const predvs::TimingModel timing(sc.closed_loop.timing);
  EXPECT_NEAR(timing.visionLatency(), 2.0 * timing.framePeriod(), 1e-12);
}

TEST(Scenarios, OpenLoopExperimentsMatchMethods) {
  // E1-E4 set-ups of docs/MODELS.md §10 (paper 000 §6.1/6.2).
  const auto e4 = predvs::loadScenario(predvs::resolveScenario("e4-circle"));
  EXPECT_EQ(e4.kind, predvs::ScenarioKind::OpenLoop);
  EXPECT_EQ(e4.trajectory, "circle");
  EXPECT_EQ(e4.trajectory_params.values().at("radius"), 20.0);
  EXPECT_EQ(e4.trajectory_params.values().at("omega"), 0.15);
  const auto e2 = predvs::loadScenario(predvs::resolveScenario("e2-accel-jump"));
  EXPECT_EQ(e2.trajectory_params.values().at("t_jump"), 14.0);
  EXPECT_EQ(e2.trajectory_params.values().at("ax_jump"), 30.0);
}

// --------------------------------------------------------------------------------------------
// helpers

TEST(TrackCsv, InterpolationAndMedianPeriod) {
  constexpr double kTol = 1e-12;  // exact arithmetic up to rounding
  const std::vector<double> t = {0.0, 1.0, 2.0, 3.5};
  const std::vector<double> y = {0.0, 10.0, NAN, 40.0};
  EXPECT_NEAR(predvs::interpolateAt(t, y, 0.5), 5.0, kTol);
  EXPECT_NEAR(predvs::interpolateAt(t, y, 2.0), 22.0, kTol);  // skips the missing sample: 10 + 30 * 1 / 2.5
  EXPECT_TRUE(std::isnan(predvs::interpolateAt(t, y, 4.0)));   // no extrapolation
  EXPECT_NEAR(predvs::medianPeriod(t), 1.0, kTol);
  EXPECT_NEAR(predvs::medianPeriod({0.0, 0.1, 0.2, 0.5}), 0.1, kTol);
}

/// The median of the consecutive differences by sorting a copy (medianPeriod's general path).
double medianBySorting(const std::vector<double>& t) {
  std::vector<double> d;
  for (size_t i = 1; i < t.size(); ++i) d.push_back(t[i] - t[i - 1]);
  std::sort(d.begin(), d.end());
  const size_t mid = d.size() / 2;
  return d.size() % 2 == 1 ? d[mid] : 0.5 * (d[mid - 1] + d[mid]);
}

TEST(TrackCsv, MedianPeriodIsTheSameBitsWithFewOrManyDistinctPeriods) {
  // GIVEN times from a steady clock written with a few digits (few distinct differences, the
  // counted path), with dropped frames, and times with jitter (every difference distinct: the
  // sorted path), each with an odd and an even number of differences, and times with a repeat
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const double period : {1.0 / 30.0, 1.0 / 60.0, 0.1}) {
    for (const size_t rows : {2u, 3u, 1000u, 1001u, 20000u}) {
      for (const bool jitter : {false, true}) {
        std::vector<double> t;
        double clock = 12345.6;
        while (t.size() < rows) {
          clock += period * (unit(rng) < 0.05 ? 2.0 : 1.0) * (jitter ? 1.0 + 0.1 * (unit(rng) - 0.5) : 1.0);
          t.push_back(std::round(clock * 1e6) / 1e6);  // 6 decimals, as a CSV might hold them
        }
        // THEN the median is the one of the sorted differences, to the bit
        const double got = predvs::medianPeriod(t), want = medianBySorting(t);
        EXPECT_EQ(std::memcmp(&got, &want, sizeof got), 0)
            << "period " << period << " rows " << rows << " jitter " << jitter << ": " << got << " vs " << want;
      }
    }
  }
  const std::vector<double> repeat = {0.0, 0.1, 0.1, 0.2, 0.4};  // a zero difference: the sorted path
  EXPECT_EQ(predvs::medianPeriod(repeat), medianBySorting(repeat));
}

}  // namespace
