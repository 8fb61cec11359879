// `predvs servo`: runs every predictor of a scenario on the same seed, then writes the outputs.
//
// Output directory (default out/<scenario>):
//   log.csv        one row per (predictor, control tick): `predictor` then the servo layer's trace
//                  columns. Closed loop: t_s, t_acq_s, meas_u0..meas_v3 (latest delivered, delayed
//                  measurement), pred_u0..pred_v3 (features the task used), true_u0..true_v3,
//                  error_px (RMS over the 4 points of ||true - desired||), vx, vy, vz, wx, wy, wz
//                  (applied camera twist, m/s and rad/s). Open loop: t_s, t_acq_s, t_pred_s,
//                  horizon_s, meas_x, meas_y, pred_x, pred_y, true_x, true_y, error (px; no
//                  command). Empty cell = not available (NaN).
//   summary.json   scenario, kind, file, description, seed, duration, command line, --set overrides, metric
//                  definitions and, per predictor, its parameters and metrics (servo/metrics.h).
//   error.png      error norm versus time, every predictor in one plot (error.gp + trace_*.dat,
//                  whose last column is a trailing running RMS of the error over max(1 s, 5 % of
//                  the run)); open loop adds a second panel with that running RMS, because the
//                  per-tick prediction error is dominated by measurement noise
//   trajectories.png  image-plane trajectories: closed loop, one panel per predictor with the 4
//                  true feature tracks, the features the task used and the desired points; open
//                  loop, the true path, the measurements and each predictor's forecasts
//                  (trajectories.gp + desired.dat)
// The runs happen before the directory is created, so a failing run leaves nothing behind.
#include "servo_command.h"

#include "gnuplot.h"
#include "output_dir.h"
#include "scenario.h"
#include "scenario_file.h"

#include "predvs/predictors/predictor.h"
#include "predvs/servo/trajectory.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <set>
#include <sstream>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A run of one predictor, in the common shape of both kinds of scenario.
struct Run {
  std::string predictor;
  Params params;
  bool prediction_used = true;
  std::vector<std::vector<double>> rows;  ///< trace rows, columns = Report::columns
  Metrics metrics;
};

struct Report {
  const Scenario* scenario = nullptr;
  std::vector<std::string> columns;
  std::vector<std::string> feature_names;  ///< closed loop: the task's feature names
  std::vector<Run> runs;
  Eigen::VectorXd desired_px;  ///< closed loop only: s* (pairs plotted as image points)
};

size_t columnIndex(const Report& r, const std::string& name) {
  for (size_t i = 0; i < r.columns.size(); ++i)
    if (r.columns[i] == name) return i;
  throw std::logic_error("trace column '" + name + "' missing");
}

std::string csvCell(double x) {
  if (!std::isfinite(x)) return "";
  std::ostringstream s;
  s << std::setprecision(10) << x;
  return s.str();
}

std::string datCell(double x) {
  if (!std::isfinite(x)) return "NaN";
  std::ostringstream s;
  s << std::setprecision(8) << x;
  return s.str();
}

std::string fixedCell(double x, int precision) {
  if (!std::isfinite(x)) return "-";
  std::ostringstream s;
  if (std::fabs(x) >= 1e5)
    s << std::setprecision(3) << std::scientific << x;
  else
    s << std::fixed << std::setprecision(precision) << x;
  return s.str();
}

/// A file-name-safe version of a predictor name.
std::string safeName(const std::string& s) {
  std::string out;
  for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
  return out;
}

nlohmann::json metricsJson(const Metrics& m) {
  return {{"rmse_px", m.rmse},
          {"final_error_px", m.final_error},
          {"max_error_px", m.max_error},
          {"peak_error_px", m.peak_error},
          {"iae_px_s", m.iae},
          {"settling_time_s", m.settling_time_s},
          {"control_effort", m.control_effort},
          {"steady_samples", m.steady_samples}};
}

