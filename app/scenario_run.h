// predvs app — one seeded run of one predictor on a scenario: the single path by which `predvs
// servo` (one run per predictor, with its trace) and `predvs compare` (many runs, figures only)
// run a scenario, so that both report the same figures under the same names for the same seed.
//
// Closed loop: runServoLoop() on the scenario's ServoConfig with that seed; figures
// ServoResult::values. Open loop: runChannelExperiment() on the scenario's trajectory (any number
// of channels) with that seed; figures openLoopRunValues() (servo/run_metrics.h).
//
// Trace rows (kept on request), one per control tick, columns RunLayout::columns:
//   closed loop  ServoLoop::traceColumns(): t_s, t_acq_s, meas_<f>.., pred_<f>.., true_<f>..
//                (f the task's features), error_px, the robot's command components, the task's
//                diagnostics
//   open loop    t_s, t_acq_s, t_pred_s, horizon_s, meas_<c>.., pred_<c>.., true_<c>.. (c the
//                trajectory's channels), error
// Empty (NaN) where a value is not available.
#pragma once

#include "predictor_choice.h"
#include "scenario.h"

#include "predvs/predictors/params.h"

#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace predvs {

/// What the columns of a scenario's trace rows are (the same for every predictor of a scenario).
struct RunLayout {
  std::vector<std::string> columns;      ///< trace columns, in row order
  std::string time_column = "t_s";       ///< control tick time
  std::string error_column;              ///< "error_px" (closed) or "error" (open)
  std::vector<std::string> features;     ///< task features (closed) or trajectory channels (open)
  std::vector<std::string> commands;     ///< command components (closed loop; empty open loop)
  std::vector<std::string> command_units;  ///< their units, when the robot states them (else empty)
  std::vector<std::string> diagnostics;  ///< the task's diagnostics (closed loop; may be empty)
  Eigen::VectorXd desired;               ///< s* (closed loop; empty open loop)

  /// 1-based column of `name` (gnuplot's `using` numbering); std::logic_error if absent.
  size_t column(const std::string& name) const;
};

/// One run of one predictor.
struct RunRecord {
  std::string predictor;
  NamedValues values;              ///< the run's figures (servo/run_metrics.h), same names every run
  std::vector<double> t_s, error;  ///< the error the figures are of, per control tick
  int steady_samples = 0;          ///< samples in the metrics' steady window
  bool prediction_used = true;     ///< closed loop: whether the compensation + prediction path ran
  RunLayout layout;
  std::vector<std::vector<double>> rows;  ///< trace rows (only when asked for)
  /// The predictor's own diagnostics per trace row (Predictor::diagnostics(), e.g. imm's mode
  /// probabilities; only with the trace): names, and one row of values per trace row.
  std::vector<std::string> diagnostic_names;
  std::vector<std::vector<double>> diagnostic_rows;
};

/// Runs predictor `p` on `scenario` with `seed` (which replaces the scenario's). Every call builds
/// its own trajectory, noise, predictor and loop, so calls may run on parallel threads. Throws
/// std::invalid_argument for a configuration the servo layer rejects.
RunRecord runScenarioOnce(const Scenario& scenario, const ScenarioPredictor& p, std::uint64_t seed, bool keep_trace);

/// Replaces the scenario's predictors by `chosen` (elements as parsePredictorChoice() reads them),
/// in that order; no-op when `chosen` is empty. A bare word that labels an entry of the scenario
/// takes that entry as it is (`--predictors st-akf-pm-switch` on E12). Otherwise each starts from the parameters of the scenario's
/// entry of the same label when that entry has the same type (else of the entry named TYPE whose
/// type is TYPE, else the defaults), and the element's KEY=VALUE replace those keys. So on E12
/// `--predictors st-akf-pm,switch=st-akf-pm:pm_on_alarm=1` runs the scenario's st-akf-pm twice,
/// once with each alarm action. Throws std::invalid_argument "OPTION: 'X' listed twice" for a
/// repeated label, or "FILE: ..." for a predictor that cannot be built for the scenario.
void choosePredictors(Scenario& scenario, const std::vector<std::string>& chosen, const std::string& option);

/// What the error of a scenario is and its units, for reports: "px (...)" closed loop and on
/// image trajectories, "scenario units (mm in the E12 scenarios)" on onset-sinusoid.
std::string errorUnits(const Scenario& scenario);
/// The short unit of the error for axis labels ("px" or "mm").
std::string errorUnitLabel(const Scenario& scenario);
/// One sentence defining the per-tick error e of a scenario kind.
std::string errorDefinition(ScenarioKind kind);

/// Events of a scenario's run that the error plots mark.
struct RunEvents {
  std::vector<OcclusionInterval> occlusions;                  ///< frames acquired inside are lost
  double onset_s = std::numeric_limits<double>::quiet_NaN();  ///< open loop: onset of the motion, when > 0
};
RunEvents runEvents(const Scenario& scenario);

}  // namespace predvs
