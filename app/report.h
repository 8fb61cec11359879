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

#include "number_text.h"
#include "scenario.h"
#include "scenario_run.h"

#include <nlohmann/json.hpp>

#include <ostream>
#include <string>
#include <vector>

namespace predvs {

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
/// gnuplot commands that shade the occlusions and mark the onset of a run on a time axis (plots.h).
std::string eventMarks(const RunEvents& events);

}  // namespace predvs
