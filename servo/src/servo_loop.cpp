#include "predvs/servo/servo_loop.h"

#include "predvs/predictors/named_enum.h"
#include "predvs/tasks/point_task.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void requirePositive(const char* key, double v) {
  if (!(v > 0.0) || !std::isfinite(v)) {
    std::ostringstream msg;
    msg << key << " must be > 0, got " << v;
    throw std::invalid_argument(msg.str());
  }
}

/// A frame on its way through the vision pipeline.
struct Measurement {
  double t_acq_s;
  long release_tick;
  PointFeatures points;
  Eigen::VectorXd ego;  // E(t_acq): the image displacement the robot's own motion has caused
  Eigen::VectorXd p;    // p(t_acq): integral of the applied command
};

struct Command {
  long apply_tick;
  Eigen::VectorXd u;     // limited command
  Eigen::VectorXd dego;  // J_task u delta: feature displacement it causes over one tick
};

constexpr EnumName<ForecastMode> kForecastModes[] = {
    {ForecastMode::Feature, "feature"}, {ForecastMode::Feedforward, "feedforward"}, {ForecastMode::Both, "both"}};
constexpr EnumName<Compensation> kCompensations[] = {
    {Compensation::Auto, "auto"}, {Compensation::On, "on"}, {Compensation::Off, "off"}};

/// The scene, robot and task of a configuration, validated.
struct Composition {
  Scene scene;
  std::unique_ptr<Robot> robot;
  std::unique_ptr<Task> task;

  explicit Composition(const ServoConfig& c) : scene(c.scene) {
    requirePositive("camera.px", c.camera.px);
    requirePositive("camera.py", c.camera.py);
    robot = makeRobot(c.robot.name, c.robot.params);
    TaskContext ctx;
    ctx.camera = c.camera;
    ctx.desired_points = scene.desired(c.camera);
    ctx.command_space = robot->commandSpace();
    const TimingModel timing(c.timing);
    ctx.base_period_s = timing.basePeriod();
    ctx.frame_period_s = timing.framePeriod();
    ctx.nominal_delay_frames = timing.nominalHorizonFrames();
    ctx.seed = c.seed;
    task = makeTask(c.task.name, c.task.params, ctx);
  }
};

}  // namespace

ForecastMode parseForecastMode(const std::string& name) { return enumFromName(kForecastModes, "servo.forecast", name); }
std::string forecastModeName(ForecastMode mode) { return enumToName(kForecastModes, mode); }
Compensation parseCompensation(const std::string& name) {
  return enumFromName(kCompensations, "servo.compensation", name);
}
std::string compensationName(Compensation c) { return enumToName(kCompensations, c); }

int servoChannels(const ServoConfig& config) { return Composition(config).task->featureSize(); }

struct ServoLoop::Impl {
  Impl(const ServoConfig& c, Predictor& p)
      : config(c), timing(c.timing), parts(c), predictor(p), lost(c.lost, parts.task->featureSize()) {}

  ServoConfig config;
  TimingModel timing;
  Composition parts;
  Predictor& predictor;
  LostFeatureTracker lost;
  std::unique_ptr<FeatureSource> source;
  bool compensate = false;
  bool wants_truth_jacobian = false;
  int n_features = 0;
  int n_command = 0;

  long k = 0;
  long last_tick = 0;
  std::deque<Measurement> pending;
  std::deque<Command> commands;
  bool have_measurement = false;
  double t_acq_latest = kNaN;
  bool frame_lost = false;
  Eigen::VectorXd latest;    // latest finite value of every feature channel
  Eigen::VectorXd depths;    // latest finite depth of every point
  Eigen::VectorXd ego;       // E(t)
  Eigen::VectorXd p;         // integral of the applied command
  Command active;
  Eigen::VectorXd no_rate;   // empty: no feed-forward
  Eigen::VectorXd measured_dropped;  // lost.action drop: latest with the dropped channels NaN
  ServoSample sample;
  FailureKind failure = FailureKind::None;  // metrics.outcome: the first failing state
  double failure_time_s = kNaN;

  Task& task() { return *parts.task; }
  Robot& robot() { return *parts.robot; }

