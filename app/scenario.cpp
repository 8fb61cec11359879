#include "scenario.h"

#include "app_error.h"
#include "scenario_file.h"
#include "scenario_override.h"

#include "predvs/predictors/predictor.h"
#include "predvs/servo/paper_trajectories.h"
#include "predvs/servo/trajectory.h"

#include <cstdlib>
#include <map>
#include <cctype>
#include <set>

namespace predvs {
namespace {

/// (key, line) of YAML entries, in priority order, to point an error from a lower layer at the
/// key it quotes (parameter keys first, then the name of the thing they belong to).
using KeyLines = std::vector<std::pair<std::string, int>>;

/// Runs f(); a std::invalid_argument from a lower layer is rethrown as "FILE:LINE: message",
/// LINE being the line of the first key of `keys` quoted in the message, else `line`.
template <class F>
auto withLocation(const std::string& file, int line, const KeyLines& keys, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    int where = line;
    for (const auto& kv : keys)
      if (msg.find("'" + kv.first + "'") != std::string::npos ||
          (kv.first.find('.') != std::string::npos && msg.find(kv.first) != std::string::npos)) {
        where = kv.second;
        break;
      }
    throwAt(file, where, msg);
  }
}

/// The optional mapping `key` of `parent`, read by `read(section)` and then checked for unknown
/// keys; absent or null, nothing is read and the defaults stay.
template <class F>
void readSection(YamlSection& parent, const std::string& key, F&& read) {
  parent.allow(key);
  if (!parent.has(key)) return;
  YamlSection s(parent.node(key), parent.file(), parent.qualified(key));
  read(s);
  s.finish();
}

/// Numeric parameters from a YAML mapping (every value must be a finite number).
/// With `words`, a scalar that is not a number is kept as a word (Params::text).
Params readParams(const YAML::Node& node, const std::string& file, const std::string& section, KeyLines* lines,
                  const std::set<std::string>& skip = {}, bool words = false) {
  Params params;
  if (!node.IsDefined() || node.IsNull()) return params;
  if (!node.IsMap()) throwAt(file, yamlLine(node), "'" + section + "': expected a mapping of parameter: number");
  refuseKeysGivenTwice(node, file, section);
  for (const auto& kv : node) {
    const std::string key = kv.first.Scalar();
    if (skip.count(key)) continue;
    if (words && kv.second.IsScalar()) {
      char* end = nullptr;
      const std::string& text = kv.second.Scalar();
      std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0' || end == text.c_str()) {
        params.setText(key, text);
        if (lines) lines->emplace_back(key, yamlLine(kv.first));
        if (lines) lines->emplace_back(section + "." + key, yamlLine(kv.first));  // "task.interaction ..."
        continue;
      }
    }
    params.set(key, yamlNumber(kv.second, file, "'" + section + "." + key + "'"));
    if (lines) lines->emplace_back(key, yamlLine(kv.first));
    if (lines) lines->emplace_back(section + "." + key, yamlLine(kv.first));  // "task.lambda must be > 0"
  }
  return params;
}

void readTiming(YamlSection& root, TimingConfig& t) {
  if (!root.has("timing")) {
    root.allow("timing");
    return;
  }
  YamlSection s(root.node("timing"), root.file(), "timing");
  t.base_period_s = s.number("base_period_s", t.base_period_s, 1e-6, 10.0);
  t.frame_period_n = static_cast<int>(s.integer("frame_period_n", t.frame_period_n, 1, 10000));
  if (s.has("delay_frames")) {
    for (const char* k : {"acquisition_lag_s", "processing_lag_s"})
      if (s.has(k)) s.fail(k, "give either timing.delay_frames or the lags acquisition_lag_s/processing_lag_s, not both");
    const double h = s.number("delay_frames", 0.0, 0.0, 2.0);
    const double frame_s = t.base_period_s * t.frame_period_n;
    t.acquisition_lag_s = t.processing_lag_s = 0.5 * h * frame_s;
  } else {
    s.allow("delay_frames");
    t.acquisition_lag_s = s.number("acquisition_lag_s", t.acquisition_lag_s, 0.0, 100.0);
    t.processing_lag_s = s.number("processing_lag_s", t.processing_lag_s, 0.0, 100.0);
  }
  t.controller_lag_s = s.number("controller_lag_s", t.controller_lag_s, 0.0, 100.0);
  t.servo_lag_s = s.number("servo_lag_s", t.servo_lag_s, 0.0, 100.0);
  t.motion_lag_s = s.number("motion_lag_s", t.motion_lag_s, 0.0, 100.0);
  t.model_motion_lag = s.boolean("model_motion_lag", t.model_motion_lag);
  t.pipeline = s.enumValue("pipeline", t.pipeline, parsePipeline);
  s.finish();
  withLocation(s.file(), s.line(), {}, [&] { return TimingModel(t); });
}

