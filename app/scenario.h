// predvs app — a scenario file mapped onto the servo layer's configuration structs.
//
// YAML schema (every key optional unless marked; an unknown key anywhere is an error naming the
// file, its line and the key; defaults are those of the servo layer's structs):
//
//   description: one line shown by `predvs list`                                   (string)
//   kind: open-loop | closed-loop                                                  (REQUIRED)
//   seed: 1                      integer >= 0, seeds the measurement noise
//   duration_s: 20 (open) / 25 (closed)
//   timing:                      TimingConfig (docs/MODELS.md §0)
//     base_period_s: 0.04        control period delta
//     frame_period_n: 1          vision period T = N delta
//     delay_frames: H            shorthand for the vision latency t_ac + t_p = H T, split evenly
//                                (t_ac = t_p = H T / 2); 0 <= H <= 2 so that the parallel pipeline
//                                can sustain it; excludes acquisition_lag_s / processing_lag_s
//     acquisition_lag_s: 0.04, processing_lag_s: 0.04, controller_lag_s: 0, servo_lag_s: 0,
//     motion_lag_s: 0, model_motion_lag: false, pipeline: parallel | serial
//   noise: {model: gaussian | uniform | none, sigma: px, round: false}
//   metrics: {steady_start_fraction: 0.5, final_fraction: 0.1, settling_band: 0.05,
//             response_window_s: 3,  open loop: the lag and overshoot after a manoeuvre are the
//                                   largest over this window after it, s (servo/metrics.h)
//             per_feature: false,   closed loop: also mean_e_<f>, rms_e_<f>, max_e_<f> per feature
//             outcome: false,       closed loop: converged / failed figures and the stop at a failure
//                                   (servo/metrics.h, Outcome), with converge_px: 1 (threshold on
//                                   the error, px), converge_hold_s: 1, fail_outside_image: true,
//                                   fail_robot_limit: true}
//   lost: {timeout_s: 1, action: hold | drop | extrapolate}
//                                a feature channel without a measurement for timeout_s (> 0,
//                                acquisition times, s) or more is no longer extrapolated: held at
//                                its last measured value, or (closed loop, a law that can) dropped
//                                from the task; extrapolate = the policy off; a whole target lost
//                                past timeout_s restarts the predictor at re-acquisition
//                                (servo/lost_feature_policy.h)
//   predictors:                  list of names or {name: LABEL, type: NAME, params: {key: value}}
//                                (REQUIRED, at least one; NAME from the predictor registry; LABEL
//                                unique in the list, letters, digits, '-' and '_'; without type:
//                                the label is the registry name. The same predictor may appear
//                                several times under different labels with different params, e.g.
//                                {name: st-akf-pm-switch, type: st-akf-pm, params: {pm_on_alarm: 1}})
//   runs: N                      integer >= 1, runs per predictor in `predvs compare` (run r uses
//                                seed + r); absent: compare's default (ignored by `predvs servo`)
//   sweep: {PATH: [v1, v2, ...]} `predvs compare` runs the scenario once per value, each run of
//                                it being the file loaded with `--set PATH=v` (so every value is
//                                validated like the key itself); PATH is any dotted scenario path
//                                (scenario_override.h): noise.sigma (E6), timing.delay_frames,
//                                task.lambda, predictors.cs-akf.params.a_max, ...; not kind, seed,
//                                runs, description or sweep itself. Several keys make a grid: the
//                                product of their values, in file order (the first key varies
//                                slowest), each cell the file loaded with every KEY=v of the cell,
//                                in that order; a key twice, or a key that contains an earlier one
//                                (task after task.lambda), is an error. The nested spelling
//                                {timing: {frame_period_n: [...]}} is timing.frame_period_n.
//                                `predvs servo` ignores it (it runs the value the file gives)
//   -- open-loop only (prediction experiment E1-E4, units: px) --
//   trajectory: {type: line | accel-jump | zigzag | circle | sinusoid | static | e6-target |
//                onset-sinusoid, <its params>}
//                                (REQUIRED; params as in servo/trajectory.h and
//                                servo/paper_trajectories.h; the type fixes the number of channels:
//                                2 for the planar ones, 3 for e6-target, 1 for onset-sinusoid)
//   occlusions: [{start_s: a, end_s: b}, ...]
//   -- closed-loop only (servo/servo_loop.h: a feature source, the predictor, a task and a robot) --
//   camera: {px: 800, py: 800, u0: 320, v0: 240, width: 2 u0, height: 2 v0}   (width x height: the
//                                image, px; only the outside-image failure of metrics.outcome uses it)
//   target: {square_side_m: 0.1 | points: [[x, y, z], ...] (m, object frame),
//            desired_depth_m: 0.5 | desired_pose: [tx, ty, tz, tux, tuy, tuz] (cdMo),
//            pose: [6] (wMo at t = 0; default identity),
//            trajectory: {type: circle, <params in metres>}}   (type change replaces all params;
//                                the object translates in the world x-y plane, servo/scene.h)
//   initial_pose: [tx, ty, tz, thetaux, thetauy, thetauz]     m and rad, desired camera frame
//   task:   {type: ibvs (default) | NAME, <its parameters>}  (`predvs list` shows the tasks; ibvs:
//                                lambda: 1.0, interaction: current | desired | mean)
//   robot:  {type: free-camera (default) | NAME, <its parameters>} (free-camera:
//                                max_translation_mps: 0.2, max_rotation_radps: 0.7, saturation: 1)
//   source: {type: geometric (default) | dots | apriltag | NAME, <its parameters>} (dots, apriltag:
//           rendered images through a tracker, servo/rendered_image_source.h)
//   occlusions: [{start_s: a, end_s: b}, ...]   frames acquired inside see no point
//   servo: {forecast: feature | feedforward | both, compensation: auto | on | off}
#pragma once

