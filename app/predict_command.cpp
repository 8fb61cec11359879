#include "predict_command.h"

#include "report.h"

#include "gnuplot.h"
#include "output_dir.h"

#include "predvs/predictors/predictor.h"

#include <nlohmann/json.hpp>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <algorithm>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

nlohmann::json errorsJson(const PredictionErrors& e) {
  nlohmann::json j;
  j["rmse_px"] = e.n > 0 ? e.rmse_px : kNaN;
  j["rmse_u_px"] = e.n > 0 ? e.rmse_u_px : kNaN;
  j["rmse_v_px"] = e.n > 0 ? e.rmse_v_px : kNaN;
  j["n"] = e.n;
  return j;
}

/// Appends x as csvNumber(x, precision) would write it (printf "%.{precision}g": std::to_chars in
/// the general format is specified to give the same characters), without a stream or a temporary
/// string; nothing for a non-finite x (an empty cell), or `nan_text` when given.
void appendNumber(std::string& out, double x, int precision, const char* nan_text = "") {
  if (!std::isfinite(x)) {
    out += nan_text;
    return;
  }
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::general, precision);
  out.append(buf, r.ptr);
}

/// Writes `text` to `path` in one call; throws std::runtime_error naming the file on failure.
void writeWhole(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!f) throw std::runtime_error(path + ": write failed");
}

}  // namespace

size_t plotStride(size_t rows) { return rows <= kMaxPlotRows ? 1 : (rows + kMaxPlotRows - 1) / kMaxPlotRows; }

namespace {

/// y interpolated at t_s[i] + horizon_s for every row i (interpolateAt), computed once per point
/// and shared by every predictor's scoring.
std::vector<double> referenceAt(const std::vector<double>& t_s, const std::vector<double>& y, double horizon_s) {
  std::vector<double> r(t_s.size());
  for (size_t i = 0; i < t_s.size(); ++i) r[i] = interpolateAt(t_s, y, t_s[i] + horizon_s);
  return r;
}

/// The RMSEs of n (u, v) errors from their sums of squares (NaN when n == 0).
PredictionErrors fromSquareSums(double su, double sv, int n) {
  PredictionErrors e;
  e.n = n;
  if (n == 0) {
    e.rmse_px = e.rmse_u_px = e.rmse_v_px = kNaN;
    return e;
  }
  e.rmse_u_px = std::sqrt(su / n);
  e.rmse_v_px = std::sqrt(sv / n);
  e.rmse_px = std::sqrt((su + sv) / n);
  return e;
}

/// predictionErrors against references already interpolated at t + horizon (referenceAt).
PredictionErrors errorsAgainst(const std::vector<double>& u_pred, const std::vector<double>& v_pred,
                               const std::vector<double>& u_ref_at, const std::vector<double>& v_ref_at) {
  double su = 0.0, sv = 0.0;
  int n = 0;
  for (size_t i = 0; i < u_pred.size(); ++i) {
    if (!std::isfinite(u_pred[i]) || !std::isfinite(v_pred[i])) continue;
    const double ur = u_ref_at[i], vr = v_ref_at[i];
    if (!std::isfinite(ur) || !std::isfinite(vr)) continue;
    su += (u_pred[i] - ur) * (u_pred[i] - ur);
    sv += (v_pred[i] - vr) * (v_pred[i] - vr);
    ++n;
  }
  return fromSquareSums(su, sv, n);
}

}  // namespace

PredictionErrors predictionErrors(const std::vector<double>& t_s, const std::vector<double>& u_pred,
                                  const std::vector<double>& v_pred, double horizon_s,
                                  const std::vector<double>& u_ref, const std::vector<double>& v_ref) {
  return errorsAgainst(u_pred, v_pred, referenceAt(t_s, u_ref, horizon_s), referenceAt(t_s, v_ref, horizon_s));
}

PredictionErrors pooledErrors(const std::vector<PredictionErrors>& parts) {
  double su = 0.0, sv = 0.0;
  int n = 0;
  for (const auto& p : parts) {
    if (p.n == 0) continue;
    su += p.rmse_u_px * p.rmse_u_px * p.n;
    sv += p.rmse_v_px * p.rmse_v_px * p.n;
    n += p.n;
  }
  return fromSquareSums(su, sv, n);
}