void readNoise(YamlSection& root, NoiseConfig& n) {
  if (!root.has("noise")) {
    root.allow("noise");
    return;
  }
  YamlSection s(root.node("noise"), root.file(), "noise");
  n.kind = s.enumValue("model", n.kind, parseNoiseKind);
  n.sigma = s.number("sigma", n.sigma, 0.0, 1e6);
  n.round_to_integer = s.boolean("round", n.round_to_integer);
  s.finish();
  withLocation(s.file(), s.line(), {}, [&] { return NoiseModel(n, 1).standardDeviation(); });
}

void readMetrics(YamlSection& root, MetricsOptions& m, bool closed_loop) {
  if (!root.has("metrics")) {
    root.allow("metrics");
    return;
  }
  YamlSection s(root.node("metrics"), root.file(), "metrics");
  m.steady_start_fraction = s.number("steady_start_fraction", m.steady_start_fraction, 0.0, 1.0);
  m.final_fraction = s.number("final_fraction", m.final_fraction, 0.0, 1.0);
  m.settling_band = s.number("settling_band", m.settling_band, 0.0, 1.0);
  m.response_window_s = s.number("response_window_s", m.response_window_s, 1e-9, 1e9);
  m.per_feature = s.boolean("per_feature", m.per_feature);
  m.outcome = s.boolean("outcome", m.outcome);
  if (m.outcome && !closed_loop)
    s.fail("outcome", "the outcome of a positioning run (converged / failed) is for closed-loop scenarios only");
  m.converge_px = s.number("converge_px", m.converge_px, 0.0, 1e9);
  m.converge_hold_s = s.number("converge_hold_s", m.converge_hold_s, 0.0, 1e9);
  m.fail_outside_image = s.boolean("fail_outside_image", m.fail_outside_image);
  m.fail_robot_limit = s.boolean("fail_robot_limit", m.fail_robot_limit);
  s.finish();
  withLocation(s.file(), s.line(), {}, [&] { return computeMetrics({}, {}, m); });  // the layer's own range checks
  withLocation(s.file(), s.line(), {}, [&] { return computeOutcome({}, {}, FailureKind::None, 0.0, m).converged; });
}

/// trajectory: {type: NAME, key: number, ...}; returns the type and fills params (validated).
std::string readTrajectory(const YAML::Node& node, const std::string& file, const std::string& section,
                           Params& params, int* channels = nullptr) {
  if (!node.IsMap()) throwAt(file, yamlLine(node), "'" + section + "': expected a mapping {type: NAME, params...}");
  const YAML::Node type = node["type"];
  if (!type.IsDefined() || !type.IsScalar())
    throwAt(file, yamlLine(node), "'" + section + ".type': missing (expected one of the trajectory names)");
  const std::string name = type.Scalar();
  KeyLines lines;
  params = readParams(node, file, section, &lines, {"type"});
  lines.emplace_back(name, yamlLine(type));
  if (channels)  // open loop: any N-channel trajectory
    *channels = withLocation(file, yamlLine(node), lines, [&] { return makeChannelTrajectory(name, params)->channels(); });
  else
    withLocation(file, yamlLine(node), lines, [&] { return makeTrajectory(name, params); });
  return name;
}

