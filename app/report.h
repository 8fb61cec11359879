// predvs app — what `predvs servo` and `predvs compare` have in common when they report: the
// figures of a run by name (servo/run_metrics.h), summarised over runs, as tables (terminal and
// markdown), CSV cells, JSON and metric definitions. One module, so that both commands print and
// write the same names, the same columns and the same number formats.
//
// A servo report is a compare report of one run per predictor: every cell is a Stats of one value
// (n = 1, std = 0, or n = 0 for NaN).
//
// Table columns (tableMetrics(), both commands): rmse, final, max, peak, iae, settling_s, effort,
// the task's run summary values (closed loop), and in open loop the occlusion figures but occl_max,
// the manoeuvre response, the per-channel pos_mse_/vel_mse_ when the scenario sweeps noise.sigma or
// does not have 2 channels, and false_alarms_per_min, detected, detect_delay_frames when the
// trajectory declares an onset, and with metrics.outcome converged, convergence_time_s and failed
// (not failure_time_s and the fail_* kinds); every figure is in the CSV / JSON. With a predictor named `hold`
// among the rows, the terminal table adds "vs hold" = rmse of hold / rmse of the row.
#pragma once

#include "output_dir.h"
#include "scenario.h"

#include "predvs/predictors/params.h"

#include <nlohmann/json.hpp>

#include <limits>
#include <ostream>
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

/// Rows (predictors, in display order) by metrics.
struct MetricTable {
  std::vector<std::string> metrics;
  std::vector<std::string> rows;
  std::vector<std::vector<Stats>> cells;  ///< [row][metric]
  int runs = 1;                           ///< runs per cell (markdown marks n < runs as (n/runs))
};

/// The figures of `names` that go into the tables of `scenario` (header rule), in their order.
std::vector<std::string> tableMetrics(const std::vector<std::string>& names, const Scenario& scenario);
/// When the rows hold imm, kf-cv and kf-ca: one line "imm / best of kf-cv, kf-ca (rmse): R (within
/// 10 %)" plus imm / hold when `hold` is a row (issue 11's target for imm); empty otherwise.
std::string immAgainstSingleModels(const MetricTable& table);
/// Means in fixed-width columns, plus "vs hold" when a row is `hold` (then a footnote line), plus
/// immAgainstSingleModels' line when it applies.
void printMetricTable(const MetricTable& table, std::ostream& out);
/// A markdown table: "| # | predictor | m1 | ..." with mean ± std (std only with n > 1).
std::string markdownMetricTable(const MetricTable& table);

/// {name: definition} for `names` (servo/run_metrics.h; the task's run summary values of a closed
/// loop point at the task's header).
nlohmann::json metricDefinitionsJson(const std::vector<std::string>& names, const Scenario& scenario);
/// {key: value} of a predictor's parameters.
nlohmann::json paramsJson(const Params& params);

/// Writes `text` to `name` in the staging directory (std::runtime_error naming the file if it fails).
void writeTextFile(const StagedOutputDir& dir, const std::string& name, const std::string& text);

}  // namespace predvs
