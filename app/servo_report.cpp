#include "servo_report.h"

#include "gnuplot.h"
#include "plots.h"
#include "report.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string traceFile(const RunRecord& run) { return "trace_" + fileSafe(run.predictor) + ".dat"; }

std::string seedTitle(const Scenario& sc) { return sc.name + " (seed " + std::to_string(sc.seed()) + ")"; }

std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

/// "A:B" for gnuplot's using.
std::string cols(size_t a, size_t b) { return std::to_string(a) + ":" + std::to_string(b); }

/// Window of the running RMS column of the plot data (s): the open-loop error is dominated by
/// frame-to-frame noise; its running RMS shows which predictor is better where.
double runningWindowS(const Scenario& sc) { return std::max(1.0, 0.05 * sc.durationS()); }

std::string logCsv(const ServoReport& r) {
  // Predictor diagnostics (e.g. imm's mu_cv_0): the union of the runs' names as trailing columns,
  // empty for a predictor without that name.
  std::vector<std::string> diag;
  for (const auto& run : r.runs)
    for (const auto& n : run.diagnostic_names)
      if (std::find(diag.begin(), diag.end(), n) == diag.end()) diag.push_back(n);
  std::ostringstream csv;
  csv << "predictor";
  for (const auto& c : r.runs.front().layout.columns) csv << "," << c;
  for (const auto& n : diag) csv << "," << n;
  csv << "\n";
  for (const auto& run : r.runs) {
    std::vector<long> at(diag.size(), -1);  // index of each union column in this run's diagnostics
    for (size_t k = 0; k < diag.size(); ++k)
      for (size_t m = 0; m < run.diagnostic_names.size(); ++m)
        if (run.diagnostic_names[m] == diag[k]) at[k] = static_cast<long>(m);
    for (size_t i = 0; i < run.rows.size(); ++i) {
      csv << run.predictor;
      for (double x : run.rows[i]) csv << "," << csvNumber(x, 10);
      for (size_t k = 0; k < diag.size(); ++k) {
        csv << ",";
        if (at[k] >= 0 && i < run.diagnostic_rows.size())
          csv << csvNumber(run.diagnostic_rows[i][static_cast<size_t>(at[k])], 10);
      }
      csv << "\n";
    }
  }
  return csv.str();
}

std::vector<std::string> metricNames(const ServoReport& r) {
  std::vector<std::string> names;
  for (const auto& kv : r.runs.front().values) names.push_back(kv.first);
  return names;
}

std::string summaryJson(const ServoReport& r) {
  const Scenario& sc = *r.scenario;
  nlohmann::json j;
  j["scenario"] = sc.name;
  j["scenario_file"] = sc.path;
  j["description"] = sc.description;
  j["kind"] = scenarioKindName(sc.kind);
  j["seed"] = sc.seed();
  j["duration_s"] = sc.durationS();
  j["command"] = r.command_line;
  j["overrides"] = overrideTexts(r.overrides);
  j["sweep_not_run"] = sc.sweeps.empty() ? nlohmann::json(nullptr) : nlohmann::json(sweepKeysText(sc.sweeps));
  j["error_definition"] = errorDefinition(sc.kind);
  j["error_units"] = errorUnits(sc);
  j["metric_definitions"] = metricDefinitionsJson(metricNames(r), sc);
  j["predictors"] = nlohmann::json::array();
  for (size_t i = 0; i < r.runs.size(); ++i) {
    const RunRecord& run = r.runs[i];
    nlohmann::json p;
    p["name"] = run.predictor;
    p["type"] = sc.predictors[i].typeName();
    p["params"] = paramsJson(sc.predictors[i].params);
    if (sc.kind == ScenarioKind::ClosedLoop) p["prediction_used"] = run.prediction_used;
    p["steps"] = run.rows.size();
    p["steady_samples"] = run.steady_samples;
    p["metrics"] = nlohmann::json::object();
    for (const auto& kv : run.values) p["metrics"][kv.first] = jsonNumber(kv.second);
    j["predictors"].push_back(p);
  }
  return j.dump(2) + "\n";
}