std::vector<ScenarioPredictor> readPredictors(YamlSection& root, int channels) {
  const YAML::Node list = root.node("predictors");
  const std::string& file = root.file();
  if (!list.IsDefined() || list.IsNull())
    throwAt(file, root.line(), "missing required key 'predictors' (a list of predictor names or {name, type, params})");
  if (!list.IsSequence() || list.size() == 0)
    throwAt(file, yamlLine(list), "'predictors': expected a non-empty list of names or {name: LABEL, type: NAME, params: {...}}");
  std::vector<ScenarioPredictor> out;
  std::set<std::string> seen;
  for (size_t i = 0; i < list.size(); ++i) {
    const YAML::Node item = list[i];
    ScenarioPredictor p;
    p.line = yamlLine(item);
    KeyLines lines;
    if (item.IsScalar()) {
      p.name = item.Scalar();
    } else {
      YamlSection s(item, file, "predictors[" + std::to_string(i) + "]");
      p.name = s.requiredString("name");
      if (s.node("type").IsDefined()) p.type = s.requiredString("type");
      p.params = readParams(s.node("params"), file, s.qualified("params"), &lines, {}, true);  // words: model: cv
      s.finish();
    }
    if (p.type.empty()) p.type = p.name;
    if (const std::string why = predictorLabelProblem(p.name, p.type); !why.empty())
      throwAt(file, p.line, "'predictors': " + why);
    if (!seen.insert(p.name).second)
      throwAt(file, p.line, "'predictors': predictor '" + p.name + "' listed twice (give the second one its own "
                            "name and type: {name: LABEL, type: " + p.type + ", params: {...}})");
    lines.emplace_back(p.type, p.line);
    withLocation(file, p.line, lines, [&] { return makePredictor(p.type, channels, p.params); });
    out.push_back(p);
  }
  return out;
}

/// Top-level keys a sweep may not change: they identify the scenario or fix how compare runs it
/// (runs and seeds are per scenario, not per variant).
const std::set<std::string> kUnsweepable = {"kind", "seed", "runs", "description", "sweep"};

/// Why `key` cannot be swept ("" when it can): malformed as a --set path, or unsweepable.
std::string sweepKeyProblem(const std::string& key) {
  std::vector<std::string> path;
  try {
    path = parseScenarioOverride(key + "=0").path;
  } catch (const OverrideError&) {
    return "expected a dotted scenario path such as timing.delay_frames, got '" + key + "'";
  }
  if (kUnsweepable.count(path.front()))
    return "'" + path.front() + "' cannot be swept (sweep a value that changes a run, e.g. noise.sigma, "
           "timing.delay_frames, task.lambda, predictors.NAME.params.KEY)";
  return "";
}

/// A sweep value as YAML text that parses back to the same node: a scalar as written when that
/// reads back as itself (0.5, feature), else YAML flow style (quoted strings, lists, mappings).
std::string yamlText(const YAML::Node& node) {
  if (node.IsScalar()) {
    try {
      const YAML::Node back = YAML::Load(node.Scalar());
      if (back.IsScalar() && back.Scalar() == node.Scalar()) return node.Scalar();
    } catch (const YAML::Exception&) {
    }
  }
  YAML::Emitter e;
  e << YAML::Flow << node;
  return e.c_str();
}

/// Checks the values of a sweep (non-empty, distinct); `fail(what)` throws.
template <class Fail>
void checkSweepValues(const ScenarioSweep& sw, Fail&& fail) {
  if (sw.values.empty()) fail("expected a non-empty list of values");
  std::set<std::string> seen;
  for (const auto& v : sw.values)
    if (!seen.insert(v).second) fail("value '" + v + "' is listed twice");
}

