// predvs app — the feature-track CSV read by `predvs predict` and written by the reports.
//
// A track holds N image points over a sequence of frames. One header row, then data rows,
// comma-separated; the format is detected from the header:
//
//   long  (a column `point`): one row per (frame, point), as `predvs track` writes tracks.csv:
//           t, point, u, v [, u_true, v_true]
//         rows of the same frame have the same t and are consecutive; a point missing from a
//         frame's rows is not measured at that frame; a point twice in one frame is an error.
//         Point ids are integers or names: all integers -> points sorted by value, otherwise in
//         order of first appearance.
//   wide  (no `point` column): one row per frame, as tracks_wide.csv:
//           t, u0, v0, u1, v1, ... [, u0_true, v0_true, ...]
//         the indices 0..N-1 without a gap, each point with both u<i> and v<i>; truth columns
//         optional, per point in pairs, only for points that have u<i>, v<i>. The single-point
//         header t, u, v [, u_true, v_true] is the N = 1 case (point "0"); it is not mixed with
//         indexed columns.
//
// Both: t is the acquisition time in seconds, finite, strictly increasing from frame to frame;
// u, v in pixels; an EMPTY cell means "no measurement of that coordinate at this frame" (dropped
// frame, occlusion, a tracker's lost feature): the predictors then run predict-only for it. Columns
// may come in any order. What spreadsheets and other tools write is accepted: a UTF-8 byte-order
// mark before the header, CRLF line ends, blank lines, and extra columns of any other name, which
// are ignored and listed (FeatureTrack::ignored_columns, summary.json `ignored_columns`). A column
// name given twice is an error. Every other defect (wrong cell count, non-numeric or non-finite
// cell, missing or non-increasing t, an inconsistent point set, no data rows) throws
// std::invalid_argument "FILE:LINE: what was expected".
#pragma once

#include "predvs/servo/sampled_signal.h"  // interpolateAt, medianPeriod

#include <cstddef>
#include <string>
#include <vector>

namespace predvs {

/// A track loaded from CSV: frames (rows of t) x points. Missing cells are NaN.
struct FeatureTrack {
  std::string path;
  std::string format;                        ///< "long" or "wide"
  std::vector<std::string> point_names;      ///< N: the long format's ids, "0".."N-1" for wide
  std::vector<double> t_s;                   ///< frame times
  std::vector<std::vector<double>> u_px, v_px;  ///< [point][frame]
  std::vector<std::vector<double>> u_true_px, v_true_px;  ///< [point][frame]; empty without truth columns
  std::vector<std::string> ignored_columns;  ///< header names that are not part of the format, in order
  bool hasTruth() const { return !u_true_px.empty(); }
  size_t size() const { return t_s.size(); }
  int points() const { return static_cast<int>(point_names.size()); }
};

/// Files whose data rows take fewer bytes are parsed on one thread whatever `jobs` says.
constexpr size_t kParallelParseMinBytes = size_t{4} << 20;

/// Reads and validates a feature-track CSV (format above).
/// jobs >= 2: the data rows of a wide-format file (one row per frame) of at least
/// parallel_min_bytes are cut at line ends into up to 4 * jobs pieces parsed on `jobs` threads and
/// appended in order (the long format is always read on one thread). The track is the same, value
/// for value, as with one thread; so is any error: a piece that meets a defect (or a time that does
/// not increase from one piece to the next) hands the file to the one-thread parse, which reports it
/// with its line.
FeatureTrack readFeatureTrack(const std::string& path, int jobs = 1,
                              size_t parallel_min_bytes = kParallelParseMinBytes);

/// Parses one CSV cell as a finite double. Empty (after trimming) -> NaN if allow_empty, else an
/// error. Throws std::invalid_argument "FILE:LINE: column 'COL': expected ..." otherwise.
double parseCell(const std::string& cell, const std::string& file, int line, const std::string& column,
                 bool allow_empty);

/// Splits one CSV line on commas (no quoting: predvs files hold numbers and plain names only).
std::vector<std::string> splitCsvLine(const std::string& line);

}  // namespace predvs