  /// metrics.outcome: the failure of the true state at t with the robot as it is now (metrics.h,
  /// Outcome: behind the camera, then outside the image, then at a robot limit).
  void checkFailure(double t) {
    const MetricsOptions& o = config.metrics;
    const PointFeatures& truth = parts.scene.project(t, robot().cameraPose(), config.camera);
    FailureKind kind = FailureKind::None;
    for (Eigen::Index i = 0; i < truth.Z_m.size() && kind == FailureKind::None; ++i)
      if (!(truth.Z_m(i) > 0.0)) kind = FailureKind::Behind;
    if (kind == FailureKind::None && o.fail_outside_image)
      for (Eigen::Index i = 0; i < truth.Z_m.size(); ++i) {
        const double u = truth.uv_px(2 * i), v = truth.uv_px(2 * i + 1);
        if (!(u >= 0.0 && u < config.image_width_px && v >= 0.0 && v < config.image_height_px)) {
          kind = FailureKind::OutsideImage;
          break;
        }
      }
    if (kind == FailureKind::None && o.fail_robot_limit && robot().atLimit()) kind = FailureKind::RobotLimit;
    if (kind != FailureKind::None) {
      failure = kind;
      failure_time_s = t;
    }
  }

  /// The target rate fed to the task at t, in `feedforward` and `both` alike: the predictor's velocity
  /// for a feed-forward (Predictor::feedforwardVelocity(), judged at a law's bandwidth, not scaled
  /// by the forecast's blend with hold).
  Eigen::VectorXd targetRates(double t) const { return predictor.feedforwardVelocities(t); }

  void deliver(const Measurement& m) {
    const Eigen::VectorXd f = task().features(m.points);
    const Eigen::VectorXd fed = compensate ? Eigen::VectorXd(f - m.ego) : f;
    // The whole target lost past lost.timeout_s and back: restart the predictor from this frame.
    if (lost.observe(m.t_acq_s, fed)) predictor.reset();
    predictor.update(m.t_acq_s, fed);
    if (sample.predictor_diagnostics.size() > 0) {
      const NamedValues diag = predictor.diagnostics();
      for (size_t i = 0; i < diag.size(); ++i) sample.predictor_diagnostics(static_cast<Eigen::Index>(i)) = diag[i].second;
    }
    Eigen::VectorXd rate = compensate ? targetRates(m.t_acq_s) : Eigen::VectorXd();
    if (rate.size())
      for (int i = 0; i < n_features; ++i)
        if (lost.expired(i)) rate(i) = 0.0;
    task().observe(TaskMeasurement{m.t_acq_s, f, m.p, rate});
    for (int i = 0; i < n_features; ++i)
      if (std::isfinite(f(i))) latest(i) = f(i);
    for (Eigen::Index i = 0; i < depths.size(); ++i)
      if (m.points.seen[static_cast<size_t>(i)] && std::isfinite(m.points.Z_m(i))) depths(i) = m.points.Z_m(i);
    t_acq_latest = m.t_acq_s;
    frame_lost = std::none_of(m.points.seen.begin(), m.points.seen.end(), [](bool seen) { return seen; });
    have_measurement = true;
  }