/// The axes under `node` (a mapping of the sweep block): a key whose value is a list is an axis;
/// a key whose value is a mapping continues the path (the nested spelling {noise: {sigma: [...]}},
/// what `--set sweep.noise.sigma=[...]` writes, is the dotted key noise.sigma), in file order.
void readSweepAxes(const YAML::Node& node, const std::string& prefix, const std::string& file,
                   std::vector<ScenarioSweep>& axes) {
  if (node.size() == 0)
    throwAt(file, yamlLine(node), "'sweep" + (prefix.empty() ? "" : "." + prefix) +
                                      "': expected a mapping {PATH: [v1, v2, ...], ...} of dotted scenario paths");
  for (const auto& kv : node) {
    const std::string key = (prefix.empty() ? "" : prefix + ".") + kv.first.Scalar();
    if (kv.second.IsMap()) {
      readSweepAxes(kv.second, key, file, axes);
      continue;
    }
    ScenarioSweep sw;
    sw.key = key;
    const int line = yamlLine(kv.first);
    sw.origin = fileLocation(file, line, "sweep");
    const std::string problem = sweepKeyProblem(sw.key);
    if (!problem.empty()) throwAt(file, line, "'sweep': " + problem);
    if (!kv.second.IsSequence()) throwAt(file, yamlLine(kv.second), "'sweep." + sw.key + "': expected a list of values");
    for (const auto& v : kv.second) sw.values.push_back(yamlText(v));
    checkSweepValues(sw, [&](const std::string& what) { throwAt(file, line, "'sweep." + sw.key + "': " + what); });
    axes.push_back(std::move(sw));
  }
}

/// sweep: {PATH: [v1, v2, ...], PATH2: [...]} (any kind; the values are checked when compare
/// loads them): one key is a sweep, several a grid over the product of their values.
void readSweep(YamlSection& root, Scenario& sc) {
  root.allow("sweep");
  if (!root.has("sweep")) return;
  const YAML::Node node = root.node("sweep");
  const std::string& file = root.file();
  if (!node.IsMap())
    throwAt(file, yamlLine(node), "'sweep': expected a mapping {PATH: [v1, v2, ...], ...} of dotted scenario paths");
  std::vector<ScenarioSweep> axes;
  readSweepAxes(node, "", file, axes);
  checkSweepAxes(axes);
  setScenarioSweeps(sc, axes);
}

/// The keys both kinds share, into PredictionExperimentConfig or ServoConfig (same field names).
template <class Config>
void readCommon(YamlSection& root, Config& c, bool closed_loop) {
  c.duration_s = root.number("duration_s", c.duration_s, 1e-6, 1e6);
  readTiming(root, c.timing);
  readNoise(root, c.noise);
  readMetrics(root, c.metrics, closed_loop);
  readSection(root, "lost", [&](YamlSection& s) {
    c.lost.timeout_s = s.number("timeout_s", c.lost.timeout_s, 1e-6, 1e6);
    c.lost.action = s.enumValue("action", c.lost.action, parseLostAction);
    if (c.lost.action == LostAction::Drop && !closed_loop)
      s.fail("action", "'drop' needs a closed loop (a task that runs without the feature); an open-loop scenario "
                       "takes 'hold' or 'extrapolate'");
  });
}

void readOcclusions(YamlSection& root, std::vector<OcclusionInterval>& out);

void readOpenLoop(YamlSection& root, Scenario& sc) {
  PredictionExperimentConfig& c = sc.open_loop;
  readCommon(root, c, false);
  if (!root.has("trajectory"))
    throwAt(root.file(), root.line(), "missing required key 'trajectory' ({type: line|accel-jump|zigzag|circle|...})");
  sc.trajectory = readTrajectory(root.node("trajectory"), root.file(), "trajectory", sc.trajectory_params, &sc.channels);
  readOcclusions(root, c.occlusions);
  sc.predictors = readPredictors(root, sc.channels);
}