Report runScenario(const Scenario& sc, std::ostream& err) {
  Report report;
  report.scenario = &sc;
  const size_t n = sc.predictors.size();
  for (size_t i = 0; i < n; ++i) {
    const ScenarioPredictor& sp = sc.predictors[i];
    err << "predvs: [" << (i + 1) << "/" << n << "] " << sc.name << ": " << sp.name << " ..." << std::flush;
    const auto start = std::chrono::steady_clock::now();
    Run run;
    run.predictor = sp.name;
    run.params = sp.params;
    if (sc.kind == ScenarioKind::OpenLoop) {
      report.columns = predictionTraceColumns();
      auto trajectory = makeTrajectory(sc.trajectory, sc.trajectory_params);
      auto predictor = makePredictor(sp.name, 2, sp.params);
      const PredictionResult result = runPredictionExperiment(sc.open_loop, *trajectory, *predictor);
      for (const auto& s : result.trace) run.rows.push_back(predictionTraceRow(s));
      run.metrics = result.metrics;
    } else {
      auto predictor = makePredictor(sp.name, sc.channels, sp.params);
      const ServoResult result = runServoLoop(sc.closed_loop, *predictor);
      report.columns = result.columns;
      report.feature_names.clear();
      for (const auto& c : result.columns)
        if (c.rfind("true_", 0) == 0) report.feature_names.push_back(c.substr(5));
      for (const auto& s : result.trace) run.rows.push_back(ServoLoop::traceRow(s));
      run.metrics = result.metrics;
      run.prediction_used = result.prediction_used;
      report.desired_px = result.desired;
    }
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    err << " " << run.rows.size() << " steps in " << std::fixed << std::setprecision(2) << secs << " s\n"
        << std::defaultfloat;
    report.runs.push_back(std::move(run));
  }
  return report;
}

void writeLog(const Report& r, const StagedOutputDir& dir) {
  std::ofstream csv(dir.file("log.csv"));
  csv << "predictor";
  for (const auto& c : r.columns) csv << "," << c;
  csv << "\n";
  for (const auto& run : r.runs)
    for (const auto& row : run.rows) {
      csv << run.predictor;
      for (double x : row) csv << "," << csvCell(x);
      csv << "\n";
    }
  if (!csv) throw std::runtime_error(dir.file("log.csv") + ": write failed");
}

void writeSummary(const Report& r, const ScenarioRunOptions& o, const StagedOutputDir& dir) {
  const Scenario& sc = *r.scenario;
  nlohmann::json j;
  j["scenario"] = sc.name;
  j["scenario_file"] = sc.path;
  j["description"] = sc.description;
  j["kind"] = scenarioKindName(sc.kind);
  j["seed"] = sc.seed();
  j["duration_s"] = sc.durationS();
  j["command"] = o.command_line;
  j["overrides"] = overrideTexts(o.overrides);
  j["error_definition"] =
      sc.kind == ScenarioKind::OpenLoop
          ? "open loop: ||predicted - true|| of the target position at the time the command would take effect (px)"
          : "closed loop: RMS over the 4 points of ||true - desired|| image feature distance (px)";
  j["metric_definitions"] = {
      {"rmse_px", "sqrt(mean e^2) over the steady window (from metrics.steady_start_fraction of the run)"},
      {"final_error_px", "mean e over the last metrics.final_fraction of the run"},
      {"max_error_px", "max e over the steady window"},
      {"peak_error_px", "max e over the whole run"},
      {"iae_px_s", "integral of e dt over the whole run"},
      {"settling_time_s", "first time after which e stays within final + settling_band * (peak - final); null if never"},
      {"control_effort", "sum of ||v||^2 dt of the applied camera twist (closed loop only)"}};
  j["predictors"] = nlohmann::json::array();
  for (const auto& run : r.runs) {
    nlohmann::json p;
    p["name"] = run.predictor;
    p["params"] = nlohmann::json::object();
    for (const auto& kv : run.params.values()) p["params"][kv.first] = kv.second;
    if (sc.kind == ScenarioKind::ClosedLoop) p["prediction_used"] = run.prediction_used;
    p["steps"] = run.rows.size();
    p["metrics"] = metricsJson(run.metrics);
    j["predictors"].push_back(p);
  }
  std::ofstream js(dir.file("summary.json"));
  js << j.dump(2) << "\n";
  if (!js) throw std::runtime_error(dir.file("summary.json") + ": write failed");
}

