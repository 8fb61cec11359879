#include "cli.h"

#include "calibrate_command.h"
#include "campaign.h"
#include "compare_command.h"
#include "output_dir.h"
#include "parallel_for.h"
#include "predict_command.h"
#include "scenario_file.h"
#include "scenario_inputs.h"
#include "scenario_override.h"
#include "scenario_run.h"
#include "servo_command.h"
#include "track_command.h"
#include "track_csv.h"
#include "track_commands.h"
#include "fit_command.h"

#include "predvs/calibration/noise_fit.h"
#include "app_error.h"
#include "gnuplot.h"

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

std::string oneLine(std::string s) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  std::replace(s.begin(), s.end(), '\r', ' ');
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

/// A finite number from an argument; errors name the option.
double parseNumberArg(const std::string& option, const std::string& text) {
  const char* begin = text.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (text.empty() || end == begin || *end != '\0')
    throw std::invalid_argument(option + ": expected a number, got '" + text + "'");
  if (!std::isfinite(v) || errno == ERANGE)
    throw std::invalid_argument(option + ": expected a finite number, got '" + text + "'");
  return v;
}

long parseIntegerArg(const std::string& option, const std::string& text, long lo, long hi) {
  const char* begin = text.c_str();
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(begin, &end, 10);
  if (text.empty() || end == begin || *end != '\0' || errno == ERANGE || v < lo || v > hi)
    throw std::invalid_argument(option + ": expected an integer in [" + std::to_string(lo) + ", " +
                                std::to_string(hi) + "], got '" + text + "'");
  return static_cast<long>(v);
}

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

