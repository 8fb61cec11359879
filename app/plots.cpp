#include "plots.h"

#include "gnuplot.h"
#include "number_text.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace predvs {

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
     << "set datafile missing 'NaN'\nset grid\n"
     << f.setup;
  if (f.panels.size() > 1)
    gp << "set multiplot layout " << rows << "," << cols << " title " << gnuplotQuote(f.title) << "\n";
  for (const PlotPanel& p : f.panels) {
    gp << "set size noratio\nset autoscale x\nset autoscale xfix\nset yrange [*:*] noreverse\n"
       << "unset logscale y\nset format y '% h'\nset key inside top right opaque font ',9' samplen 2\n"
       << "set title " << gnuplotQuote(f.panels.size() > 1 ? p.title : f.title + (p.title.empty() ? "" : ": " + p.title))
       << "\nset xlabel " << gnuplotQuote(p.xlabel) << "\nset ylabel " << gnuplotQuote(p.ylabel) << "\n";
    if (p.log_y) gp << "set logscale y\nset format y '%g'\n";
    gp << p.setup << "plot ";
    for (size_t k = 0; k < p.lines.size(); ++k) {
      const PlotLine& l = p.lines[k];
      gp << (k ? ", \\\n     " : "");
      if (l.file.empty())
        gp << l.using_spec;
      else
        gp << "'" << l.file << "'" << (l.select.empty() ? "" : " " + l.select) << " using " << l.using_spec;
      gp << " with " << l.style << " lc rgb '" << l.color << "' "
         << (l.title.empty() ? std::string("notitle") : "title " + gnuplotQuote(l.title));
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

// The envelope of a long table (plots.h): per slice of the x span (at most a pixel column), the
// time columns' first and last value and every other column's min and max, in the order the data
// reached them; slices of 1 or 2 rows are copied.
std::vector<double> plotEnvelope(const std::vector<double>& x, const std::vector<EnvelopeColumn>& columns,
                                 size_t slices) {
  if (x.empty()) return {};
  std::vector<bool> is_x;
  for (const EnvelopeColumn& c : columns) is_x.push_back(c.is_x);
  EnvelopeBuilder envelope(is_x, x.front(), x.back(), slices);
  std::vector<double> row(columns.size());
  for (size_t i = 0; i < x.size(); ++i) {
    for (size_t c = 0; c < columns.size(); ++c) row[c] = columns[c].values[i];
    envelope.add(x[i], row.data());
  }
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

void EnvelopeBuilder::add(double x, const double* row) {
  const size_t width = is_x_.size();
  const size_t b = sliceOf(x);
  if (count_ > 0 && b != slice_) endSlice();
  if (count_ == 0) {
    slice_ = b;
    for (size_t c = 0; c < width; ++c) {
      lo_[c] = std::numeric_limits<double>::infinity();
      hi_[c] = -lo_[c];
    }
  }
  if (count_ < 2) std::copy(row, row + width, first_two_.begin() + static_cast<std::ptrdiff_t>(count_ * width));
  std::copy(row, row + width, last_.begin());
  for (size_t c = 0; c < width; ++c) {
    // min and max with NaN skipped (a comparison with NaN is false); the first row of each kept
    const double v = row[c];
    if (v < lo_[c]) {
      lo_[c] = v;
      lo_at_[c] = count_;
    }
    if (v > hi_[c]) {
      hi_[c] = v;
      hi_at_[c] = count_;
    }
  }
  ++count_;
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
