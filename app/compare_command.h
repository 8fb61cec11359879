// predvs app — `predvs compare`: every chosen predictor on every chosen scenario, many seeded runs
// each, in parallel, summarised as a leaderboard with plots. Every predictor of a cell runs on the
// same seeds in one run, so that "predictor A beats predictor B" is a like-for-like claim.
//
// Runs and seeds: a scenario runs `runs` times per predictor (--runs, else the scenario's `runs:`
// key, else kDefaultRuns); run r (0-based) uses seed S + r for every predictor, S = --seed or the
// scenario's seed.
// Sweeps: a scenario with `sweep: {PATH: [v1, v2, ...]}` (scenario.h; e.g. noise.sigma in E6,
// timing.delay_frames in delay-study), or every chosen scenario under `--sweep PATH=v1,v2,...`
// (which replaces a scenario's own sweep), runs once per value, each value a "variant" named
// <scenario>@<KEY>=<value> (KEY the last segment of PATH: e6-noise-study@sigma=10,
// delay-study@delay_frames=1) with the same seeds. A variant is the scenario file loaded again with
// the --set overrides and then PATH=value, so a value is validated like any scenario key and a bad
// one is the error "ORIGIN PATH=value (scenario NAME): ..." (ORIGIN "FILE:LINE: sweep" or
// "--sweep"), before anything runs. Every run builds its own trajectory, noise generator,
// predictor (or servo loop), so the numbers do not depend on --jobs or on the order of the runs.
// Grids: several --sweep options (or a `sweep:` block with several keys) run the product of their
// values; each cell is a variant named <scenario>@<KEY1>=<v1>,<KEY2>=<v2> (e10@lambda=1.4,
// frame_period_n=8; the whole paths when two keys share their last segment), the scenario loaded
// with every KEY=value of the cell, in the order of the keys (the first varies slowest), with the
// same seeds in every cell; a bad cell is "ORIGIN KEY1=v1, KEY2=v2 (scenario NAME): ...". A run is
// thus identified by (scenario, cell values, predictor, seed) and computed from them alone (the
// basis for sharding and resuming a grid, issue #9).
// Predictors: --predictors all (the registry) or a list; each uses the parameters the scenario
// gives it when the scenario lists it, its defaults otherwise; without --predictors, each
// scenario's own list.
//
// Figures per run: the same names `predvs servo` prints and writes, computed in the servo layer
// (servo/include/predvs/servo/run_metrics.h has the list and definitions; leaderboard.json repeats
// the definitions under metric_definitions). Open loop (the error e is ||predicted - true|| over
// the channels at the effect time, in the scenario's units): rmse, final, max, peak, iae,
// settling_s; pos_mse_<ch>, vel_mse_<ch> per channel; with occlusions occl_rmse, occl_max,
// occl_end_error, reacq_error, reacq_1s_rmse; alarms, false_alarms_per_min; with an onset after
// t = 0 (E12) detected, detect_delay_frames; with a manoeuvre (E1-E3, E12) resp_max_lag,
// resp_overshoot, resp_mean_3s, resp_time_s. Closed loop (e is the task's tracking error, px):
// rmse, final, max, peak, iae, settling_s, effort, with metrics.outcome converged,
// convergence_time_s, failed, failure_time_s, fail_behind, fail_image, fail_robot (servo/metrics.h,
// Outcome; a failed run stops early and has NaN steady figures), then the task's run summary (e.g.
// jacobian_error_final for ibvs-broyden, sliding_rms_final for vsc, lyap_bound_positive_fraction
// for vtc).
// Aggregates over runs: n (finite values), mean, std (sample, 0 for one run), min, max.
//
// Output directory (default out/compare), created only when everything succeeded:
//   leaderboard.csv   scenario,variant,predictor,metric,n,mean,std,min,max,median (one row per metric)
//                     (a variant id with a comma, a grid cell's, is quoted)
//   leaderboard.json  the same, nested, with each scenario's runs, seeds, units, metric
//                     definitions and sweep ({key, values, from}; each variant's sweep_value) or, for
//                     a grid, grid (a list of them; each variant's grid_values {key: value}), the
//                     --set overrides and the --sweep (applied to every scenario: its text, a list
//                     of texts for a grid, null without)
//   leaderboard.md    one table per variant (for a sweep: its first and last value; for a grid:
//                     its first and last cell), predictors
//                     ranked by mean rmse, mean ± std, the columns of report.h (tableMetrics(): the
//                     same columns `predvs servo` prints); the terminal shows the same tables
//                     (means) with "vs hold" when hold is among the predictors
//   error_<variant>.png  mean over runs of the error versus time, one line per predictor, each
//                     with about 20 markers of its own shape, staggered, so that coinciding lines
//                     stay told apart (for a sweep: its first and last value; occlusions shaded,
//                     an onset marked), with
//                     error_<variant>.gp / .dat; the file id of a variant is
//                     <scenario>_<KEY><value> (error_e6-noise-study_sigma10.png)
//   mse_vs_sigma_<scenario>.png  open-loop noise.sigma sweeps: position and velocity MSE per
//                     channel versus sigma_n, one line per predictor (paper 001 Fig. 8 analogue)
//   rmse_vs_<KEY>_<scenario>.png  any other one-key sweep: median over the runs of rmse (bars
//                     from the best to the worst run) versus the swept value, one line per
//                     predictor (values that are not numbers are placed in order, labelled with
//                     their text)
//   grid_<scenario>.csv  every swept scenario (one key or a grid): one row per cell and predictor,
//                     scenario,variant,<every swept path>,predictor,n,converged_fraction,
//                     convergence_time_median_s,failed_fraction,fail_behind_fraction,
//                     fail_image_fraction,fail_robot_fraction,rmse_median,rmse_n (fractions over the
//                     n runs; the median convergence time over the converged runs, the median rmse
//                     over the rmse_n runs that have one, i.e. did not fail; the outcome columns are
//                     empty without metrics.outcome)
//   heatmap_<scenario>[_<KEY><value>..].png  a grid of two or more keys (paper 003 Fig. 4
//                     analogue): the first key across, the second up, one panel per predictor,
//                     coloured by the median convergence time, grey where no run converged (dark
//                     when some failed), a cross where some run failed, each cell labelled; one
//                     figure per combination of the values of the further keys (task.type as a
//                     third key: one heat map per task)
//   report.html       the leaderboard (sortable), heat maps, plots, scenario set-ups and command in one
//                     self-contained page (campaign_html.h)
//   runs/             one record per run (campaign.h); a shard (--shard I/N) writes only runs/ and
//                     shard.json
// Campaigns (campaign.h, issue #12): the outputs are byte-identical whatever --jobs, the MPI ranks
// (mpirun), the shards merged (predvs merge) or --resume: they hold no wall time or thread count,
// and the command without --out, --jobs, --shard, --resume, --stop-after.
#pragma once

