#include "track_cli.h"

#include "app_error.h"
#include "cli_args.h"
#include "fit_command.h"
#include "gnuplot.h"
#include "number_text.h"
#include "output_dir.h"
#include "parallel_for.h"
#include "predict_command.h"
#include "track_commands.h"
#include "track_csv.h"

#include "predvs/calibration/noise_fit.h"
#include "predvs/predictors/predictor.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

namespace predvs {
namespace {

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
  std::string glitch_sigmas;       ///< --glitch-sigmas G (setGlitchSigmas; default: the predictors' own, 0)
};

/// Sets the params of a parameter file on the specs shown under the name of one of its entries
/// (--params FILE; a file names registry predictors, so a labelled spec is not set by it).
void applyParamsFile(const std::string& file, std::vector<PredictorSpec>& specs) {
  bool any = false;
  for (const auto& f : readParamsFile(file))
    for (auto& s : specs)
      if (s.shownName() == f.name) {
        s.params.setAll(f.params);
        any = true;
      }
  if (!any) throw std::invalid_argument("--params " + file + ": names none of the predictors being run");
}

int runPredict(const PredictArgs& a, const std::string& command_line, std::ostream& out) {
  // Validate every argument before touching the file system.
  StagedOutputDir::checkReplaceable(a.out_dir, {a.input, a.params_file});
  std::vector<PredictorSpec> specs = predictorSpecs(a.predictor);
  if (!a.params_file.empty()) applyParamsFile(a.params_file, specs);
  std::set<std::string> given;  // PREDICTOR.KEY of every --param, which may come once
  for (const auto& kv : a.params) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0)
      throw std::invalid_argument("--param: expected [PREDICTOR.]KEY=VALUE, got '" + kv + "'");
    std::string key = kv.substr(0, eq);
    if (!given.insert(key.find('.') == std::string::npos ? specs.front().shownName() + "." + key : key).second)
      throw std::invalid_argument("--param " + key + ": given twice");
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
  if (!a.glitch_sigmas.empty()) setGlitchSigmas(specs, parseNumberArg("--glitch-sigmas", a.glitch_sigmas));
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
  // The frame period, measured once (a 2 M-row track: a 2 M-element median) for the horizon and
  // summary.json; NaN when the track has no two rows (--horizon-s only).
  double period_s = std::numeric_limits<double>::quiet_NaN();
  if (delay_frames >= 0) {
    if (track.size() < 2)
      throw std::invalid_argument(fileLocation(a.input, 0, "--delay-frames needs at least two data rows to measure the frame period"));
    period_s = medianPeriod(track.t_s);
    horizon_s = delay_frames * period_s;
    setHorizonFrames(specs, delay_frames);
  } else if (track.size() >= 2) {
    period_s = medianPeriod(track.t_s);
    if (horizon_s > 0.0) setHorizonFrames(specs, horizon_s / period_s);
  }
  // --fit: each predictor's noise fitted on the first fit_split of the rows (all rows without
  // --fit-split), then run on the whole track; with --fit-split only the rest is scored.
  const auto fit_rows = static_cast<size_t>(std::floor(fit_split * static_cast<double>(track.size())));
  std::ostringstream fit_log;
  if (a.fit && a.fit_split.empty()) fit_options = inSampleFitOptions(fit_options);  // every row is scored
  if (a.no_warm_start && !a.fit) throw std::invalid_argument("--no-warm-start: needs --fit");
  if (a.no_warm_start && !a.fit_split.empty())
    throw std::invalid_argument("--no-warm-start: not with --fit-split (the warm start is used in sample only)");
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
  // With --fit-split only the rows after the fit are scored; predictions.csv has every row.
  PredictionFiles files;
  files.delay_frames = delay_frames;
  files.frame_period_s = period_s;  // measured above
  files.command_line = command_line;
  files.plots = !a.no_plots;
  if (a.fit && !a.fit_split.empty() && fit_rows < track.size()) files.score_from = fit_rows;
  StagedOutputDir dir(a.out_dir);
  const PredictionReport report = predictToFiles(track, specs, horizon_s, files, dir, jobs);
  if (std::all_of(report.runs.begin(), report.runs.end(),
                  [](const PredictionRun& r) { return r.vs_measurement.n == 0 && r.vs_truth.n == 0; }))
    throw std::invalid_argument(fileLocation(a.input, 0,
                                             "no prediction " + csvNumber(horizon_s) + " s ahead can be scored on its " +
                                                 std::to_string(track.size()) + " rows" +
                                                 (files.score_from > 0 ? " after --fit-split" : "") +
                                                 " (--delay-frames, --horizon-s)"));
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

}  // namespace

std::vector<PredictorSpec> predictorSpecs(const std::string& text) {
  return parsePredictorSpecs("--predictor", text == "all" ? std::vector<std::string>{"all"} : splitList("--predictor", text));
}

