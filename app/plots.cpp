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
  const size_t rows = x.size(), width = columns.size();
  std::vector<double> out;
  if (rows == 0) return out;
  slices = std::max<size_t>(1, slices);
  out.reserve(std::min(rows, 2 * slices) * width);
  const double x0 = x.front(), span = x.back() - x.front();
  const double scale = span > 0.0 ? static_cast<double>(slices) / span : 0.0;
  auto sliceOf = [&](size_t i) {
    const double b = std::floor((x[i] - x0) * scale);
    return b >= static_cast<double>(slices - 1) ? slices - 1 : static_cast<size_t>(std::max(0.0, b));
  };
  auto copyRow = [&](size_t i) {
    for (const EnvelopeColumn& c : columns) out.push_back(c.values[i]);
  };
  const double kNaN = std::numeric_limits<double>::quiet_NaN();
  size_t begin = 0;
  while (begin < rows) {
    const size_t b = sliceOf(begin);
    size_t end = begin + 1;
    while (end < rows && sliceOf(end) == b) ++end;
    if (end - begin <= 2) {
      for (size_t i = begin; i < end; ++i) copyRow(i);
      begin = end;
      continue;
    }
    const size_t first_row = out.size();
    out.resize(first_row + 2 * width);
    double* row_a = out.data() + first_row;
    double* row_b = row_a + width;
    for (size_t c = 0; c < width; ++c) {
      const double* v = columns[c].values;
      if (columns[c].is_x) {
        row_a[c] = v[begin];
        row_b[c] = v[end - 1];
        continue;
      }
      // min and max with NaN skipped (a comparison with NaN is false); the loop vectorises
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (size_t i = begin; i < end; ++i) {
        lo = v[i] < lo ? v[i] : lo;
        hi = v[i] > hi ? v[i] : hi;
      }
      if (!(lo <= hi)) {  // no number in the slice
        row_a[c] = row_b[c] = kNaN;
        continue;
      }
      size_t i = begin;
      while (v[i] != lo && v[i] != hi) ++i;  // which extreme the data reaches first
      row_a[c] = v[i];
      row_b[c] = v[i] == lo ? hi : lo;
    }
    begin = end;
  }
  return out;
}

}  // namespace predvs