#include "scenario.h"
#include "scenario_override.h"

#include <ostream>
#include <string>
#include <vector>

namespace predvs {

struct CompareOptions {
  std::vector<std::string> scenarios;   ///< names or .yaml paths; {"all"} = every scenario file
  std::vector<std::string> inputs;      ///< the files given (--set-file, --camera, --params): not under --out
  std::vector<std::string> predictors;  ///< names; {"all"} = registry; empty = each scenario's list
  int runs = 0;                         ///< > 0 overrides every scenario's runs
  bool seed_given = false;
  unsigned long seed = 0;               ///< base seed S when seed_given
  std::vector<ScenarioOverride> overrides;  ///< --set PATH=VALUE, applied to every scenario
  /// --sweep PATH=V1,V2 (parseSweepOption), once per axis (several: a grid, checkSweepAxes());
  /// empty = the scenarios' own
  std::vector<ScenarioSweep> sweeps;
  int jobs = 0;                         ///< worker threads; 0 = std::thread::hardware_concurrency()
  std::string out_dir = "out/compare";
  bool plots = true;
  bool progress_bar = false;            ///< redraw a bar on `err` (a terminal); else a few lines
  std::string command_line;             ///< recorded in leaderboard.json / .md (campaignArgs(): without --out, --jobs, ...)
  // Campaigns (campaign.h, issue #12)
  int shard_index = 0;                  ///< --shard I/N: I (1-based); 0 = the whole campaign
  int shard_count = 0;                  ///< N
  std::string resume_dir;               ///< --resume DIR: reuse the run records found there
  int stop_after = 0;                   ///< --stop-after N (test hook): fail after N runs are stored
};

/// Runs without a `runs:` key and without --runs.
constexpr int kDefaultRuns = 20;

/// Validates everything, runs, writes the outputs and prints the leaderboard. Throws
/// std::invalid_argument / std::runtime_error on bad input (nothing is written then).
void runCompareCommand(const CompareOptions& options, std::ostream& out, std::ostream& err);

}  // namespace predvs