std::string traceFile(const Run& run) { return "trace_" + safeName(run.predictor) + ".dat"; }

void writePlots(const Report& r, const StagedOutputDir& dir) {
  const Scenario& sc = *r.scenario;
  const bool open = sc.kind == ScenarioKind::OpenLoop;
  const size_t t_col = columnIndex(r, "t_s") + 1;
  const size_t e_col = columnIndex(r, open ? "error" : "error_px") + 1;
  // Plot data: the trace columns plus a trailing running RMS of the error over the last
  // `window_s` seconds (the open-loop error is dominated by frame-to-frame noise; its running RMS
  // shows which predictor is better where).
  const double window_s = std::max(1.0, 0.05 * sc.durationS());
  for (const auto& run : r.runs) {
    std::ofstream dat(dir.file(traceFile(run)));
    dat << "#";
    for (const auto& c : r.columns) dat << " " << c;
    dat << " running_rms_error_" << window_s << "s\n";
    size_t first = 0;
    double sum_sq = 0.0;
    size_t count = 0;
    for (size_t k = 0; k < run.rows.size(); ++k) {
      const auto& row = run.rows[k];
      const double e = row[e_col - 1], t = row[t_col - 1];
      if (std::isfinite(e)) sum_sq += e * e, ++count;
      while (first < k && run.rows[first][t_col - 1] <= t - window_s) {
        const double old = run.rows[first][e_col - 1];
        if (std::isfinite(old)) sum_sq -= old * old, --count;
        ++first;
      }
      for (size_t i = 0; i < row.size(); ++i) dat << (i ? " " : "") << datCell(row[i]);
      dat << " " << datCell(count > 0 ? std::sqrt(std::max(0.0, sum_sq) / static_cast<double>(count)) : kNaN) << "\n";
    }
  }
  const size_t rms_col = r.columns.size() + 1;

  // Error norm versus time.
  {
    std::ofstream gp(dir.file("error.gp"));
    const std::string what = open ? "prediction error at the effect time" : "image tracking error";
    const std::string ylabel = open ? "||predicted - true|| [px]" : "RMS over 4 points of ||s - s*|| [px]";
    std::ostringstream window;
    window << std::setprecision(3) << window_s;
    auto plotAll = [&](size_t col, const char* style) {
      gp << "plot ";
      for (size_t k = 0; k < r.runs.size(); ++k)
        gp << (k ? ", \\\n     " : "") << "'" << traceFile(r.runs[k]) << "' using " << t_col << ":" << col << " with lines "
           << style << " lc rgb '" << seriesColor(k) << "' title " << gnuplotQuote(r.runs[k].predictor);
      gp << "\n";
    };
    gp << "# Regenerate with: gnuplot error.gp\n"
       << "set datafile missing 'NaN'\n"
       << "set xlabel 'time t [s]'\nset grid\nset autoscale xfix\nset key top right box opaque\n";
    if (open) {
      gp << "set terminal pngcairo size 1100,900 enhanced font 'Sans,11'\nset output 'error.png'\n"
         << "set multiplot layout 2,1 title "
         << gnuplotQuote(sc.name + " (seed " + std::to_string(sc.seed()) + "): " + what) << "\n"
         << "set title 'per control tick'\nset ylabel " << gnuplotQuote(ylabel) << "\n";
      plotAll(e_col, "lw 1");
      gp << "set title " << gnuplotQuote("running RMS over the last " + window.str() + " s") << "\n"
         << "set ylabel " << gnuplotQuote("RMS of the error [px]") << "\n";
      plotAll(rms_col, "lw 2");
      gp << "unset multiplot\n";
    } else {
      gp << "set terminal pngcairo size 1100,650 enhanced font 'Sans,11'\nset output 'error.png'\n"
         << "set title " << gnuplotQuote(sc.name + " (seed " + std::to_string(sc.seed()) + "): " + what) << "\n"
         << "set ylabel " << gnuplotQuote(ylabel) << "\nset logscale y\nset format y '%g'\n";
      plotAll(e_col, "lw 1.5");
    }
  }
  runGnuplot(dir.staging().string(), "error.gp");

  // Image-plane trajectories.
  std::ofstream gp(dir.file("trajectories.gp"));
  gp << "# Regenerate with: gnuplot trajectories.gp\n"
     << "set datafile missing 'NaN'\nset grid\nset size ratio -1\n";
  if (open) {
    const size_t mx = columnIndex(r, "meas_x") + 1, px = columnIndex(r, "pred_x") + 1,
                 tx = columnIndex(r, "true_x") + 1;
    const size_t pt = columnIndex(r, "t_pred_s") + 1;
    gp << "set terminal pngcairo size 1800,700 enhanced font 'Sans,11'\n"
       << "set output 'trajectories.png'\n"
       << "set multiplot layout 1,3 title "
       << gnuplotQuote(sc.name + " (seed " + std::to_string(sc.seed()) +
                       "): target in the image; forecasts drawn at the effect time they aim at")
       << "\nset key outside below horizontal maxcols 3\n";
    // Every panel draws the same series: forecasts, measurements (at their acquisition time), truth.
    auto panel = [&](const std::string& title, const std::string& xlabel, const std::string& ylabel,
                     const std::string& pred_using, const std::string& meas_using, const std::string& true_using) {
      gp << "set title " << gnuplotQuote(title) << "\nset xlabel " << gnuplotQuote(xlabel) << "\nset ylabel "
         << gnuplotQuote(ylabel) << "\nplot ";
      for (size_t k = 0; k < r.runs.size(); ++k)
        gp << (k ? ", \\\n     '" : "'") << traceFile(r.runs[k]) << "' using " << pred_using
           << " with lines lw 1.2 lc rgb '" << seriesColor(k) << "' title " << gnuplotQuote(r.runs[k].predictor + " forecast");
      gp << ", \\\n     '" << traceFile(r.runs.front()) << "' using " << meas_using
         << " with points pt 7 ps 0.4 lc rgb 'gray30' title 'measured (delayed, noisy)'"
         << ", \\\n     '" << traceFile(r.runs.front()) << "' using " << true_using
         << " with lines dt 2 lw 2.5 lc rgb 'black' title 'true'\n";
    };
    auto cols = [](size_t a, size_t b) { return std::to_string(a) + ":" + std::to_string(b); };
    const size_t ta = columnIndex(r, "t_acq_s") + 1;
    gp << "set grid\nset size ratio -1\nset yrange [*:*] reverse\n";
    panel("image plane", "u [px]", "v [px] (rows, downwards)", cols(px, px + 1), cols(mx, mx + 1), cols(tx, tx + 1));
    gp << "set size noratio\nset yrange [*:*] noreverse\nset autoscale xfix\n";
    panel("u versus time", "time [s]", "u [px]", cols(pt, px), cols(ta, mx), cols(pt, tx));
    panel("v versus time", "time [s]", "v [px]", cols(pt, px + 1), cols(ta, mx + 1), cols(pt, tx + 1));
    gp << "unset multiplot\n";
  } else {
    const int pairs = static_cast<int>(r.desired_px.size() / 2);
    {
      std::ofstream des(dir.file("desired.dat"));
      des << "# u_px v_px (desired features s*)\n";
      for (int i = 0; i < pairs; ++i) des << datCell(r.desired_px(2 * i)) << " " << datCell(r.desired_px(2 * i + 1)) << "\n";
    }
    const size_t tu = columnIndex(r, "true_" + r.feature_names.front()) + 1,
                 pu = columnIndex(r, "pred_" + r.feature_names.front()) + 1;
    const size_t n = r.runs.size();
    const size_t cols = n <= 1 ? 1 : 2, rows = (n + cols - 1) / cols;
    gp << "set terminal pngcairo size " << (cols * 650) << "," << (rows * 560 + 60) << " enhanced font 'Sans,10'\n"
       << "set output 'trajectories.png'\n"
       << "set multiplot layout " << rows << "," << cols << " title "
       << gnuplotQuote(sc.name + ": image-plane trajectories of the features (seed " + std::to_string(sc.seed()) + ")")
       << "\n"
       << "set xlabel 'u [px]'\nset ylabel 'v [px]'\n"
       << "set key outside below horizontal\n";
    // One frame for every panel, so the predictors can be compared by eye.
    double umin = INFINITY, umax = -INFINITY, vmin = INFINITY, vmax = -INFINITY;
    for (const auto& run : r.runs)
      for (const auto& row : run.rows)
        for (size_t base : {tu - 1, pu - 1})
          for (size_t i = 0; i < static_cast<size_t>(pairs); ++i) {
            const double u = row[base + 2 * i], v = row[base + 2 * i + 1];
            if (!std::isfinite(u) || !std::isfinite(v)) continue;
            umin = std::min(umin, u), umax = std::max(umax, u), vmin = std::min(vmin, v), vmax = std::max(vmax, v);
          }
    for (int i = 0; i < pairs; ++i) {
      umin = std::min(umin, r.desired_px(2 * i)), umax = std::max(umax, r.desired_px(2 * i));
      vmin = std::min(vmin, r.desired_px(2 * i + 1)), vmax = std::max(vmax, r.desired_px(2 * i + 1));
    }
    if (std::isfinite(umin) && std::isfinite(vmin)) {
      const double mu = 0.05 * (umax - umin) + 1.0, mv = 0.05 * (vmax - vmin) + 1.0;
      gp << "set xrange [" << umin - mu << ":" << umax + mu << "]\n"
         << "set yrange [" << vmax + mv << ":" << vmin - mv << "]   # image rows grow downwards\n";
    } else {
      gp << "set yrange [*:*] reverse\n";
    }
    for (size_t k = 0; k < n; ++k) {
      const std::string f = "'" + traceFile(r.runs[k]) + "'";
      gp << "set title " << gnuplotQuote("predictor " + r.runs[k].predictor) << "\n"
         << "plot ";
      for (int i = 0; i < pairs; ++i)
        gp << (i ? ", " : "") << f << " using " << (tu + 2 * static_cast<size_t>(i)) << ":"
           << (tu + 2 * static_cast<size_t>(i) + 1) << " with lines lw 2 lc rgb '" << seriesColor(k) << "' title "
           << (i == 0 ? gnuplotQuote("true features") : std::string("''"));
      for (int i = 0; i < pairs; ++i)
        gp << ", " << f << " using " << (pu + 2 * static_cast<size_t>(i)) << ":" << (pu + 2 * static_cast<size_t>(i) + 1)
           << " with lines lw 0.7 lc rgb 'gray30' title "
           << (i == 0 ? gnuplotQuote(r.runs[k].prediction_used ? "features used by the task (predicted)"
                                                               : "features used by the task (delayed)")
                      : std::string("''"));
      gp << ", " << f << " every ::0::0 using " << tu << ":" << (tu + 1)
         << " with points pt 6 ps 1.5 lc rgb 'black' title 'start'";
      for (int i = 1; i < pairs; ++i)
        gp << ", " << f << " every ::0::0 using " << (tu + 2 * static_cast<size_t>(i)) << ":"
           << (tu + 2 * static_cast<size_t>(i) + 1) << " with points pt 6 ps 1.5 lc rgb 'black' notitle";
      gp << ", 'desired.dat' using 1:2 with points pt 2 ps 2 lw 2 lc rgb 'black' title 'desired s*'\n";
    }
    gp << "unset multiplot\n";
  }
  gp.close();
  runGnuplot(dir.staging().string(), "trajectories.gp");
}