/// A component section {type: NAME, key: value, ...} (task, robot, source): the name (default:
/// the spec's own) and its parameters, numbers or words. Validated by the loop's construction.
void readComponent(YamlSection& root, const std::string& key, ComponentSpec& spec, KeyLines& lines) {
  root.allow(key);
  if (!root.has(key)) return;
  const YAML::Node node = root.node(key);
  const std::string& file = root.file();
  if (node.IsNull()) return;
  if (!node.IsMap()) throwAt(file, yamlLine(node), "'" + key + "': expected a mapping {type: NAME, parameters...}");
  const YAML::Node type = node["type"];
  // Parameter keys before the component's name: an error quoting both ("unknown parameter 'k' for
  // task 'vsc'") points at the key's line.
  spec.params = readParams(node, file, key, &lines, {"type"}, true);
  if (type.IsDefined()) {
    if (!type.IsScalar()) throwAt(file, yamlLine(type), "'" + key + ".type': expected a name");
    spec.name = type.Scalar();
    lines.emplace_back(spec.name, yamlLine(type));
  }
}

/// A 6-vector pose [tx, ty, tz, thetaux, thetauy, thetauz] (m, rad).
Pose6 readPose(YamlSection& s, const std::string& key) {
  const auto v = s.numbers(key, {}, 6);
  Pose6 p;
  for (int i = 0; i < 6; ++i) p(i) = v[static_cast<size_t>(i)];
  return p;
}

/// occlusions: [{start_s: a, end_s: b}, ...] (both kinds).
void readOcclusions(YamlSection& root, std::vector<OcclusionInterval>& out) {
  root.allow("occlusions");
  const YAML::Node occ = root.node("occlusions");
  if (!occ.IsDefined() || occ.IsNull()) return;
  if (!occ.IsSequence()) throwAt(root.file(), yamlLine(occ), "'occlusions': expected a list of {start_s, end_s}");
  for (size_t i = 0; i < occ.size(); ++i) {
    YamlSection s(occ[i], root.file(), "occlusions[" + std::to_string(i) + "]");
    OcclusionInterval o;
    o.start_s = s.requiredNumber("start_s", 0.0, 1e6);
    o.end_s = s.requiredNumber("end_s", 0.0, 1e6);
    if (!(o.end_s > o.start_s)) s.fail("end_s", "expected end_s > start_s");
    s.finish();
    out.push_back(o);
  }
}

