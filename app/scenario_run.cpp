#include "scenario_run.h"

#include "predvs/predictors/predictor.h"
#include "predvs/servo/channel_experiment.h"
#include "predvs/servo/paper_trajectories.h"
#include "predvs/servo/run_metrics.h"
#include "predvs/servo/servo_loop.h"
#include "predvs/servo/timing_model.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <set>
#include <stdexcept>

namespace predvs {
namespace {

/// A scenario predictor's params told about its run, unless the scenario gives the keys: the longest
/// horizon the run asks for (horizon_frames, predictor.h horizonFramesParam; as predict and track
/// tell theirs, predict_command.h setHorizonFrames), and whether a control loop uses it
/// (closed_loop, predictor.h closedLoopParam).
Params toldTheRun(const Params& params, const TimingConfig& timing, bool closed_loop) {
  Params told = params;
  told.setUnlessGiven("horizon_frames", TimingModel(timing).longestHorizonFrames());
  if (closed_loop) told.setUnlessGiven("closed_loop", 1.0);
  return told;
}

RunRecord runClosedLoop(const Scenario& sc, const ScenarioPredictor& p, std::uint64_t seed, bool keep_trace) {
  ServoConfig cfg = sc.closed_loop;
  cfg.seed = seed;
  cfg.predictor_diagnostics = keep_trace;  // only a kept trace writes them
  auto predictor = makePredictor(p.typeName(), sc.channels, toldTheRun(p.params, cfg.timing, true));
  const ServoResult r = runServoLoop(cfg, *predictor);
  RunRecord rec;
  rec.predictor = p.name;
  rec.values = r.values;
  rec.steady_samples = r.metrics.steady_samples;
  rec.prediction_used = r.prediction_used;
  for (const auto& s : r.trace) rec.t_s.push_back(s.t_s), rec.error.push_back(s.error);
  RunLayout& l = rec.layout;
  l.columns = r.columns;
  l.command_units = r.command_units;
  l.error_column = "error_px";
  l.desired = r.desired;
  // traceColumns(): t_s, t_acq_s, 3 x features, error_px, commands, diagnostics.
  const size_t n_features = static_cast<size_t>(r.desired.size());
  const size_t n_commands = r.trace.empty() ? 0 : static_cast<size_t>(r.trace.front().command.size());
  const size_t first_command = 2 + 3 * n_features + 1;
  for (size_t i = 0; i < n_features; ++i) l.features.push_back(r.columns[2 + 2 * n_features + i].substr(5));
  for (size_t i = first_command; i < r.columns.size(); ++i)
    (i < first_command + n_commands ? l.commands : l.diagnostics).push_back(r.columns[i]);
  if (keep_trace) {
    for (const auto& s : r.trace) rec.rows.push_back(ServoLoop::traceRow(s));
    if (!r.predictor_diagnostic_names.empty()) {
      rec.diagnostic_names = r.predictor_diagnostic_names;
      for (const auto& s : r.trace)
        rec.diagnostic_rows.emplace_back(s.predictor_diagnostics.data(),
                                         s.predictor_diagnostics.data() + s.predictor_diagnostics.size());
    }
  }
  return rec;
}

RunRecord runOpenLoop(const Scenario& sc, const ScenarioPredictor& p, std::uint64_t seed, bool keep_trace) {
  PredictionExperimentConfig cfg = sc.open_loop;
  cfg.seed = seed;
  const auto traj = makeChannelTrajectory(sc.trajectory, sc.trajectory_params);
  auto predictor = makePredictor(p.typeName(), traj->channels(), toldTheRun(p.params, cfg.timing, false));
  const ChannelExperimentResult r = runChannelExperiment(cfg, *traj, *predictor);
  RunRecord rec;
  rec.predictor = p.name;
  rec.values = openLoopRunValues(r, cfg, *traj);
  rec.steady_samples = r.metrics.steady_samples;
  for (const auto& s : r.trace) rec.t_s.push_back(s.t_s), rec.error.push_back(s.error);
  RunLayout& l = rec.layout;
  l.features = r.channel_names;
  l.error_column = "error";
  l.columns = {"t_s", "t_acq_s", "t_pred_s", "horizon_s"};
  for (const char* prefix : {"meas_", "pred_", "true_"})
    for (const auto& c : l.features) l.columns.push_back(prefix + c);
  l.columns.push_back(l.error_column);
  if (keep_trace)
    for (const auto& s : r.trace) {
      std::vector<double> row = {s.t_s, s.t_acq_s, s.t_pred_s, s.t_pred_s - s.t_acq_s};
      for (const Eigen::VectorXd* v : {&s.measured, &s.predicted, &s.truth})
        for (Eigen::Index c = 0; c < v->size(); ++c) row.push_back((*v)(c));
      row.push_back(s.error);
      rec.rows.push_back(std::move(row));
      if (!r.diagnostic_names.empty())
        rec.diagnostic_rows.emplace_back(s.diagnostics.data(), s.diagnostics.data() + s.diagnostics.size());
    }
  if (keep_trace) rec.diagnostic_names = r.diagnostic_names;
  return rec;
}

}  // namespace

size_t RunLayout::column(const std::string& name) const {
  for (size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return i + 1;
  throw std::logic_error("trace column '" + name + "' missing");
}

RunRecord runScenarioOnce(const Scenario& sc, const ScenarioPredictor& p, std::uint64_t seed, bool keep_trace) {
  return sc.kind == ScenarioKind::ClosedLoop ? runClosedLoop(sc, p, seed, keep_trace)
                                             : runOpenLoop(sc, p, seed, keep_trace);
}

void choosePredictors(Scenario& sc, const std::vector<std::string>& chosen, const std::string& option) {
  if (chosen.empty()) return;
  std::set<std::string> seen;
  std::vector<ScenarioPredictor> ps;
  for (const auto& text : chosen) {
    const PredictorChoice c = parsePredictorChoice(text, option);
    if (!seen.insert(c.label).second)
      throw std::invalid_argument(option + ": '" + c.label + "' listed twice (give each its own LABEL=TYPE:...)");
    ScenarioPredictor p;
    p.name = c.label;
    p.type = c.type;
    const ScenarioPredictor* base = nullptr;
    if (c.bare)  // a label of the scenario's list: that entry as it is
      for (const auto& own : sc.predictors)
        if (own.name == c.label) base = &own;
    if (!base && !isPredictor(c.type)) {
      std::string labels;
      for (const auto& own : sc.predictors) labels += (labels.empty() ? "" : ", ") + own.name;
      throw std::invalid_argument(option + ": unknown predictor '" + c.type +
                                  "' (neither a predictor of `predvs list` nor a label of " + sc.path + ": " + labels + ")");
    }
    if (!base)
      for (const auto& own : sc.predictors)
        if (own.name == c.label && own.typeName() == c.type) base = &own;
    if (!base)
      for (const auto& own : sc.predictors)
        if (own.name == c.type && own.typeName() == c.type) base = &own;
    if (base) {
      p.type = base->typeName();
      p.params = base->params;
      p.line = base->line;
    }
    p.params.setAll(c.params);
    try {
      makePredictor(p.type, sc.channels, p.params);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(sc.path + ": " + option + " '" + text + "': " + e.what());
    }
    ps.push_back(p);
  }
  sc.predictors = ps;
}

std::string errorUnits(const Scenario& sc) {
  if (sc.kind == ScenarioKind::ClosedLoop) return "px (the task's tracking error: RMS over the points of ||s_i - s*_i||)";
  if (sc.trajectory == "onset-sinusoid") return "scenario units (mm in the E12 scenarios)";
  return "px";
}

std::string errorUnitLabel(const Scenario& sc) {
  return sc.kind == ScenarioKind::OpenLoop && sc.trajectory == "onset-sinusoid" ? "mm" : "px";
}

std::string errorDefinition(ScenarioKind kind) {
  return kind == ScenarioKind::OpenLoop
             ? "open loop: ||predicted - true|| over the channels at the time the command would take effect, in the "
               "scenario's units"
             : "closed loop: the task's tracking error of the true features (point tasks: RMS over the points of "
               "||s_i - s*_i||), px";
}

RunEvents runEvents(const Scenario& sc) {
  RunEvents ev;
  if (sc.kind == ScenarioKind::ClosedLoop) {
    ev.occlusions = sc.closed_loop.occlusions;
    return ev;
  }
  ev.occlusions = sc.open_loop.occlusions;
  const double onset = makeChannelTrajectory(sc.trajectory, sc.trajectory_params)->onsetTime();
  if (onset > 0.0) ev.onset_s = onset;
  return ev;
}

}  // namespace predvs