/// trace_<predictor>.dat: the trace columns plus a trailing running RMS of the error.
void writeTraceData(const ServoReport& r, const StagedOutputDir& dir) {
  const RunLayout& l = r.runs.front().layout;
  const size_t t_col = l.column(l.time_column) - 1, e_col = l.column(l.error_column) - 1;
  const double window_s = runningWindowS(*r.scenario);
  for (const auto& run : r.runs) {
    std::ostringstream dat;
    dat << "#";
    for (const auto& c : l.columns) dat << " " << c;
    dat << " running_rms_error_" << window_s << "s\n";
    size_t first = 0, count = 0;
    double sum_sq = 0.0;
    for (size_t k = 0; k < run.rows.size(); ++k) {
      const auto& row = run.rows[k];
      const double e = row[e_col], t = row[t_col];
      if (std::isfinite(e)) sum_sq += e * e, ++count;
      while (first < k && run.rows[first][t_col] <= t - window_s) {
        const double old = run.rows[first][e_col];
        if (std::isfinite(old)) sum_sq -= old * old, --count;
        ++first;
      }
      for (size_t i = 0; i < row.size(); ++i) dat << (i ? " " : "") << datNumber(row[i]);
      dat << " " << datNumber(count > 0 ? std::sqrt(std::max(0.0, sum_sq) / static_cast<double>(count)) : kNaN) << "\n";
    }
    writeTextFile(dir, traceFile(run), dat.str());
  }
}

/// One line per predictor of trace column `column` versus time.
std::vector<PlotLine> perPredictor(const ServoReport& r, size_t column, const std::string& style,
                                   const std::string& suffix = "", int dash = 1) {
  std::vector<PlotLine> lines;
  const size_t t = r.runs.front().layout.column("t_s");
  for (size_t k = 0; k < r.runs.size(); ++k)
    lines.push_back({traceFile(r.runs[k]), cols(t, column), style + " dt " + std::to_string(dash), seriesColor(k),
                     r.runs[k].predictor + suffix, ""});
  return lines;
}

/// The extent of image points, drawn as a square frame with equal scales (so that a narrow
/// motion stays readable and the geometry is true).
struct PlaneExtent {
  double umin = INFINITY, umax = -INFINITY, vmin = INFINITY, vmax = -INFINITY;
  void add(double u, double v) {
    if (!std::isfinite(u) || !std::isfinite(v)) return;
    umin = std::min(umin, u), umax = std::max(umax, u), vmin = std::min(vmin, v), vmax = std::max(vmax, v);
  }
  /// gnuplot commands: ranges with a 5 % margin, v growing downwards when `rows_down` (image rows).
  std::string frame(bool rows_down) const {
    std::ostringstream gp;
    gp << "set size ratio -1\n";
    if (!std::isfinite(umin)) return gp.str() + (rows_down ? "set yrange [*:*] reverse\n" : "");
    const double half = 0.55 * std::max(umax - umin, vmax - vmin) + 1.0;
    const double cu = 0.5 * (umin + umax), cv = 0.5 * (vmin + vmax);
    gp << "set xrange [" << cu - half << ":" << cu + half << "]\n";
    if (rows_down)
      gp << "set yrange [" << cv + half << ":" << cv - half << "]   # image rows grow downwards\n";
    else
      gp << "set yrange [" << cv - half << ":" << cv + half << "]\n";
    return gp.str();
  }
};

/// error.png: the error norm versus time, one line per predictor; open loop adds its running RMS.
void plotError(const ServoReport& r, const StagedOutputDir& dir) {
  const Scenario& sc = *r.scenario;
  const RunLayout& l = r.runs.front().layout;
  const bool open = sc.kind == ScenarioKind::OpenLoop;
  const std::string unit = errorUnitLabel(sc);
  PlotFigure f;
  f.base = "error";
  f.title = seedTitle(sc) + ": " + (open ? "prediction error at the effect time" : "tracking error");
  f.setup = eventMarks(runEvents(sc));
  PlotPanel tick;
  tick.title = open ? "per control tick" : "";
  tick.ylabel = open ? "||predicted - true|| [" + unit + "]" : "tracking error e [px]";
  tick.log_y = !open;
  tick.lines = perPredictor(r, l.column(l.error_column), open ? "lines lw 1" : "lines lw 1.5");
  f.panels.push_back(tick);
  if (open) {
    std::ostringstream window;
    window << std::setprecision(3) << runningWindowS(sc);
    PlotPanel rms;
    rms.title = "running RMS over the last " + window.str() + " s";
    rms.ylabel = "RMS of the error [" + unit + "]";
    rms.lines = perPredictor(r, l.columns.size() + 1, "lines lw 2");
    f.panels.push_back(rms);
    f.panel_height_px = 430;
  }
  drawFigure(dir, f);
}

