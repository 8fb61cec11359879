#include "cli.h"

#include "calibrate_command.h"
#include "campaign.h"
#include "compare_command.h"
#include "fit_command.h"
#include "number_text.h"
#include "output_dir.h"
#include "scenario_file.h"
#include "scenario_inputs.h"
#include "scenario_override.h"
#include "scenario_run.h"
#include "servo_command.h"
#include "track_cli.h"
#include "track_command.h"

#include "predvs/predictors/glitch_gate.h"
#include "predvs/predictors/predictor.h"
#include "predvs/servo/feature_source.h"
#include "predvs/servo/image_tracker.h"
#include "predvs/servo/robot.h"
#include "predvs/tasks/task.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <limits>
#include <iostream>
#include <sstream>
#include <unistd.h>

namespace predvs {
namespace {

// ---------------------------------------------------------------------------------------------
/// One section of `predvs list`: a title and (name, summary) rows aligned on the longest name.
template <class Rows>
void listSection(std::ostream& out, const std::string& title, const Rows& rows) {
  out << title << "\n";
  size_t w = 4;
  for (const auto& r : rows) w = std::max(w, r.name.size());
  for (const auto& r : rows) out << "  " << std::left << std::setw(static_cast<int>(w)) << r.name << "  " << r.summary << "\n";
}

/// servo's and compare's --params.
constexpr const char* kParamsFileHelp =
    "predictor parameter file (fit-noise), or the name of one of predvs's own (pre-issue-11, ...): each "
    "entry becomes --set predictors.NAME.params.KEY=VALUE";

/// A CLI11 check: a length > 0 (m) ("" when it is one, else why not).
std::string positiveLength(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0' && v > 0.0 && std::isfinite(v) ? "" : "expected a length > 0 (m), got '" + text + "'";
}

int runList(std::ostream& out) {
  listSection(out, "Predictors (predvs predict --predictor NAME, scenario `predictors:` lists):", predictorRegistry());
  listSection(out, "\nTasks, control laws (closed-loop scenario `task: {type: NAME, ...}`):", taskRegistry());
  listSection(out, "\nRobots (closed-loop scenario `robot: {type: NAME, ...}`):", robotRegistry());
  listSection(out, "\nFeature sources (closed-loop scenario `source: {type: NAME, ...}`):", featureSourceRegistry());
  listSection(out, "\nImage trackers (predvs track --source NAME, --set KEY=VALUE for their parameters):",
              imageTrackerRegistry());
  struct Row {
    std::string name, summary;
  };
  std::vector<Row> rows;
  for (const auto& s : listScenarios()) rows.push_back({s.name, s.description});
  listSection(out, "\nScenarios (predvs servo --scenario NAME, predvs compare --scenarios A,B), in " + scenariosDir() + ":", rows);
  if (rows.empty()) out << "  (none found)\n";
  return 0;
}

/// --params FILE for servo / compare: one `--set predictors.NAME.params.KEY=VALUE` per entry.
void paramsFileOverrides(const std::string& file, std::vector<ScenarioOverride>& overrides) {
  for (const auto& f : readParamsFile(file)) {
    std::ostringstream v;
    for (const auto& kv : f.params.values()) {
      v.str("");
      v << std::setprecision(10) << kv.second;
      overrides.push_back(parseScenarioOverride("predictors." + f.name + ".params." + kv.first + "=" + v.str()));
    }
    for (const auto& kv : f.params.texts())
      overrides.push_back(parseScenarioOverride("predictors." + f.name + ".params." + kv.first + "=" + kv.second));
  }
}

// ---------------------------------------------------------------------------------------------
struct TrackArgs {
  std::string images, source = "dots", predictor = "all", delay_frames = "2", fps = "30", out_dir = "out/track";
  std::string strip_frames = "4", max_frames;
  std::string glitch_sigmas = csvNumber(kTrackerGlitchSigmas);  ///< --glitch-sigmas G
  std::vector<std::string> sets;
  bool no_plots = false;
};

int runTrack(const TrackArgs& a, const std::string& command_line, std::ostream& out, std::ostream& err) {
  StagedOutputDir::checkReplaceable(a.out_dir, {a.images});
  TrackOptions o;
  o.images = a.images;
  o.source = a.source;
  o.predictors = predictorSpecs(a.predictor);
  setGlitchSigmas(o.predictors, parseNumberArg("--glitch-sigmas", a.glitch_sigmas));
  o.delay_frames = static_cast<int>(parseIntegerArg("--delay-frames", a.delay_frames, 0, 100000));
  setHorizonFrames(o.predictors, o.delay_frames);
  o.fps = parseNumberArg("--fps", a.fps);
  if (!(o.fps > 0.0)) throw std::invalid_argument("--fps: expected a number > 0, got '" + a.fps + "'");
  o.strip_frames = static_cast<int>(parseIntegerArg("--strip-frames", a.strip_frames, 0, 50));
  if (!a.max_frames.empty()) o.max_frames = parseIntegerArg("--max-frames", a.max_frames, 1, 1000000000L);
  for (const auto& kv : a.sets) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) throw std::invalid_argument("--set: expected KEY=VALUE, got '" + kv + "'");
    o.source_params.set(kv.substr(0, eq), parseNumberArg("--set " + kv.substr(0, eq), kv.substr(eq + 1)));
  }
  o.out_dir = a.out_dir;
  o.plots = !a.no_plots;
  o.progress = &err == &std::cerr && ::isatty(STDERR_FILENO);
  o.command_line = command_line;
  runTrackCommand(o, out, err);
  return 0;
}