// ---------------------------------------------------------------------------------------------
/// One section of `predvs list`: a title and (name, summary) rows aligned on the longest name.
template <class Rows>
void listSection(std::ostream& out, const std::string& title, const Rows& rows) {
  out << title << "\n";
  size_t w = 4;
  for (const auto& r : rows) w = std::max(w, r.name.size());
  for (const auto& r : rows) out << "  " << std::left << std::setw(static_cast<int>(w)) << r.name << "  " << r.summary << "\n";
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

// ---------------------------------------------------------------------------------------------
struct PredictArgs {
  std::string input;
  std::string predictor;
  std::string horizon_s;
  std::string delay_frames;
  std::string out_dir;
  std::vector<std::string> params;
  bool no_plots = false;
  std::string jobs;         ///< --jobs N (default: every core)
  std::string params_file;  ///< --params FILE (fit_command.h)
  bool fit = false;         ///< --fit
  std::string fit_split;    ///< --fit-split F
  std::string fit_objective;  ///< --fit-objective likelihood|prediction (default prediction at the horizon)
  std::string fit_select_holdout;  ///< --fit-select-holdout F (fit-noise --select-holdout)
  bool no_warm_start = false;      ///< --no-warm-start (track-study's)
};

/// Sets the params of a parameter file on the specs shown under the name of one of its entries
/// (--params FILE; a file names registry predictors, so a labelled spec is not set by it).
void applyParamsFile(const std::string& file, std::vector<PredictorSpec>& specs) {
  bool any = false;
  for (const auto& f : readParamsFile(file))
    for (auto& s : specs)
      if (s.shownName() == f.name) {
        for (const auto& kv : f.params.values()) s.params.set(kv.first, kv.second);
        for (const auto& kv : f.params.texts()) s.params.setText(kv.first, kv.second);
        any = true;
      }
  if (!any) throw std::invalid_argument("--params " + file + ": names none of the predictors being run");
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

/// --predictor of predict and track (parsePredictorSpecs, predict_command.h).
std::vector<PredictorSpec> predictorSpecs(const std::string& text) {
  return parsePredictorSpecs("--predictor", text == "all" ? std::vector<std::string>{"all"} : splitList(text));
}

int runPredict(const PredictArgs& a, const std::string& command_line, std::ostream& out) {
  // Validate every argument before touching the file system.
  std::vector<PredictorSpec> specs = predictorSpecs(a.predictor);
  if (!a.params_file.empty()) applyParamsFile(a.params_file, specs);
  for (const auto& kv : a.params) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0)
      throw std::invalid_argument("--param: expected [PREDICTOR.]KEY=VALUE, got '" + kv + "'");
    std::string key = kv.substr(0, eq);
    const std::string text = kv.substr(eq + 1);
    double number = 0.0;
    const bool word = classifyParamText(text, &number) == ParamText::Word;  // model=cv
    const double value = word ? 0.0 : parseNumberArg("--param " + key, text);
    std::string scope;
    const auto dot = key.find('.');
    if (dot != std::string::npos) {
      scope = key.substr(0, dot);
      key = key.substr(dot + 1);
      const bool run = std::any_of(specs.begin(), specs.end(), [&](const PredictorSpec& s) { return s.shownName() == scope; });
      if (!run) requirePredictor("--param " + kv.substr(0, eq), scope);  // unknown, or known but not run (below)
    } else if (specs.size() > 1) {
      throw std::invalid_argument("--param " + key + ": with --predictor all or several predictors, scope each "
                                  "parameter as PREDICTOR." + key + "=VALUE");
    }
    bool applied = false;
    for (auto& s : specs)
      if (scope.empty() || s.shownName() == scope) {
        if (word)
          s.params.setText(key, text);
        else
          s.params.set(key, value);
        applied = true;
      }
    if (!applied)
      throw std::invalid_argument("--param " + kv.substr(0, eq) + ": predictor '" + scope + "' is not being run");
  }
  // Build each predictor once to reject unknown parameter keys now, naming the option.
  for (const auto& s : specs) {
    try {
      makePredictor(s.name, 2, s.params);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("--param: ") + e.what());
    }
  }
  if (a.horizon_s.empty() == a.delay_frames.empty())
    throw std::invalid_argument("--horizon-s / --delay-frames: expected exactly one of them");
  double horizon_s = 0.0;
  int delay_frames = -1;
  if (!a.horizon_s.empty()) {
    horizon_s = parseNumberArg("--horizon-s", a.horizon_s);
    if (horizon_s < 0.0) throw std::invalid_argument("--horizon-s: expected a number >= 0, got '" + a.horizon_s + "'");
  } else {
    delay_frames = static_cast<int>(parseIntegerArg("--delay-frames", a.delay_frames, 0, 1000000));
  }
  double fit_split = 1.0;
  if (!a.fit_split.empty()) {
    if (!a.fit) throw std::invalid_argument("--fit-split: needs --fit");
    fit_split = parseNumberArg("--fit-split", a.fit_split);
    if (!(fit_split > 0.0 && fit_split < 1.0))
      throw std::invalid_argument("--fit-split: expected a fraction in (0, 1), got '" + a.fit_split + "'");
  }
  NoiseFitOptions fit_options;
  fit_options.objective = FitObjective::Prediction;
  if (!a.fit_objective.empty()) {
    if (!a.fit) throw std::invalid_argument("--fit-objective: needs --fit");
    try {
      fit_options.objective = parseFitObjective(a.fit_objective);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("--fit-objective: ") + e.what());
    }
  }
  if (!a.fit_select_holdout.empty()) {
    if (!a.fit) throw std::invalid_argument("--fit-select-holdout: needs --fit");
    fit_options.select_holdout = parseNumberArg("--fit-select-holdout", a.fit_select_holdout);
    if (!validSelectHoldout(fit_options.select_holdout))
      throw std::invalid_argument("--fit-select-holdout: expected a fraction in [0, 0.9], got '" + a.fit_select_holdout + "'");
  }
  const int jobs = a.jobs.empty() ? hardwareJobs() : static_cast<int>(parseIntegerArg("--jobs", a.jobs, 1, 1024));
  if (!a.no_plots) requireGnuplot();

  const FeatureTrack track = readFeatureTrack(a.input, jobs);
  double period_s = 0.0;  // with --delay-frames: measured once (a 2 M-row track: a 2 M-element median)
  if (delay_frames >= 0) {
    if (track.size() < 2)
      throw std::invalid_argument(fileLocation(a.input, 0, "--delay-frames needs at least two data rows to measure the frame period"));
    period_s = medianPeriod(track.t_s);
    horizon_s = delay_frames * period_s;
  }
  // --fit: each predictor's noise fitted on the first fit_split of the rows (all rows without
  // --fit-split), then run on the whole track; with --fit-split only the rest is scored.
  const auto fit_rows = static_cast<size_t>(std::floor(fit_split * static_cast<double>(track.size())));
  std::ostringstream fit_log;
  if (a.fit && a.fit_split.empty()) fit_options = inSampleFitOptions(fit_options);  // every row is scored
  if (a.no_warm_start && !a.fit) throw std::invalid_argument("--no-warm-start: needs --fit");
  if (a.fit) {
    // The predictors that seed others' fits (the fixed KFs) first, the others warm started from
    // their fitted values (noise_fit.h fitOrder, NoiseFitOptions::seed_fits); printed in the
    // predictors' order.
    std::vector<std::string> names;
    std::vector<Params> structures;
    for (const auto& s : specs) {
      names.push_back(s.name);
      structures.push_back(s.params);
    }
    const FitTrack fit_track = fitTrackOf(track, fit_rows);
    std::vector<std::string> logs(specs.size());
    fit_options.horizon_s = horizon_s;  // the score is what is fitted
    for (size_t j : fitOrder(names, structures)) {
      auto& s = specs[j];
      if (s.name == "hold") continue;
      try {
        const NoiseFitResult fit = fitNoise(s.name, s.params, fit_track, fit_options);
        s.params = fit.params;
        // warm start for fits scored in sample only (no --fit-split), as track-study's
        if (!a.no_warm_start && a.fit_split.empty()) fit_options.seed_fits[s.name] = fit.params;
        std::ostringstream o;
        if (!s.label.empty()) o << s.label << " = ";  // printFit names the registry predictor
        printFit(fit, o);
        logs[j] = o.str();
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(a.input + ": --fit " + s.shownName() + ": " + e.what());
      }
    }
    for (const auto& l : logs) fit_log << l;
  }
  PredictionReport report = predictTrack(track, specs, horizon_s, jobs);
  if (a.fit && fit_rows < track.size() && !a.fit_split.empty())
    for (auto& run : report.runs) {
      // Score only the rows after the fit: the predictions made before it are blanked.
      std::vector<PredictionErrors> vs_meas, vs_truth;
      for (size_t p = 0; p < run.points.size(); ++p) {
        PointPrediction& pp = run.points[p];
        std::vector<double> u = pp.u_pred_px, v = pp.v_pred_px;
        for (size_t i = 0; i < fit_rows && i < u.size(); ++i) u[i] = v[i] = std::numeric_limits<double>::quiet_NaN();
        pp.vs_measurement = predictionErrors(track.t_s, u, v, horizon_s, track.u_px[p], track.v_px[p]);
        vs_meas.push_back(pp.vs_measurement);
        if (track.hasTruth()) {
          pp.vs_truth = predictionErrors(track.t_s, u, v, horizon_s, track.u_true_px[p], track.v_true_px[p]);
          vs_truth.push_back(pp.vs_truth);
        }
      }
      run.vs_measurement = pooledErrors(vs_meas);
      if (track.hasTruth()) run.vs_truth = pooledErrors(vs_truth);
    }

  StagedOutputDir dir(a.out_dir);
  writePredictionOutputs(track, report, delay_frames, command_line, !a.no_plots, dir, jobs);
  dir.commit();

  out << fit_log.str();
  printPredictionTable(report, track, out);
  if (a.fit && !a.fit_split.empty())
    out << "fitted on rows 1.." << fit_rows << ", scored on rows " << fit_rows + 1 << ".." << track.size() << "\n";
  out << "horizon " << horizon_s << " s";
  if (delay_frames >= 0) out << " (" << delay_frames << " frames of " << period_s << " s)";
  out << "; wrote " << (dir.target() / "predictions.csv").string() << ", summary.json"
      << (a.no_plots ? "" : ", predictions.png") << "\n";
  return 0;
}