PredictionReport predictTrack(const FeatureTrack& track, const std::vector<PredictorSpec>& predictors,
                              double horizon_s) {
  if (!(horizon_s >= 0.0) || !std::isfinite(horizon_s))
    throw std::invalid_argument("the prediction horizon must be a finite number >= 0 s");
  PredictionReport report;
  report.horizon_s = horizon_s;
  const int n = track.points();
  // The references at t + horizon, per point: measured and (if any) true.
  std::vector<std::vector<double>> u_meas_at, v_meas_at, u_true_at, v_true_at;
  for (size_t p = 0; p < static_cast<size_t>(n); ++p) {
    u_meas_at.push_back(referenceAt(track.t_s, track.u_px[p], horizon_s));
    v_meas_at.push_back(referenceAt(track.t_s, track.v_px[p], horizon_s));
    if (!track.hasTruth()) continue;
    u_true_at.push_back(referenceAt(track.t_s, track.u_true_px[p], horizon_s));
    v_true_at.push_back(referenceAt(track.t_s, track.v_true_px[p], horizon_s));
  }
  for (const auto& spec : predictors) {
    PredictionRun run;
    run.spec = spec;
    run.points.resize(static_cast<size_t>(n));
    for (auto& pt : run.points) {
      pt.u_pred_px.reserve(track.size());
      pt.v_pred_px.reserve(track.size());
    }
    auto predictor = makePredictor(spec.name, 2 * n, spec.params);
    Eigen::VectorXd z(2 * n);
    for (size_t i = 0; i < track.size(); ++i) {
      for (int p = 0; p < n; ++p) {
        z(2 * p) = track.u_px[static_cast<size_t>(p)][i];
        z(2 * p + 1) = track.v_px[static_cast<size_t>(p)][i];
      }
      predictor->update(track.t_s[i], z);
      const Eigen::VectorXd x = predictor->predictPositions(track.t_s[i] + horizon_s);
      for (int p = 0; p < n; ++p) {
        run.points[static_cast<size_t>(p)].u_pred_px.push_back(x(2 * p));
        run.points[static_cast<size_t>(p)].v_pred_px.push_back(x(2 * p + 1));
      }
    }
    std::vector<PredictionErrors> meas, truth;
    for (int p = 0; p < n; ++p) {
      const size_t pp = static_cast<size_t>(p);
      PointPrediction& pt = run.points[pp];
      pt.vs_measurement = errorsAgainst(pt.u_pred_px, pt.v_pred_px, u_meas_at[pp], v_meas_at[pp]);
      meas.push_back(pt.vs_measurement);
      if (track.hasTruth()) {
        pt.vs_truth = errorsAgainst(pt.u_pred_px, pt.v_pred_px, u_true_at[pp], v_true_at[pp]);
        truth.push_back(pt.vs_truth);
      }
    }
    run.vs_measurement = pooledErrors(meas);
    if (track.hasTruth()) run.vs_truth = pooledErrors(truth);
    report.runs.push_back(std::move(run));
  }
  return report;
}

