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

TEST_F(PlotKey, MarkedLinesShowStaggeredMarkersAndKeepOneKeyEntryEach) {
  if (!predvs::gnuplotAvailable()) GTEST_SKIP() << "gnuplot not installed";
  // GIVEN a panel with markers every 4 rows: two titled lines that coincide, an untitled line, a
  // titled point series and a titled line that already selects rows
  predvs::StagedOutputDir dir(path("marked"));
  std::string dat;
  for (int i = 0; i < 40; ++i) dat += std::to_string(i) + " " + std::to_string(1 + i % 3) + "\n";
  predvs::writeTextFile(dir, "d.dat", dat);
  predvs::PlotFigure f;
  f.base = "marked";
  f.title = "markers";
  predvs::PlotPanel p;
  p.marker_rows = 4;
  p.log_y = true;
  p.lines = {{"d.dat", "1:2", "lines lw 1.6", "red", "a", ""},
             {"d.dat", "1:2", "lines lw 1.6 dt 2", "blue", "b", ""},
             {"d.dat", "1:2", "lines", "black", "", ""},
             {"d.dat", "1:2", "points pt 7", "green", "c", ""},
             {"d.dat", "1:2", "lines", "grey", "d", "every ::0::9"}};
  f.panels = {p};
  // WHEN it is drawn
  predvs::drawFigure(dir, f);
  const std::string gp = slurp(dir.file("marked.gp"));
  EXPECT_TRUE(std::filesystem::exists(dir.file("marked.png")));
  // THEN each titled line is drawn without a key entry, its markers every 4 rows start at row
  // k * 4 / 2 for the k-th of the two marked lines, and its key entry is the function NaN with the
  // line's style and the marker
  EXPECT_NE(gp.find("'d.dat' using 1:2 with lines lw 1.6 lc rgb 'red' notitle"), std::string::npos) << gp;
  EXPECT_NE(gp.find("'d.dat' every 4::0 using 1:2 with points pt 6 ps 0.9 lc rgb 'red' notitle"), std::string::npos) << gp;
  EXPECT_NE(gp.find("NaN with linespoints lw 1.6 pt 6 ps 0.9 lc rgb 'red' title \"a\""), std::string::npos) << gp;
  EXPECT_NE(gp.find("'d.dat' every 4::2 using 1:2 with points pt 4 ps 0.9 lc rgb 'blue' notitle"), std::string::npos) << gp;
  EXPECT_NE(gp.find("NaN with linespoints lw 1.6 dt 2 pt 4 ps 0.9 lc rgb 'blue' title \"b\""), std::string::npos) << gp;
  // ... and the untitled line, the point series and the line with its own row selection are as without markers
  EXPECT_NE(gp.find("'d.dat' using 1:2 with lines lc rgb 'black' notitle"), std::string::npos) << gp;
  EXPECT_NE(gp.find("'d.dat' using 1:2 with points pt 7 lc rgb 'green' title \"c\""), std::string::npos) << gp;
  EXPECT_NE(gp.find("'d.dat' every ::0::9 using 1:2 with lines lc rgb 'grey' title \"d\""), std::string::npos) << gp;
  size_t every = 0;
  for (size_t at = gp.find(" every 4::"); at != std::string::npos; at = gp.find(" every 4::", at + 1)) ++every;
  EXPECT_EQ(every, 2u);
}

}  // namespace
