// predvs app — `predvs servo`: every predictor of one scenario (closed or open loop, any number of
// features or channels) on the same seed, with plots of that one run.
//
// Runs: one per predictor, the run `predvs compare --runs 1 --seed S` makes for it (scenario_run.h),
// so both commands report the same figures under the same names (servo/run_metrics.h). A
// scenario's `sweep:` is not run: servo runs the value the scenario file itself gives (e6-noise-
// study: sigma 10; delay-study: 2 frames) and says so on stderr; `runs:` is ignored.
//
// Output directory (default out/<scenario>), renamed into place only when everything is written:
//   log.csv        one row per (predictor, control tick): `predictor` then the trace columns
//                  (scenario_run.h). Closed loop: t_s, t_acq_s, meas_<f>.. (latest delivered,
//                  delayed measurement), pred_<f>.. (features the task used), true_<f>.. (f the
//                  task's features: u0, v0, ... for ibvs; x_i, y_i, d_x for vtc), error_px (the
//                  task's tracking error), the applied command (vx .. wz for a camera, joint or
//                  wheel speeds otherwise), the task's diagnostics (e.g. jacobian_error; sliding_norm,
//                  s_u, s_v, gain_q; lyap_f, lyap_bound). Open loop: t_s, t_acq_s, t_pred_s,
//                  horizon_s, meas_<c>.., pred_<c>.., true_<c>.. (c the trajectory's channels: x, y;
//                  x_i, y_i, d_x for E6/E7; x for E12), error. Empty cell = not available (NaN).
//   summary.json   scenario, kind, file, description, seed, duration, command line, --set
//                  overrides, the sweep not run (or null), error definition and units, metric
//                  definitions and, per predictor, its parameters, steps, steady samples and
//                  metrics: the run's figures by name (rmse, final, max, peak, iae, settling_s,
//                  effort, the task's run summary; open loop the figures of run_metrics.h)
//   error.png      error versus time, one line per predictor (occlusions shaded, an onset marked);
//                  open loop adds a panel with a trailing running RMS over max(1 s, 5 % of the
//                  run), because the per-tick prediction error is dominated by measurement noise
//   trajectories.png  closed loop: one image-plane panel per predictor, the task's features taken
//                  in pairs (u, v) (an odd last one, e.g. vtc's d_x, is left to features.png): true
//                  tracks, the features the task used, start and desired points; open loop: the
//                  first two channels as a plane, then every channel versus time, with each
//                  predictor's forecasts (at the effect time they aim at), the measurements and the
//                  truth
//   features.png   closed loop: every task feature versus time, one panel each, one line per
//                  predictor, the desired value dashed
//   command.png    closed loop: every component of the applied command versus time
//   diagnostics.png  closed loop, a task with diagnostics: every diagnostic versus time, one line
//                  per predictor; diagnostics whose names share the part before the first '_'
//                  share a panel (vtc: lyap_f, its bound lyap_bound and lyap_f_bar)
// Each PNG comes with its gnuplot script NAME.gp and the data it reads (trace_<predictor>.dat:
// the trace columns plus the running RMS; desired.dat), so `gnuplot NAME.gp` redraws it.
// The table printed on stdout has the columns `predvs compare` prints (report.h), plus "vs hold".
#pragma once

#include "scenario_override.h"

#include <ostream>
#include <string>
#include <vector>

namespace predvs {

struct ScenarioRunOptions {
  std::string scenario = "ibvs-moving-target";  ///< name in data/scenarios or a .yaml path
  std::vector<std::string> inputs;               ///< the files given (--set-file, --camera, --params): not under --out
  std::vector<std::string> predictors;           ///< overrides the scenario's list when not empty
  bool seed_given = false;
  unsigned long seed = 0;                        ///< overrides the scenario's seed when seed_given
  std::vector<ScenarioOverride> overrides;       ///< --set PATH=VALUE, applied before validation
  std::string out_dir;                           ///< empty: out/<scenario name>
  bool plots = true;
  std::string command_line;                      ///< recorded in summary.json
};

/// Loads, runs and reports a scenario. Throws std::invalid_argument / std::runtime_error for bad
/// input (the output directory is then not created).
void runScenarioCommand(const ScenarioRunOptions& options, std::ostream& out, std::ostream& err);

}  // namespace predvs