void writePredictionOutputs(const FeatureTrack& track, const PredictionReport& report, int delay_frames,
                            const std::string& command_line, bool plots, StagedOutputDir& dir) {
  const int n = track.points();
  const bool single = n == 1;
  {
    // csvCell's format (10 significant digits), built in a buffer written out every ~4 MB.
    const std::string csv_path = dir.file("predictions.csv");
    std::ofstream csv_file(csv_path, std::ios::binary);
    constexpr size_t kChunk = size_t{4} << 20;
    std::string csv;
    csv.reserve(kChunk + 4096);
    auto flush = [&] {
      csv_file.write(csv.data(), static_cast<std::streamsize>(csv.size()));
      csv.clear();
    };
    csv += single ? "t,u,v,t_target" : "t,point,u,v,t_target";
    for (const auto& run : report.runs) csv += "," + run.spec.name + ".u_pred," + run.spec.name + ".v_pred";
    csv += '\n';
    for (size_t i = 0; i < track.size(); ++i)
      for (int p = 0; p < n; ++p) {
        const size_t pp = static_cast<size_t>(p);
        appendNumber(csv, track.t_s[i], 10);
        csv += ',';
        if (!single) (csv += track.point_names[pp]) += ',';
        appendNumber(csv, track.u_px[pp][i], 10);
        csv += ',';
        appendNumber(csv, track.v_px[pp][i], 10);
        csv += ',';
        appendNumber(csv, track.t_s[i] + report.horizon_s, 10);
        for (const auto& run : report.runs) {
          csv += ',';
          appendNumber(csv, run.points[pp].u_pred_px[i], 10);
          csv += ',';
          appendNumber(csv, run.points[pp].v_pred_px[i], 10);
        }
        csv += '\n';
        if (csv.size() >= kChunk) flush();
      }
    flush();
    if (!csv_file) throw std::runtime_error(csv_path + ": write failed");
  }

  nlohmann::json summary;
  summary["command"] = command_line;
  summary["input"] = track.path;
  summary["format"] = track.format;
  summary["points"] = track.point_names;
  summary["ignored_columns"] = track.ignored_columns;
  summary["rows"] = track.size();
  summary["horizon_s"] = report.horizon_s;
  summary["delay_frames"] = delay_frames >= 0 ? nlohmann::json(delay_frames) : nlohmann::json(nullptr);
  summary["frame_period_s"] = track.size() >= 2 ? medianPeriod(track.t_s) : kNaN;
  summary["error_reference"] =
      "prediction made at t compared with the measurement (and truth) linearly interpolated at t + horizon_s; "
      "per point, and overall over every (frame, point) pair";
  summary["predictors"] = nlohmann::json::array();
  for (const auto& run : report.runs) {
    nlohmann::json p;
    p["name"] = run.spec.name;
    p["params"] = nlohmann::json::object();
    for (const auto& kv : run.spec.params.values()) p["params"][kv.first] = kv.second;
    p["vs_measurement"] = errorsJson(run.vs_measurement);
    p["vs_truth"] = track.hasTruth() ? errorsJson(run.vs_truth) : nlohmann::json(nullptr);
    p["per_point"] = nlohmann::json::array();
    for (int k = 0; k < n; ++k) {
      const PointPrediction& pt = run.points[static_cast<size_t>(k)];
      nlohmann::json q;
      q["point"] = track.point_names[static_cast<size_t>(k)];
      q["vs_measurement"] = errorsJson(pt.vs_measurement);
      q["vs_truth"] = track.hasTruth() ? errorsJson(pt.vs_truth) : nlohmann::json(nullptr);
      p["per_point"].push_back(q);
    }
    summary["predictors"].push_back(p);
  }
  {
    std::ofstream js(dir.file("summary.json"));
    js << summary.dump(2) << "\n";
    if (!js) throw std::runtime_error(dir.file("summary.json") + ": write failed");
  }

  if (!plots) return;
  // Plot data (the first point): measured points at their time, predictions at the time they are
  // made for; every plotStride()-th row only (all of them up to kMaxPlotRows rows).
  const size_t stride = plotStride(track.size());
  {
    std::string dat = "# t_s u_px v_px t_target_s u_true_px v_true_px";
    for (const auto& run : report.runs) dat += " " + run.spec.name + ".u_pred " + run.spec.name + ".v_pred";
    if (stride > 1) dat += "\n# 1 row in " + std::to_string(stride) + " of " + std::to_string(track.size());
    dat += '\n';
    auto num = [&](double x) { appendNumber(dat, x, 8, "NaN"); };  // datNumber's format
    for (size_t i = 0; i < track.size(); i += stride) {
      num(track.t_s[i]);
      dat += ' ';
      num(track.u_px[0][i]);
      dat += ' ';
      num(track.v_px[0][i]);
      dat += ' ';
      num(track.t_s[i] + report.horizon_s);
      dat += ' ';
      num(track.hasTruth() ? track.u_true_px[0][i] : kNaN);
      dat += ' ';
      num(track.hasTruth() ? track.v_true_px[0][i] : kNaN);
      for (const auto& run : report.runs) {
        dat += ' ';
        num(run.points[0].u_pred_px[i]);
        dat += ' ';
        num(run.points[0].v_pred_px[i]);
      }
      dat += '\n';
    }
    writeWhole(dir.file("predictions_plot.dat"), dat);
  }
  std::ofstream gp(dir.file("predictions.gp"));
  std::ostringstream title;
  title << "Prediction " << std::setprecision(4) << report.horizon_s << " s ahead";
  if (delay_frames >= 0) title << " (" << delay_frames << " frames)";
  if (!single) title << ", point " << track.point_names[0] << " of " << n << " (all in predictions.csv)";
  if (stride > 1) title << ", 1 row in " << stride << " of " << track.size() << " drawn";
  gp << "# Regenerate with: gnuplot predictions.gp\n"
     << "set terminal pngcairo size 1200,850 enhanced font 'Sans,10'\n"
     << "set output 'predictions.png'\n"
     << "set datafile missing 'NaN'\n"
     << "set multiplot layout 2,1 title "
     << gnuplotQuote(title.str() + ": each predictor's forecast is drawn at the time it is made for") << "\n"
     << "set grid\nset autoscale xfix\nset xlabel 'time t [s]'\n"
     << "set key outside right top vertical Left reverse samplen 2\n";
  for (int axis = 0; axis < 2; ++axis) {
    const char* name = axis == 0 ? "u" : "v";
    gp << "set title " << gnuplotQuote(std::string("image coordinate ") + name + " (measured vs predicted)") << "\n"
       << "set ylabel '" << name << " [px]'\n"
       << "plot 'predictions_plot.dat' using 1:" << (2 + axis)
       << " with points pt 7 ps 0.5 lc rgb 'black' title 'measured'";
    for (size_t k = 0; k < report.runs.size(); ++k)
      gp << ", '' using 4:" << (7 + 2 * k + static_cast<size_t>(axis)) << " with lines lw 1.5 lc rgb '"
         << seriesColor(k) << "' title " << gnuplotQuote(report.runs[k].spec.name);
    if (track.hasTruth())
      gp << ", '' using 1:" << (5 + axis) << " with lines dt 2 lw 2 lc rgb 'black' title 'true'";
    gp << "\n";
  }
  gp << "unset multiplot\n";
  gp.close();
  runGnuplot(dir.staging().string(), "predictions.gp");
}