void readClosedLoop(YamlSection& root, Scenario& sc) {
  ServoConfig& c = sc.closed_loop;
  readCommon(root, c, true);
  const std::string& file = root.file();
  readSection(root, "camera", [&](YamlSection& s) {
    c.camera.px = s.number("px", c.camera.px, 1e-6, 1e7);
    c.camera.py = s.number("py", c.camera.py, 1e-6, 1e7);
    c.camera.u0 = s.number("u0", c.camera.u0, -1e7, 1e7);
    c.camera.v0 = s.number("v0", c.camera.v0, -1e7, 1e7);
    // The principal point at the image centre unless the size is given (640 x 480 by default).
    c.image_width_px = s.number("width", 2.0 * c.camera.u0, 1.0, 1e7);
    c.image_height_px = s.number("height", 2.0 * c.camera.v0, 1.0, 1e7);
  });
  readSection(root, "target", [&](YamlSection& s) {
    SceneConfig& t = c.scene;
    t.square_side_m = s.number("square_side_m", t.square_side_m, 1e-9, 1e3);
    t.desired_depth_m = s.number("desired_depth_m", t.desired_depth_m, 1e-9, 1e3);
    if (s.has("points")) {
      const YAML::Node pts = s.node("points");
      if (!pts.IsSequence() || pts.size() == 0)
        throwAt(file, yamlLine(pts), "'target.points': expected a list of [x, y, z] points (m, object frame)");
      t.points.resize(3, static_cast<Eigen::Index>(pts.size()));
      for (size_t i = 0; i < pts.size(); ++i) {
        if (!pts[i].IsSequence() || pts[i].size() != 3)
          throwAt(file, yamlLine(pts[i]), "'target.points[" + std::to_string(i) + "]': expected [x, y, z]");
        for (size_t r = 0; r < 3; ++r)
          t.points(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(i)) =
              yamlNumber(pts[i][r], file, "'target.points[" + std::to_string(i) + "]'");
      }
    }
    s.allow("points");
    if (s.has("desired_pose")) {
      if (s.has("desired_depth_m")) s.fail("desired_pose", "give either desired_pose or desired_depth_m, not both");
      t.desired_pose = readPose(s, "desired_pose");
      t.desired_pose_given = true;
    }
    s.allow("desired_pose");
    if (s.has("pose")) t.object_pose = readPose(s, "pose");
    s.allow("pose");
    if (s.has("trajectory"))
      t.trajectory = readTrajectory(s.node("trajectory"), file, "target.trajectory", t.trajectory_params);
    s.allow("trajectory");
    withLocation(file, s.line(), {}, [&] { return Scene(t).points(); });
  });
  if (root.has("initial_pose")) c.initial_pose = readPose(root, "initial_pose");
  root.allow("initial_pose");
  readOcclusions(root, c.occlusions);
  KeyLines lines;
  readComponent(root, "task", c.task, lines);
  readComponent(root, "robot", c.robot, lines);
  readComponent(root, "source", c.source, lines);
  readSection(root, "servo", [&](YamlSection& s) {
    c.forecast = s.enumValue("forecast", c.forecast, parseForecastMode);
    c.compensation = s.enumValue("compensation", c.compensation, parseCompensation);
  });
  // The composition checks itself (every component's keys, the task against the robot).
  sc.channels = withLocation(file, root.line(), lines, [&] { return servoChannels(c); });
  sc.predictors = readPredictors(root, sc.channels);
  auto hold = makePredictor("hold", sc.channels);
  withLocation(file, 0, lines, [&] { return ServoLoop(c, *hold).done(); });
}

/// The strict parse of a scenario document read from `path`.
Scenario parseScenario(const YAML::Node& doc, const std::string& path) {
  if (!doc.IsDefined() || doc.IsNull()) throwAt(path, 0, "the file is empty (expected a scenario mapping with 'kind:')");
  YamlSection root(doc, path, "");
  Scenario sc;
  sc.path = path;
  sc.name = scenarioName(path);
  sc.description = root.string("description", "");
  const std::string kind = root.requiredString("kind");
  if (kind == "open-loop") {
    sc.kind = ScenarioKind::OpenLoop;
  } else if (kind == "closed-loop") {
    sc.kind = ScenarioKind::ClosedLoop;
  } else {
    root.fail("kind", "expected open-loop or closed-loop, got '" + kind + "'");
  }
  // Unknown top-level keys first (a misspelt 'trajectory' is reported as such, not as missing).
  static const std::set<std::string> kCommon = {"description", "kind", "seed", "duration_s", "timing",
                                                "noise", "metrics", "predictors", "runs", "sweep", "lost"};
  static const std::set<std::string> kOpen = {"trajectory", "occlusions"};
  static const std::set<std::string> kClosed = {"camera", "target", "initial_pose", "task", "servo", "robot",
                                                "source", "occlusions"};
  const auto& own = sc.kind == ScenarioKind::OpenLoop ? kOpen : kClosed;
  for (const auto& kv : doc) {
    const std::string key = kv.first.Scalar();
    if (kCommon.count(key) || own.count(key)) continue;
    std::string expected;
    for (const auto* set : {&kCommon, &own})
      for (const auto& k : *set) expected += (expected.empty() ? "" : ", ") + k;
    throwAt(path, yamlLine(kv.first), "unknown key '" + key + "' for " + (sc.kind == ScenarioKind::OpenLoop ? "an " : "a ") + kind + " scenario (expected one of: " +
                                          expected + ")");
  }
  const long seed = root.integer("seed", 1, 0, 2147483647L);
  sc.runs = static_cast<int>(root.integer("runs", 0, 1, 100000));
  if (sc.kind == ScenarioKind::OpenLoop)
    readOpenLoop(root, sc);
  else
    readClosedLoop(root, sc);
  readSweep(root, sc);
  sc.setSeed(static_cast<std::uint64_t>(seed));
  root.finish();
  return sc;
}

}  // namespace

