#include "track_csv.h"

#include "app_error.h"
#include "large_buffer.h"
#include "parallel_for.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <string_view>
#include <tuple>
#include <unordered_map>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

namespace predvs {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string_view trimView(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

/// splitCsvLine into views of `line` (trimmed), reusing `cells`' storage.
void splitCsvView(std::string_view line, std::vector<std::string_view>& cells) {
  cells.clear();
  std::string_view::size_type start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    cells.push_back(trimView(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
}

/// parseCell on a trimmed view. Fast path: std::from_chars (no allocation, locale-free); anything
/// it does not take whole as a finite normal value (a leading '+', hex, inf/nan, out of range, junk) goes
/// through parseCell, so accepted values and error messages are exactly parseCell's.
double parseCellView(std::string_view cell, const std::string& file, int line, const std::string& column,
                     bool allow_empty) {
  if (!cell.empty()) {
    double value = 0.0;
    const auto r = std::from_chars(cell.data(), cell.data() + cell.size(), value);
    if (r.ec == std::errc() && r.ptr == cell.data() + cell.size() && std::isfinite(value) &&
        (value == 0.0 || std::fabs(value) >= std::numeric_limits<double>::min()))  // subnormals: parseCell
      return value;
  }
  return parseCell(std::string(cell), file, line, column, allow_empty);
}

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
  const double value = std::strtod(begin, &end);
  // strtod also reads hexadecimal ("0x10" is 16): a CSV of decimals does not mean it.
  if (end == begin || *end != '\0' || cell.find_first_of("xX") != std::string::npos)
    throwAt(file, line, "column '" + column + "': expected a number, got '" + cell + "'");
  // An underflow (1e-320, a subnormal, or 0) is a finite number; an overflow is +-inf.
  if (!std::isfinite(value))
    throwAt(file, line, "column '" + column + "': expected a finite number, got '" + cell + "'");
  return value;
}

namespace {

/// One column of the wide format: axis 'u' / 'v' of point `index`, measured or true.
struct WideColumn {
  char axis;
  int index;  ///< -1: the unindexed single-point name (u, v, u_true, v_true)
  bool truth;
};

/// u<i>, v<i>, u<i>_true, v<i>_true, or the unindexed u, v, u_true, v_true; false for any other.
bool parseWideColumn(const std::string& name, WideColumn& out) {
  if (name.size() < 1 || (name[0] != 'u' && name[0] != 'v')) return false;
  std::string rest = name.substr(1);
  out.axis = name[0];
  out.truth = false;
  const std::string suffix = "_true";
  if (rest.size() >= suffix.size() && rest.compare(rest.size() - suffix.size(), suffix.size(), suffix) == 0) {
    out.truth = true;
    rest.erase(rest.size() - suffix.size());
  }
  if (rest.empty()) {
    out.index = -1;
    return true;
  }
  if (rest.size() > 6 || rest.find_first_not_of("0123456789") != std::string::npos) return false;
  if (rest.size() > 1 && rest[0] == '0') return false;  // u01 is not point 1: an extra column
  out.index = std::stoi(rest);
  return true;
}

std::string wideName(char axis, int index, bool truth) {
  return std::string(1, axis) + (index >= 0 ? std::to_string(index) : std::string()) + (truth ? "_true" : "");
}

/// An integer point id of the long format ("3", "-1"); false for a name.
bool integerId(const std::string& id, long& value) {
  if (id.empty()) return false;
  const char* begin = id.c_str();
  char* end = nullptr;
  errno = 0;
  value = std::strtol(begin, &end, 10);
  return end != begin && *end == '\0' && errno != ERANGE;
}

struct LongRow {
  double t;
  std::string id;
  double u, v, u_true, v_true;
  int line;
};

/// A file's bytes: mapped read-only when it is a regular file (the page cache's own pages: no
/// zeroed buffer, no copy of a 100 MB track), else read whole into memory (a pipe, /dev/stdin).
/// Throws as readFeatureTrack does when the file cannot be opened.
class FileText {
 public:
  explicit FileText(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throwAt(path, 0, "cannot open the file for reading (expected a CSV with columns t,u,v or t,point,u,v)");
    struct stat st {};
    const bool stated = ::fstat(fd, &st) == 0;
    if (stated && S_ISDIR(st.st_mode)) {
      ::close(fd);
      throwAt(path, 0, "is a directory, expected a CSV with columns t,u,v or t,point,u,v");
    }
    if (stated && S_ISREG(st.st_mode) && st.st_size > 0) {
      void* p = ::mmap(nullptr, static_cast<size_t>(st.st_size), PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
      if (p != MAP_FAILED) {
        map_ = p;
        map_size_ = static_cast<size_t>(st.st_size);
        ::madvise(map_, map_size_, MADV_SEQUENTIAL);
      }
    }
    if (!map_) {
      char buf[1 << 16];
      ssize_t got;
      while ((got = ::read(fd, buf, sizeof buf)) > 0) copy_.append(buf, static_cast<size_t>(got));
      // A read error (a directory) leaves what was read, as the stream read did: "the file is empty".
    }
    ::close(fd);
  }
  ~FileText() {
    if (map_) ::munmap(map_, map_size_);
  }
  FileText(const FileText&) = delete;
  FileText& operator=(const FileText&) = delete;
  std::string_view text() const {
    return map_ ? std::string_view(static_cast<const char*>(map_), map_size_) : std::string_view(copy_);
  }

 private:
  void* map_ = nullptr;
  size_t map_size_ = 0;
  std::string copy_;
};

/// Every column of a track, in one order: t, then u, v of each point, then the true u, v of each.
std::vector<std::vector<double>*> columnsOf(FeatureTrack& f) {
  std::vector<std::vector<double>*> c{&f.t_s};
  for (size_t p = 0; p < f.u_px.size(); ++p) c.push_back(&f.u_px[p]), c.push_back(&f.v_px[p]);
  for (size_t p = 0; p < f.u_true_px.size(); ++p) c.push_back(&f.u_true_px[p]), c.push_back(&f.v_true_px[p]);
  return c;
}

/// The parallel parse of a wide file's data rows, text[begin, end): cut into pieces at line ends,
/// each parsed on the pool into its own columns by parse(piece_begin, piece_end, 0, out) (line
/// numbers are not known there and not needed: a piece that meets a defect gives up), then
/// appended in order. Returns false, with `track` untouched, when it was not tried (one thread, a
/// small file) or when a piece met a defect or the time did not increase from one piece to the
/// next: the caller then parses the whole on one thread, which reports the defect with its line.
template <class Size, class Parse>
bool parseWideInPieces(std::string_view text, size_t begin, int jobs, size_t min_bytes, FeatureTrack& track,
                       Size& sizeColumns, Parse& parse) {
  const size_t bytes = text.size() - begin;
  if (jobs < 2 || bytes < min_bytes || bytes == 0) return false;
  // Four pieces per thread (a thread held up by another process does not hold up the rest), none
  // under 1 MB (or min_bytes / 4 when that is less: tests).
  const size_t piece_min = std::max<size_t>(1, std::min<size_t>(size_t{1} << 20, min_bytes / 4));
  const size_t want = std::min<size_t>(static_cast<size_t>(jobs) * 4, std::max<size_t>(2, bytes / piece_min));
  std::vector<size_t> cut{begin};
  for (size_t k = 1; k < want; ++k) {
    const size_t guess = std::max(cut.back(), begin + bytes / want * k);
    const auto nl = text.find('\n', guess);
    if (nl == std::string_view::npos) break;
    if (nl + 1 > cut.back() && nl + 1 < text.size()) cut.push_back(nl + 1);
  }
  cut.push_back(text.size());
  const size_t pieces = cut.size() - 1;
  if (pieces < 2) return false;
  std::vector<FeatureTrack> part(pieces);
  std::vector<char> failed(pieces, 0);
  parallelFor(pieces, jobs, [&](size_t k) {
    try {
      sizeColumns(part[k]);
      parse(cut[k], cut[k + 1], 0, part[k]);
    } catch (...) {
      failed[k] = 1;  // the serial parse finds it again and names its line
    }
  });
  double last_t = -std::numeric_limits<double>::infinity();
  bool any = false;
  for (size_t k = 0; k < pieces; ++k) {
    if (failed[k]) return false;
    if (part[k].t_s.empty()) continue;
    if (any && !(part[k].t_s.front() > last_t)) return false;
    last_t = part[k].t_s.back();
    any = true;
  }
  // Appended in order, one column per item.
  size_t rows = 0;
  for (size_t k = 0; k < pieces; ++k) rows += part[k].t_s.size();
  const std::vector<std::vector<double>*> dest = columnsOf(track);
  parallelFor(dest.size(), jobs, [&](size_t c) {
    std::vector<double>& to = *dest[c];
    reserveLarge(to, rows);  // huge pages where offered, no zeroing first (large_buffer.h)
    for (size_t k = 0; k < pieces; ++k) {
      std::vector<double>& from = *columnsOf(part[k])[c];
      to.insert(to.end(), from.begin(), from.end());
      std::vector<double>().swap(from);
    }
  });
  return true;
}

}  // namespace

FeatureTrack readFeatureTrack(const std::string& path, int jobs, size_t parallel_min_bytes) {
  // The whole file, mapped (or, for what cannot be mapped, read in one go); lines are views into it
  // (split on '\n' as std::getline does).
  const FileText file(path);
  const std::string_view text = file.text();
  size_t pos = 0;
  auto nextLine = [&](std::string_view& out) {
    if (pos >= text.size()) return false;
    const auto nl = text.find('\n', pos);
    const size_t end = nl == std::string_view::npos ? text.size() : nl;
    out = std::string_view(text.data() + pos, end - pos);
    pos = nl == std::string_view::npos ? text.size() : nl + 1;
    return true;
  };

  FeatureTrack track;
  track.path = path;
  std::string line;
  std::string_view line_view;
  int line_no = 0;
  std::vector<std::string> header;
  int header_line = 0;
  while (nextLine(line_view)) {
    line.assign(line_view.data(), line_view.size());
    ++line_no;
    if (line_no == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);  // UTF-8 byte-order mark
    if (trim(line).empty()) continue;
    header = splitCsvLine(line);
    header_line = line_no;
    break;
  }
  if (header.empty())
    throwAt(path, 0, "the file is empty (expected a header row 't,u,v[,u_true,v_true]', 't,u0,v0,u1,v1,...' or "
                     "'t,point,u,v')");

  std::map<std::string, int> column;
  for (size_t i = 0; i < header.size(); ++i) {
    const std::string& name = header[i];
    if (name.empty()) throwAt(path, header_line, "column " + std::to_string(i + 1) + " has no name");
    if (column.count(name)) throwAt(path, header_line, "column '" + name + "' appears twice");
    column[name] = static_cast<int>(i);
  }
  if (!column.count("t")) throwAt(path, header_line, "missing required column 't'");
  const bool long_format = column.count("point") != 0;
  track.format = long_format ? "long" : "wide";

  // Which columns the format reads; every other one is ignored (and listed).
  std::vector<bool> used(header.size(), false);
  used[static_cast<size_t>(column["t"])] = true;
  // Wide: (axis, index, truth) -> column.
  std::map<std::tuple<char, int, bool>, int> wide;
  int n_points = 0;
  bool truth = false;
  if (long_format) {
    for (const char* name : {"point", "u", "v", "u_true", "v_true"})
      if (column.count(name)) used[static_cast<size_t>(column[name])] = true;
    for (const char* required : {"u", "v"})
      if (!column.count(required))
        throwAt(path, header_line, std::string("missing required column '") + required + "' (long format: t,point,u,v)");
    if (column.count("u_true") != column.count("v_true"))
      throwAt(path, header_line, "columns u_true and v_true must be given together");
    truth = column.count("u_true") != 0;
  } else {
    bool indexed = false, single = false;
    for (size_t i = 0; i < header.size(); ++i) {
      WideColumn c{};
      if (!parseWideColumn(header[i], c)) continue;
      used[i] = true;
      (c.index < 0 ? single : indexed) = true;
      wide[{c.axis, c.index, c.truth}] = static_cast<int>(i);
    }
    if (single && indexed)
      throwAt(path, header_line,
              "both the single-point columns (u, v) and indexed ones (u0, v0, ...): expected one or the other");
    // Every point index needs u<i> and v<i>; the indices run 0..N-1; truth only for those points.
    std::map<int, int> seen_axes;  // index -> measured columns seen
    for (const auto& kv : wide)
      if (!std::get<2>(kv.first)) ++seen_axes[std::get<1>(kv.first)];
    for (const auto& kv : wide) {
      const char axis = std::get<0>(kv.first);
      const int index = std::get<1>(kv.first);
      const bool is_truth = std::get<2>(kv.first);
      const char other = axis == 'u' ? 'v' : 'u';
      if (!is_truth && !wide.count({other, index, false}))
        throwAt(path, header_line, "missing required column '" + wideName(other, index, false) + "' (given '" +
                                       wideName(axis, index, false) + "')");
      if (is_truth && !seen_axes.count(index))
        throwAt(path, header_line, "column '" + wideName(axis, index, true) + "' has no measured point (no '" +
                                       wideName('u', index, false) + "', '" + wideName('v', index, false) + "')");
      if (is_truth && !wide.count({other, index, true}))
        throwAt(path, header_line, "columns '" + wideName('u', index, true) + "' and '" + wideName('v', index, true) +
                                       "' must be given together");
      truth = truth || is_truth;
    }
    if (seen_axes.empty())
      throwAt(path, header_line, "no point columns: expected u,v (one point), u0,v0,u1,v1,... (wide) or point,u,v (long)");
    n_points = static_cast<int>(seen_axes.size());
    if (indexed)
      for (int i = 0; i < n_points; ++i)
        if (!seen_axes.count(i))
          throwAt(path, header_line, "point indices must run 0.." + std::to_string(n_points - 1) +
                                         " without a gap: missing '" + wideName('u', i, false) + "', '" +
                                         wideName('v', i, false) + "'");
  }
  for (size_t i = 0; i < header.size(); ++i)
    if (!used[i]) track.ignored_columns.push_back(header[i]);

  // Column indices and names resolved once (not per row).
  const int col_t = column["t"];
  const int col_point = long_format ? column["point"] : -1;
  const int col_u = long_format ? column["u"] : -1, col_v = long_format ? column["v"] : -1;
  const int col_ut = long_format && truth ? column["u_true"] : -1, col_vt = long_format && truth ? column["v_true"] : -1;
  struct PointColumns {
    int u, v, u_true, v_true;  ///< -1: no such column
    std::string u_name, v_name, u_true_name, v_true_name;
  };
  std::vector<PointColumns> point_columns;
  if (!long_format) {
    const int first = wide.count({'u', -1, false}) ? -1 : 0;
    for (int p = 0; p < n_points; ++p) {
      const int index = first < 0 ? -1 : p;
      auto find = [&](char axis, bool is_truth) {
        const auto it = wide.find({axis, index, is_truth});
        return it == wide.end() ? -1 : it->second;
      };
      point_columns.push_back({find('u', false), find('v', false), find('u', true), find('v', true),
                               wideName('u', index, false), wideName('v', index, false), wideName('u', index, true),
                               wideName('v', index, true)});
    }
  }
  // The wide rows of text[begin, end) (whole lines) appended to `out` (t_s, u_px, ... sized to the
  // points), `line` counting from the line before the first; throws at the first defect. flatten:
  // the splitting and the push_backs inlined, as they were in the loop this came from (GCC left them
  // out of line here: 8 % more time).
  auto parseWideRows = [&](size_t begin, size_t end, int line, FeatureTrack& out) __attribute__((flatten)) {
    std::vector<std::string_view> cells;
    auto cellOf = [&](int col) { return cells[static_cast<size_t>(col)]; };
    // Room for every line (no regrowth of the columns on the way).
    const size_t lines = static_cast<size_t>(std::count(text.begin() + static_cast<std::ptrdiff_t>(begin),
                                                        text.begin() + static_cast<std::ptrdiff_t>(end), '\n')) + 1;
    for (std::vector<double>* column : columnsOf(out)) column->reserve(column->size() + lines);
    size_t at = begin;
    while (at < end) {
      const auto nl = text.find('\n', at);
      const size_t stop = nl == std::string_view::npos || nl >= end ? end : nl;
      const std::string_view row(text.data() + at, stop - at);
      at = stop == end ? end : stop + 1;
      ++line;
      if (trimView(row).empty()) continue;
      splitCsvView(row, cells);
      if (cells.size() != header.size())
        throwAt(path, line, "expected " + std::to_string(header.size()) + " cells, got " + std::to_string(cells.size()));
      const double t = parseCellView(cellOf(col_t), path, line, "t", false);
      if (!out.t_s.empty() && !(t > out.t_s.back()))
        throwAt(path, line, "column 't': expected a time after the previous row's (strictly increasing), got " +
                                std::string(cellOf(col_t)));
      out.t_s.push_back(t);
      for (int p = 0; p < n_points; ++p) {
        const size_t pp = static_cast<size_t>(p);
        const PointColumns& c = point_columns[pp];
        out.u_px[pp].push_back(parseCellView(cellOf(c.u), path, line, c.u_name, true));
        out.v_px[pp].push_back(parseCellView(cellOf(c.v), path, line, c.v_name, true));
        if (!truth) continue;
        const bool has = c.u_true >= 0;
        out.u_true_px[pp].push_back(has ? parseCellView(cellOf(c.u_true), path, line, c.u_true_name, true) : kNaN);
        out.v_true_px[pp].push_back(has ? parseCellView(cellOf(c.v_true), path, line, c.v_true_name, true) : kNaN);
      }
    }
    return line;
  };
  auto sizeColumns = [&](FeatureTrack& out) {
    out.u_px.resize(static_cast<size_t>(n_points));
    out.v_px.resize(static_cast<size_t>(n_points));
    if (truth) {
      out.u_true_px.resize(static_cast<size_t>(n_points));
      out.v_true_px.resize(static_cast<size_t>(n_points));
    }
  };
  if (!long_format) {
    sizeColumns(track);
    if (!parseWideInPieces(text, pos, jobs, parallel_min_bytes, track, sizeColumns, parseWideRows))
      line_no = parseWideRows(pos, text.size(), line_no, track);  // one thread, or a defect to report
    if (track.t_s.empty()) throwAt(path, line_no, "no data rows after the header (expected at least one)");
    for (int p = 0; p < n_points; ++p) track.point_names.push_back(std::to_string(p));
    return track;
  }

  std::vector<std::string_view> cells;
  auto cellOf = [&](int col) { return cells[static_cast<size_t>(col)]; };
  std::vector<LongRow> long_rows;
  while (nextLine(line_view)) {
    ++line_no;
    if (trimView(line_view).empty()) continue;
    splitCsvView(line_view, cells);
    if (cells.size() != header.size())
      throwAt(path, line_no,
              "expected " + std::to_string(header.size()) + " cells, got " + std::to_string(cells.size()));
    const double t = parseCellView(cellOf(col_t), path, line_no, "t", false);
    LongRow r{t, std::string(cellOf(col_point)), kNaN, kNaN, kNaN, kNaN, line_no};
    if (r.id.empty()) throwAt(path, line_no, "column 'point': expected a point id (integer or name), got an empty cell");
    if (!long_rows.empty() && t < long_rows.back().t)
      throwAt(path, line_no, "column 't': expected the rows of a frame together and frames in increasing time, got " +
                                 std::string(cellOf(col_t)) + " after a later frame");
    r.u = parseCellView(cellOf(col_u), path, line_no, "u", true);
    r.v = parseCellView(cellOf(col_v), path, line_no, "v", true);
    if (truth) {
      r.u_true = parseCellView(cellOf(col_ut), path, line_no, "u_true", true);
      r.v_true = parseCellView(cellOf(col_vt), path, line_no, "v_true", true);
    }
    long_rows.push_back(std::move(r));
  }

  // Long: the point set (integers sorted by value, else in order of first appearance), then frames.
  if (long_rows.empty()) throwAt(path, line_no, "no data rows after the header (expected at least one)");
  bool all_integers = true;
  for (const auto& r : long_rows) {
    long v = 0;
    all_integers = all_integers && integerId(r.id, v);
  }
  std::unordered_map<std::string, int> index_of;
  if (all_integers) {
    std::map<long, std::string> sorted;
    for (auto& r : long_rows) {
      long v = 0;
      integerId(r.id, v);
      r.id = std::to_string(v);  // "07" and "7" are one point
      sorted.emplace(v, r.id);
    }
    for (const auto& kv : sorted) {
      index_of[kv.second] = static_cast<int>(track.point_names.size());
      track.point_names.push_back(kv.second);
    }
  } else {
    for (const auto& r : long_rows)
      if (!index_of.count(r.id)) {
        index_of[r.id] = static_cast<int>(track.point_names.size());
        track.point_names.push_back(r.id);
      }
  }
  const size_t n = track.point_names.size();
  track.u_px.assign(n, {});
  track.v_px.assign(n, {});
  if (truth) {
    track.u_true_px.assign(n, {});
    track.v_true_px.assign(n, {});
  }
  std::vector<int> frame_line(n, 0);  // line of the point's row in the current frame (0: none yet)
  for (const auto& r : long_rows) {
    if (track.t_s.empty() || r.t > track.t_s.back()) {
      track.t_s.push_back(r.t);
      for (size_t p = 0; p < n; ++p) {
        track.u_px[p].push_back(kNaN);
        track.v_px[p].push_back(kNaN);
        if (truth) track.u_true_px[p].push_back(kNaN), track.v_true_px[p].push_back(kNaN);
        frame_line[p] = 0;
      }
    }
    const size_t p = static_cast<size_t>(index_of[r.id]);
    if (frame_line[p] != 0)
      throwAt(path, r.line, "column 'point': point '" + r.id + "' appears twice in the frame at t = " +
                                std::to_string(r.t) + " (first on line " + std::to_string(frame_line[p]) + ")");
    frame_line[p] = r.line;
    track.u_px[p].back() = r.u;
    track.v_px[p].back() = r.v;
    if (truth) track.u_true_px[p].back() = r.u_true, track.v_true_px[p].back() = r.v_true;
  }
  return track;
}

}  // namespace predvs
