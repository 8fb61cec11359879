// predvs app — the feature-track CSV read by `predvs predict` and written by the reports.
//
// Input format (one header row, then one row per frame, comma-separated):
//   t        acquisition time in seconds, finite, strictly increasing (required)
//   u, v     measured image coordinates in pixels (required columns); an EMPTY cell means "no
//            measurement of that coordinate at this frame" (dropped frame, occlusion): the
//            predictors then run predict-only for it
//   u_true, v_true   optional ground truth in pixels (empty cell = unknown)
// Columns may come in any order; an unknown or repeated column name is an error. Blank lines are
// skipped. Every other defect (wrong cell count, non-numeric or non-finite cell, missing or
// non-increasing t, no data rows) throws std::invalid_argument "FILE:LINE: what was expected".
#pragma once

#include <string>
#include <vector>

namespace predvs {

/// A track loaded from CSV. Missing cells are NaN.
struct FeatureTrack {
  std::string path;
  std::vector<double> t_s;
  std::vector<double> u_px, v_px;
  std::vector<double> u_true_px, v_true_px;  ///< empty vectors when the file has no truth columns
  bool hasTruth() const { return !u_true_px.empty(); }
  size_t size() const { return t_s.size(); }
};

/// Reads and validates a feature-track CSV (format above).
FeatureTrack readFeatureTrack(const std::string& path);

/// Parses one CSV cell as a finite double. Empty (after trimming) -> NaN if allow_empty, else an
/// error. Throws std::invalid_argument "FILE:LINE: column 'COL': expected ..." otherwise.
double parseCell(const std::string& cell, const std::string& file, int line, const std::string& column,
                 bool allow_empty);

/// Splits one CSV line on commas (no quoting: predvs files hold numbers and plain names only).
std::vector<std::string> splitCsvLine(const std::string& line);

/// Median of the positive differences of consecutive times (the frame period of a track).
/// Throws std::invalid_argument when fewer than two times are given.
double medianPeriod(const std::vector<double>& t_s);

/// Linear interpolation of the samples (t_s, y) at time t, using only finite y. NaN when t lies
/// outside the span of the finite samples (no extrapolation).
double interpolateAt(const std::vector<double>& t_s, const std::vector<double>& y, double t);

}  // namespace predvs
