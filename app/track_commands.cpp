#include "track_commands.h"

#include "parallel_runs.h"
#include "number_text.h"
#include "predict_command.h"

#include "output_dir.h"

#include "predvs/calibration/noise_fit.h"
#include "predvs/predictors/predictor.h"
#include "predvs/servo/maneuver_tracks.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

namespace predvs {
namespace {

/// The checks of the generator's options shared by make-track and track-study, naming the option
/// (the generator's own checks would name its config keys).
void checkGeneratorArgs(double duration_s, double drop_prob, double glitch_prob, double glitch_px) {
  if (!(duration_s > 0.0 && duration_s <= 1e6)) throw std::invalid_argument("--duration-s: expected a duration in (0, 1e6] s");
  if (!(drop_prob >= 0.0 && drop_prob <= 0.5)) throw std::invalid_argument("--drop: expected a probability in [0, 0.5]");
  if (!(glitch_prob >= 0.0 && glitch_prob <= 0.5)) throw std::invalid_argument("--glitch: expected a probability in [0, 0.5]");
  if (!(glitch_px > 0.0 && std::isfinite(glitch_px))) throw std::invalid_argument("--glitch-px: expected a size > 0 px");
}

bool validNoisePx(double s) { return s >= 0.0 && std::isfinite(s); }
bool validRateHz(double r) { return r >= 1.0 && r <= 1000.0; }

}  // namespace

int runMakeTrack(const MakeTrackArgs& a, std::ostream& out) {
  ManeuverTrackConfig c;
  c.kind = parseManeuverKind(a.kind);
  if (!validRateHz(a.rate_hz)) throw std::invalid_argument("--rate-hz: expected a rate in [1, 1000] Hz");
  if (!validNoisePx(a.noise_px)) throw std::invalid_argument("--noise-px: expected a finite standard deviation >= 0 px");
  checkGeneratorArgs(a.duration_s, a.drop_prob, a.glitch_prob, a.glitch_px);
  if (a.seed < 0) throw std::invalid_argument("--seed: expected an integer >= 0");
  if (a.draw < 0) throw std::invalid_argument("--draw: expected an integer >= 0");
  if (a.out.empty()) throw std::invalid_argument("--out: expected a file path");
  c.rate_hz = a.rate_hz;
  c.noise_px = a.noise_px;
  c.duration_s = a.duration_s;
  c.drop_prob = a.drop_prob;
  c.seed = static_cast<std::uint64_t>(a.seed);
  c.draw = static_cast<std::uint64_t>(a.draw);
  c.glitch_prob = a.glitch_prob;
  c.glitch_px = a.glitch_px;
  const ManeuverTrack track = generateManeuverTrack(c);

  namespace fs = std::filesystem;
  std::error_code ec;
  // A link is written through (the file it names is replaced); a device, pipe or socket is refused:
  // the temporary file renamed over it would replace the node itself.
  const fs::path target = fs::is_symlink(a.out, ec) ? fs::weakly_canonical(fs::path(a.out), ec) : fs::path(a.out);
  if (fs::is_directory(target, ec)) throw std::invalid_argument("--out: '" + a.out + "' is a directory, expected a file path");
  if (fs::exists(target, ec) && !fs::is_regular_file(target, ec))
    throw std::invalid_argument("--out: '" + a.out + "' exists and is not a regular file");
  const fs::path parent = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(parent, ec))
    throw std::invalid_argument("--out: '" + parent.string() + "' " + (fs::exists(parent, ec) ? "is not a directory" : "does not exist"));
  const fs::path tmp = parent / ("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()));
  {
    std::ofstream csv(tmp);
    csv << "t,u,v,u_true,v_true\n";
    for (size_t i = 0; i < track.size(); ++i)
      csv << csvCell(track.t_s[i]) << "," << csvCell(track.u_px[i]) << "," << csvCell(track.v_px[i]) << ","
          << csvCell(track.u_true_px[i]) << "," << csvCell(track.v_true_px[i]) << "\n";
    if (!csv) {
      fs::remove(tmp, ec);
      throw std::runtime_error("--out: cannot write '" + a.out + "'");
    }
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw std::runtime_error("--out: cannot write '" + a.out + "': " + ec.message());
  }
  size_t dropped = 0;
  for (double u : track.u_px) dropped += std::isfinite(u) ? 0 : 1;
  out << "wrote " << a.out << ": " << maneuverKindName(c.kind) << ", " << track.size() << " frames at " << c.rate_hz
      << " Hz, noise " << c.noise_px << " px, " << dropped << " dropped frames, ";
  if (c.glitch_prob > 0.0) out << track.glitches << " glitches of " << c.glitch_px << " px, ";
  out << "seed " << c.seed;
  if (c.draw > 0) out << ", draw " << c.draw;
  out << "\n";
  return 0;
}

int runTrackStudy(const TrackStudyArgs& a, std::ostream& out, std::ostream& err) {
  if (!a.out.empty()) StagedOutputDir::checkReplaceable(a.out, {});
  std::vector<ManeuverKind> kinds;
  if (a.kinds.empty() || (a.kinds.size() == 1 && a.kinds[0] == "all"))
    kinds = maneuverKinds();
  else
    for (const auto& k : a.kinds) kinds.push_back(parseManeuverKind(k));
  // A grid axis given a value twice would count its tracks twice.
  const auto once = [](const auto& values, const std::string& option) {
    for (size_t i = 0; i < values.size(); ++i)
      if (std::find(values.begin(), values.begin() + static_cast<long>(i), values[i]) != values.begin() + static_cast<long>(i))
        throw std::invalid_argument(option + ": a value listed twice");
  };
  once(kinds, "--kinds");
  once(a.rates_hz, "--rates");
  once(a.noises_px, "--noise");
  // names: the label of each entry (the registry name unless LABEL= was given), types: its
  // registry predictor, inline: its KEY=VALUE (parsePredictorSpecs, predict_command.h).
  std::vector<std::string> names, types;
  std::vector<Params> inline_params;
  std::vector<PredictorSpec> specs =
      parsePredictorSpecs("--predictors", a.predictors.empty() ? std::vector<std::string>{"all"} : a.predictors);
  setGlitchSigmas(specs, a.glitch_sigmas);
  for (const PredictorSpec& s : specs) {
    names.push_back(s.shownName());
    types.push_back(s.name);
    inline_params.push_back(s.params);
  }
  // hold first (every ratio is to its RMSE on the same track): added when not listed, moved when
  // listed later.
  const auto hold_at = std::find(names.begin(), names.end(), "hold");
  if (hold_at == names.end()) {
    names.insert(names.begin(), "hold");
    types.insert(types.begin(), "hold");
    inline_params.insert(inline_params.begin(), Params{});
  } else {
    const auto k = static_cast<size_t>(hold_at - names.begin());  // hold's own (predictorLabelProblem)
    std::rotate(names.begin(), names.begin() + static_cast<long>(k), names.begin() + static_cast<long>(k) + 1);
    std::rotate(types.begin(), types.begin() + static_cast<long>(k), types.begin() + static_cast<long>(k) + 1);
    std::rotate(inline_params.begin(), inline_params.begin() + static_cast<long>(k),
                inline_params.begin() + static_cast<long>(k) + 1);
  }
  const auto typeOf = [&](const std::string& label) -> std::string {
    const auto it = std::find(names.begin(), names.end(), label);
    return it == names.end() ? label : types[static_cast<size_t>(it - names.begin())];
  };
  if (a.seeds < 1) throw std::invalid_argument("--seeds: expected an integer >= 1");
  if (a.seed < 0) throw std::invalid_argument("--seed: expected an integer >= 0");
  if (a.draws < 1) throw std::invalid_argument("--draws: expected an integer >= 1");
  checkGeneratorArgs(a.duration_s, a.drop_prob, a.glitch_prob, a.glitch_px);
  if (a.delay_frames < 0) throw std::invalid_argument("--delay-frames: expected an integer >= 0");
  for (double r : a.rates_hz)
    if (!validRateHz(r)) throw std::invalid_argument("--rates: expected rates in [1, 1000] Hz");
  for (double s : a.noises_px)
    if (!validNoisePx(s)) throw std::invalid_argument("--noise: expected finite standard deviations >= 0 px");
  std::map<std::string, Params> fixed;
  for (const auto& kv : a.params) {
    const auto eq = kv.find('='), dot = kv.find('.');
    if (eq == std::string::npos || dot == std::string::npos || dot > eq)
      throw std::invalid_argument("--param: expected PREDICTOR.KEY=VALUE, got '" + kv + "'");
    const std::string name = kv.substr(0, dot), key = kv.substr(dot + 1, eq - dot - 1), text = kv.substr(eq + 1);
    if (fixed[name].has(key)) throw std::invalid_argument("--param " + kv.substr(0, eq) + ": given twice");
    if (!isPredictor(typeOf(name))) throw std::invalid_argument("--param " + kv + ": unknown predictor '" + name + "'");
    if (std::find(names.begin(), names.end(), name) == names.end())
      throw std::invalid_argument("--param " + kv + ": predictor '" + name + "' is not being run (--predictors)");
    double v = 0.0;
    switch (classifyParamText(text, &v)) {
      case ParamText::Number: fixed[name].set(key, v); break;
      case ParamText::Word: fixed[name].setText(key, text); break;  // r: auto, model: cv (the predictor checks it)
      case ParamText::Invalid:
        throw std::invalid_argument("--param " + kv + ": expected a number or a word (auto, cv, ...)");
    }
  }
  for (size_t j = 0; j < names.size(); ++j)  // an entry's KEY=VALUE, then --param LABEL.KEY on top
    for (const auto& kv : inline_params[j].values())
      fixed[names[j]].setUnlessGiven(kv.first, kv.second);
  for (size_t j = 0; j < names.size(); ++j)
    for (const auto& kv : inline_params[j].texts())
      if (!fixed[names[j]].has(kv.first)) fixed[names[j]].setText(kv.first, kv.second);
  for (const auto& [name, p] : fixed) {
    try {
      makePredictor(typeOf(name), 2, p);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("--param: ") + e.what());
    }
  }
  // The horizon asked for (predict_command.h setHorizonFrames), on every entry.
  for (const auto& name : names) fixed[name].setUnlessGiven("horizon_frames", a.delay_frames);
  if (a.fit && !(a.fit_split > 0.0 && a.fit_split <= 1.0))
    throw std::invalid_argument("--fit-split: expected a fraction in (0, 1] (1 = fit and score the whole track)");
  // --fit-split 1: each predictor fitted on every row of the track and scored on every row, as
  // `predict --fit` without --fit-split does (the issue's --fit, in sample); F < 1: fitted on the
  // first F of the rows and scored on the rest only (out of sample, the stricter check).
  const bool whole_track = a.fit && a.fit_split >= 1.0;