std::string ScenarioSweep::shortKey() const {
  const auto dot = key.rfind('.');
  return dot == std::string::npos ? key : key.substr(dot + 1);
}

ScenarioOverride ScenarioSweep::valueOverride(size_t i) const { return parseScenarioOverride(key + "=" + values.at(i)); }

void checkSweepAxes(const std::vector<ScenarioSweep>& axes) {
  auto segments = [](const std::string& key) { return parseScenarioOverride(key + "=0").path; };
  for (size_t b = 0; b < axes.size(); ++b)
    for (size_t a = 0; a < b; ++a) {
      if (axes[a].key == axes[b].key)
        throw std::invalid_argument(axes[b].origin + ": '" + axes[b].key + "' is swept twice (one axis per key)");
      // A later axis that contains an earlier one would overwrite it in every cell.
      const auto pa = segments(axes[a].key), pb = segments(axes[b].key);
      if (pb.size() < pa.size() && std::equal(pb.begin(), pb.end(), pa.begin()))
        throw std::invalid_argument(axes[b].origin + ": '" + axes[b].key + "' would replace '" + axes[a].key +
                                    "', swept before it; give '" + axes[b].key + "' first");
    }
}

size_t gridCells(const std::vector<ScenarioSweep>& axes) {
  if (axes.empty()) return 0;
  size_t n = 1;
  for (const auto& a : axes) n *= a.values.size();
  return n;
}

std::vector<size_t> gridIndices(const std::vector<ScenarioSweep>& axes, size_t cell) {
  std::vector<size_t> idx(axes.size());
  for (size_t a = axes.size(); a-- > 0;) {
    idx[a] = cell % axes[a].values.size();
    cell /= axes[a].values.size();
  }
  return idx;
}

std::string sweepKeysText(const std::vector<ScenarioSweep>& axes) {
  std::string text;
  for (const auto& a : axes) text += (text.empty() ? "" : " x ") + a.key;
  return text;
}

void setScenarioSweeps(Scenario& sc, const std::vector<ScenarioSweep>& axes) {
  sc.sweeps = axes;
  sc.sigma_sweep.clear();
  if (axes.size() != 1 || axes.front().key != "noise.sigma") return;
  for (const auto& v : axes.front().values) {
    char* end = nullptr;
    const double x = std::strtod(v.c_str(), &end);
    if (end == v.c_str() || *end != '\0') {  // not a number: the variant's load will say so
      sc.sigma_sweep.clear();
      return;
    }
    sc.sigma_sweep.push_back(x);
  }
}