  const ServoSample& step() {
    const double t = timing.tickTime(k);
    const vpHomogeneousMatrix wMc = robot().cameraPose();
    const PointFeatures truth = parts.scene.project(t, wMc, config.camera);

    // Acquisition, then delivery of every frame whose release tick has come.
    if (timing.isAcquisitionTick(k)) {
      FeatureFrame frame = source->acquire(t, wMc);
      pending.push_back(Measurement{frame.t_acq_s, timing.releaseTick(frame.t_acq_s), std::move(frame.points), ego, p});
    }
    while (!pending.empty() && pending.front().release_tick <= k) {
      deliver(pending.front());
      pending.pop_front();
    }

    sample.t_s = t;
    sample.truth = task().features(truth);
    sample.error = task().trackingError(sample.truth);
    sample.t_acq_s = have_measurement ? t_acq_latest : kNaN;
    sample.frame_lost = frame_lost;
    sample.measured = have_measurement ? latest : Eigen::VectorXd::Constant(n_features, kNaN);
    sample.predicted = Eigen::VectorXd::Constant(n_features, kNaN);
    sample.lost_expired = lost.anyExpired();

    // Control at t_c = t (no command before the first image: the robot waits).
    if (have_measurement) {
      const double t_eff = timing.effectTime(t);
      Eigen::VectorXd s_used = latest;
      Eigen::VectorXd rate;
      Eigen::VectorXd ego_eff;
      if (!compensate) {
        s_used = predictor.predictPositions(t_eff);
      } else {
        // E(t_eff): the displacement so far plus that of the queued commands acting before t_eff.
        ego_eff = ego;
        const long eff_tick = timing.tickAtOrAfter(t_eff);
        for (const Command& c : commands)
          if (c.apply_tick < eff_tick) ego_eff += c.dego;
        if (config.forecast != ForecastMode::Feedforward) s_used = predictor.predictPositions(t_eff) + ego_eff;
        if (config.forecast != ForecastMode::Feature) rate = targetRates(t_eff);
      }
      // A channel the predictor has not seen yet acts on its latest value.
      for (int i = 0; i < n_features; ++i)
        if (!std::isfinite(s_used(i))) s_used(i) = latest(i);
      // The lost-feature policy (lost_feature_policy.h): an expired channel is held or dropped.
      const Eigen::VectorXd* measured_in = &latest;
      if (sample.lost_expired) {
        const bool drop = config.lost.action == LostAction::Drop;
        if (drop) measured_dropped = latest;
        for (int i = 0; i < n_features; ++i) {
          if (!lost.expired(i)) continue;
          if (rate.size()) rate(i) = 0.0;
          if (drop) {
            s_used(i) = kNaN;
            measured_dropped(i) = kNaN;
          } else if (!compensate) {
            s_used(i) = lost.lastValue(i);  // = latest(i): the raw last measurement
          } else if (config.forecast != ForecastMode::Feedforward) {
            s_used(i) = lost.lastValue(i) + ego_eff(i);
          }  // feedforward: s_used(i) is latest(i) already
        }
        if (drop) measured_in = &measured_dropped;
      }
      sample.predicted = s_used;
      const Eigen::MatrixXd Jc = robot().cameraJacobian();
      const Eigen::VectorXd q = robot().state();
      Eigen::MatrixXd J_true;
      if (wants_truth_jacobian) J_true = PointTask::pixelInteraction(truth.uv_px, truth.Z_m, config.camera) * Jc;
      const TaskInput in{t, t_acq_latest, *measured_in, s_used, rate.size() ? rate : no_rate, depths, Jc, q, J_true};
      const Eigen::VectorXd u = robot().limit(task().computeCommand(in));
      Command c{timing.commandApplyTick(k), u, Eigen::VectorXd::Zero(n_features)};
      if (compensate) c.dego = task().featureJacobian() * (u * timing.basePeriod());
      commands.push_back(std::move(c));
      const NamedValues diag = task().diagnostics();
      for (size_t i = 0; i < diag.size(); ++i) sample.diagnostics(static_cast<Eigen::Index>(i)) = diag[i].second;
    }

    // The command acting over [t, t + delta): the latest whose apply tick has come.
    while (!commands.empty() && commands.front().apply_tick <= k) {
      active = std::move(commands.front());
      commands.pop_front();
    }
    robot().step(active.u, timing.basePeriod());
    ego += active.dego;
    p += active.u * timing.basePeriod();
    sample.command = active.u;
    ++k;
    // The state this step led to (the next tick's; the scene keeps the projection for it).
    if (config.metrics.outcome && k <= last_tick) checkFailure(timing.tickTime(k));
    return sample;
  }
};