#include "predictor_choice.h"
#include "scenario_override.h"

#include "predvs/predictors/params.h"
#include "predvs/servo/prediction_experiment.h"
#include "predvs/servo/servo_loop.h"

#include <cstdint>
#include <string>
#include <vector>

namespace predvs {

enum class ScenarioKind { OpenLoop, ClosedLoop };

/// One entry of a scenario's predictor list. `name` is its label: unique in the list, shown in the
/// leaderboards, plots and traces, and the NAME of `--set predictors.NAME.params.KEY`; `type` is
/// the registry predictor it builds (`predvs list`). An entry without `type:` has type == name, so
/// one predictor can be listed several times under different labels with different parameters:
///   - {name: kf-cv-paper, type: kf-cv, params: {r: 5, q: 20}}
struct ScenarioPredictor {
  std::string name;  ///< label (unique in the list)
  Params params;
  int line = 0;      ///< line in the scenario file (0 when given on the command line)
  std::string type;  ///< registry name ("" means: the same as name)

  const std::string& typeName() const { return type.empty() ? name : type; }
};

/// A parameter sweep (`sweep:` in a scenario, or `predvs compare --sweep`): the scenario is run
/// once per value, each value applied as the override KEY=VALUE to the scenario document. Several
/// sweeps are the axes of a grid (the product of their values).
struct ScenarioSweep {
  std::string key;                  ///< dotted scenario path, as in --set ("timing.delay_frames")
  std::vector<std::string> values;  ///< each value as YAML text (flow style), in the given order
  std::string origin;               ///< prefix of errors about a value: "FILE:LINE: sweep" or "--sweep"

  bool empty() const { return key.empty(); }
  /// The last segment of the key ("sigma" for noise.sigma): names the variants and the plots.
  std::string shortKey() const;
  /// The override KEY=VALUE of value `i`.
  ScenarioOverride valueOverride(size_t i) const;
};

struct Scenario {
  std::string path;         ///< file it was read from
  std::string name;         ///< file stem
  std::string description;
  ScenarioKind kind = ScenarioKind::ClosedLoop;
  std::vector<ScenarioPredictor> predictors;
  // open loop
  PredictionExperimentConfig open_loop;
  std::string trajectory;   ///< trajectory type (open loop)
  Params trajectory_params;
  int channels = 8;         ///< predictor channels: the trajectory's (open loop), the task's features (closed loop)
  std::vector<ScenarioSweep> sweeps;  ///< `sweep:` axes, in order (empty: none; several: a grid)
  std::vector<double> sigma_sweep;  ///< the values of a lone noise.sigma sweep (else empty)
  int runs = 0;             ///< `runs:` (0 when absent)
  // closed loop
  ServoConfig closed_loop;

  std::uint64_t seed() const { return kind == ScenarioKind::OpenLoop ? open_loop.seed : closed_loop.seed; }
  void setSeed(std::uint64_t seed);
  double durationS() const { return kind == ScenarioKind::OpenLoop ? open_loop.duration_s : closed_loop.duration_s; }
};

/// Reads and validates a scenario file (every key, the timing model, the trajectory, every
/// predictor and its parameters). Throws std::invalid_argument "FILE:LINE: ..." on any defect.
/// `overrides` (`--set PATH=VALUE`, scenario_override.h) are applied in order to the document
/// before the validation; a defect they cause is reported as "--set PATH=VALUE (scenario NAME):
/// ...", naming the first override whose addition makes the parse fail.
Scenario loadScenario(const std::string& path, const std::vector<ScenarioOverride>& overrides = {});

/// Parses `predvs compare --sweep PATH=V1,V2,...` (or PATH=[V1, V2, ...], YAML list syntax, for
/// values that contain commas). Throws std::invalid_argument "--sweep: ..." when there is no '=',
/// the path is malformed or forbidden (see `sweep:` above), the list is empty or a value repeats.
ScenarioSweep parseSweepOption(const std::string& text);

/// Checks the axes of a grid: no key twice, no key that contains an earlier one (it would replace
/// it in every cell). Throws std::invalid_argument "ORIGIN: ..." naming the key.
void checkSweepAxes(const std::vector<ScenarioSweep>& axes);

/// Replaces the sweep axes of `scenario` (and sigma_sweep) by `axes` (empty: no sweep).
void setScenarioSweeps(Scenario& scenario, const std::vector<ScenarioSweep>& axes);

/// Number of cells of a grid: the product of the axes' value counts (0 without axes).
size_t gridCells(const std::vector<ScenarioSweep>& axes);
/// The value index on every axis of cell `cell` (0 <= cell < gridCells()): the first axis varies
/// slowest, the last fastest.
std::vector<size_t> gridIndices(const std::vector<ScenarioSweep>& axes, size_t cell);
/// "task.lambda x timing.frame_period_n".
std::string sweepKeysText(const std::vector<ScenarioSweep>& axes);

/// The scenario at each cell of its sweep axes, in cell order: loadScenario(scenario.path,
/// overrides + {KEY1=v1, KEY2=v2, ...}), with the same `sweeps` member. A cell that the scenario
/// rejects throws std::invalid_argument "ORIGIN KEY1=v1, KEY2=v2 (scenario NAME): <what was
/// expected>" (ORIGIN that of the axis whose value broke the parse; one axis: "ORIGIN KEY=VALUE
/// (scenario NAME): ..."). No axes give no scenarios.
std::vector<Scenario> loadSweepVariants(const Scenario& scenario, const std::vector<ScenarioOverride>& overrides);

std::string scenarioKindName(ScenarioKind kind);

}  // namespace predvs