/// trajectories.png, open loop: the first two channels as a plane (image points when the units
/// are px: rows grow downwards), then every channel versus time; forecasts are drawn at the
/// effect time they aim at, measurements at their acquisition time.
void plotOpenTrajectories(const ServoReport& r, const StagedOutputDir& dir) {
  const Scenario& sc = *r.scenario;
  const RunLayout& l = r.runs.front().layout;
  const std::string unit = errorUnitLabel(sc);
  const std::string first = traceFile(r.runs.front());
  auto series = [&](const std::string& meas_using, const std::string& pred_using, const std::string& true_using) {
    std::vector<PlotLine> lines;
    for (size_t k = 0; k < r.runs.size(); ++k)
      lines.push_back({traceFile(r.runs[k]), pred_using, "lines lw 1.2", seriesColor(k), r.runs[k].predictor + " forecast", ""});
    lines.push_back({first, meas_using, "points pt 7 ps 0.4", "gray30", "measured (delayed, noisy)", ""});
    lines.push_back({first, true_using, "lines dt 2 lw 2.5", "black", "true", ""});
    return lines;
  };
  const std::string key = "set key outside below horizontal maxcols 3 noopaque\n";
  const std::string events = eventMarks(runEvents(sc));  // on the panels versus time
  PlotFigure f;
  f.base = "trajectories";
  f.title = seedTitle(sc) + ": the target's channels; forecasts drawn at the effect time they aim at";
  const auto& ch = l.features;
  if (ch.size() >= 2) {
    PlotPanel plane;
    plane.title = ch[0] + " and " + ch[1] + (ch.size() > 2 ? " (" + join(ch) + ")" : "");
    plane.xlabel = ch[0] + " [" + unit + "]";
    plane.ylabel = ch[1] + " [" + unit + "]" + (unit == "px" ? " (rows, downwards)" : "");
    PlaneExtent extent;
    for (const auto& run : r.runs)
      for (const auto& row : run.rows)
        for (const char* prefix : {"meas_", "pred_", "true_"})
          extent.add(row[l.column(prefix + ch[0]) - 1], row[l.column(prefix + ch[1]) - 1]);
    plane.setup = key + extent.frame(unit == "px");
    auto pair = [&](const std::string& prefix) { return cols(l.column(prefix + ch[0]), l.column(prefix + ch[1])); };
    plane.lines = series(pair("meas_"), pair("pred_"), pair("true_"));
    f.panels.push_back(plane);
  }
  const size_t t_acq = l.column("t_acq_s"), t_pred = l.column("t_pred_s");
  for (const auto& c : ch) {
    PlotPanel p;
    p.title = c + " versus time";
    p.ylabel = c + " [" + unit + "]";
    p.setup = key + events;
    p.lines = series(cols(t_acq, l.column("meas_" + c)), cols(t_pred, l.column("pred_" + c)),
                     cols(t_pred, l.column("true_" + c)));
    f.panels.push_back(p);
  }
  f.columns = f.panels.size() <= 3 ? f.panels.size() : 2;
  if (f.panels.size() > 1) f.panel_width_px = 620, f.panel_height_px = 600;  // a lone panel: the defaults
  drawFigure(dir, f);
}

