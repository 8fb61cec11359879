#include "track_csv.h"

#include "app_error.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>

namespace predvs {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

std::vector<std::string> splitCsvLine(const std::string& line) {
  std::vector<std::string> cells;
  std::string::size_type start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    cells.push_back(trim(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return cells;
}

double parseCell(const std::string& raw, const std::string& file, int line, const std::string& column,
                 bool allow_empty) {
  const std::string cell = trim(raw);
  if (cell.empty()) {
    if (allow_empty) return kNaN;
    throwAt(file, line, "column '" + column + "': expected a number, got an empty cell");
  }
  const char* begin = cell.c_str();
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(begin, &end);
  if (end == begin || *end != '\0')
    throwAt(file, line, "column '" + column + "': expected a number, got '" + cell + "'");
  if (!std::isfinite(value) || errno == ERANGE)
    throwAt(file, line, "column '" + column + "': expected a finite number, got '" + cell + "'");
  return value;
}

FeatureTrack readFeatureTrack(const std::string& path) {
  std::ifstream in(path);
  if (!in) throwAt(path, 0, "cannot open the file for reading (expected a CSV with columns t,u,v)");

  FeatureTrack track;
  track.path = path;
  std::string line;
  int line_no = 0;
  std::vector<std::string> header;
  int header_line = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (trim(line).empty()) continue;
    header = splitCsvLine(line);
    header_line = line_no;
    break;
  }
  if (header.empty()) throwAt(path, 0, "the file is empty (expected a header row 't,u,v[,u_true,v_true]')");

  static const std::vector<std::string> kKnown = {"t", "u", "v", "u_true", "v_true"};
  std::map<std::string, int> column;
  for (size_t i = 0; i < header.size(); ++i) {
    const std::string& name = header[i];
    if (std::find(kKnown.begin(), kKnown.end(), name) == kKnown.end())
      throwAt(path, header_line,
              "unknown column '" + name + "' (expected t, u, v and optionally u_true, v_true)");
    if (column.count(name)) throwAt(path, header_line, "column '" + name + "' appears twice");
    column[name] = static_cast<int>(i);
  }
  for (const char* required : {"t", "u", "v"})
    if (!column.count(required)) throwAt(path, header_line, std::string("missing required column '") + required + "'");
  if (column.count("u_true") != column.count("v_true"))
    throwAt(path, header_line, "columns u_true and v_true must be given together");
  const bool truth = column.count("u_true") != 0;

  while (std::getline(in, line)) {
    ++line_no;
    if (trim(line).empty()) continue;
    const auto cells = splitCsvLine(line);
    if (cells.size() != header.size())
      throwAt(path, line_no,
              "expected " + std::to_string(header.size()) + " cells, got " + std::to_string(cells.size()));
    const double t = parseCell(cells[column["t"]], path, line_no, "t", false);
    if (!track.t_s.empty() && !(t > track.t_s.back()))
      throwAt(path, line_no, "column 't': expected a time after the previous row's (strictly increasing), got " +
                                 trim(cells[column["t"]]));
    track.t_s.push_back(t);
    track.u_px.push_back(parseCell(cells[column["u"]], path, line_no, "u", true));
    track.v_px.push_back(parseCell(cells[column["v"]], path, line_no, "v", true));
    if (truth) {
      track.u_true_px.push_back(parseCell(cells[column["u_true"]], path, line_no, "u_true", true));
      track.v_true_px.push_back(parseCell(cells[column["v_true"]], path, line_no, "v_true", true));
    }
  }
  if (track.t_s.empty()) throwAt(path, line_no, "no data rows after the header (expected at least one)");
  return track;
}

double medianPeriod(const std::vector<double>& t_s) {
  if (t_s.size() < 2) throw std::invalid_argument("at least two rows are needed to measure the frame period");
  std::vector<double> dt;
  dt.reserve(t_s.size() - 1);
  for (size_t i = 1; i < t_s.size(); ++i) dt.push_back(t_s[i] - t_s[i - 1]);
  const size_t mid = dt.size() / 2;
  std::nth_element(dt.begin(), dt.begin() + static_cast<long>(mid), dt.end());
  if (dt.size() % 2 == 1) return dt[mid];
  const double upper = dt[mid];
  const double lower = *std::max_element(dt.begin(), dt.begin() + static_cast<long>(mid));
  return 0.5 * (lower + upper);
}

double interpolateAt(const std::vector<double>& t_s, const std::vector<double>& y, double t) {
  // Last finite sample at or before t, first finite sample at or after t.
  const auto it = std::lower_bound(t_s.begin(), t_s.end(), t);
  long hi = static_cast<long>(it - t_s.begin());
  const long n = static_cast<long>(t_s.size());
  while (hi < n && !std::isfinite(y[static_cast<size_t>(hi)])) ++hi;
  if (hi >= n) return kNaN;
  if (t_s[static_cast<size_t>(hi)] == t) return y[static_cast<size_t>(hi)];
  long lo = static_cast<long>(it - t_s.begin()) - 1;
  while (lo >= 0 && !std::isfinite(y[static_cast<size_t>(lo)])) --lo;
  if (lo < 0) return kNaN;
  const double t0 = t_s[static_cast<size_t>(lo)], t1 = t_s[static_cast<size_t>(hi)];
  const double w = (t - t0) / (t1 - t0);
  return (1.0 - w) * y[static_cast<size_t>(lo)] + w * y[static_cast<size_t>(hi)];
}

}  // namespace predvs