ServoLoop::ServoLoop(const ServoConfig& config, Predictor& predictor) {
  requirePositive("duration_s", config.duration_s);
  if (!config.initial_pose.allFinite()) throw std::invalid_argument("initial_pose must be finite");
  for (size_t i = 0; i < config.occlusions.size(); ++i)
    if (!(config.occlusions[i].start_s < config.occlusions[i].end_s))
      throw std::invalid_argument("occlusions[" + std::to_string(i) + "]: start_s must be < end_s");
  impl_ = std::make_unique<Impl>(config, predictor);
  Impl& m = *impl_;
  m.n_features = m.task().featureSize();
  m.n_command = m.robot().commandSpace().size();
  if (predictor.channels() != m.n_features)
    throw std::invalid_argument("servo loop: predictor '" + predictor.name() + "' has " +
                                std::to_string(predictor.channels()) + " channels, task '" + m.task().name() +
                                "' has " + std::to_string(m.n_features) + " features");
  if (config.lost.action == LostAction::Drop && !m.task().canDropFeatures())
    throw std::invalid_argument("lost.action: 'drop' needs a law that runs without some of its features; task '" +
                                m.task().name() + "' cannot (use lost.action: hold)");
  m.compensate = config.compensation == Compensation::On ||
                 (config.compensation == Compensation::Auto && predictor.extrapolates());
  predictor.reset();

  // The camera starts at initial_pose relative to the desired camera frame.
  const vpHomogeneousMatrix wMc0 = m.parts.scene.desiredCameraPose() * poseMatrix(config.initial_pose);
  m.robot().reset(wMc0);
  const PointFeatures start = m.parts.scene.project(0.0, m.robot().cameraPose(), config.camera);
  for (int i = 0; i < start.points(); ++i)
    if (!start.seen[static_cast<size_t>(i)]) throw std::invalid_argument("initial_pose puts the camera behind the target");

  FeatureSourceContext sctx;
  sctx.scene = &m.parts.scene;
  sctx.camera = config.camera;
  sctx.noise = config.noise;
  sctx.seed = config.seed;
  sctx.occlusions = config.occlusions;
  sctx.image_width_px = config.image_width_px;
  sctx.image_height_px = config.image_height_px;
  m.source = makeFeatureSource(config.source.name, config.source.params, sctx);
  if (m.source->points() != m.parts.scene.points())
    throw std::invalid_argument("source '" + m.source->name() + "' reports " + std::to_string(m.source->points()) +
                                " points, the target has " + std::to_string(m.parts.scene.points()));

  m.wants_truth_jacobian = m.task().needsTrueJacobian();
  m.latest = Eigen::VectorXd::Constant(m.n_features, kNaN);
  m.depths = m.parts.scene.desired(config.camera).Z_m;
  m.ego = Eigen::VectorXd::Zero(m.n_features);
  m.p = Eigen::VectorXd::Zero(m.n_command);
  m.active = Command{0, Eigen::VectorXd::Zero(m.n_command), Eigen::VectorXd::Zero(m.n_features)};
  m.sample.diagnostics = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(m.task().diagnostics().size()), kNaN);
  if (config.predictor_diagnostics)
    m.sample.predictor_diagnostics = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(predictor.diagnostics().size()), kNaN);
  m.last_tick = m.timing.tickAtOrAfter(config.duration_s);
  if (config.metrics.outcome) {
    // The options' own range checks, before anything runs.
    computeOutcome({}, {}, FailureKind::None, kNaN, config.metrics);
    if (config.metrics.fail_outside_image) {
      requirePositive("camera.width", config.image_width_px);
      requirePositive("camera.height", config.image_height_px);
    }
    m.checkFailure(0.0);
  }
}

ServoLoop::~ServoLoop() = default;

bool ServoLoop::done() const { return impl_->k > impl_->last_tick || impl_->failure != FailureKind::None; }
FailureKind ServoLoop::failure() const { return impl_->failure; }
double ServoLoop::failureTime() const { return impl_->failure_time_s; }
const ServoSample& ServoLoop::step() { return impl_->step(); }
bool ServoLoop::predictionUsed() const { return impl_->compensate; }
const Eigen::VectorXd& ServoLoop::desiredFeatures() const { return impl_->parts.task->desiredFeatures(); }
const Task& ServoLoop::task() const { return *impl_->parts.task; }
const Robot& ServoLoop::robot() const { return *impl_->parts.robot; }

std::vector<std::string> ServoLoop::valueNames() const {
  std::vector<std::string> names;
  for (const auto& kv : metricValues(Metrics{})) names.push_back(kv.first);
  if (impl_->config.metrics.outcome)
    for (const auto& kv : outcomeValues(Outcome{})) names.push_back(kv.first);
  if (impl_->config.metrics.per_feature) {
    const auto features = task().featureNames();
    for (const char* prefix : {"mean_e_", "rms_e_", "max_e_"})
      for (const auto& f : features) names.push_back(prefix + f);
  }
  if (!impl_->config.occlusions.empty()) {
    for (const auto& kv : occlusionValues({}, {}, {})) names.push_back(kv.first);
    names.push_back(lostPolicyValue({}, 0.0).first);
  }
  for (const auto& kv : task().runSummary()) names.push_back(kv.first);
  return names;
}