ScenarioSweep parseSweepOption(const std::string& text) {
  const auto eq = text.find('=');
  const std::string usage =
      "--sweep: expected PATH=V1,V2,... (or PATH=[V1, V2, ...]) with a dotted scenario path such as "
      "timing.delay_frames=0,1,2, got '" + text + "'";
  if (eq == std::string::npos || eq == 0) throw std::invalid_argument(usage);
  ScenarioSweep sw;
  sw.key = text.substr(0, eq);
  sw.origin = "--sweep";
  const std::string problem = sweepKeyProblem(sw.key);
  if (!problem.empty()) throw std::invalid_argument("--sweep: " + problem);
  const std::string list = text.substr(eq + 1);
  auto trimmed = [](const std::string& x) {
    const auto b = x.find_first_not_of(" \t");
    return b == std::string::npos ? std::string() : x.substr(b, x.find_last_not_of(" \t") - b + 1);
  };
  if (trimmed(list).rfind('[', 0) == 0) {
    YAML::Node node;
    try {
      node = YAML::Load(list);
    } catch (const YAML::Exception& e) {
      throw std::invalid_argument("--sweep " + text + ": not a valid YAML list (" + e.msg + ")");
    }
    if (!node.IsSequence()) throw std::invalid_argument(usage);
    for (const auto& v : node) sw.values.push_back(yamlText(v));
  } else {
    size_t start = 0;
    while (true) {
      const auto comma = list.find(',', start);
      const std::string v = trimmed(list.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      if (v.empty()) throw std::invalid_argument(usage + " (empty value)");
      sw.values.push_back(v);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  checkSweepValues(sw, [&](const std::string& what) { throw std::invalid_argument("--sweep " + text + ": " + what); });
  return sw;
}

std::vector<Scenario> loadSweepVariants(const Scenario& sc, const std::vector<ScenarioOverride>& overrides) {
  std::vector<Scenario> out;
  const std::vector<ScenarioSweep>& axes = sc.sweeps;
  for (size_t cell = 0; cell < gridCells(axes); ++cell) {
    const std::vector<size_t> idx = gridIndices(axes, cell);
    std::vector<ScenarioOverride> all = overrides;
    std::vector<std::string> texts;
    std::string text;
    for (size_t a = 0; a < axes.size(); ++a) {
      all.push_back(axes[a].valueOverride(idx[a]));
      texts.push_back(axes[a].key + "=" + axes[a].values[idx[a]]);
      text += (a ? ", " : "") + texts.back();
    }
    try {
      Scenario v = loadScenario(sc.path, all);
      setScenarioSweeps(v, axes);
      out.push_back(std::move(v));
    } catch (const std::invalid_argument& e) {
      // loadScenario blames the first override that breaks the parse: here one of the cell's
      // values, since the scenario loaded without them ("--set TEXT (scenario NAME): WHAT" or
      // "--set TEXT: WHAT"); the error names the origin of that axis and the whole cell.
      std::string what = e.what();
      size_t blamed = 0;
      bool found = false;
      for (size_t a = 0; a < texts.size() && !found; ++a)
        for (const auto& head : {"--set " + texts[a] + " (scenario " + sc.name + "): ", "--set " + texts[a] + ": "})
          if (what.rfind(head, 0) == 0) {
            what = what.substr(head.size());
            blamed = a;
            found = true;
            break;
          }
      if (!found && what.rfind("--set: ", 0) == 0) what = what.substr(7);
      throw std::invalid_argument(axes[blamed].origin + " " + text + " (scenario " + sc.name + "): " + what);
    }
  }
  return out;
}

std::string scenarioKindName(ScenarioKind kind) { return kind == ScenarioKind::OpenLoop ? "open-loop" : "closed-loop"; }

void Scenario::setSeed(std::uint64_t seed) {
  open_loop.seed = seed;
  closed_loop.seed = seed;
}

Scenario loadScenario(const std::string& path, const std::vector<ScenarioOverride>& overrides) {
  // The document with the first n overrides applied, parsed strictly (the file is read again for
  // each attempt: a node copy would lose the line marks the errors quote).
  auto attempt = [&](size_t n) {
    YAML::Node doc = loadYamlFile(path);
    if (doc.IsMap())  // anything else is the file's own defect, reported by the parse
      for (size_t i = 0; i < n; ++i) applyScenarioOverride(doc, overrides[i]);
    return parseScenario(doc, path);
  };
  try {
    return attempt(overrides.size());
  } catch (const OverrideError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    if (overrides.empty()) throw;
    // Blame the first override whose addition makes the parse fail (none: the file's own error).
    for (size_t n = 0; n < overrides.size(); ++n) {
      try {
        attempt(n);
      } catch (const std::invalid_argument& prefix_error) {
        if (n == 0) throw;
        throw std::invalid_argument(overrideErrorMessage(overrides[n - 1], path, prefix_error.what()));
      }
    }
    throw std::invalid_argument(overrideErrorMessage(overrides.back(), path, e.what()));
  }
}

}  // namespace predvs