  NoiseFitOptions fit_options;
  try {
    fit_options.objective = parseFitObjective(a.fit_objective);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("--fit-objective: ") + e.what());
  }
  if (a.fit_starts < 1 || a.fit_starts > 50) throw std::invalid_argument("--fit-starts: expected an integer in [1, 50]");
  if (a.jobs < 1 || a.jobs > 256) throw std::invalid_argument("--jobs: expected an integer in [1, 256]");
  fit_options.starts = a.fit_starts;
  if (!validSelectHoldout(a.fit_select)) throw std::invalid_argument("--fit-select-holdout: expected a fraction in [0, 0.9]");
  fit_options.select_holdout = a.fit_select;
  // Warm start (noise_fit.h NoiseFitOptions::seed_fits) for fits scored in sample only (--fit-split 1),
  // as the burn-in rule inSampleFitOptions: at split 0.5 it lost 1-2 tracks of the 12/20/45 Hz grid
  // for five predictors (docs/PERFORMANCE.md "Warm start").
  const bool fit_seeds = !a.no_warm_start && whole_track;

  struct Row {
    std::string kind;
    double rate_hz, noise_px;
    long seed, draw;
    std::string predictor;
    TrackScore score;
    double ratio;
    std::string variant;  ///< with --fit: the structural variant the fit kept (e.g. model=ca), else empty
  };
  const auto trackKey = [](const Row& r) {
    std::ostringstream k;
    k << r.kind << " " << r.rate_hz << " Hz " << r.noise_px << " px #" << r.seed;
    if (r.draw > 0) k << "/d" << r.draw;
    return k.str();
  };

  std::vector<ManeuverTrackConfig> configs;
  for (ManeuverKind kind : kinds)
    for (double rate : a.rates_hz)
      for (double noise : a.noises_px)
        for (int s = 0; s < a.seeds; ++s)
          for (int d = 0; d < a.draws; ++d) {
            ManeuverTrackConfig c;
            c.kind = kind;
            c.rate_hz = rate;
            c.noise_px = noise;
            c.duration_s = a.duration_s;
            c.drop_prob = a.drop_prob;
            c.seed = static_cast<std::uint64_t>(a.seed + s);
            c.draw = static_cast<std::uint64_t>(d);
            c.glitch_prob = a.glitch_prob;
            c.glitch_px = a.glitch_px;
            configs.push_back(c);
          }
  // One track per work item; the rows of track i go to per_track[i], so the order (and every
  // figure) does not depend on --jobs.
  std::vector<std::vector<Row>> per_track(configs.size());
  const auto runTrack = [&](size_t i) {
    const ManeuverTrackConfig& c = configs[i];
    const ManeuverTrack track = generateManeuverTrack(c);
    const double horizon = a.delay_frames / c.rate_hz;
    double hold_rmse = std::numeric_limits<double>::quiet_NaN();
    const size_t split = a.fit ? (whole_track ? track.size() : static_cast<size_t>(a.fit_split * static_cast<double>(track.size()))) : 0;
    const size_t first_scored = whole_track ? 0 : split;
    FitTrack head;
    head.t_s.assign(track.t_s.begin(), track.t_s.begin() + static_cast<long>(split));
    head.channels = {std::vector<double>(track.u_px.begin(), track.u_px.begin() + static_cast<long>(split)),
                     std::vector<double>(track.v_px.begin(), track.v_px.begin() + static_cast<long>(split))};
    NoiseFitOptions fo = whole_track ? inSampleFitOptions(fit_options) : fit_options;
    fo.horizon_s = horizon;  // the command's own horizon: the score is what is fitted
    // --fit: the predictors that seed others' fits (the fixed KFs) first, then the others, warm
    // started from those fitted values (noise_fit.h fitOrder, NoiseFitOptions::seed_fits).
    std::vector<Params> fitted(names.size());
    std::vector<std::string> variants(names.size());
    for (size_t j = 0; j < names.size(); ++j) fitted[j] = fixed.count(names[j]) ? fixed.at(names[j]) : Params{};
    if (a.fit)
      for (size_t j : fitOrder(types, fitted)) {
        if (types[j] == "hold") continue;
        NoiseFitResult fit;
        try {
          fit = fitNoise(types[j], fitted[j], head, fo);
        } catch (const std::invalid_argument& e) {
          const Row named{maneuverKindName(c.kind), c.rate_hz, c.noise_px, static_cast<long>(c.seed),
                          static_cast<long>(c.draw), names[j], {}, 0.0, ""};
          throw std::invalid_argument("track " + trackKey(named) + ": --fit " + names[j] + ": " + e.what() +
                                      " (--duration-s, --fit-split)");
        }
        fitted[j] = fit.params;
        variants[j] = fit.variant;  // the structure, then the forecast variant (if one was kept)
        if (!fit.forecast_variant.empty()) variants[j] += (variants[j].empty() ? "" : ",") + fit.forecast_variant;
        if (fit_seeds) fo.seed_fits[types[j]] = fit.params;
      }
    for (size_t j = 0; j < names.size(); ++j) {
      const std::string& name = names[j];
      const Params& params = fitted[j];
      const std::string& variant = variants[j];
      auto p = makePredictor(types[j], 2, params);
      const TrackScore sc = scoreOnTrack(track, *p, horizon, first_scored);
      if (name == "hold") hold_rmse = sc.rmse_truth_px;
      per_track[i].push_back({maneuverKindName(c.kind), c.rate_hz, c.noise_px, static_cast<long>(c.seed), static_cast<long>(c.draw), name, sc,
                              sc.rmse_truth_px / hold_rmse, variant});
      if (name != "hold") continue;
      if (sc.n == 0)
        throw std::invalid_argument("track " + trackKey(per_track[i].back()) + ": no prediction " +
                                    std::to_string(a.delay_frames) + " frames ahead is scored on its " +
                                    std::to_string(track.size()) + " frames (--duration-s, --delay-frames" +
                                    (a.fit ? ", --fit-split" : "") + ")");
      if (!(hold_rmse > 0.0))
        throw std::invalid_argument("track " + trackKey(per_track[i].back()) +
                                    ": hold predicts the truth exactly (no noise, no horizon), so there is no ratio to "
                                    "hold (--noise, --delay-frames)");
    }
  };
  if (a.jobs == 1) {
    for (size_t i = 0; i < configs.size(); ++i) runTrack(i);
  } else {
    ParallelOptions po;
    po.workers = a.jobs;
    po.label = "track-study";
    runParallel(configs.size(), runTrack, po, err);
  }
  std::vector<Row> rows;
  for (auto& v : per_track) rows.insert(rows.end(), v.begin(), v.end());
  // "kind rate Hz noise px #seed", "/dD" after the seed for a draw D > 0: a track's name and key.
  // Summary per predictor.
  size_t w = 9;
  for (const auto& n : names) w = std::max(w, n.size());
  out << std::left << std::setw(static_cast<int>(w)) << "predictor" << std::right << std::setw(12) << "beats hold"
      << std::setw(12) << "mean ratio" << std::setw(12) << "worst ratio" << "  worst track (kind rate noise seed)\n";
  for (const auto& name : names) {
    if (name == "hold") continue;
    int wins = 0, total = 0;
    double sum = 0.0, worst = -1.0;
    const Row* worst_row = nullptr;
    for (const auto& r : rows) {
      if (r.predictor != name) continue;
      ++total;
      if (r.ratio < 1.0) ++wins;
      sum += std::log(r.ratio);
      if (r.ratio > worst) {
        worst = r.ratio;
        worst_row = &r;
      }
    }
    out << std::left << std::setw(static_cast<int>(w)) << name << std::right << std::setw(12)
        << (std::to_string(wins) + "/" + std::to_string(total)) << std::setw(12) << std::fixed << std::setprecision(3)
        << std::exp(sum / std::max(1, total)) << std::setw(12) << worst << "  " << (worst_row ? trackKey(*worst_row) : "")
        << "\n";
    out.unsetf(std::ios::fixed);
  }
  out << "ratio = RMSE vs truth / RMSE(hold) vs truth, " << a.delay_frames
      << " frames ahead; mean = geometric mean over tracks\n";
  // imm against the best of its single models, track by track.
  const auto has = [&](const char* n) { return std::find(names.begin(), names.end(), n) != names.end(); };
  if (has("imm") && has("kf-cv") && has("kf-ca")) {
    std::map<std::string, double> best, imm;  // key: kind rate noise seed
    for (const auto& r : rows) {
      const std::string k = trackKey(r);
      if (r.predictor == "imm") imm[k] = r.score.rmse_truth_px;
      if (r.predictor == "kf-cv" || r.predictor == "kf-ca")
        best[k] = best.count(k) ? std::min(best[k], r.score.rmse_truth_px) : r.score.rmse_truth_px;
    }
    int within = 0;
    double worst = 0.0, sum = 0.0;
    std::string worst_key;
    for (const auto& [k, v] : imm) {
      const double ratio = v / best[k];
      within += ratio <= 1.1 ? 1 : 0;
      sum += std::log(ratio);
      if (ratio > worst) {
        worst = ratio;
        worst_key = k;
      }
    }
    out << "imm / best of kf-cv, kf-ca: within 10 % on " << within << "/" << imm.size() << " tracks, geometric mean "
        << std::setprecision(3) << std::exp(sum / std::max<size_t>(1, imm.size())) << ", worst " << worst << " ("
        << worst_key << ")\n";
  }

  // Adaptive predictors against the best fixed KF (kf-cv, kf-ca, cs-akf) run on the same track
  // (issue 11 item 3, second criterion: within 10 % on every track).
  {
    const std::vector<std::string> fixed_kfs = {"kf-cv", "kf-ca", "cs-akf"};
    std::vector<std::string> present_fixed, adaptive;
    for (const auto& n : names) {
      if (n == "hold") continue;
      if (std::find(fixed_kfs.begin(), fixed_kfs.end(), n) != fixed_kfs.end())
        present_fixed.push_back(n);
      else
        adaptive.push_back(n);
    }
    if (!present_fixed.empty() && !adaptive.empty()) {
      std::map<std::string, double> best;
      for (const auto& r : rows)
        if (std::find(present_fixed.begin(), present_fixed.end(), r.predictor) != present_fixed.end()) {
          const std::string k = trackKey(r);
          best[k] = best.count(k) ? std::min(best[k], r.score.rmse_truth_px) : r.score.rmse_truth_px;
        }
      std::string fixed_list;
      for (const auto& f : present_fixed) fixed_list += (fixed_list.empty() ? "" : ", ") + f;
      out << "\n" << std::left << std::setw(static_cast<int>(w)) << "adaptive" << std::right << std::setw(12)
          << "within 10%" << std::setw(12) << "mean ratio" << std::setw(12) << "worst ratio"
          << "  worst track   (ratio = RMSE vs truth / best of " << fixed_list << (a.fit ? ", all fitted" : "") << ")\n";
      for (const auto& name : adaptive) {
        int within = 0, total = 0;
        double sum = 0.0, worst = -1.0;
        std::string worst_key;
        for (const auto& r : rows) {
          if (r.predictor != name) continue;
          const double ratio = r.score.rmse_truth_px / best[trackKey(r)];
          ++total;
          within += ratio <= 1.1 ? 1 : 0;
          sum += std::log(ratio);
          if (ratio > worst) {
            worst = ratio;
            worst_key = trackKey(r);
          }
        }
        out << std::left << std::setw(static_cast<int>(w)) << name << std::right << std::setw(12)
            << (std::to_string(within) + "/" + std::to_string(total)) << std::setw(12) << std::fixed
            << std::setprecision(3) << std::exp(sum / std::max(1, total)) << std::setw(12) << worst << "  " << worst_key
            << "\n";
        out.unsetf(std::ios::fixed);
      }
      // The same count per kind, for the adaptive predictors and the fixed KFs themselves: which
      // model family wins where.
      if (kinds.size() > 1) {
        out << "within 10 % of that best, per kind:\n" << std::left << std::setw(static_cast<int>(w)) << "predictor"
            << std::right;
        for (ManeuverKind kind : kinds) out << std::setw(9) << maneuverKindName(kind);
        out << "\n";
        std::vector<std::string> listed = adaptive;
        listed.insert(listed.end(), present_fixed.begin(), present_fixed.end());
        for (const auto& name : listed) {
          out << std::left << std::setw(static_cast<int>(w)) << name << std::right;
          for (ManeuverKind kind : kinds) {
            int within = 0, total = 0;
            for (const auto& r : rows) {
              if (r.predictor != name || r.kind != maneuverKindName(kind)) continue;
              ++total;
              within += r.score.rmse_truth_px / best[trackKey(r)] <= 1.1 ? 1 : 0;
            }
            out << std::setw(9) << (std::to_string(within) + "/" + std::to_string(total));
          }
          out << "\n";
        }
      }
    }
  }
  if (a.fit) {
    if (whole_track)
      out << "fitted on the whole of each track";
    else
      out << "fitted on the first " << a.fit_split << " of each track";
    out << " by " << fitObjectiveName(fit_options.objective)
        << (fit_options.objective == FitObjective::Prediction
                ? " (squared error of the " + std::to_string(a.delay_frames) + "-frame prediction vs the later measurements)"
                : " (innovation log-likelihood)")
        << ", " << a.fit_starts << " start" << (a.fit_starts > 1 ? "s" : "")
        << (fit_seeds ? " (+1 warm start from the fixed KFs' fits, +2 for a CS structure: from cs-akf's and from kf-ca's)" : "")
        << (whole_track ? "; scored on the whole track (in sample, as predict --fit)\n" : "; scored on the rest\n");
  }
  if (a.fit) {
    // Which structure the fit kept, per predictor that offers several (Predictor::structuralVariants),
    // with the forecast variant it kept, if any (Predictor::forecastVariants).
    std::map<std::string, std::map<std::string, int>> kept;
    for (const auto& r : rows)
      if (!r.variant.empty()) ++kept[r.predictor][r.variant];
    for (const auto& name : names) {
      if (!kept.count(name)) continue;
      out << "fit kept for " << name << ":";
      for (const auto& kv : kept.at(name)) out << " " << kv.first << " on " << kv.second;
      out << " tracks\n";
    }
  }

  if (!a.out.empty()) {
    StagedOutputDir dir(a.out);
    std::ofstream csv(dir.file("study.csv"));
    csv << "kind,rate_hz,noise_px,seed,predictor,rmse_truth_px,rmse_meas_px,n,ratio_to_hold,fit_variant,draw\n";
    for (const auto& r : rows)
      csv << r.kind << "," << r.rate_hz << "," << r.noise_px << "," << r.seed << "," << r.predictor << ","
          << csvCell(r.score.rmse_truth_px) << "," << csvCell(r.score.rmse_meas_px) << "," << r.score.n << ","
          << csvCell(r.ratio) << "," << [&] {
               std::string v = r.variant;  // "key=value,key=value": one CSV cell
               std::replace(v.begin(), v.end(), ',', ';');
               return v;
             }() << "," << r.draw << "\n";
    if (!csv) throw std::runtime_error(dir.file("study.csv") + ": write failed");
    csv.close();
    dir.commit();
    out << "wrote " << (dir.target() / "study.csv").string() << "\n";
  }
  return 0;
}

}  // namespace predvs
