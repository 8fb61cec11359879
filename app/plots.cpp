#include "plots.h"

#include "gnuplot.h"
#include "number_text.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace predvs {

namespace {

/// `set offsets` that keep the data of a linear, autoscaled panel below its key: the key (top
/// right, opaque) takes about 15 px per titled line plus 10 px of a plot area about ph - 90 px high,
/// a fraction f of it, so the y range is extended upwards by g = f / (1 - f) of itself (at most 1).
/// Before, the key hid the data under it (command.png's wz, near 0 in the last seconds).
std::string keyHeadroom(const PlotPanel& p, int ph) {
  const auto titled = std::count_if(p.lines.begin(), p.lines.end(), [](const PlotLine& l) { return !l.title.empty(); });
  if (titled == 0 || p.log_y) return "set offsets 0, 0, 0, 0\n";
  const double f = std::min(0.5, (15.0 * static_cast<double>(titled) + 10.0) / std::max(100.0, ph - 90.0));
  std::ostringstream out;
  out << "set offsets 0, 0, graph " << fixedNumber(f / (1.0 - f), 3) << ", 0\n";
  return out.str();
}

}  // namespace

void drawFigure(const StagedOutputDir& dir, const PlotFigure& f) {
  const size_t n = std::max<size_t>(1, f.panels.size());
  const size_t cols = f.columns > 0 ? f.columns : (n <= 3 ? 1 : 2);
  const size_t rows = (n + cols - 1) / cols;
  const int pw = f.panel_width_px > 0 ? f.panel_width_px : (cols == 1 ? 1100 : 700);
  const int ph = f.panel_height_px > 0 ? f.panel_height_px : (n == 1 ? 600 : 330);
  std::ostringstream gp;
  gp << "# Regenerate with: gnuplot " << f.base << ".gp\n"
     << "set terminal pngcairo size " << static_cast<int>(cols) * pw << "," << static_cast<int>(rows) * ph + 60
     << " noenhanced font 'Sans,10'\n"
     << "set output '" << f.base << ".png'\n"
     << "set datafile missing 'NaN'\nset grid\n";
  if (f.panels.size() > 1)
    gp << "set multiplot layout " << rows << "," << cols << " title " << gnuplotQuote(f.title) << "\n";
  for (const PlotPanel& p : f.panels) {
    // Labels, objects and arrows persist from panel to panel in a multiplot: each panel starts
    // without them, then gets the figure's (f.setup: e.g. the event marks) and its own.
    gp << "unset label\nunset object\nunset arrow\n" << f.setup;
    gp << "set size noratio\nset autoscale x\nset autoscale xfix\nset yrange [*:*] noreverse\n"
       << "unset logscale y\nset format y '% h'\nset key inside top right opaque font ',9' samplen 2\n"
       << "set title " << gnuplotQuote(f.panels.size() > 1 ? p.title : f.title + (p.title.empty() ? "" : ": " + p.title))
       << "\nset xlabel " << gnuplotQuote(p.xlabel) << "\nset ylabel " << gnuplotQuote(p.ylabel) << "\n";
    if (p.log_y) gp << "set logscale y\nset format y '%g'\n";
    gp << keyHeadroom(p, ph);
    gp << p.setup << "plot ";
    auto marked = [&](const PlotLine& l) {
      return p.marker_rows > 0 && !l.file.empty() && !l.title.empty() && l.select.find("every") == std::string::npos &&
             l.style.rfind("lines", 0) == 0 && l.style.rfind("linespoints", 0) != 0;
    };
    size_t n_marked = 0;
    for (const PlotLine& l : p.lines) n_marked += marked(l);
    size_t k_marked = 0;
    for (size_t k = 0; k < p.lines.size(); ++k) {
      const PlotLine& l = p.lines[k];
      gp << (k ? ", \\\n     " : "");
      const std::string source =
          l.file.empty() ? std::string() : "'" + l.file + "'" + (l.select.empty() ? "" : " " + l.select);
      if (l.file.empty())
        gp << l.using_spec;
      else
        gp << source << " using " << l.using_spec;
      const std::string color = " lc rgb '" + l.color + "' ";
      if (!marked(l)) {
        gp << " with " << l.style << color << (l.title.empty() ? std::string("notitle") : "title " + gnuplotQuote(l.title));
        continue;
      }
      // The line without a key entry, its markers, then the key entry alone: the function NaN, which
      // draws nothing (a data series of NaN would be skipped with its key entry, under `set datafile
      // missing 'NaN'`).
      const std::string marker = " pt " + std::to_string(markerType(k_marked)) + " ps 0.9";
      const size_t first = k_marked * p.marker_rows / n_marked;
      gp << " with " << l.style << color << "notitle, \\\n     " << source << " every " << p.marker_rows
         << "::" << first << " using " << l.using_spec << " with points" << marker << color << "notitle, \\\n     "
         << "NaN with linespoints" << l.style.substr(5) << marker << color
         << "title " << gnuplotQuote(l.title);
      ++k_marked;
    }
    gp << "\n";
  }
  if (f.panels.size() > 1) gp << "unset multiplot\n";
  writeTextFile(dir, f.base + ".gp", gp.str());
  runGnuplot(dir.staging().string(), f.base + ".gp");
}