std::vector<std::string> ServoLoop::traceColumns() const {
  std::vector<std::string> c = {"t_s", "t_acq_s"};
  const auto features = task().featureNames();
  for (const char* prefix : {"meas_", "pred_", "true_"})
    for (const auto& f : features) c.push_back(prefix + f);
  c.push_back("error_px");
  for (const auto& n : robot().commandSpace().names) c.push_back(n);
  for (const auto& kv : task().diagnostics()) c.push_back(kv.first);
  return c;
}

std::vector<double> ServoLoop::traceRow(const ServoSample& s) {
  std::vector<double> r = {s.t_s, s.t_acq_s};
  for (const Eigen::VectorXd* f : {&s.measured, &s.predicted, &s.truth})
    for (Eigen::Index i = 0; i < f->size(); ++i) r.push_back((*f)(i));
  r.push_back(s.error);
  for (Eigen::Index i = 0; i < s.command.size(); ++i) r.push_back(s.command(i));
  for (Eigen::Index i = 0; i < s.diagnostics.size(); ++i) r.push_back(s.diagnostics(i));
  return r;
}

ServoResult ServoLoop::run() {
  ServoResult r;
  r.predictor = impl_->predictor.name();
  r.prediction_used = impl_->compensate;
  r.desired = desiredFeatures();
  r.columns = traceColumns();
  r.command_units = robot().commandSpace().units;
  if (impl_->config.predictor_diagnostics)
    for (const auto& kv : impl_->predictor.diagnostics()) r.predictor_diagnostic_names.push_back(kv.first);
  r.trace.reserve(static_cast<size_t>(impl_->last_tick + 1));
  while (!done()) r.trace.push_back(step());
  std::vector<double> ts, es;
  std::vector<Eigen::VectorXd> us;
  ts.reserve(r.trace.size());
  es.reserve(r.trace.size());
  us.reserve(r.trace.size());
  for (const auto& s : r.trace) {
    ts.push_back(s.t_s);
    es.push_back(s.error);
    us.push_back(s.command);
  }
  const MetricsOptions& options = impl_->config.metrics;
  r.metrics = computeMetrics(ts, es, options, &us);
  if (options.outcome) {
    r.outcome = computeOutcome(ts, es, impl_->failure, impl_->failure_time_s, options);
    if (r.outcome.failed()) r.metrics = withoutSteadyState(r.metrics);  // no steady state (metrics.h)
  }
  r.values = metricValues(r.metrics);
  if (options.outcome)
    for (auto& kv : outcomeValues(r.outcome)) r.values.push_back(std::move(kv));
  if (options.per_feature) {
    std::vector<Eigen::VectorXd> truth;
    truth.reserve(r.trace.size());
    for (const auto& s : r.trace) truth.push_back(s.truth);
    for (auto& kv : featureErrorValues(ts, truth, r.desired, task().featureNames(), options)) {
      if (r.outcome.failed()) kv.second = kNaN;
      r.values.push_back(std::move(kv));
    }
  }
  if (!impl_->config.occlusions.empty()) {
    std::vector<bool> lost;
    lost.reserve(r.trace.size());
    for (const auto& s : r.trace) lost.push_back(s.frame_lost);
    for (auto& kv : occlusionValues(ts, es, lost)) r.values.push_back(std::move(kv));
    std::vector<bool> expired;
    expired.reserve(r.trace.size());
    for (const auto& s : r.trace) expired.push_back(s.lost_expired);
    r.values.push_back(lostPolicyValue(expired, impl_->timing.basePeriod()));
  }
  for (const auto& kv : task().runSummary()) r.values.push_back(kv);
  return r;
}

ServoResult runServoLoop(const ServoConfig& config, Predictor& predictor) {
  ServoLoop loop(config, predictor);
  return loop.run();
}

}  // namespace predvs
