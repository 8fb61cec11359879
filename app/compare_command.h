// predvs app — `predvs compare`: every chosen predictor on every chosen scenario, many seeded runs
// each, in parallel, summarised as a leaderboard with plots (METHODS §10: "a figure that predictor
// A beats predictor B is only claimed when measured on the same seeds in one run").
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
// Predictors: --predictors all (the registry) or a list; each uses the parameters the scenario
// gives it when the scenario lists it, its defaults otherwise; without --predictors, each
// scenario's own list.
//
// Metrics per run (open loop: the error is ||predicted - true|| over the channels at the effect
// time, in the scenario's units; closed loop: RMS image error of the 4 points, px):
//   rmse, final, peak, iae, settling_s   as in servo/metrics.h (rmse over the steady window)
//   effort                               closed loop: control effort (metrics.h)
//   pos_mse_<ch>, vel_mse_<ch>           open loop, per channel: MSE of the position and of the
//                                        velocity over the run (paper 001 Table 2)
//   occl_rmse, occl_max                  with occlusions: RMS / max error over the ticks whose latest
//                                        delivered frame was lost (prediction through the occlusion)
//   occl_end_error                       with occlusions: error at the last tick before a frame is
//                                        delivered again (the extrapolation over the whole gap)
//   reacq_error, reacq_1s_rmse           with occlusions: error at the first tick after a frame is
//                                        delivered again, and RMS error over the following 1 s
//                                        (these three: means over the occlusions of the run)
//   alarms, false_alarms_per_min         open loop: discontinuity-monitor alarms (st-akf family;
//                                        0 for the others), and those that are not the detection
//                                        of the onset, per minute of run
//   detected, detect_delay_frames        trajectory with an onset after t = 0 (E12): 1 if an alarm came from a
//                                        frame acquired in [t_onset, t_onset + kDetectWindowS), and
//                                        its delay in frames after the first frame at or after the
//                                        onset (NaN when not detected)
//   resp_max_lag, resp_overshoot,        trajectory with a manoeuvre (E1 start, E2 jump, E3 switch, E12 onset;
//   resp_mean_3s, resp_time_s            servo/trajectory.h): the largest lag behind and overshoot past the
//                                        change (error projected on its direction, 0.5 s trailing mean),
//                                        mean error over the 3 s after it, and the time from it until the
//                                        error settles (servo/metrics.h, computeResponse)
// Aggregates over runs: n (finite values), mean, std (sample, 0 for one run), min, max.
//
// Output directory (default out/compare), created only when everything succeeded:
//   leaderboard.csv   scenario,variant,predictor,metric,n,mean,std,min,max (one row per metric)
//   leaderboard.json  the same, nested, with each scenario's runs, seeds, units and sweep ({key,
//                     values, from}; each variant's sweep_value), the --set overrides and the
//                     --sweep (applied to every scenario; null without)
//   leaderboard.md    one table per variant (for a sweep: its first and last value), predictors
//                     ranked by mean rmse, mean ± std
//   error_<variant>.png  mean over runs of the error versus time, one line per predictor (for a
//                     sweep: its first and last value), with error_<variant>.gp / .dat; the file id
//                     of a variant is <scenario>_<KEY><value> (error_e6-noise-study_sigma10.png)
//   mse_vs_sigma_<scenario>.png  open-loop noise.sigma sweeps: position and velocity MSE per
//                     channel versus sigma_n, one line per predictor (paper 001 Fig. 8 analogue)
//   rmse_vs_<KEY>_<scenario>.png  any other sweep: mean ± std over the runs of rmse versus the
//                     swept value, one line per predictor (values that are not numbers are placed
//                     in order, labelled with their text)
#pragma once

#include "scenario.h"
#include "scenario_override.h"

#include <ostream>
#include <string>
#include <vector>

namespace predvs {

struct CompareOptions {
  std::vector<std::string> scenarios;   ///< names or .yaml paths; {"all"} = every scenario file
  std::vector<std::string> predictors;  ///< names; {"all"} = registry; empty = each scenario's list
  int runs = 0;                         ///< > 0 overrides every scenario's runs
  bool seed_given = false;
  unsigned long seed = 0;               ///< base seed S when seed_given
  std::vector<ScenarioOverride> overrides;  ///< --set PATH=VALUE, applied to every scenario
  ScenarioSweep sweep;                  ///< --sweep PATH=V1,V2 (parseSweepOption); empty = the scenarios' own
  int jobs = 0;                         ///< worker threads; 0 = std::thread::hardware_concurrency()
  std::string out_dir = "out/compare";
  bool plots = true;
  bool progress_bar = false;            ///< redraw a bar on `err` (a terminal); else a few lines
  std::string command_line;             ///< recorded in leaderboard.json / .md
};

/// Runs without a `runs:` key and without --runs.
constexpr int kDefaultRuns = 20;
/// An alarm counts as detecting the onset when it comes from a frame acquired within this long
/// after the onset (s).
constexpr double kDetectWindowS = 0.5;

/// Validates everything, runs, writes the outputs and prints the leaderboard. Throws
/// std::invalid_argument / std::runtime_error on bad input (nothing is written then).
void runCompareCommand(const CompareOptions& options, std::ostream& out, std::ostream& err);

}  // namespace predvs
