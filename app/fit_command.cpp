#include "fit_command.h"

#include "number_text.h"
#include "output_dir.h"
#include "track_csv.h"

#include "predvs/calibration/noise_fit.h"
#include "predvs/calibration/param_file.h"
#include "predvs/predictors/predictor.h"
#include "predvs/servo/data_dir.h"

#include <nlohmann/json.hpp>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>
#include <stdexcept>

namespace predvs {

std::string resolveParamsFile(const std::string& name_or_path) {
  std::error_code ec;
  if (std::filesystem::exists(name_or_path, ec) || name_or_path.find('/') != std::string::npos) return name_or_path;
  const std::filesystem::path installed = std::filesystem::path(dataDir()) / "params" / name_or_path;
  for (const std::string& candidate : {installed.string(), installed.string() + ".yaml"})
    if (std::filesystem::is_regular_file(candidate, ec)) return candidate;
  return name_or_path;
}

std::vector<PredictorSpec> readParamsFile(const std::string& path) {
  std::vector<PredictorSpec> specs;
  for (const auto& e : readParamFile(resolveParamsFile(path))) specs.push_back({e.name, e.params});
  return specs;
}

std::string paramsFileText(const std::vector<PredictorSpec>& specs, const std::vector<std::string>& comment) {
  std::vector<ParamFileEntry> entries;
  for (const auto& s : specs) entries.push_back({s.name, s.params});
  return paramFileText(entries, comment);
}

FitTrack fitTrackOf(const FeatureTrack& track, size_t rows) {
  FitTrack f;
  rows = std::min(rows, track.size());
  f.t_s.assign(track.t_s.begin(), track.t_s.begin() + static_cast<long>(rows));
  for (int p = 0; p < track.points(); ++p) {
    const auto& u = track.u_px[static_cast<size_t>(p)];
    const auto& v = track.v_px[static_cast<size_t>(p)];
    f.channels.emplace_back(u.begin(), u.begin() + static_cast<long>(rows));
    f.channels.emplace_back(v.begin(), v.begin() + static_cast<long>(rows));
  }
  return f;
}

void printFit(const NoiseFitResult& fit, std::ostream& out) {
  out << fit.predictor << ": " << fit.innovations << " innovations, " << fit.iterations << " iterations ("
      << fit.termination << ")\n";
  out << "  " << std::left << std::setw(14) << "parameter" << std::right << std::setw(14) << "start" << std::setw(14)
      << "fitted" << std::setw(30) << "95% interval" << "\n";
  for (const auto& v : fit.values) {
    std::ostringstream iv;
    if (v.held)
      iv << "(held: start value)";
    else if (std::isfinite(v.std_log))
      iv << "[" << std::setprecision(4) << v.lo95 << ", " << v.hi95 << "]";
    else
      iv << "(no covariance)";
    out << "  " << std::left << std::setw(14) << v.key << std::right << std::setw(14) << std::setprecision(5)
        << v.initial << std::setw(14) << v.value << std::setw(30) << iv.str() << (v.at_bound ? "  at bound" : "")
        << "\n";
  }
  out << "  log-likelihood " << std::fixed << std::setprecision(2) << fit.loglik_before << " -> " << fit.loglik_after
      << " (per innovation " << std::setprecision(4) << fit.loglik_before / std::max(1, fit.innovations) << " -> "
      << fit.loglik_after / std::max(1, fit.innovations) << ")"
      << (fit.objective == FitObjective::Likelihood ? "  [maximised]" : "") << "\n";
  out << "  h-step RMSE vs later measurements (h = " << std::setprecision(4) << fit.horizon_s << " s) "
      << fit.rmse_before_px << " -> " << fit.rmse_after_px << " px"
      << (fit.objective == FitObjective::Prediction ? "  [minimised]" : "");
  if (fit.starts > 1)
    out << "; " << fit.starts << " starts" << (fit.warm_start ? " (the last warm, from the fixed KFs' fits)" : "")
        << ", kept #" << fit.best_start << (fit.warm_start_kept ? " (warm)" : "");
  out << "\n";
  if (!fit.variants.empty()) {
    const bool held_out = std::isfinite(fit.variants.front().objective_holdout);
    out << "  structure (fitted each, kept the best " << (fit.objective == FitObjective::Prediction ? "RMSE" : "log-likelihood")
        << (held_out ? " on the held-out last rows" : "") << "):";
    for (const auto& v : fit.variants) {
      out << "  " << v.variant << " " << std::setprecision(4) << v.objective_before << " -> " << v.objective_after;
      if (std::isfinite(v.objective_holdout)) out << " (held out " << v.objective_holdout << ")";
      out << (v.variant == fit.variant ? " [kept]" : "");
    }
    out << "\n";
  }
  if (!fit.forecast_variants.empty()) {
    out << "  forecast (with the fitted noise, kept the best RMSE): own " << std::setprecision(4) << fit.rmse_own_forecast_px
        << (fit.forecast_variant.empty() ? " [kept]" : "");
    for (const auto& v : fit.forecast_variants)
      out << "  " << v.variant << " " << std::setprecision(4) << v.objective_after
          << (v.variant == fit.forecast_variant ? " [kept]" : "");
    out << "\n";
  }
  out.unsetf(std::ios::fixed);
}

int runFitNoise(const FitNoiseArgs& a, std::ostream& out) {
  StagedOutputDir::checkReplaceable(a.out, {a.input, a.params_file});
  if (!isPredictor(a.predictor)) throw std::invalid_argument("--predictor: unknown predictor '" + a.predictor + "'");
  try {
    fitParameters(a.predictor);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("--predictor: ") + e.what());
  }
  Params base;
  if (!a.params_file.empty()) {
    bool named = false;
    for (const auto& s : readParamsFile(a.params_file))
      if (s.name == a.predictor) {
        base = s.params;
        named = true;
      }
    if (!named) throw std::invalid_argument("--params " + a.params_file + ": has no entry for " + a.predictor);
  }
  std::set<std::string> given;
  for (const auto& kv : a.params) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) throw std::invalid_argument("--param: expected KEY=VALUE, got '" + kv + "'");
    if (!given.insert(kv.substr(0, eq)).second) throw std::invalid_argument("--param " + kv.substr(0, eq) + ": given twice");
    const std::string text = kv.substr(eq + 1);
    double v = 0.0;
    switch (classifyParamText(text, &v)) {
      case ParamText::Number: base.set(kv.substr(0, eq), v); break;
      case ParamText::Word: base.setText(kv.substr(0, eq), text); break;  // model: cv: the predictor checks it below
      case ParamText::Invalid:
        throw std::invalid_argument("--param " + kv.substr(0, eq) + ": expected a number or a word, got '" + text + "'");
    }
  }
  try {
    makePredictor(a.predictor, 2, base);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("--param: ") + e.what());
  }
  if (a.burn_in < 0) throw std::invalid_argument("--burn-in: expected an integer >= 0");
  NoiseFitOptions opt;
  try {
    opt.objective = parseFitObjective(a.objective);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("--objective: ") + e.what());
  }
  if (a.horizon_frames < 0) throw std::invalid_argument("--horizon-frames: expected an integer >= 0");
  // 0 frames ahead the prediction is scored against the measurement it was just given: the fit
  // would chase the noise (q without bound), not predict.
  if (a.horizon_frames < 1 && opt.objective == FitObjective::Prediction)
    throw std::invalid_argument("--horizon-frames: expected an integer >= 1 with --objective prediction");
  if (a.starts < 1 || a.starts > 50) throw std::invalid_argument("--starts: expected an integer in [1, 50]");
  const FeatureTrack track = readFeatureTrack(a.input);
  if (track.size() < 2) throw std::invalid_argument(a.input + ": need at least two data rows to measure the frame period");
  opt.burn_in_frames = a.burn_in;
  opt.horizon_s = a.horizon_frames * medianPeriod(track.t_s);
  opt.starts = a.starts;
  if (!validSelectHoldout(a.select_holdout))
    throw std::invalid_argument("--select-holdout: expected a fraction in [0, 0.9]");
  opt.select_holdout = a.select_holdout;
  NoiseFitResult fit;
  try {
    fit = fitNoise(a.predictor, base, fitTrackOf(track, track.size()), opt);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(a.input + ": " + e.what());
  }

  StagedOutputDir dir(a.out);
  std::ostringstream ll;
  ll << std::fixed << std::setprecision(2) << fit.loglik_before << " -> " << fit.loglik_after;
  std::ostringstream rm;
  rm << std::fixed << std::setprecision(4) << fit.rmse_before_px << " -> " << fit.rmse_after_px;
  const std::string yaml = paramsFileText(
      {{a.predictor, fit.params}},
      {"predvs fit-noise: " + a.predictor + " fitted on " + a.input + " (" + std::to_string(track.size()) + " rows)",
       "objective: " + fitObjectiveName(fit.objective) + "; innovation log-likelihood " + ll.str() + " over " +
           std::to_string(fit.innovations) + " innovations; " + std::to_string(a.horizon_frames) +
           "-frame RMSE " + rm.str() + " px",
       "command: " + a.command_line});
  {
    std::ofstream f(dir.file("params.yaml"));
    f << yaml;
    if (!f) throw std::runtime_error(dir.file("params.yaml") + ": write failed");
  }
  nlohmann::json j;
  j["command"] = a.command_line;
  j["input"] = a.input;
  j["predictor"] = a.predictor;
  j["objective"] = fit.objective == FitObjective::Prediction
                       ? "h-step prediction error 1/2 sum (p(t_k + h) - z(t_k + h))^2, z interpolated, rows >= burn_in"
                       : "innovation log-likelihood -1/2 sum(log(2 pi S) + eps^2/S), rows >= burn_in";
  j["objective_name"] = fitObjectiveName(fit.objective);
  j["horizon_frames"] = a.horizon_frames;
  j["horizon_s"] = fit.horizon_s;
  j["residuals"] = fit.residuals;
  j["rmse_before_px"] = fit.rmse_before_px;
  j["rmse_after_px"] = fit.rmse_after_px;
  j["starts"] = fit.starts;
  j["best_start"] = fit.best_start;
  j["burn_in_frames"] = a.burn_in;
  j["innovations"] = fit.innovations;
  j["loglik_before"] = fit.loglik_before;
  j["loglik_after"] = fit.loglik_after;
  j["iterations"] = fit.iterations;
  j["termination"] = fit.termination;
  j["covariance_ok"] = fit.covariance_ok;
  j["fitted"] = nlohmann::json::array();
  for (const auto& v : fit.values)
    j["fitted"].push_back({{"key", v.key},
                           {"start", v.initial},
                           {"value", v.value},
                           {"std_log", std::isfinite(v.std_log) ? nlohmann::json(v.std_log) : nlohmann::json(nullptr)},
                           {"ci95", std::isfinite(v.std_log) ? nlohmann::json({v.lo95, v.hi95}) : nlohmann::json(nullptr)},
                           {"at_bound", v.at_bound},
                           {"held", v.held}});
  j["params"] = paramsJson(fit.params);
  j["variant"] = fit.variant;
  j["variants"] = nlohmann::json::array();
  for (const auto& v : fit.variants)
    j["variants"].push_back({{"variant", v.variant},
                             {"objective_before", v.objective_before},
                             {"objective_after", v.objective_after},
                             {"objective_holdout", std::isfinite(v.objective_holdout) ? nlohmann::json(v.objective_holdout)
                                                                                      : nlohmann::json(nullptr)}});
  j["forecast_variant"] = fit.forecast_variant;
  j["rmse_own_forecast_px"] = std::isfinite(fit.rmse_own_forecast_px) ? nlohmann::json(fit.rmse_own_forecast_px) : nlohmann::json(nullptr);
  j["forecast_variants"] = nlohmann::json::array();
  for (const auto& v : fit.forecast_variants)
    j["forecast_variants"].push_back({{"variant", v.variant}, {"rmse_px", v.objective_after}});
  j["select_holdout"] = a.select_holdout;
  {
    std::ofstream f(dir.file("fit.json"));
    f << j.dump(2) << "\n";
    if (!f) throw std::runtime_error(dir.file("fit.json") + ": write failed");
  }
  dir.commit();
  printFit(fit, out);
  out << "wrote " << (dir.target() / "params.yaml").string() << ", fit.json\n";
  return 0;
}

}  // namespace predvs