struct TrackSubcommands::State {
  PredictArgs predict_args;
  FitNoiseArgs fit_noise_args;
  MakeTrackArgs make_track_args;
  TrackStudyArgs track_study_args;
  std::string ts_kinds = "all", ts_predictors = "all", ts_rates = "10,15,30,60", ts_noise = "0.5,1.5,3";
  CLI::App* predict = nullptr;
  CLI::App* fit_noise = nullptr;
  CLI::App* make_track = nullptr;
  CLI::App* track_study = nullptr;
};

TrackSubcommands::TrackSubcommands(CLI::App& app) : s_(std::make_unique<State>()) {
  PredictArgs& pa = s_->predict_args;
  CLI::App* predict = s_->predict = app.add_subcommand("predict", "Open-loop prediction of a recorded feature track (CSV)");
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
      "(the first point; beyond 20,000 rows the minimum and maximum of each series over 1200 equal time slices are drawn, predictions.csv keeps all; "
      "below them each predictor's RMS error per time slice of about 8 frames, every point). "
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
  auto* h = predict->add_option("--horizon-s", pa.horizon_s, "prediction horizon in seconds (>= 0); give this or --delay-frames")->type_name("S");
  auto* d = predict->add_option("--delay-frames", pa.delay_frames,
                                "prediction horizon in frames: H times the median frame period of the input (the predictors "
                                "are told it as horizon_frames, and learn their blend with hold on the horizons up to it)")
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
  predict->add_option("--glitch-sigmas", pa.glitch_sigmas,
                      "the glitch gate on every predictor that does not set glitch_sigmas itself: a measurement G sigmas "
                      "off the line of the two before it is held in doubt until the next frame shows a tracker glitch or a "
                      "step (docs/MODELS.md §16); 0 = off (the default); `predvs track` uses 8")
      ->type_name("G");
  predict->add_option("--params", pa.params_file,
                      "parameter file (YAML, as written by fit-noise; or the name of one of predvs's own, e.g. "
                      "pre-issue-11) for the predictors it names (not a LABEL=NAME "
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

  FitNoiseArgs& fna = s_->fit_noise_args;
  CLI::App* fit_noise = s_->fit_noise = app.add_subcommand("fit-noise", "Fit a predictor's noise parameters on a track (Ceres: innovation likelihood or h-step prediction error)");
  fit_noise->footer("--objective likelihood (default): maximises the innovation log-likelihood -1/2 sum(log(2 pi S) + eps^2/S) of the predictor over the "
                    "track (rows after --burn-in) over its noise parameters on a log scale within bounds (L-BFGS, "
                    "numeric derivatives); the uncertainty is the inverse Fisher information (ceres::Covariance). "
                    "--objective prediction: minimises the mean squared error of the prediction --horizon-frames ahead of every row "
                    "against the track's measurement interpolated at that time (bounded Levenberg-Marquardt); the uncertainty is "
                    "the Gauss-Newton covariance of that least-squares problem scaled by the residual variance; r is held at its start value (h-step errors depend on q/r only); "
                    "then the blend with hold on one horizon (hold_blend_frames: 1) is run with the fitted noise and kept if its h-step error is lower (not for imm). "
                    "Fitted keys: kf-cv, kf-ca, st-akf, st-akf-pm, fakf-classic: q, r; cs-akf: alpha, a_max, a_neg_max, r; "
                    "cs-akf-adaptive, fakf: alpha, sigma_min_sq, sigma_max_sq, r; stkf: r, q (model: ca, the default), "
                    "r, q_pos, q_vel (model: cv); imm: q_cv, q_ca, r. Writes DIR/params.yaml (use with predict/servo/compare "
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
  MakeTrackArgs& mta = s_->make_track_args;
  CLI::App* make_track = s_->make_track = app.add_subcommand("make-track", "Write one generated maneuvering track (truth kept) as a predict input CSV");
  make_track->footer("Kinds: smooth, turns, stops, bursts, zigzag, hand (servo/include/predvs/servo/maneuver_tracks.h). "
                     "Writes FILE with t,u,v,u_true,v_true (through a link; an existing device or pipe is refused); an "
                     "empty u,v cell is a dropped frame.\nErrors: one line 'predvs: error: ...' on stderr, exit status 2, "
                     "FILE not written.");
  make_track->add_option("--kind", mta.kind, "motion kind")->capture_default_str()->type_name("KIND");
  make_track->add_option("--rate-hz", mta.rate_hz, "frame rate in Hz, 1 to 1000")->capture_default_str()->type_name("HZ");
  make_track->add_option("--noise-px", mta.noise_px, "Gaussian noise std per coordinate, px")->capture_default_str()->type_name("PX");
  make_track->add_option("--duration-s", mta.duration_s, "duration in s")->capture_default_str()->type_name("S");
  make_track->add_option("--drop", mta.drop_prob, "probability of a dropped frame, 0 to 0.5; with probability drop/5 an occlusion of 0.1-0.3 s begins")->capture_default_str()->type_name("P");
  make_track->add_option("--seed", mta.seed, "random seed")->capture_default_str()->type_name("N");
  make_track->add_option("--draw", mta.draw, "draw of the noise and the dropped frames over the motion of --seed: 0 = the track's own, D > 0 another independent one (the same truth)")->capture_default_str()->type_name("D");
  make_track->add_option("--glitch", mta.glitch_prob, "probability that a measured frame is a tracker glitch: u, v displaced by --glitch-px for that frame only (own random stream: noise and drops unchanged)")->capture_default_str()->type_name("P");
  make_track->add_option("--glitch-px", mta.glitch_px, "size of a glitch, px")->capture_default_str()->type_name("PX");
  make_track->add_option("--out", mta.out, "output CSV file")->required()->type_name("FILE");

  TrackStudyArgs& tsa = s_->track_study_args;
  std::string &ts_kinds = s_->ts_kinds, &ts_predictors = s_->ts_predictors, &ts_rates = s_->ts_rates,
              &ts_noise = s_->ts_noise;
  CLI::App* track_study = s_->track_study = app.add_subcommand("track-study", "Every predictor against hold on a grid of generated maneuvering tracks");
  track_study->footer("For each kind x rate x noise x seed (x draw), generates a track (make-track), predicts --delay-frames ahead "
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
  track_study->add_option("--draws", tsa.draws, "draws of the noise and the dropped frames per motion (make-track --draw 0..N-1): how much of a result is the luck of where the gaps fall")->capture_default_str()->type_name("N");
  track_study->add_option("--duration-s", tsa.duration_s, "track duration, s")->capture_default_str()->type_name("S");
  track_study->add_option("--drop", tsa.drop_prob, "dropped-frame probability")->capture_default_str()->type_name("P");
  track_study->add_option("--glitch", tsa.glitch_prob, "probability that a measured frame is a tracker glitch (make-track --glitch)")->capture_default_str()->type_name("P");
  track_study->add_option("--glitch-px", tsa.glitch_px, "size of a glitch, px")->capture_default_str()->type_name("PX");
  track_study->add_option("--glitch-sigmas", tsa.glitch_sigmas, "the glitch gate on every predictor that does not set glitch_sigmas itself (predict --glitch-sigmas; 0 = off)")->capture_default_str()->type_name("G");
  track_study->add_option("--delay-frames", tsa.delay_frames, "prediction horizon in frames (told to the predictors as horizon_frames)")->capture_default_str()->type_name("H");
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
}

TrackSubcommands::~TrackSubcommands() = default;

std::vector<std::string> TrackSubcommands::names() {
  CLI::App app;  // the names the constructor gives them, not a second list of them
  const TrackSubcommands tracks(app);
  std::vector<std::string> out;
  for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) out.push_back(sub->get_name());
  return out;
}

std::optional<int> TrackSubcommands::run(const std::string& command_line, std::ostream& out, std::ostream& err) const {
  State& s = *s_;
  if (s.predict->parsed()) return runPredict(s.predict_args, command_line, out);
  if (s.make_track->parsed()) return runMakeTrack(s.make_track_args, out);
  if (s.fit_noise->parsed()) {
    FitNoiseArgs a = s.fit_noise_args;
    a.command_line = command_line;
    return runFitNoise(a, out);
  }
  if (s.track_study->parsed()) {
    TrackStudyArgs a = s.track_study_args;
    // The fit's options do nothing without --fit, and the warm start is used only when the fit is
    // scored in sample (--fit-split 1): refused, as predict refuses them.
    for (const char* o : {"--fit-split", "--fit-objective", "--fit-starts", "--fit-select-holdout", "--no-warm-start"})
      if (!a.fit && s.track_study->count(o) > 0) throw std::invalid_argument(std::string(o) + ": needs --fit");
    if (a.no_warm_start && a.fit_split < 1.0)
      throw std::invalid_argument("--no-warm-start: needs --fit-split 1 (the warm start is used in sample only)");
    a.kinds = splitList("--kinds", s.ts_kinds);
    a.predictors = splitList("--predictors", s.ts_predictors);
    a.rates_hz.clear();
    for (const auto& r : splitList("--rates", s.ts_rates)) a.rates_hz.push_back(parseNumberArg("--rates", r));
    a.noises_px.clear();
    for (const auto& r : splitList("--noise", s.ts_noise)) a.noises_px.push_back(parseNumberArg("--noise", r));
    a.command_line = command_line;
    return runTrackStudy(a, out, err);
  }
  return std::nullopt;
}

int runTrackCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  CLI::App app{"predvs: the commands on feature tracks (predict, fit-noise, make-track, track-study); "
               "`predvs --help` lists every command.", "predvs"};
  app.require_subcommand(1);
  app.footer("Errors: one line 'predvs: error: ...' on stderr, exit status 2, no output directory.");
  const TrackSubcommands tracks(app);
  const std::string command_line = commandLine(args);
  return parseAndRun(app, args, out, err, [&] { return *tracks.run(command_line, out, err); });
}

}  // namespace predvs
