// `predvs track-study --param PREDICTOR.KEY=WORD`: a word such as `model=cv` (st-akf, st-akf-pm,
// fakf-classic, docs/MODELS.md §3, §5) reaches the predictor; a word the predictor does not take is
// a one-line error naming the key.
#include "app/cli_test_utils.h"

#include <gtest/gtest.h>

#include <string>

namespace predvs {
namespace {

using apptest::CliRun;
using apptest::run;
using apptest::slurp;

class TrackStudyModelParam : public apptest::ScratchDirTest {
 protected:
  TrackStudyModelParam() : ScratchDirTest("predvs_tsmodel_test") {}
};

TEST_F(TrackStudyModelParam, AModelWordChangesTheFilterAndABadOneIsNamed) {
  // GIVEN one short track, st-akf on its default model and on `model=cv`
  const std::vector<std::string> grid = {"track-study", "--kinds", "stops", "--rates", "15", "--noise", "1",
                                         "--seeds", "1", "--duration-s", "5", "--predictors", "st-akf"};
  auto with = [&grid](std::vector<std::string> extra) {
    std::vector<std::string> a = grid;
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  const CliRun ca = run(with({"--out", path("ca")}));
  const CliRun cv = run(with({"--param", "st-akf.model=cv", "--out", path("cv")}));
  const CliRun ca_spelt = run(with({"--param", "st-akf.model=ca", "--out", path("ca_spelt")}));
  ASSERT_EQ(ca.code, 0) << ca.err;
  ASSERT_EQ(cv.code, 0) << cv.err;
  ASSERT_EQ(ca_spelt.code, 0) << ca_spelt.err;
  // THEN `model=ca` is the default, and `model=cv` is another filter (other errors on the same track)
  EXPECT_EQ(slurp(path("ca") + "/study.csv"), slurp(path("ca_spelt") + "/study.csv"));
  EXPECT_NE(slurp(path("ca") + "/study.csv"), slurp(path("cv") + "/study.csv"));
  // AND a word the predictor does not know, or a word for a numeric key, is a one-line error
  expectError(run(with({"--param", "st-akf.model=singer", "--out", path("bad")})), "'model'", path("bad"));
  expectError(run(with({"--param", "st-akf.q=fast", "--out", path("bad")})), "'q'", path("bad"));
  expectError(run(with({"--param", "st-akf.q=1e", "--out", path("bad")})), "expected a number or a word", path("bad"));
}

}  // namespace
}  // namespace predvs
