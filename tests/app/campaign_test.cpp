// Campaigns of `predvs compare` (app/campaign.h, issue #12): the same outputs, byte for byte,
// from one process, from mpirun with 2 and 3 ranks, from shards 1/3..3/3 merged, and from a
// campaign interrupted (--stop-after, the test hook) and resumed; stale records are not reused; a
// missing or duplicated shard is an error naming it; report.html loads in a headless Chromium.
#include "campaign.h"
#include "campaign_mpi.h"
#include "cli_test_utils.h"
#include "gnuplot.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <regex>
#include <string>
#include <vector>

namespace fs = std::filesystem;

using namespace predvs::apptest;  // run(), CliRun, slurp(), ScratchDirTest (cli_test_utils.h)

namespace {

/// Every regular file under `dir` (relative path -> bytes).
std::map<std::string, std::string> tree(const std::string& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[fs::relative(e.path(), dir).string()] = slurp(e.path().string());
  return files;
}

/// Expects the two output directories to hold the same files with the same bytes.
void expectSameOutputs(const std::string& a, const std::string& b) {
  const auto x = tree(a), y = tree(b);
  std::vector<std::string> nx, ny;
  for (const auto& kv : x) nx.push_back(kv.first);
  for (const auto& kv : y) ny.push_back(kv.first);
  ASSERT_EQ(nx, ny) << a << " vs " << b;
  for (const auto& kv : x) EXPECT_TRUE(kv.second == y.at(kv.first)) << kv.first << " differs: " << a << " vs " << b;
}

/// Runs a shell command; its exit status and its stdout+stderr.
std::pair<int, std::string> shell(const std::string& command) {
  std::string output;
  FILE* p = ::popen((command + " 2>&1").c_str(), "r");
  if (!p) return {-1, ""};
  char buf[4096];
  for (size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) output.append(buf, n);
  const int status = ::pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

bool onPath(const std::string& program) { return shell("command -v " + program + " >/dev/null").first == 0; }

std::string quoted(const std::string& s) { return "'" + s + "'"; }

class CampaignTest : public ScratchDirTest {
 protected:
  CampaignTest() : ScratchDirTest("predvs_campaign_test") {}
  void SetUp() override {
    ScratchDirTest::SetUp();
    // A 2 x 2 grid of a small positioning task, two predictors, 3 seeds: 24 runs (0.1 s).
    scenario_ = write("tiny.yaml",
                      "description: tiny positioning grid\nkind: closed-loop\nseed: 5\nruns: 3\nduration_s: 5\n"
                      "timing: {base_period_s: 0.01, frame_period_n: 1, delay_frames: 1}\n"
                      "noise: {model: gaussian, sigma: 0.5}\nmetrics: {outcome: true}\n"
                      "target: {square_side_m: 0.1, desired_depth_m: 0.5, trajectory: {type: static}}\n"
                      "initial_pose: [0, 0, 0, 0, 0, 2.618]\n"
                      "task: {lambda: 1.0, interaction: current}\nrobot: {saturation: 0}\npredictors: [hold, kf-cv]\n");
  }
  /// The campaign's command line (without --out), plus `extra`.
  std::vector<std::string> campaign(std::vector<std::string> extra = {}) const {
    std::vector<std::string> a = {"compare", "--scenarios", scenario_, "--sweep", "task.lambda=2,4",
                                  "--sweep", "timing.frame_period_n=1,16"};
    if (!predvs::gnuplotAvailable()) a.push_back("--no-plots");
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  }
  CliRun compare(const std::string& out, std::vector<std::string> extra = {}) const {
    auto a = campaign(extra);
    a.push_back("--out");
    a.push_back(out);
    return run(a);
  }
  std::string single() {
    const std::string out = path("single");
    if (!fs::exists(out)) {
      const CliRun r = compare(out);
      EXPECT_EQ(r.code, 0) << r.err;
    }
    return out;
  }
  static size_t records(const std::string& dir) {
    size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir)) n += e.path().extension() == ".json";
    return n;
  }
  std::string scenario_;
};

TEST_F(CampaignTest, EveryRunIsStoredAsOneRecordAndTheOutputsDoNotDependOnTheThreads) {
  // GIVEN the campaign on 2 threads and on 1 WHEN compared
  const std::string one = path("one");
  ASSERT_EQ(compare(one, {"--jobs", "1"}).code, 0);
  // THEN the output directory has one record per run, keyed by cell, predictor and seed
  EXPECT_EQ(records(single() + "/runs"), 24u);
  const std::string rec = slurp(single() + "/runs/tiny_lambda_4_frame_period_n_16__kf-cv__seed7.json");
  EXPECT_NE(rec.find("\"variant\":\"tiny@lambda=4,frame_period_n=16\""), std::string::npos) << rec;
  EXPECT_NE(rec.find("\"predvs_version\""), std::string::npos);
  EXPECT_NE(rec.find("\"scenario_hash\""), std::string::npos);
  // AND the outputs are byte-identical (no wall time, no thread count, no --out / --jobs in them)
  expectSameOutputs(single(), one);
  EXPECT_FALSE(fs::exists(single() + ".partial"));
}