std::vector<std::vector<size_t>> groupByPrefix(const std::vector<std::string>& names) {
  std::vector<std::vector<size_t>> groups;
  std::vector<std::string> keys;
  for (size_t i = 0; i < names.size(); ++i) {
    const std::string key = names[i].substr(0, names[i].find('_'));  // the whole name without '_'
    const auto at = std::find(keys.begin(), keys.end(), key);
    if (at == keys.end()) {
      keys.push_back(key);
      groups.push_back({i});
    } else {
      groups[static_cast<size_t>(at - keys.begin())].push_back(i);
    }
  }
  return groups;
}

int dashType(size_t k) { return static_cast<int>(k % 5) + 1; }

int markerType(size_t k) {
  // Open and filled shapes gnuplot's cairo terminals draw alike: circle, square, triangle up and
  // down, diamond, pentagon, then their filled forms.
  static const int kTypes[] = {6, 4, 8, 10, 12, 14, 7, 5, 9, 11, 13, 15};
  return kTypes[k % (sizeof kTypes / sizeof kTypes[0])];
}

// The envelope of a long table (plots.h): per slice of the x span (at most a pixel column), the
// time columns' first and last value and every other column's min and max, in the order the data
// reached them; slices of 1 or 2 rows are copied.
std::vector<double> plotEnvelope(const std::vector<double>& x, const std::vector<EnvelopeColumn>& columns,
                                 size_t slices) {
  if (x.empty()) return {};
  std::vector<bool> is_x;
  for (const EnvelopeColumn& c : columns) is_x.push_back(c.is_x);
  EnvelopeBuilder envelope(is_x, x.front(), x.back(), slices);
  envelope.addBlock(x.data(), x.size(), columns.data());
  return envelope.table();
}

EnvelopeBuilder::EnvelopeBuilder(std::vector<bool> is_x, double x_first, double x_last, size_t slices)
    : is_x_(std::move(is_x)), x0_(x_first), slices_(std::max<size_t>(1, slices)) {
  const double span = x_last - x_first;
  scale_ = span > 0.0 ? static_cast<double>(slices_) / span : 0.0;
  const size_t width = is_x_.size();
  first_two_.resize(2 * width);
  last_.resize(width);
  lo_.resize(width);
  hi_.resize(width);
  lo_at_.resize(width);
  hi_at_.resize(width);
}

size_t EnvelopeBuilder::sliceOf(double x) const {
  const double b = std::floor((x - x0_) * scale_);
  return b >= static_cast<double>(slices_ - 1) ? slices_ - 1 : static_cast<size_t>(std::max(0.0, b));
}