void printTable(const Report& r, std::ostream& out) {
  const bool closed = r.scenario->kind == ScenarioKind::ClosedLoop;
  size_t w = 9;
  for (const auto& run : r.runs) w = std::max(w, run.predictor.size());
  const int c = 12;
  out << std::left << std::setw(static_cast<int>(w)) << "predictor" << std::right << std::setw(c) << "RMSE[px]"
      << std::setw(c) << "final[px]" << std::setw(c) << "max[px]" << std::setw(c) << "IAE[px s]" << std::setw(c)
      << "settle[s]";
  if (closed) out << std::setw(c) << "effort";
  // With `hold` in the run: how many times lower each predictor's steady RMSE is than no prediction.
  double hold_rmse = kNaN;
  for (const auto& run : r.runs)
    if (run.predictor == "hold") hold_rmse = run.metrics.rmse;
  const bool vs_hold = std::isfinite(hold_rmse);
  if (vs_hold) out << std::setw(c) << "vs hold";
  out << "\n";
  for (const auto& run : r.runs) {
    const Metrics& m = run.metrics;
    out << std::left << std::setw(static_cast<int>(w)) << run.predictor << std::right << std::setw(c)
        << fixedCell(m.rmse, 3) << std::setw(c) << fixedCell(m.final_error, 3) << std::setw(c)
        << fixedCell(m.max_error, 3) << std::setw(c) << fixedCell(m.iae, 2) << std::setw(c)
        << fixedCell(m.settling_time_s, 2);
    if (closed) out << std::setw(c) << fixedCell(m.control_effort, 4);
    if (vs_hold) out << std::setw(c - 1) << fixedCell(hold_rmse / m.rmse, 1) << "x";
    out << "\n";
  }
  if (vs_hold) out << "(vs hold: steady RMSE of hold / steady RMSE of the predictor; steady = second half of the run)\n";
}

}  // namespace