/// --set-file, then --camera (scenario_inputs.h): the overrides that come before every --set.
std::vector<ScenarioOverride> fileOverrides(const std::string& set_file, const std::string& camera,
                                            const std::string& camera_name, bool name_given) {
  std::vector<ScenarioOverride> o;
  if (!set_file.empty()) o = setFileOverrides(set_file);
  if (name_given && camera.empty()) throw std::invalid_argument("--camera-name: needs --camera FILE");
  if (!camera.empty()) {
    const auto c = cameraOverrides(camera, camera_name);
    o.insert(o.end(), c.begin(), c.end());
  }
  return o;
}

}  // namespace

int runCli(std::vector<std::string> args, std::ostream& out, std::ostream& err) {
  const std::string command_line = commandLine(args);
  CLI::App app{"predvs: predictive visual servoing. Compare feature predictors that compensate "
               "the vision delay, open-loop on recorded tracks and in closed-loop IBVS.", "predvs"};
  app.require_subcommand(1);
  app.footer("Errors: one line 'predvs: error: ...' on stderr, exit status 2, no output directory.");

  app.add_subcommand("list", "List the registered predictors and the scenarios (with the data directory they are read from).");
  const TrackSubcommands tracks(app);  // predict, fit-noise, make-track, track-study (track_cli.h)


  TrackArgs ta;
  CLI::App* track = app.add_subcommand("track", "Track points through an image sequence or video and score the predictors on them");
  track->footer(
      "Reads the frames (a printf pattern such as ViSP-images/mire-2/image.%04d.pgm, a directory of images, one image, "
      "or a video), stamps frame k with t = k / fps, runs the image tracker --source on every frame (parameters: "
      "--set KEY=VALUE, see `predvs list` and the tracker's header), then runs each predictor on each point's track "
      "and compares the prediction made at frame r for H frames later with the measurement at frame r + H. "
      "A missing, corrupt or differently sized frame is a logged skip (one stderr line each); a frame where every "
      "point is lost is logged. Prints the leaderboard (RMSE, median, max in px, pooled and per point). Writes "
      "DIR/tracks.csv (t,point,u,v; empty u,v = not measured: `predvs predict` reads it), tracks_wide.csv "
      "(t,u0,v0,u1,v1,...), predictions.csv, leaderboard.csv/.json, strip.png (K frames with the tracked points and "
      "each predictor's prediction), tracks.png and errors.png (gnuplot), summary.json (frames read/skipped with "
      "reasons, points, errors).\n"
      "Errors: one line 'predvs: error: ...' on stderr, exit status 2, no output directory.");
  track->add_option("--images", ta.images, "image sequence: PATTERN with %0Nd, DIR, IMAGE or VIDEO")
      ->required()
      ->type_name("SPEC");
  track->add_option("--source", ta.source, "image tracker (see `predvs list`)")->capture_default_str()->type_name("NAME");
  track->add_option("--predictor", ta.predictor,
                    "predictor name, comma list, or 'all'; an element may be [LABEL=]NAME[:KEY=VALUE...] as in predict")
      ->capture_default_str()
      ->type_name("NAME|A,B|all");
  track->add_option("--delay-frames", ta.delay_frames, "prediction horizon H in frames (told to the predictors as horizon_frames)")->capture_default_str()->type_name("H");
  track->add_option("--fps", ta.fps, "frame rate of the recording (time stamps t = k / fps)")
      ->capture_default_str()
      ->type_name("F");
  track->add_option("--set", ta.sets, "tracker parameter KEY=VALUE (repeatable), e.g. --set points=5")->type_name("KEY=VALUE");
  track->add_option("--strip-frames", ta.strip_frames, "frames drawn side by side in strip.png (0: none)")
      ->capture_default_str()
      ->type_name("K");
  track->add_option("--max-frames", ta.max_frames, "read at most N frames")->type_name("N");
  track->add_option("--glitch-sigmas", ta.glitch_sigmas,
                    "the glitch gate on every predictor that does not set glitch_sigmas itself: a point G sigmas off the "
                    "line of the two frames before it is held in doubt until the next frame shows a tracker glitch (kept "
                    "out of the predictor) or a step (docs/MODELS.md §16); 0 = off")
      ->capture_default_str()
      ->type_name("G");
  track->add_option("--out", ta.out_dir, "output directory, replaced only when the run succeeds")
      ->capture_default_str()
      ->type_name("DIR");
  track->add_flag("--no-plots", ta.no_plots, "do not draw tracks.png / errors.png (no gnuplot needed)");

  ScenarioRunOptions so;
  std::string predictors_csv, seed_text, servo_params_file;
  std::vector<std::string> servo_sets;
  bool servo_no_plots = false;
  CLI::App* servo =
      app.add_subcommand("servo", "Run a scenario (closed loop or open loop) once per predictor on one seed, with plots");
  servo->footer(
      "Runs every predictor of the scenario on the same seed. A closed-loop scenario (kind: closed-loop; "
      "the default ibvs-moving-target is IBVS on a moving 4-point target with a 2-frame vision delay, "
      "comparing hold, kf-cv and cs-akf-adaptive) runs the servo loop once per predictor; an open-loop "
      "scenario (kind: open-loop: e1-line .. e4-circle, e6-noise-study, e7-occlusion, e12-*) runs the "
      "prediction experiment on its trajectory's channels. Each predictor is told the longest horizon the "
      "scenario's timing asks for (horizon_frames) and, in closed loop, closed_loop: 1 (every filter with a "
      "raise of its process noise then adapts it until its innovations are white, or until their lag-one "
      "correlation is q_white_rho (0.2 for kf-ca, st-akf, st-akf-pm and imm), unless the keys that set it are "
      "given; imm leaves its constant-position mode out; a filter coasts through a gap with coast_tau_s 0.5 s "
      "instead of 0.2), "
      "unless the scenario gives them. A scenario's sweep is not "
      "run (servo runs the "
      "value its file gives; `predvs compare` runs the sweep). `predvs list` shows the scenarios. Prints "
      "the figures of each run under the names `predvs compare` uses (rmse, final, max, peak, iae, "
      "settling_s, effort, the law's run summary; open loop: per-channel MSE, occlusion, alarm and "
      "response figures). Writes DIR/log.csv (one row per predictor and control tick; a predictor's own "
      "diagnostics, e.g. imm's mode probabilities, as trailing columns), DIR/summary.json "
      "(figures per predictor with their definitions, scenario, seed, command line), DIR/error.png and "
      "DIR/trajectories.png, and in closed loop DIR/features.png, DIR/command.png and, for a law with "
      "diagnostics, DIR/diagnostics.png (with their gnuplot scripts and data). "
      "--set PATH=VALUE changes one value of the scenario file before it is validated, e.g. "
      "--set servo.forecast=feature, --set task.lambda=6, --set duration_s=6, "
      "--set predictors.kf-cv.params.q=50 (a list element is chosen by index or by name; a name "
      "the list lacks is added); the overrides are recorded in summary.json.\n"
      "Errors: one line 'predvs: error: ...' on stderr, exit status 2, no output directory.");
  servo->add_option("--scenario", so.scenario, "scenario name (predvs list), or a path to a .yaml file")
      ->capture_default_str()
      ->type_name("NAME|FILE");
  servo->add_option("--predictors", predictors_csv,
                    "comma-separated predictors replacing the scenario's list, each [LABEL=]TYPE[:KEY=VALUE...] "
                    "(one the scenario lists keeps its params; the same TYPE twice under two labels, e.g. "
                    "kf-cv,kf-cv-r5=kf-cv:r=5; default: the scenario's list)")
      ->type_name("A,B,C");
  servo->add_option("--set", servo_sets,
                    "override a scenario value (repeatable): PATH is a dotted YAML path, VALUE is YAML; "
                    "unknown keys and bad values are errors as in the file")
      ->type_name("PATH=VALUE");
  std::string servo_camera, servo_camera_name, servo_set_file;
  servo->add_option("--camera", servo_camera,
                    "ViSP camera XML (e.g. from `predvs calibrate camera`): sets camera.px, py, u0, v0, width, height")
      ->type_name("FILE");
  servo->add_option("--camera-name", servo_camera_name, "camera name in the --camera file (default: its first camera)")
      ->type_name("NAME");
  servo->add_option("--set-file", servo_set_file,
                    "YAML fragment of scenario keys applied as --set overrides before them (e.g. the timing.yaml of "
                    "`predvs calibrate latency`)")
      ->type_name("FILE");
  servo->add_option("--seed", seed_text, "random seed, overriding the scenario's (default: the scenario's)")
      ->type_name("N");
  servo->add_option("--out", so.out_dir, "output directory, replaced only when the run succeeds (default: out/<scenario>)")
      ->type_name("DIR");
  servo->add_flag("--no-plots", servo_no_plots, "do not draw PNG plots (no gnuplot needed)");
  servo->add_option("--params", servo_params_file, kParamsFileHelp)->type_name("FILE");

  CompareOptions co;
  std::string cmp_scenarios = "all", cmp_predictors, cmp_runs, cmp_seed, cmp_jobs;
  std::vector<std::string> cmp_sets;
  bool cmp_no_plots = false;
  std::string cmp_params_file;
  CLI::App* compare = app.add_subcommand(
      "compare", "Leaderboard: every predictor on every scenario, many seeded runs in parallel");
  compare->footer(
      "Runs each chosen predictor on each chosen scenario (open and closed loop; a scenario with "
      "`sweep: {PATH: [...]}`, e.g. e6-noise-study or delay-study, once per value) N times, run r with seed S + r for "
      "every predictor, on a pool of threads; every run builds its own predictor and noise generator, so the "
      "numbers do not depend on --jobs. Without --runs a scenario runs as often as its `runs:` key says "
      "(default 20). Predictors take the parameters their scenario gives them, their defaults otherwise, and "
      "are told the longest horizon of the scenario's timing (horizon_frames) and, in closed loop, "
      "closed_loop: 1 (predictor.h), unless it gives them. "
      "Writes DIR/leaderboard.csv, leaderboard.json, leaderboard.md (mean, std, min, max and median over runs of "
      "each metric), error_<scenario>.png (mean error versus time) and, for sweeps, mse_vs_sigma_<scenario>.png "
      "(noise.sigma, open loop) or rmse_vs_<KEY>_<scenario>.png. "
      "--sweep PATH=V1,V2,... (or PATH=[V1, V2]) runs every chosen scenario once per value of the scenario "
      "path PATH, replacing the scenarios' own sweeps, e.g. --scenarios ibvs-moving-target --sweep "
      "timing.delay_frames=0,1,2 or --sweep predictors.cs-akf.params.a_max=5,20,50; the variants are named "
      "SCENARIO@KEY=VALUE (KEY: the last segment of PATH). Several --sweep options make a grid: the product of "
      "their values (the first varies slowest), variants SCENARIO@KEY1=V1,KEY2=V2, the same seeds in every cell, "
      "grid_<scenario>.csv (converged and failed fractions, median convergence time and rmse per cell and predictor; "
      "the outcome needs metrics.outcome: true, e.g. --set metrics.outcome=true) and heatmap_<scenario>.png "
      "(convergence time over the first two keys, failures marked; one per value of any further key). "
      "--set PATH=VALUE changes one value of every chosen scenario file before it is validated (so a key "
      "that a scenario kind does not have is an error for that scenario), e.g. "
      "--scenarios e2-accel-jump --predictors cs-akf --set predictors.cs-akf.params.a_max=100; the overrides "
      "are recorded in leaderboard.json. Metric definitions: leaderboard.json (metric_definitions), "
      "servo/include/predvs/servo/run_metrics.h.\n"
      "Errors: one line 'predvs: error: ...' on stderr, exit status 2, no output directory.");
  compare->add_option("--scenarios", cmp_scenarios, "comma-separated scenario names or .yaml paths, or 'all'")
      ->capture_default_str()
      ->type_name("A,B|all");
  compare->add_option("--predictors", cmp_predictors,
                      "comma-separated predictors or 'all' (default: each scenario's own list); each is "
                      "[LABEL=]TYPE[:KEY=VALUE...]: the registry predictor TYPE under the name LABEL (default "
                      "TYPE) with its KEY=VALUE parameters on top of the scenario's, so one predictor can run "
                      "with several parameter sets, e.g. st-akf-pm,st-akf-pm-switch=st-akf-pm:pm_on_alarm=1")
      ->type_name("A,B|all");
  compare->add_option("--runs", cmp_runs, "runs per predictor and scenario, overriding the scenarios' runs: keys")
      ->type_name("N");
  compare->add_option("--seed", cmp_seed, "base seed S (run r uses S + r; default: each scenario's seed)")
      ->type_name("S");
  compare->add_option("--jobs", cmp_jobs, "worker threads (default: every core)")->type_name("J");
  compare->add_option("--set", cmp_sets,
                      "override a value in every chosen scenario (repeatable): PATH is a dotted YAML path, "
                      "VALUE is YAML")
      ->type_name("PATH=VALUE");
  std::vector<std::string> cmp_sweeps;
  compare->add_option("--sweep", cmp_sweeps,
                      "run every chosen scenario once per value of a scenario path (replaces their own sweep:); "
                      "repeated: a grid over the product of the values")
      ->type_name("PATH=V1,V2,...");
  std::string cmp_camera, cmp_camera_name, cmp_set_file;
  compare->add_option("--camera", cmp_camera, "ViSP camera XML: sets camera.px, py, u0, v0, width, height of every scenario")
      ->type_name("FILE");
  compare->add_option("--camera-name", cmp_camera_name, "camera name in the --camera file (default: its first camera)")
      ->type_name("NAME");
  compare->add_option("--set-file", cmp_set_file, "YAML fragment of scenario keys applied as --set overrides before them")
      ->type_name("FILE");
  compare->add_option("--out", co.out_dir, "output directory, replaced only when the run succeeds")
      ->capture_default_str()
      ->type_name("DIR");
  compare->add_flag("--no-plots", cmp_no_plots, "do not draw PNG plots (no gnuplot needed)");
  // Campaigns (app/campaign.h, README "Campaigns")
  std::string cmp_shard, cmp_stop_after;
  compare->add_option("--shard", cmp_shard,
                      "run only the I-th of N deterministic slices of the runs and write their records and "
                      "shard.json (join them with predvs merge)")
      ->type_name("I/N");
  compare->add_option("--resume", co.resume_dir,
                      "reuse the run records of an interrupted (DIR.partial) or earlier campaign or shard; compute "
                      "only the rest")
      ->type_name("DIR");
  compare->add_option("--stop-after", cmp_stop_after, "test hook: fail after N runs are stored (then --resume)")
      ->type_name("N");
  MergeOptions mg;
  bool mg_no_plots = false;
  CLI::App* merge = app.add_subcommand("merge", "Leaderboard, grids, plots and report.html of a campaign from its shards");
  merge->footer(
      "Reads the directories written by `predvs compare ... --shard I/N --out DIR_I` for I = 1..N (each exactly "
      "once; a missing or duplicated shard is an error naming it) and writes the outputs one `predvs compare` "
      "would (byte-identical).\nErrors: one line 'predvs: error: ...' on stderr, exit status 2, no output directory.");
  merge->add_option("dirs", mg.dirs, "shard output directories")->required()->type_name("DIR");
  merge->add_option("--out", mg.out_dir, "output directory, replaced only when the merge succeeds")
      ->capture_default_str()
      ->type_name("DIR");
  merge->add_flag("--no-plots", mg_no_plots, "do not draw PNG plots (no gnuplot needed)");

  compare->add_option("--params", cmp_params_file, kParamsFileHelp)->type_name("FILE");


  CLI::App* calibrate = app.add_subcommand("calibrate", "Calibrate a camera from pattern images, or the vision delay from a servo log");
  calibrate->require_subcommand(1);
  CalibrateCameraOptions cc;
  bool cc_no_plots = false;
  CLI::App* cal_camera = calibrate->add_subcommand("camera", "Camera intrinsics from images of a planar pattern (OpenCV)");
  cal_camera->footer(
      "Detects the pattern in every image (an image where it is not found is rejected and named), calibrates "
      "with OpenCV's calibrateCamera (5 coefficients; k1 only for ViSP's model with distortion; none for ViSP's "
      "model without), prints the RMS reprojection error per image and overall, and writes DIR/camera.xml (ViSP: "
      "`predvs servo --camera DIR/camera.xml`), DIR/camera.yaml (OpenCV), DIR/residuals.csv, DIR/summary.json and "
      "DIR/residuals.png. Circles: dark dots on a light background (ViSP's grid2d.pdf: 6 x 6, 0.03 m; the "
      "grid36-*.pgm images of visp-images-data). Guide: docs/CALIBRATION.md.\n"
      "Errors: one line 'predvs: error: ...' on stderr, exit status 2, no output directory.");
  cal_camera->add_option("--images", cc.images, "a directory of images, a quoted glob pattern, or one image")
      ->required()
      ->type_name("DIR|PATTERN");
  cal_camera->add_option("--pattern", cc.pattern, "circles | chessboard | apriltag")->capture_default_str()->type_name("KIND");
  cal_camera->add_option("--rows", cc.rows, "dots, inner corners or tags per column")->capture_default_str();
  cal_camera->add_option("--cols", cc.cols, "per row")->capture_default_str();
  cal_camera->add_option("--spacing", cc.spacing_m, "centre (corner) spacing in metres")->capture_default_str()->type_name("M");
  cal_camera->add_option("--diameter", cc.diameter_m, "circles: dot diameter in metres (default 2/3 of the spacing)")
      ->type_name("M")
      ->check(positiveLength);
  cal_camera->add_option("--tag-size", cc.tag_size_m, "apriltag: tag side in metres (default 0.8 of the spacing)")
      ->type_name("M")
      ->check(positiveLength);
  cal_camera->add_option("--name", cc.name, "camera name in camera.xml")->capture_default_str();
  cal_camera->add_option("--out", cc.out_dir, "output directory, replaced only when the run succeeds")->capture_default_str()->type_name("DIR");
  cal_camera->add_flag("--no-plots", cc_no_plots, "do not draw residuals.png (no gnuplot needed)");
  CalibrateLatencyOptions cl;
  bool cl_no_plots = false;
  CLI::App* cal_latency = calibrate->add_subcommand("latency", "Vision delay from a servo log (predvs servo's log.csv)");
  cal_latency->footer(
      "Fits the delivered features on the integrated command for every delay candidate from 0 to "
      "--max-delay-s and reports the best delay with its uncertainty (calibration/latency_estimation.h): "
      "with --camera or --intrinsics, the point model (image points of a camera driven by a camera twist) over "
      "the whole run; otherwise a generic local fit around the start of motion; with acquisition stamps (t_acq_s) also the lag between the logged command and the "
      "camera motion. Writes DIR/timing.yaml (`predvs servo --set-file DIR/timing.yaml`), DIR/latency.json and "
      "DIR/profile.png. The log must start with the robot at rest. Log format and guide: docs/CALIBRATION.md.\n"
      "Errors: one line 'predvs: error: ...' on stderr, exit status 2, no output directory.");
  cal_latency->add_option("--log", cl.log, "servo log CSV (predvs servo's log.csv)")->required()->type_name("FILE");
  cal_latency->add_option("--predictor", cl.predictor, "the run to use when the log has several (default: the first)")->type_name("NAME");
  cal_latency->add_option("--commands", cl.commands, "command columns (default: those of vx,vy,vz,wx,wy,wz present)")->type_name("A,B,...");
  cal_latency->add_option("--camera", cl.camera,
                          "ViSP camera XML of the logged camera: fit the point model (image points, camera twist) "
                          "over the whole run")
      ->type_name("FILE");
  cal_latency->add_option("--camera-name", cl.camera_name, "camera name in the --camera file (default: its first)")->type_name("NAME");
  cal_latency->add_option("--intrinsics", cl.intrinsics, "the point model with these intrinsics (px), e.g. 800,800,320,240")
      ->type_name("PX,PY,U0,V0");
  cal_latency->add_option("--max-delay-s", cl.max_delay_s, "largest delay searched (s)")->capture_default_str()->type_name("S");
  cal_latency->add_option("--window-s", cl.window_s, "seconds of log after the start of motion + max delay in the fit")
      ->capture_default_str()
      ->type_name("S");
  cal_latency->add_option("--out", cl.out_dir, "output directory, replaced only when the run succeeds")->capture_default_str()->type_name("DIR");
  cal_latency->add_flag("--no-plots", cl_no_plots, "do not draw profile.png (no gnuplot needed)");

  return parseAndRun(app, args, out, err, [&]() -> int {
    if (app.got_subcommand("list")) return runList(out);
    if (const auto status = tracks.run(command_line, out, err)) return *status;
    if (app.got_subcommand("track")) return runTrack(ta, command_line, out, err);
    if (app.got_subcommand("calibrate")) {
      if (calibrate->got_subcommand("camera")) {
        cc.plots = !cc_no_plots;
        cc.command_line = command_line;
        runCalibrateCamera(cc, out, err);
      } else {
        cl.plots = !cl_no_plots;
        cl.command_line = command_line;
        runCalibrateLatency(cl, out, err);
      }
      return 0;
    }
    if (app.got_subcommand("merge")) {
      mg.plots = !mg_no_plots;
      runMergeCommand(mg, out, err);
      return 0;
    }
    if (app.got_subcommand("compare")) {
      if (!cmp_shard.empty()) {
        const ShardSpec shard = parseShard(cmp_shard);
        co.shard_index = shard.index;
        co.shard_count = shard.count;
      }
      if (!cmp_stop_after.empty()) co.stop_after = static_cast<int>(parseIntegerArg("--stop-after", cmp_stop_after, 1, 100000000));
      co.scenarios = splitList("--scenarios", cmp_scenarios);
      if (compare->count("--predictors")) co.predictors = splitList("--predictors", cmp_predictors);
      if (!cmp_runs.empty()) co.runs = static_cast<int>(parseIntegerArg("--runs", cmp_runs, 1, 100000));
      if (!cmp_seed.empty()) {
        co.seed_given = true;
        co.seed = static_cast<unsigned long>(parseIntegerArg("--seed", cmp_seed, 0, 2147483647L));
      }
      co.overrides = fileOverrides(cmp_set_file, cmp_camera, cmp_camera_name, compare->count("--camera-name") > 0);
      co.inputs = {cmp_set_file, cmp_camera, cmp_params_file};
      if (!cmp_params_file.empty()) paramsFileOverrides(cmp_params_file, co.overrides);
      for (const auto& text : cmp_sets) co.overrides.push_back(parseScenarioOverride(text));
      for (const auto& text : cmp_sweeps) co.sweeps.push_back(parseSweepOption(text));
      checkSweepAxes(co.sweeps);
      if (!cmp_jobs.empty()) co.jobs = static_cast<int>(parseIntegerArg("--jobs", cmp_jobs, 1, 1024));
      co.plots = !cmp_no_plots;
      co.progress_bar = &err == &std::cerr && ::isatty(STDERR_FILENO);
      co.command_line = commandLine(campaignArgs(args));  // without --out, --jobs, --shard, --resume
      runCompareCommand(co, out, err);
      return 0;
    }
    // servo
    so.plots = !servo_no_plots;
    if (servo->count("--predictors")) so.predictors = splitList("--predictors", predictors_csv);
    for (const auto& text : so.predictors) parsePredictorChoice(text, "--predictors");
    if (!seed_text.empty()) {
      so.seed_given = true;
      so.seed = static_cast<unsigned long>(parseIntegerArg("--seed", seed_text, 0, 2147483647L));
    }
    so.overrides = fileOverrides(servo_set_file, servo_camera, servo_camera_name, servo->count("--camera-name") > 0);
    so.inputs = {servo_set_file, servo_camera, servo_params_file};
    if (!servo_params_file.empty()) paramsFileOverrides(servo_params_file, so.overrides);
    for (const auto& text : servo_sets) so.overrides.push_back(parseScenarioOverride(text));
    so.command_line = command_line;
    runScenarioCommand(so, out, err);
    return 0;
  });
}

}  // namespace predvs
