// drawFigure() (app/plots.h): a panel whose lines have titles gets headroom above its data for its
// key (inside top right, opaque), so that the key hides no data; a log-y panel and a panel without a
// key get none.
#include "cli_test_utils.h"
#include "gnuplot.h"
#include "number_text.h"
#include "plots.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

using namespace predvs::apptest;

namespace {

class PlotKey : public ScratchDirTest {
 protected:
  PlotKey() : ScratchDirTest("predvs_plot_key_test") {}
};

TEST_F(PlotKey, APanelWithAKeyGetsHeadroomForIt) {
  if (!predvs::gnuplotAvailable()) GTEST_SKIP() << "gnuplot not installed";
  // GIVEN a figure of three panels on one data file: two titled lines, the same on a log y axis,
  // and one untitled line
  predvs::StagedOutputDir dir(path("fig"));
  predvs::writeTextFile(dir, "d.dat", "0 1 2\n1 2 3\n2 3 1\n");
  predvs::PlotFigure f;
  f.base = "fig";
  f.title = "key headroom";
  predvs::PlotPanel keyed;
  keyed.lines = {{"d.dat", "1:2", "lines", "red", "a", ""}, {"d.dat", "1:3", "lines", "blue", "b", ""}};
  predvs::PlotPanel logged = keyed;
  logged.log_y = true;
  predvs::PlotPanel bare;
  bare.lines = {{"d.dat", "1:2", "lines", "red", "", ""}};
  f.panels = {keyed, logged, bare};
  // WHEN it is drawn
  predvs::drawFigure(dir, f);
  const std::string gp = slurp(dir.file("fig.gp"));
  EXPECT_TRUE(std::filesystem::exists(dir.file("fig.png")));
  // THEN the keyed panel's y range is extended upwards (2 lines of 15 px and 10 px of a 330 px
  // panel's 240 px plot area: f = 40 / 240, g = f / (1 - f) = 0.2), and the others' are not
  const size_t first = gp.find("set offsets");
  ASSERT_NE(first, std::string::npos) << gp;
  EXPECT_EQ(gp.substr(first, 31), "set offsets 0, 0, graph 0.200, ");
  const size_t second = gp.find("set offsets", first + 1), third = gp.find("set offsets", second + 1);
  ASSERT_NE(third, std::string::npos);
  EXPECT_EQ(gp.substr(second, 23), "set offsets 0, 0, 0, 0\n");
  EXPECT_EQ(gp.substr(third, 23), "set offsets 0, 0, 0, 0\n");
}

}  // namespace
