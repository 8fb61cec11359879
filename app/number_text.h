// predvs app — number text and small outputs shared by every command that writes files: the
// summary of a figure over runs (Stats), the number formats of CSV cells, gnuplot data, tables and
// JSON, file-safe names, a predictor's parameters as JSON and a text file in a staging directory.
// Nothing here knows scenarios (report.h builds the metric tables on it), so the track commands
// (track_cli.h) use it without the servo layer.
#pragma once

#include "output_dir.h"

#include "predvs/predictors/params.h"

#include <nlohmann/json.hpp>

#include <limits>
#include <string>
#include <vector>

namespace predvs {

/// Summary of one figure over runs (NaN runs skipped).
struct Stats {
  int n = 0;  ///< finite values
  double mean = std::numeric_limits<double>::quiet_NaN();
  double std = std::numeric_limits<double>::quiet_NaN();  ///< sample std (0 for one value)
  double min = std::numeric_limits<double>::quiet_NaN();
  double max = std::numeric_limits<double>::quiet_NaN();
  /// Middle value (mean of the two middle ones for an even count): what a typical run gives even
  /// when a few runs diverge (E9's unstable runs on the arm make the mean meaningless).
  double median = std::numeric_limits<double>::quiet_NaN();
};
Stats stats(const std::vector<double>& xs);

/// Number formats: CSV / JSON-like text ("" for NaN, `precision` significant digits), gnuplot data
/// ("NaN"), and tables (3 decimals, 1 from 100 on, scientific beyond 1e5 or under 1e-3; "-" for NaN).
std::string csvNumber(double x, int precision = 6);
std::string datNumber(double x);
std::string tableNumber(double x);
/// A CSV cell that round-trips a pixel coordinate or a time: "" for NaN, 10 significant digits.
std::string csvCell(double x);
/// Fixed-point text with `decimals` decimals, "-" for NaN (tables).
std::string fixedNumber(double x, int decimals);
/// JSON number, null for NaN.
nlohmann::json jsonNumber(double x);
/// A file-name-safe version of a name (anything but [A-Za-z0-9_-] becomes '_').
std::string fileSafe(const std::string& s);

/// {key: value} of a predictor's parameters.
nlohmann::json paramsJson(const Params& params);
/// {name: value} of named values (Predictor::tallies(), summed over a run's instances).
nlohmann::json namedValuesJson(const NamedValues& values);

/// Writes `text` to `name` in the staging directory (std::runtime_error naming the file if it fails).
void writeTextFile(const StagedOutputDir& dir, const std::string& name, const std::string& text);

}  // namespace predvs