namespace {

/// Row r of a block's columns into out[0..width).
void gatherRow(const EnvelopeColumn* columns, size_t width, size_t r, double* out) {
  for (size_t c = 0; c < width; ++c) out[c] = columns[c].at(r);
}

/// The min and max of values[i0..i1) (plus shift when Shifted) into lo, hi and the row (counted from
/// `count` at i0) where each was first reached; NaN cells skipped (a comparison with NaN is false).
template <bool Shifted>
void extremes(const double* values, double shift, size_t i0, size_t i1, size_t count, double& lo, double& hi,
              size_t& lo_at, size_t& hi_at) {
  double l = lo, h = hi;
  size_t l_at = lo_at, h_at = hi_at;
  for (size_t r = i0; r < i1; ++r) {
    const double v = Shifted ? values[r] + shift : values[r];
    if (v < l) {
      l = v;
      l_at = count + (r - i0);
    }
    if (v > h) {
      h = v;
      h_at = count + (r - i0);
    }
  }
  lo = l;
  hi = h;
  lo_at = l_at;
  hi_at = h_at;
}

}  // namespace

void EnvelopeBuilder::addBlock(const double* x, size_t n, const EnvelopeColumn* columns) {
  const size_t width = is_x_.size();
  size_t i = 0;
  while (i < n) {
    // Rows i..j-1: the block's run of rows in slice b (x is non-decreasing).
    const size_t b = sliceOf(x[i]);
    size_t j = i + 1;
    while (j < n && sliceOf(x[j]) == b) ++j;
    if (count_ > 0 && b != slice_) endSlice();
    if (count_ == 0) {
      slice_ = b;
      for (size_t c = 0; c < width; ++c) {
        lo_[c] = std::numeric_limits<double>::infinity();
        hi_[c] = -lo_[c];
      }
    }
    for (size_t r = i; r < j && count_ + (r - i) < 2; ++r)
      gatherRow(columns, width, r, first_two_.data() + (count_ + (r - i)) * width);
    gatherRow(columns, width, j - 1, last_.data());
    for (size_t c = 0; c < width; ++c) {
      const EnvelopeColumn& col = columns[c];
      if (is_x_[c] || !col.values) continue;  // a time column keeps its first and last row; NaN is no extreme
      if (col.shifted)
        extremes<true>(col.values, col.shift, i, j, count_, lo_[c], hi_[c], lo_at_[c], hi_at_[c]);
      else
        extremes<false>(col.values, 0.0, i, j, count_, lo_[c], hi_[c], lo_at_[c], hi_at_[c]);
    }
    count_ += j - i;
    i = j;
  }
}

void EnvelopeBuilder::endSlice() {
  const size_t width = is_x_.size();
  if (count_ <= 2) {
    out_.insert(out_.end(), first_two_.begin(), first_two_.begin() + static_cast<std::ptrdiff_t>(count_ * width));
    count_ = 0;
    return;
  }
  const double kNaN = std::numeric_limits<double>::quiet_NaN();
  const size_t first_row = out_.size();
  out_.resize(first_row + 2 * width);
  double* row_a = out_.data() + first_row;
  double* row_b = row_a + width;
  for (size_t c = 0; c < width; ++c) {
    if (is_x_[c]) {
      row_a[c] = first_two_[c];
      row_b[c] = last_[c];
    } else if (!(lo_[c] <= hi_[c])) {  // no number in the slice
      row_a[c] = row_b[c] = kNaN;
    } else if (lo_at_[c] <= hi_at_[c]) {  // the min reached first (or in the same row: min == max)
      row_a[c] = lo_[c];
      row_b[c] = hi_[c];
    } else {
      row_a[c] = hi_[c];
      row_b[c] = lo_[c];
    }
  }
  count_ = 0;
}

const std::vector<double>& EnvelopeBuilder::table() {
  if (count_ > 0) endSlice();
  return out_;
}

}  // namespace predvs
