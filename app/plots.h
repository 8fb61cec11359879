// predvs app — the gnuplot figures of `predvs servo` and `predvs compare`, built from one
// primitive: a figure is a grid of panels, a panel a list of lines read from data files in the
// output directory. Every figure is BASE.gp (the script, re-runnable by hand with `gnuplot
// BASE.gp` in that directory) drawing BASE.png.
//
// Long series: plotEnvelope() thins a table of series sampled at common times to what a PNG can
// show. The x span [x_first, x_last] is cut into B equal slices (B at least the plot's width in
// pixels, so a slice is at most one pixel column wide); a slice of n > 2 rows becomes two rows: the
// x-like columns (time) take the slice's first and its last row's value, every other column takes
// its minimum and its maximum over the slice (NaN cells skipped; NaN if the slice has none), the
// one the data reached first in the first row. A line through these two rows covers, in that
// pixel column, the same span of y as the line through all n rows (the ink a person sees), and
// goes on to the next slice from the extreme the data reached last; a spike of one row stays
// (taking every k-th row would drop it). A point series keeps its two extreme points per slice
// only: predictions.png draws a line as wide as its points under them, which inks the band that
// hundreds of points per pixel column make. Slices of 1 or 2 rows are copied as they are, so a
// table with at most 2 rows per slice comes back unchanged. (Who calls it decides when: `predvs
// predict` beyond 20,000 rows, with 1200 slices for its 1200-pixel-wide PNG.)
#pragma once

#include "cache_line.h"
#include "output_dir.h"

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace predvs {

/// One curve of a panel: `plot FILE SELECT using USING with STYLE lc rgb COLOR title TITLE`.
/// An empty file makes USING a gnuplot expression (e.g. a constant reference line).
struct PlotLine {
  std::string file;
  std::string using_spec;  ///< "1:5"
  std::string style;       ///< "lines lw 1.5", "points pt 7 ps 0.4", ...
  std::string color;       ///< "#rrggbb" or a gnuplot colour name
  std::string title;       ///< empty: notitle
  std::string select;      ///< "index 2", "every ::0::0" or empty
};

struct PlotPanel {
  std::string title, xlabel = "time t [s]", ylabel;
  bool log_y = false;
  /// > 0: every titled line read from a file (without `every` in its select) also gets a marker
  /// every marker_rows rows, its own point type, the k-th of n such lines starting at row
  /// k * marker_rows / n, and its key entry shows line and marker. Curves that coincide (a
  /// predictor and its variant with an action that never fires) then still show each one's
  /// markers; 0: lines only.
  size_t marker_rows = 0;
  std::string setup;  ///< gnuplot commands for this panel, after the per-panel defaults
  std::vector<PlotLine> lines;
};

struct PlotFigure {
  std::string base;   ///< BASE.gp draws BASE.png
  std::string title;  ///< above the grid
  std::string setup;  ///< gnuplot commands for every panel (e.g. eventMarks(), report.h)
  std::vector<PlotPanel> panels;
  size_t columns = 0;      ///< grid columns; 0: one column up to 3 panels, else 2
  int panel_width_px = 0;  ///< 0: 1100 in one column, 700 otherwise
  int panel_height_px = 0; ///< 0: 600 for a lone panel, 330 otherwise
};

/// Writes BASE.gp and runs gnuplot in the staging directory (runGnuplot(): errors throw).
/// Defaults per panel: linear y, x autoscaled to the data, grid, key inside top right. Text is
/// not "enhanced": names with '_' print as they are.
void drawFigure(const StagedOutputDir& dir, const PlotFigure& figure);

/// Panels for related names: names that share the text before their first '_' (the whole name
/// when it has none) share a panel (lyap_f, lyap_bound and lyap_f_bar; s_u and s_v); the others
/// have one each. Indices into `names`, in order of first appearance.
std::vector<std::vector<size_t>> groupByPrefix(const std::vector<std::string>& names);

/// Dash type of the k-th curve of a group: solid, then dashed patterns.
int dashType(size_t k);

/// gnuplot point type of the k-th marked curve (PlotPanel::marker_rows): open shapes, then filled.
int markerType(size_t k);

/// One column of a table given to plotEnvelope() or EnvelopeBuilder::addBlock(): its values, one per
/// row (not owned), each plus `shift` when `shifted`; NaN in every row when `values` is null.
struct EnvelopeColumn {
  const double* values = nullptr;
  bool is_x = false;  ///< true: a time column (first and last row of a slice); false: min and max
  bool shifted = false;
  double shift = 0.0;
  /// Row r's value.
  double at(size_t r) const {
    return !values ? std::numeric_limits<double>::quiet_NaN() : shifted ? values[r] + shift : values[r];
  }
};

/// The envelope of a table (see the file comment): x (finite, non-decreasing, one per row) decides
/// the slice of each row, slice b = min(B - 1, floor((x_i - x_first) / (x_last - x_first) * B))
/// (one slice when x_last == x_first); returns the thinned rows, row-major, columns.size() numbers
/// per row. B = `slices` >= 1.
std::vector<double> plotEnvelope(const std::vector<double>& x, const std::vector<EnvelopeColumn>& columns,
                                 size_t slices);

/// plotEnvelope() a block of rows at a time, for a table that is never whole in memory (`predvs
/// predict` streams its predictions in blocks of rows): addBlock() the blocks in order, then table()
/// gives what plotEnvelope() gives on the whole table, bit for bit, for any cut into blocks
/// (tests/app/plot_envelope_test.cpp). Needs the first and last x up front (they fix the slices);
/// keeps one slice's extremes and first two rows. Its state is written once per run of a block's
/// rows within one slice, not per row, and lies on lines of its own: it may be fed on one thread
/// while others compute beside it (docs/PERFORMANCE.md, "Fifteenth pass").
class alignas(kCacheLineBytes) EnvelopeBuilder {  // its state on lines of its own (cache_line.h)
 public:
  /// is_x[c]: column c is a time column (EnvelopeColumn::is_x); x_first, x_last as in plotEnvelope().
  EnvelopeBuilder(std::vector<bool> is_x, double x_first, double x_last, size_t slices);
  /// The next n rows: x[0..n) and, per column c (is_x.size() of them), columns[c]'s values[0..n)
  /// (columns[c].is_x is not read: the constructor's is_x[c] holds).
  void addBlock(const double* x, size_t n, const EnvelopeColumn* columns);
  /// The thinned rows so far, row-major (ends the slice in progress: call after the last block).
  const std::vector<double>& table();

 private:
  size_t sliceOf(double x) const;
  void endSlice();
  std::vector<bool> is_x_;
  double x0_ = 0.0, scale_ = 0.0;
  size_t slices_ = 1;
  size_t slice_ = 0, count_ = 0;  ///< the slice in progress and its rows so far (0: none yet)
  CacheLineVector<double> first_two_, last_;  ///< its first two rows; its last row
  CacheLineVector<double> lo_, hi_;           ///< per column: min and max so far (NaN cells skipped)
  CacheLineVector<size_t> lo_at_, hi_at_;     ///< the row (in the slice) where each was first reached
  std::vector<double> out_;
};

}  // namespace predvs