void printPredictionTable(const PredictionReport& report, const FeatureTrack& track, std::ostream& out) {
  const bool has_truth = track.hasTruth();
  size_t w = 9;
  for (const auto& run : report.runs) w = std::max(w, run.spec.name.size());
  out << std::left << std::setw(static_cast<int>(w)) << "predictor" << std::right << std::setw(20)
      << "RMSE vs meas [px]";
  if (has_truth) out << std::setw(20) << "RMSE vs truth [px]";
  // The n column fits the largest count with two spaces before it (7 wide up to 5 digits).
  size_t nw = 7;
  for (const auto& run : report.runs) nw = std::max(nw, std::to_string(run.vs_measurement.n).size() + 2);
  out << std::setw(static_cast<int>(nw)) << "n" << "\n";
  for (const auto& run : report.runs) {
    out << std::left << std::setw(static_cast<int>(w)) << run.spec.name << std::right << std::setw(20)
        << fixedNumber(run.vs_measurement.rmse_px, 3);
    if (has_truth) out << std::setw(20) << fixedNumber(run.vs_truth.rmse_px, 3);
    out << std::setw(static_cast<int>(nw)) << run.vs_measurement.n << "\n";
  }
  if (track.points() < 2) return;
  // Per point: one column per point.
  for (int which = 0; which < (has_truth ? 2 : 1); ++which) {
    out << "\nRMSE vs " << (which == 0 ? "measurement" : "truth") << " per point [px]\n";
    size_t cw = 8;
    for (const auto& name : track.point_names) cw = std::max(cw, name.size() + 2);
    out << std::left << std::setw(static_cast<int>(w)) << "predictor" << std::right;
    for (const auto& name : track.point_names) out << std::setw(static_cast<int>(cw)) << name;
    out << "\n";
    for (const auto& run : report.runs) {
      out << std::left << std::setw(static_cast<int>(w)) << run.spec.name << std::right;
      for (const auto& pt : run.points)
        out << std::setw(static_cast<int>(cw)) << fixedNumber(which == 0 ? pt.vs_measurement.rmse_px : pt.vs_truth.rmse_px, 3);
      out << "\n";
    }
  }
}

}  // namespace predvs