TEST_F(CampaignTest, ThreeShardsMergedGiveTheOutputsOfOneRun) {
  // GIVEN the shards 1/3, 2/3, 3/3 of the campaign
  for (int i = 1; i <= 3; ++i) {
    const CliRun r = compare(path("s" + std::to_string(i)), {"--shard", std::to_string(i) + "/3"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(records(path("s" + std::to_string(i)) + "/runs"), 8u);
    EXPECT_FALSE(fs::exists(path("s" + std::to_string(i)) + "/leaderboard.csv"));
  }
  // WHEN merged (in any order) THEN the outputs are those of one run, byte for byte
  std::vector<std::string> m = {"merge", path("s3"), path("s1"), path("s2"), "--out", path("merged")};
  if (!predvs::gnuplotAvailable()) m.push_back("--no-plots");
  const CliRun r = run(m);
  ASSERT_EQ(r.code, 0) << r.err;
  expectSameOutputs(single(), path("merged"));
}

TEST_F(CampaignTest, ShardsWithOverridesFromASetFileMergeToo) {
  // GIVEN shards of a campaign with --set-file and --set overrides (recorded as "PATH=VALUE (--set-file F)")
  const std::string frag = write("frag.yaml", "task:\n  lambda: 1.5\nnoise: {sigma: 0.4}\n");
  const std::vector<std::string> extra = {"--set-file", frag, "--set", "task.interaction=desired", "--runs", "1",
                                          "--no-plots"};
  std::vector<std::string> a = {"compare", "--scenarios", scenario_};
  a.insert(a.end(), extra.begin(), extra.end());
  for (int i = 1; i <= 2; ++i) {
    auto s = a;
    for (const char* x : {"--shard", i == 1 ? "1/2" : "2/2", "--out"}) s.push_back(x);
    s.push_back(path("s" + std::to_string(i)));
    ASSERT_EQ(run(s).code, 0);
  }
  // WHEN merged THEN the outputs are one run's
  const CliRun m = run({"merge", path("s1"), path("s2"), "--no-plots", "--out", path("merged")});
  ASSERT_EQ(m.code, 0) << m.err;
  auto one = a;
  one.push_back("--out");
  one.push_back(path("one"));
  ASSERT_EQ(run(one).code, 0);
  expectSameOutputs(path("one"), path("merged"));
}

TEST_F(CampaignTest, AMissingOrDuplicatedShardIsAnErrorNamingIt) {
  for (int i = 1; i <= 2; ++i)
    ASSERT_EQ(compare(path("s" + std::to_string(i)), {"--shard", std::to_string(i) + "/3"}).code, 0);
  expectError(run({"merge", path("s1"), path("s2"), "--no-plots", "--out", path("m")}), "shard 3/3 missing", path("m"));
  expectError(run({"merge", path("s1"), path("s2"), path("s2"), "--no-plots", "--out", path("m")}),
              "shard 2/3 given twice", path("m"));
  expectError(run({"merge", path("s1"), scenario_, "--no-plots", "--out", path("m")}), "no shard.json", path("m"));
  expectError(compare(path("x"), {"--shard", "4/3"}), "--shard: expected I/N", path("x"));
  // a record missing from a shard is named
  fs::remove(path("s2") + "/runs/tiny_lambda_2_frame_period_n_1__kf-cv__seed6.json");
  ASSERT_EQ(compare(path("s3"), {"--shard", "3/3"}).code, 0);
  expectError(run({"merge", path("s1"), path("s2"), path("s3"), "--no-plots", "--out", path("m")}),
              "tiny_lambda_2_frame_period_n_1__kf-cv__seed6.json: missing run record", path("m"));
}

TEST_F(CampaignTest, AnInterruptedCampaignResumedGivesTheSameOutputsAndComputesOnlyTheRest) {
  // GIVEN a campaign stopped after 5 stored runs (--stop-after, the test hook of an interruption)
  const std::string out = path("r");
  const CliRun stopped = compare(out, {"--jobs", "1", "--stop-after", "5"});
  EXPECT_EQ(stopped.code, 2);
  EXPECT_NE(stopped.err.find("--resume " + out + ".partial"), std::string::npos) << stopped.err;
  // THEN no output directory, and the journal holds the 5 records
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(records(out + ".partial/runs"), 5u);
  // WHEN resumed THEN only the 19 others are computed, and the outputs are one run's
  const CliRun resumed = compare(out, {"--resume", out + ".partial"});
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  EXPECT_NE(resumed.err.find("5 from the records in " + out + ".partial; computing 19 "), std::string::npos)
      << resumed.err;
  expectSameOutputs(single(), out);
  EXPECT_FALSE(fs::exists(out + ".partial"));
  // AND resuming from a finished campaign computes nothing
  const CliRun again = compare(path("again"), {"--resume", out});
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.err.find("24 from the records in " + out + "; computing 0 "), std::string::npos) << again.err;
  expectSameOutputs(single(), path("again"));
}

TEST_F(CampaignTest, AStaleRecordIsNotReused) {
  // GIVEN the records of a finished campaign, one of them from another predvs version
  const std::string from = path("from");
  ASSERT_EQ(compare(from).code, 0);
  const std::string rec = from + "/runs/tiny_lambda_2_frame_period_n_16__hold__seed5.json";
  std::string text = slurp(rec);
  text = std::regex_replace(text, std::regex("\"predvs_version\":\"[^\"]*\""), "\"predvs_version\":\"0.0.0-other\"");
  std::ofstream(rec) << text;
  // WHEN resumed THEN that run is computed again (and the outputs are one run's)
  const CliRun r = compare(path("r"), {"--resume", from});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("23 from the records in " + from + " (1 stale, not reused); computing 1 "), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("predvs version 0.0.0-other"), std::string::npos) << r.err;
  expectSameOutputs(single(), path("r"));
  // AND records of other scenario content (here another noise.sigma) are not reused either
  const CliRun changed = compare(path("c"), {"--set", "noise.sigma=0.6", "--resume", path("r")});
  ASSERT_EQ(changed.code, 0) << changed.err;
  EXPECT_NE(changed.err.find("0 from the records in " + path("r") + " (24 stale, not reused); computing 24 "),
            std::string::npos)
      << changed.err;
  EXPECT_NE(changed.err.find("scenario content changed"), std::string::npos) << changed.err;
}