// ---------------------------------------------------------------------------------------------
struct TrackArgs {
  std::string images, source = "dots", predictor = "all", delay_frames = "2", fps = "30", out_dir = "out/track";
  std::string strip_frames = "4", max_frames;
  std::vector<std::string> sets;
  bool no_plots = false;
};

int runTrack(const TrackArgs& a, const std::string& command_line, std::ostream& out, std::ostream& err) {
  TrackOptions o;
  o.images = a.images;
  o.source = a.source;
  o.predictors = predictorSpecs(a.predictor);
  o.delay_frames = static_cast<int>(parseIntegerArg("--delay-frames", a.delay_frames, 0, 100000));
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

/// True when `name` is one of the app's subcommands.
bool isSubcommand(CLI::App& app, const std::string& name) {
  for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
    if (sub->get_name() == name) return true;
  return false;
}

}  // namespace

std::string commandLine(const std::vector<std::string>& args) {
  std::string s = "predvs";
  for (const auto& a : args) {
    const bool plain = !a.empty() && a.find_first_of(" \t\"'\\$`!*?;&|<>()") == std::string::npos;
    if (plain) {
      s += " " + a;
    } else {
      std::string q = "'";
      for (char c : a) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
      s += " " + q + "'";
    }
  }
  return s;
}

