#include "report.h"

#include "predvs/servo/paper_trajectories.h"
#include "predvs/servo/run_metrics.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

namespace predvs {
namespace {

bool startsWith(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

/// Width of a table column: the name plus two, at least 11.
int columnWidth(const std::string& metric) { return std::max<int>(11, static_cast<int>(metric.size()) + 2); }

}  // namespace

std::vector<std::string> tableMetrics(const std::vector<std::string>& names, const Scenario& sc) {
  const bool open = sc.kind == ScenarioKind::OpenLoop;
  bool sweeps_sigma = false;
  for (const auto& axis : sc.sweeps) sweeps_sigma = sweeps_sigma || axis.key == "noise.sigma";
  const bool channel_mse = open && (sweeps_sigma || sc.channels != 2);
  const bool onset =
      open && std::isfinite(makeChannelTrajectory(sc.trajectory, sc.trajectory_params)->onsetTime());
  std::vector<std::string> shown;
  for (const auto& k : names) {
    bool show = true;
    if (startsWith(k, "pos_mse_") || startsWith(k, "vel_mse_")) show = channel_mse;
    if (k == "false_alarms_per_min" || k == "detected" || k == "detect_delay_frames") show = onset;
    if (k == "alarms" || k == "occl_max") show = false;
    // Outcome (metrics.outcome): the fractions converged and failed and the convergence time in
    // the tables; the failure time and kinds in CSV / JSON.
    if (k == "failure_time_s" || startsWith(k, "fail_")) show = false;
    if (show) shown.push_back(k);
  }
  return shown;
}

std::string immAgainstSingleModels(const MetricTable& t) {
  const auto rmse = std::find(t.metrics.begin(), t.metrics.end(), "rmse");
  if (rmse == t.metrics.end()) return "";
  const size_t m = static_cast<size_t>(rmse - t.metrics.begin());
  const auto mean = [&](const char* name) {
    const auto r = std::find(t.rows.begin(), t.rows.end(), name);
    return r == t.rows.end() ? std::numeric_limits<double>::quiet_NaN()
                             : t.cells[static_cast<size_t>(r - t.rows.begin())][m].mean;
  };
  const double imm = mean("imm"), cv = mean("kf-cv"), ca = mean("kf-ca"), hold = mean("hold");
  if (!std::isfinite(imm) || !std::isfinite(cv) || !std::isfinite(ca)) return "";
  const double best = std::min(cv, ca);
  std::ostringstream s;
  s << "imm / best of kf-cv, kf-ca (rmse): " << fixedNumber(imm / best, 3)
    << (imm <= 1.1 * best ? " (within 10 %)" : " (NOT within 10 %)");
  if (std::isfinite(hold))
    s << "; imm / hold: " << fixedNumber(imm / hold, 3) << (imm <= hold ? "" : " (below hold)");
  return s.str();
}

void printMetricTable(const MetricTable& t, std::ostream& out) {
  size_t w = 9;
  for (const auto& r : t.rows) w = std::max(w, r.size());
  const auto rmse = std::find(t.metrics.begin(), t.metrics.end(), "rmse");
  const size_t m_rmse = static_cast<size_t>(rmse - t.metrics.begin());
  const auto hold = std::find(t.rows.begin(), t.rows.end(), "hold");
  const bool vs_hold = rmse != t.metrics.end() && hold != t.rows.end();
  const double hold_rmse = vs_hold ? t.cells[static_cast<size_t>(hold - t.rows.begin())][m_rmse].mean : 0.0;
  constexpr int kVsHoldWidth = 10;
  out << std::left << std::setw(static_cast<int>(w)) << "predictor" << std::right;
  for (const auto& m : t.metrics) out << std::setw(columnWidth(m)) << m;
  if (vs_hold) out << std::setw(kVsHoldWidth) << "vs hold";
  out << "\n";
  for (size_t r = 0; r < t.rows.size(); ++r) {
    out << std::left << std::setw(static_cast<int>(w)) << t.rows[r] << std::right;
    for (size_t m = 0; m < t.metrics.size(); ++m) out << std::setw(columnWidth(t.metrics[m])) << tableNumber(t.cells[r][m].mean);
    if (vs_hold) {
      const double ratio = hold_rmse / t.cells[r][m_rmse].mean;
      std::ostringstream s;
      if (std::isfinite(ratio))
        s << std::fixed << std::setprecision(1) << ratio << "x";
      else
        s << "-";
      out << std::setw(kVsHoldWidth) << s.str();
    }
    out << "\n";
  }
  if (vs_hold) out << "(vs hold: rmse of hold / rmse of the predictor; rmse over the steady window)\n";
  const std::string imm = immAgainstSingleModels(t);
  if (!imm.empty()) out << imm << "\n";
}

std::string markdownMetricTable(const MetricTable& t) {
  std::ostringstream md;
  md << "| # | predictor |";
  for (const auto& m : t.metrics) md << " " << m << " |";
  md << "\n|---|---|";
  for (size_t k = 0; k < t.metrics.size(); ++k) md << "---:|";
  md << "\n";
  for (size_t r = 0; r < t.rows.size(); ++r) {
    md << "| " << (r + 1) << " | " << t.rows[r] << " |";
    for (const Stats& s : t.cells[r]) {
      md << " " << tableNumber(s.mean);
      if (s.n > 1 && std::isfinite(s.std)) md << " ± " << tableNumber(s.std);
      if (s.n < t.runs && s.n > 0) md << " (" << s.n << "/" << t.runs << ")";
      md << " |";
    }
    md << "\n";
  }
  const std::string imm = immAgainstSingleModels(t);
  if (!imm.empty()) md << "\n" << imm << "\n";
  return md.str();
}

nlohmann::json metricDefinitionsJson(const std::vector<std::string>& names, const Scenario& sc) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& name : names) {
    std::string text = runMetricDefinition(name);
    if (text.empty() && sc.kind == ScenarioKind::ClosedLoop)
      text = "run summary of task '" + sc.closed_loop.task.name + "' (defined in its header, tasks/include/predvs/tasks/)";
    j[name] = text;
  }
  return j;
}

std::string eventMarks(const RunEvents& ev) {
  std::ostringstream gp;
  for (const auto& o : ev.occlusions)
    gp << "set object rect from " << o.start_s << ", graph 0 to " << o.end_s
       << ", graph 1 fc rgb 'gray90' fs solid behind\n";
  if (!ev.occlusions.empty())
    gp << "set label 'occlusion (shaded)' at " << ev.occlusions.front().start_s << ", graph 0.97 offset 0.5,0\n";
  if (std::isfinite(ev.onset_s))
    gp << "set arrow from " << ev.onset_s << ", graph 0 to " << ev.onset_s << ", graph 1 nohead dt 2 lc rgb 'black'\n"
       << "set label 'onset' at " << ev.onset_s << ", graph 0.97 offset 0.5,0\n";
  return gp.str();
}

}  // namespace predvs