/// trajectories.png, closed loop: one image-plane panel per predictor with the features taken in
/// pairs (u, v) (an odd last feature is left out: features.png has every feature), the features
/// the task used and the desired points, all in one frame.
void plotClosedTrajectories(const ServoReport& r, const StagedOutputDir& dir) {
  const Scenario& sc = *r.scenario;
  const RunLayout& l = r.runs.front().layout;
  const size_t pairs = l.features.size() / 2;
  {
    std::ostringstream des;
    des << "# u_px v_px (desired features s*, in pairs)\n";
    for (size_t i = 0; i < pairs; ++i)
      des << datNumber(l.desired(static_cast<Eigen::Index>(2 * i))) << " "
          << datNumber(l.desired(static_cast<Eigen::Index>(2 * i + 1))) << "\n";
    writeTextFile(dir, "desired.dat", des.str());
  }
  std::vector<std::string> us, vs;
  for (size_t i = 0; i < pairs; ++i) us.push_back(l.features[2 * i]), vs.push_back(l.features[2 * i + 1]);
  const size_t tu = l.column("true_" + l.features.front()), pu = l.column("pred_" + l.features.front());
  // One frame for every panel, so the predictors can be compared by eye.
  PlaneExtent extent;
  for (const auto& run : r.runs)
    for (const auto& row : run.rows)
      for (size_t base : {tu - 1, pu - 1})
        for (size_t i = 0; i < pairs; ++i) extent.add(row[base + 2 * i], row[base + 2 * i + 1]);
  for (size_t i = 0; i < pairs; ++i)
    extent.add(l.desired(static_cast<Eigen::Index>(2 * i)), l.desired(static_cast<Eigen::Index>(2 * i + 1)));
  const std::string frame = "set key outside below horizontal noopaque\n" + extent.frame(true);
  PlotFigure f;
  f.base = "trajectories";
  f.title = sc.name + ": image-plane trajectories of the features (seed " + std::to_string(sc.seed()) + ")" +
            (l.features.size() % 2 ? "; " + l.features.back() + " is in features.png" : "");
  for (size_t k = 0; k < r.runs.size(); ++k) {
    const std::string file = traceFile(r.runs[k]);
    PlotPanel p;
    p.title = "predictor " + r.runs[k].predictor;
    p.xlabel = join(us) + " [px]";
    p.ylabel = join(vs) + " [px]";
    p.setup = frame;
    for (size_t i = 0; i < pairs; ++i)
      p.lines.push_back({file, cols(tu + 2 * i, tu + 2 * i + 1), "lines lw 2", seriesColor(k), i ? "" : "true features", ""});
    const std::string used = r.runs[k].prediction_used ? "features used by the task (predicted)"
                                                       : "features used by the task (delayed)";
    for (size_t i = 0; i < pairs; ++i)
      p.lines.push_back({file, cols(pu + 2 * i, pu + 2 * i + 1), "lines lw 0.7", "gray30", i ? "" : used, ""});
    for (size_t i = 0; i < pairs; ++i)
      p.lines.push_back({file, cols(tu + 2 * i, tu + 2 * i + 1), "points pt 6 ps 1.5", "black", i ? "" : "start",
                         "every ::0::0"});
    p.lines.push_back({"desired.dat", "1:2", "points pt 2 ps 2 lw 2", "black", "desired s*", ""});
    f.panels.push_back(p);
  }
  f.columns = r.runs.size() <= 1 ? 1 : 2;
  f.panel_width_px = 650;
  f.panel_height_px = 560;
  drawFigure(dir, f);
}

/// A figure with one panel per name, each the trace column `prefix + name` versus time, one line
/// per predictor; the scenario's occlusions and onset marked.
PlotFigure panelPerColumn(const ServoReport& r, const std::string& base, const std::string& what,
                          const std::vector<std::string>& names, const std::string& prefix, const std::string& unit) {
  const RunLayout& l = r.runs.front().layout;
  PlotFigure f;
  f.base = base;
  f.title = seedTitle(*r.scenario) + ": " + what;
  f.setup = eventMarks(runEvents(*r.scenario));
  for (const auto& name : names) {
    PlotPanel p;
    p.title = name;
    p.ylabel = name + unit;
    p.lines = perPredictor(r, l.column(prefix + name), "lines lw 1.2");
    f.panels.push_back(p);
  }
  return f;
}