TEST_F(CampaignTest, MpirunWithTwoAndThreeRanksGivesTheOutputsOfOneProcess) {
  const std::string predvs = std::string(PREDVS_BINARY_DIR) + "/app/predvs";
  if (!predvs::mpiBuilt()) GTEST_SKIP() << "predvs built without MPI (install libopenmpi-dev: scripts/install-deps.sh)";
  if (!onPath("mpirun")) GTEST_SKIP() << "mpirun not found (install openmpi-bin: scripts/install-deps.sh)";
  if (!fs::exists(predvs)) GTEST_SKIP() << predvs << " not built (cmake --build build)";
  std::string args;
  for (const auto& a : campaign()) args += " " + quoted(a);
  for (int np : {2, 3}) {
    // GIVEN the campaign under mpirun (as root: Open MPI wants the two variables)
    const std::string out = path("mpi" + std::to_string(np));
    const auto r = shell("OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 "
                         "timeout 120 mpirun --oversubscribe -np " +
                         std::to_string(np) + " " + quoted(predvs) + args + " --out " + quoted(out));
    ASSERT_EQ(r.first, 0) << r.second;
    EXPECT_NE(r.second.find("on " + std::to_string(np) + " MPI ranks"), std::string::npos) << r.second;
    // THEN the outputs are one process's, byte for byte
    expectSameOutputs(single(), out);
  }
}

TEST_F(CampaignTest, ReportHtmlLoadsInAHeadlessBrowserWithTheTableAndEveryPlot) {
  if (!predvs::gnuplotAvailable()) GTEST_SKIP() << "gnuplot not found: no plots to embed";
  const std::string html = single() + "/report.html";
  const std::string page = slurp(html);
  // THEN the page is self-contained: the plots as data: URIs, no external resource
  size_t pngs = 0;
  for (const auto& e : fs::directory_iterator(single())) pngs += e.path().extension() == ".png";
  ASSERT_GT(pngs, 0u);
  size_t embedded = 0;
  for (size_t at = 0; (at = page.find("src=\"data:image/png;base64,", at)) != std::string::npos; ++at) ++embedded;
  EXPECT_EQ(embedded, pngs);
  EXPECT_EQ(page.find("http://"), std::string::npos);
  EXPECT_EQ(page.find("https://"), std::string::npos);
  EXPECT_NE(page.find("<table id=\"leaderboard\">"), std::string::npos);
  EXPECT_NE(page.find("tiny@lambda=4,frame_period_n=16"), std::string::npos);
  // AND Chromium loads it, runs its script without error and decodes every image
  std::string browser;
  for (const char* b : {"chromium", "chromium-browser", "google-chrome"})
    if (onPath(b)) browser = b;
  if (browser.empty()) GTEST_SKIP() << "no chromium on PATH (install it: scripts/install-deps.sh); report.html not "
                                       "opened in a browser";
  const auto r = shell("timeout 120 " + browser + " --headless --disable-gpu --no-sandbox --dump-dom " +
                       quoted("file://" + html) + " 2>/dev/null");
  ASSERT_EQ(r.first, 0) << r.second;
  EXPECT_NE(r.second.find("data-report-ready=\"8\""), std::string::npos) << r.second.substr(0, 300);
  EXPECT_NE(r.second.find("data-images-loaded=\"" + std::to_string(pngs) + "/" + std::to_string(pngs) + "\""),
            std::string::npos)
      << r.second.substr(0, 300);
  EXPECT_NE(r.second.find("<th>rmse</th>"), std::string::npos);
}

}  // namespace