int runCli(std::vector<std::string> args, std::ostream& out, std::ostream& err) {
  const std::string command_line = commandLine(args);
  CLI::App app{"predvs: predictive visual servoing. Compare feature predictors that compensate "
               "the vision delay, open-loop on recorded tracks and in closed-loop IBVS.", "predvs"};
  app.require_subcommand(1);
  app.footer("Errors: one line 'predvs: error: ...' on stderr, exit status 2, no output directory.");

  app.add_subcommand("list", "List the registered predictors and the scenarios in data/scenarios.");

  PredictArgs pa;
  CLI::App* predict = app.add_subcommand("predict", "Open-loop prediction of a recorded feature track (CSV)");
  predict->footer(
      "The track holds N points, in the long format t,point,u,v[,u_true,v_true] (one row per frame and point, "
      "as `predvs track` writes tracks.csv; a point missing from a frame is not measured) or the wide one "
      "t,u0,v0,u1,v1,...[,u0_true,v0_true,...] (t,u,v is one point); a UTF-8 byte-order mark, CRLF line ends "
      "and extra columns (ignored, listed in summary.json) are accepted. "
      "Each frame's measurements are fed to the predictor (an empty u or v cell means no measurement: "
      "predict-only), then the positions at t + horizon are predicted without changing the filter. "
      "With --delay-frames H the horizon is H times the median frame period (median of t differences) "
      "of the input. Scoring: the prediction made at t is compared with the measurement at t + horizon, "
      "linearly interpolated between the nearest measured rows (exact when t + horizon is a row time), "
      "and with u_true/v_true when present; rows outside the measured span are not scored. "
      "Writes DIR/predictions.csv (t,u,v,t_target,NAME.u_pred,NAME.v_pred per predictor; with N > 1 points "
      "t,point,u,v,...), DIR/summary.json (RMSE per predictor, overall and per point) and DIR/predictions.png "
      "(the first point; beyond 20,000 rows the minimum and maximum of each series over 1200 equal time slices are drawn, predictions.csv keeps all). "
      "The simulated open-loop experiments E1-E4 run with `predvs servo --scenario e1-line` etc.\n"
      "Errors: one line 'predvs: error: ...' on stderr, exit status 2, no output directory.");
  predict->add_option("--input", pa.input, "CSV track: t,u,v | t,u0,v0,u1,v1,... | t,point,u,v (+ optional *_true columns); t in s, u,v in px")
      ->required()
      ->type_name("FILE");
  predict->add_option("--predictor", pa.predictor,
                      "predictor name (see `predvs list`), a comma list NAME,NAME,..., or 'all' to compare every one; "
                      "an element may be [LABEL=]NAME[:KEY=VALUE...] (compare's syntax), so one predictor runs with "
                      "several parameter sets, e.g. kf-cv,kf-cv-r5=kf-cv:r=5")
      ->required()
      ->type_name("NAME[,NAME...]");
  auto* h = predict->add_option("--horizon-s", pa.horizon_s, "prediction horizon in seconds (>= 0)")->type_name("S");
  auto* d = predict->add_option("--delay-frames", pa.delay_frames,
                                "prediction horizon in frames: H times the median frame period of the input")
                ->type_name("H");
  h->excludes(d);
  predict->add_option("--out", pa.out_dir, "output directory (replaced only when the run succeeds)")
      ->required()
      ->type_name("DIR");
  predict->add_option("--param", pa.params,
                      "predictor parameter KEY=VALUE (repeatable); with several predictors write PREDICTOR.KEY=VALUE "
                      "(PREDICTOR: a name or a LABEL of --predictor)")
      ->type_name("KEY=VALUE");
  predict->add_flag("--no-plots", pa.no_plots, "do not draw predictions.png (no gnuplot needed)");
  predict->add_option("--jobs", pa.jobs,
                      "threads running the predictors and writing predictions.csv (default: every core; the outputs do not depend on it)")
      ->type_name("N");
  predict->add_option("--params", pa.params_file,
                      "parameter file (YAML, as written by fit-noise) for the predictors it names (not a LABEL=NAME "
                      "entry of --predictor: give it --param LABEL.KEY=VALUE); --param wins")
      ->type_name("FILE");
  predict->add_flag("--fit", pa.fit,
                    "fit each predictor's noise (fit-noise) on the track first, then predict with the fitted values");
  predict->add_option("--fit-split", pa.fit_split,
                      "with --fit: fit on the first fraction F of the rows, score only the rest")
      ->type_name("F");
  predict->add_option("--fit-objective", pa.fit_objective,
                      "with --fit: 'prediction' (default: minimise the squared error of the prediction at the "
                      "command's horizon against the later measurements, the score itself) or 'likelihood' "
                      "(maximise the innovation log-likelihood, as fit-noise by default)")
      ->type_name("OBJ");
  predict->add_option("--fit-select-holdout", pa.fit_select_holdout,
                      "with --fit: the structure of a predictor that has several is chosen on the last fraction F of "
                      "its fit rows (fit-noise --select-holdout, the same default)")
      ->type_name("F");
  predict->add_flag("--no-warm-start", pa.no_warm_start,
                    "with --fit (without --fit-split: fitted and scored in sample): do not also start each adaptive "
                    "predictor's fit from the fixed KFs' fitted values (those among the predictors, fitted first on "
                    "the same rows)");

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
  track->add_option("--delay-frames", ta.delay_frames, "prediction horizon H in frames")->capture_default_str()->type_name("H");
  track->add_option("--fps", ta.fps, "frame rate of the recording (time stamps t = k / fps)")
      ->capture_default_str()
      ->type_name("F");
  track->add_option("--set", ta.sets, "tracker parameter KEY=VALUE (repeatable), e.g. --set points=5")->type_name("KEY=VALUE");
  track->add_option("--strip-frames", ta.strip_frames, "frames drawn side by side in strip.png (0: none)")
      ->capture_default_str()
      ->type_name("K");
  track->add_option("--max-frames", ta.max_frames, "read at most N frames")->type_name("N");
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
      "prediction experiment on its trajectory's channels. A scenario's sweep is not run (servo runs the "
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
  servo->add_option("--scenario", so.scenario, "scenario name in data/scenarios, or a path to a .yaml file")
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
  servo->add_option("--params", servo_params_file,
                    "predictor parameter file (fit-noise): each entry becomes --set predictors.NAME.params.KEY=VALUE")
      ->type_name("FILE");

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
      "(default 20). Predictors take the parameters their scenario gives them, their defaults otherwise. "
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

  compare->add_option("--params", cmp_params_file,
                      "predictor parameter file (fit-noise): each entry becomes --set predictors.NAME.params.KEY=VALUE")
      ->type_name("FILE");

  FitNoiseArgs fna;
  CLI::App* fit_noise = app.add_subcommand("fit-noise", "Fit a predictor's noise parameters on a track (Ceres: innovation likelihood or h-step prediction error)");
  fit_noise->footer("--objective likelihood (default): maximises the innovation log-likelihood -1/2 sum(log(2 pi S) + eps^2/S) of the predictor over the "
                    "track (rows after --burn-in) over its noise parameters on a log scale within bounds (L-BFGS, "
                    "numeric derivatives); the uncertainty is the inverse Fisher information (ceres::Covariance). "
                    "--objective prediction: minimises the mean squared error of the prediction --horizon-frames ahead of every row "
                    "against the track's measurement interpolated at that time (bounded Levenberg-Marquardt); the uncertainty is "
                    "the Gauss-Newton covariance of that least-squares problem scaled by the residual variance; r is held at its start value (h-step errors depend on q/r only). "
                    "Fitted keys: kf-cv, kf-ca, st-akf, st-akf-pm, fakf-classic: q, r; cs-akf: alpha, a_max, a_neg_max, r; "
                    "cs-akf-adaptive, fakf: alpha, sigma_min_sq, sigma_max_sq, r; stkf: r, "
                    "q_pos, q_vel; imm: q_cv, q_ca, r. Writes DIR/params.yaml (use with predict/servo/compare "
                    "--params) and DIR/fit.json.\n"
                    "Errors: one line 'predvs: error: ...' on stderr, exit status 2, no output directory.");
  fit_noise->add_option("--input", fna.input, "track CSV (t,u,v[,u_true,v_true]) as for predict")->required()->type_name("FILE");
  fit_noise->add_option("--predictor", fna.predictor, "predictor to fit")->required()->type_name("NAME");
  fit_noise->add_option("--param", fna.params, "fixed value, or start value of a fitted key (repeatable)")->type_name("KEY=VALUE");
  fit_noise->add_option("--params", fna.params_file, "parameter file whose entry for NAME gives fixed / start values")->type_name("FILE");
  fit_noise->add_option("--burn-in", fna.burn_in, "rows left out of the objective at the start")->capture_default_str()->type_name("N");
  fit_noise->add_option("--objective", fna.objective,
                        "likelihood (innovation log-likelihood) or prediction (squared h-step prediction error "
                        "against the track's later measurements)")
      ->capture_default_str()
      ->type_name("OBJ");
  fit_noise->add_option("--horizon-frames", fna.horizon_frames,
                        "h of the prediction objective (and of the RMSE printed) in frames: N x the median frame period")
      ->capture_default_str()
      ->type_name("N");
  fit_noise->add_option("--starts", fna.starts,
                        "starting points: the start values, then the process-noise keys moved by 10^+-2, 10^+-1, ...; the best fit is kept")
      ->capture_default_str()
      ->type_name("N");
  fit_noise->add_option("--select-holdout", fna.select_holdout,
                        "for a predictor with several structures (model, mean, adaptation): fit each on all but the "
                        "last fraction F of the rows, keep the one that does best on those, fit it on all rows; "
                        "0 = keep the best fit on all rows")
      ->capture_default_str()
      ->type_name("F");
  fit_noise->add_option("--out", fna.out, "output directory (replaced only when the fit succeeds)")->required()->type_name("DIR");

  // Generated maneuvering tracks (app/track_commands.h).
  MakeTrackArgs mta;
  CLI::App* make_track = app.add_subcommand("make-track", "Write one generated maneuvering track (truth kept) as a predict input CSV");
  make_track->footer("Kinds: smooth, turns, stops, bursts, zigzag, hand (servo/include/predvs/servo/maneuver_tracks.h). "
                     "Writes FILE with t,u,v,u_true,v_true; an empty u,v cell is a dropped frame.");
  make_track->add_option("--kind", mta.kind, "motion kind")->capture_default_str()->type_name("KIND");
  make_track->add_option("--rate-hz", mta.rate_hz, "frame rate in Hz")->capture_default_str()->type_name("HZ");
  make_track->add_option("--noise-px", mta.noise_px, "Gaussian noise std per coordinate, px")->capture_default_str()->type_name("PX");
  make_track->add_option("--duration-s", mta.duration_s, "duration in s")->capture_default_str()->type_name("S");
  make_track->add_option("--drop", mta.drop_prob, "probability of a dropped frame (bursts of 3..8 at drop/5)")->capture_default_str()->type_name("P");
  make_track->add_option("--seed", mta.seed, "random seed")->capture_default_str()->type_name("N");
  make_track->add_option("--out", mta.out, "output CSV file")->required()->type_name("FILE");

  TrackStudyArgs tsa;
  std::string ts_kinds = "all", ts_predictors = "all", ts_rates = "10,15,30,60", ts_noise = "0.5,1.5,3";
  CLI::App* track_study = app.add_subcommand("track-study", "Every predictor against hold on a grid of generated maneuvering tracks");
  track_study->footer("For each kind x rate x noise x seed, generates a track (make-track), predicts --delay-frames ahead "
                      "as `predvs predict` does and scores against the truth. Prints per predictor how many tracks it "
                      "beats hold on, and the mean / worst RMSE ratio to hold; and, when kf-cv, kf-ca or cs-akf run, "
                      "per adaptive predictor on how many tracks it is within 10 % of the best of them (with --fit: "
                      "all fitted, by default on the h-step prediction error at --delay-frames, the score itself). "
                      "--out DIR writes DIR/study.csv.");
  track_study->add_option("--kinds", ts_kinds, "comma list of kinds or 'all'")->capture_default_str()->type_name("A,B|all");
  track_study->add_option("--rates", ts_rates, "comma list of frame rates, Hz")->capture_default_str()->type_name("HZ,...");
  track_study->add_option("--noise", ts_noise, "comma list of noise std, px")->capture_default_str()->type_name("PX,...");
  track_study->add_option("--seeds", tsa.seeds, "tracks per cell (seeds S..S+N-1)")->capture_default_str()->type_name("N");
  track_study->add_option("--seed", tsa.seed, "first seed S")->capture_default_str()->type_name("S");
  track_study->add_option("--duration-s", tsa.duration_s, "track duration, s")->capture_default_str()->type_name("S");
  track_study->add_option("--drop", tsa.drop_prob, "dropped-frame probability")->capture_default_str()->type_name("P");
  track_study->add_option("--delay-frames", tsa.delay_frames, "prediction horizon in frames")->capture_default_str()->type_name("H");
  track_study->add_option("--predictors", ts_predictors, "comma list of predictors or 'all'; an element may be [LABEL=]NAME[:KEY=VALUE...] as in compare")->capture_default_str()->type_name("A,B|all");
  track_study->add_option("--param", tsa.params, "parameter of one predictor (repeatable)")->type_name("PREDICTOR.KEY=VALUE");
  track_study->add_flag("--fit", tsa.fit,
                        "fit each predictor's noise on each track (fit-noise): on its first part, scored on the rest "
                        "(--fit-split F < 1), or on the whole track, scored on the whole track (--fit-split 1)");
  track_study->add_option("--fit-split", tsa.fit_split,
                          "with --fit: fraction F in (0, 1] of each track used for fitting; F < 1 scores only the rest "
                          "(out of sample); 1 fits and scores the whole track, as `predict --fit` without --fit-split")
      ->capture_default_str()
      ->type_name("F");
  track_study->add_option("--fit-objective", tsa.fit_objective,
                          "with --fit: prediction (squared error of the --delay-frames prediction against the later "
                          "measurements of the fit part: the score is what is fitted) or likelihood (innovation log-likelihood)")
      ->capture_default_str()
      ->type_name("OBJ");
  track_study->add_option("--fit-starts", tsa.fit_starts, "with --fit: starting points per fit (fit-noise --starts)")
      ->capture_default_str()
      ->type_name("N");
  track_study->add_option("--fit-select-holdout", tsa.fit_select,
                          "with --fit: the structure of a predictor that has several is chosen on the last fraction F "
                          "of the fit part (fit-noise --select-holdout); 0 = on the whole fit part")
      ->capture_default_str()
      ->type_name("F");
  track_study->add_flag("--no-warm-start", tsa.no_warm_start,
                        "with --fit --fit-split 1 (the warm start is used in sample only): do not also start each adaptive "
                        "predictor's fit from the fixed KFs' fitted values (kf-cv, kf-ca, cs-akf, fitted first on the "
                        "same rows; docs/PERFORMANCE.md \"Warm start\")");
  track_study->add_option("--jobs", tsa.jobs, "tracks computed in parallel (threads); results do not depend on it")
      ->capture_default_str()
      ->type_name("N");
  track_study->add_option("--out", tsa.out, "optional output directory for study.csv")->type_name("DIR");

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
  cal_camera->add_option("--diameter", cc.diameter_m, "circles: dot diameter in metres (default 2/3 of the spacing)")->type_name("M");
  cal_camera->add_option("--tag-size", cc.tag_size_m, "apriltag: tag side in metres (default 0.8 of the spacing)")->type_name("M");
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

  try {
    if (!args.empty() && !args.front().empty() && args.front()[0] != '-' &&
        !isSubcommand(app, args.front())) {
      std::string known;
      for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
        known += (known.empty() ? "" : ", ") + sub->get_name();
      throw std::invalid_argument("unknown subcommand '" + args.front() + "' (expected " + known + ")");
    }
    std::vector<std::string> reversed(args.rbegin(), args.rend());
    app.parse(reversed);
    if (app.got_subcommand("list")) return runList(out);
    if (app.got_subcommand("predict")) return runPredict(pa, command_line, out);
    if (app.got_subcommand("track")) return runTrack(ta, command_line, out, err);
    if (app.got_subcommand("make-track")) return runMakeTrack(mta, out);
    if (app.got_subcommand("fit-noise")) {
      fna.command_line = command_line;
      return runFitNoise(fna, out);
    }
    if (app.got_subcommand("track-study")) {
      tsa.kinds = splitList(ts_kinds);
      tsa.predictors = splitList(ts_predictors);
      tsa.rates_hz.clear();
      for (const auto& r : splitList(ts_rates)) tsa.rates_hz.push_back(parseNumberArg("--rates", r));
      tsa.noises_px.clear();
      for (const auto& r : splitList(ts_noise)) tsa.noises_px.push_back(parseNumberArg("--noise", r));
      tsa.command_line = command_line;
      return runTrackStudy(tsa, out, err);
    }
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
      co.scenarios = splitList(cmp_scenarios);
      if (co.scenarios.empty()) throw std::invalid_argument("--scenarios: expected a comma-separated list of scenarios or 'all'");
      if (compare->count("--predictors")) {
        co.predictors = splitList(cmp_predictors);
        if (co.predictors.empty())
          throw std::invalid_argument("--predictors: expected a comma-separated list of predictor names or 'all'");
      }
      if (!cmp_runs.empty()) co.runs = static_cast<int>(parseIntegerArg("--runs", cmp_runs, 1, 100000));
      if (!cmp_seed.empty()) {
        co.seed_given = true;
        co.seed = static_cast<unsigned long>(parseIntegerArg("--seed", cmp_seed, 0, 2147483647L));
      }
      co.overrides = fileOverrides(cmp_set_file, cmp_camera, cmp_camera_name, compare->count("--camera-name") > 0);
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
    for (const auto& text : splitList(predictors_csv)) parsePredictorChoice(text, "--predictors");
    if (!predictors_csv.empty() && splitList(predictors_csv).empty())
      throw std::invalid_argument("--predictors: expected a comma-separated list of predictor names");
    so.predictors = splitList(predictors_csv);
    if (!seed_text.empty()) {
      so.seed_given = true;
      so.seed = static_cast<unsigned long>(parseIntegerArg("--seed", seed_text, 0, 2147483647L));
    }
    so.overrides = fileOverrides(servo_set_file, servo_camera, servo_camera_name, servo->count("--camera-name") > 0);
    if (!servo_params_file.empty()) paramsFileOverrides(servo_params_file, so.overrides);
    for (const auto& text : servo_sets) so.overrides.push_back(parseScenarioOverride(text));
    so.command_line = command_line;
    runScenarioCommand(so, out, err);
    return 0;
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e, out, err);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e, out, err);
  } catch (const CLI::ParseError& e) {
    err << "predvs: error: " << oneLine(e.what()) << " (see predvs --help)\n";
    return 2;
  } catch (const std::exception& e) {
    err << "predvs: error: " << oneLine(e.what()) << "\n";
    return 2;
  }
}

}  // namespace predvs