/// features.png (closed loop): every task feature versus time, the true feature of each
/// predictor's run, the desired value dashed.
void plotFeatures(const ServoReport& r, const StagedOutputDir& dir) {
  const RunLayout& l = r.runs.front().layout;
  PlotFigure f = panelPerColumn(r, "features", "the task's true features versus time (dashed: desired s*)", l.features,
                                "true_", " [px]");
  for (size_t i = 0; i < l.features.size(); ++i)
    f.panels[i].lines.push_back(
        {"", datNumber(l.desired(static_cast<Eigen::Index>(i))), "lines dt 2 lw 1.5", "black", "desired", ""});
  drawFigure(dir, f);
}

/// command.png (closed loop): every component of the applied command versus time, with its unit
/// when the robot states it (CommandSpace::units).
void plotCommand(const ServoReport& r, const StagedOutputDir& dir) {
  const RunLayout& l = r.runs.front().layout;
  PlotFigure f = panelPerColumn(r, "command", "applied command versus time (after the robot's limits)", l.commands, "", "");
  if (l.command_units.size() == l.commands.size())
    for (size_t i = 0; i < l.commands.size(); ++i) f.panels[i].ylabel = l.commands[i] + " [" + l.command_units[i] + "]";
  drawFigure(dir, f);
}

/// diagnostics.png (closed loop, a task with diagnostics): every diagnostic versus time, related
/// ones in one panel (plots.h groupByPrefix), one colour per predictor, one dash per diagnostic.
void plotDiagnostics(const ServoReport& r, const StagedOutputDir& dir) {
  const RunLayout& l = r.runs.front().layout;
  PlotFigure f;
  f.base = "diagnostics";
  f.title = seedTitle(*r.scenario) + ": diagnostics of task " + r.scenario->closed_loop.task.name + " versus time";
  f.setup = eventMarks(runEvents(*r.scenario));
  for (const auto& group : groupByPrefix(l.diagnostics)) {
    std::vector<std::string> names;
    for (size_t i : group) names.push_back(l.diagnostics[i]);
    PlotPanel p;
    p.title = join(names);
    p.ylabel = join(names);
    for (size_t j = 0; j < names.size(); ++j) {
      const auto lines = perPredictor(r, l.column(names[j]), "lines lw 1.2", names.size() > 1 ? " " + names[j] : "",
                                      dashType(j));
      p.lines.insert(p.lines.end(), lines.begin(), lines.end());
    }
    f.panels.push_back(p);
  }
  drawFigure(dir, f);
}

}  // namespace

std::vector<std::string> writeServoReport(const ServoReport& r, bool plots, const StagedOutputDir& dir) {
  writeTextFile(dir, "log.csv", logCsv(r));
  writeTextFile(dir, "summary.json", summaryJson(r));
  std::vector<std::string> written = {"log.csv", "summary.json"};
  // A run that fails at t = 0 (metrics.outcome) has no trace row: nothing to plot when none has.
  const bool any_rows = std::any_of(r.runs.begin(), r.runs.end(), [](const RunRecord& run) { return !run.rows.empty(); });
  if (!plots || !any_rows) return written;
  writeTraceData(r, dir);
  plotError(r, dir);
  written.push_back("error.png");
  if (r.scenario->kind == ScenarioKind::OpenLoop) {
    plotOpenTrajectories(r, dir);
    written.push_back("trajectories.png");
    return written;
  }
  plotClosedTrajectories(r, dir);
  plotFeatures(r, dir);
  plotCommand(r, dir);
  written.insert(written.end(), {"trajectories.png", "features.png", "command.png"});
  if (!r.runs.front().layout.diagnostics.empty()) {
    plotDiagnostics(r, dir);
    written.push_back("diagnostics.png");
  }
  return written;
}

void printServoReport(const ServoReport& r, std::ostream& out) {
  MetricTable t;
  t.metrics = tableMetrics(metricNames(r), *r.scenario);
  for (const auto& run : r.runs) {
    t.rows.push_back(run.predictor);
    std::vector<Stats> row;
    for (const auto& m : t.metrics)
      for (const auto& kv : run.values)
        if (kv.first == m) row.push_back(stats({kv.second}));
    t.cells.push_back(row);
  }
  printMetricTable(t, out);
}

}  // namespace predvs