void runScenarioCommand(const ScenarioRunOptions& o, std::ostream& out, std::ostream& err) {
  const std::string path = resolveScenario(o.scenario);
  Scenario sc = loadScenario(path, o.overrides);
  if (sc.kind == ScenarioKind::OpenLoop && sc.channels != 2)
    throw std::invalid_argument(path + ": trajectory '" + sc.trajectory + "' has " + std::to_string(sc.channels) +
                                " channels; `predvs servo` runs 2-channel (x, y) open-loop scenarios only, run this one "
                                "with `predvs compare --scenarios " + sc.name + "`");
  if (o.seed_given) sc.setSeed(o.seed);
  if (!o.predictors.empty()) {
    std::set<std::string> seen;
    const std::vector<ScenarioPredictor> scenario_predictors = sc.predictors;
    sc.predictors.clear();
    for (const auto& name : o.predictors) {
      if (!seen.insert(name).second) throw std::invalid_argument("--predictors: '" + name + "' listed twice");
      ScenarioPredictor p{name, {}, 0};  // the scenario's own entry (its params) when it lists the name
      for (const auto& own : scenario_predictors)
        if (own.name == name) p = own;
      makePredictor(name, sc.channels, p.params);  // throws naming an unknown predictor
      sc.predictors.push_back(p);
    }
  }
  if (o.plots) requireGnuplot();
  const std::string out_dir = o.out_dir.empty() ? "out/" + sc.name : o.out_dir;

  const Report report = runScenario(sc, err);

  StagedOutputDir dir(out_dir);
  writeLog(report, dir);
  writeSummary(report, o, dir);
  if (o.plots) writePlots(report, dir);
  dir.commit();

  out << sc.name << " (" << scenarioKindName(sc.kind) << ", seed " << sc.seed() << ", " << sc.durationS()
      << " s): " << (sc.kind == ScenarioKind::OpenLoop ? "prediction error" : "tracking error") << " per predictor\n";
  printTable(report, out);
  const std::string where = dir.target().string();
  out << "wrote " << where << "/log.csv, " << where << "/summary.json";
  if (o.plots) out << ", " << where << "/error.png, " << where << "/trajectories.png";
  out << "\n";
}

}  // namespace predvs
