#include "predvs/servo/servo_loop.h"

#include "predvs/predictors/named_enum.h"

#include "predvs/servo/trajectory.h"

#include <visp3/core/vpColVector.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/robot/vpRobot.h>
#include <visp3/robot/vpSimulatorCamera.h>

#include <cmath>
#include <deque>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kPoints = 4;
// Relative margin of the simulator's velocity limits over ours (see the constructor).
constexpr double kSimulatorLimitMargin = 1e-6;

void requirePositive(const char* key, double v) {
  if (!(v > 0.0) || !std::isfinite(v)) {
    std::ostringstream msg;
    msg << key << " must be > 0, got " << v;
    throw std::invalid_argument(msg.str());
  }
}

struct Measurement {
  double t_acq_s;
  long release_tick;
  FeatureVector z_px;                  // noisy pixel features
  Eigen::Matrix<double, kPoints, 1> Z;  // depths at acquisition (assumed known)
  FeatureVector ego_px;                // E(t_acq): camera-induced image displacement so far
};

struct Command {
  long apply_tick;
  CameraTwist v;          // saturated twist
  FeatureVector dego_px;  // L_px v delta: image displacement it causes over one tick
};

}  // namespace

constexpr EnumName<ForecastMode> kForecastModes[] = {
    {ForecastMode::Feature, "feature"}, {ForecastMode::Feedforward, "feedforward"}, {ForecastMode::Both, "both"}};
constexpr EnumName<Compensation> kCompensations[] = {
    {Compensation::Auto, "auto"}, {Compensation::On, "on"}, {Compensation::Off, "off"}};

ForecastMode parseForecastMode(const std::string& name) { return enumFromName(kForecastModes, "servo.forecast", name); }
std::string forecastModeName(ForecastMode mode) { return enumToName(kForecastModes, mode); }
Compensation parseCompensation(const std::string& name) {
  return enumFromName(kCompensations, "servo.compensation", name);
}
std::string compensationName(Compensation c) { return enumToName(kCompensations, c); }

struct ServoLoop::Impl {
  Impl(const ServoConfig& c, Predictor& p)
      : config(c),
        timing(c.timing),
        noise(c.noise, c.seed),
        target(makeTrajectory(c.target_trajectory, c.target_params)),
        predictor(p) {}

  ServoConfig config;
  TimingModel timing;
  NoiseModel noise;
  std::unique_ptr<Trajectory> target;
  Predictor& predictor;
  std::unique_ptr<IbvsTask> task;
  vpSimulatorCamera robot;
  vpColVector v_max = vpColVector(6);
  bool compensate = false;

  Eigen::Matrix<double, 3, kPoints> oP;  // points in the target frame
  Eigen::Vector2d target_p0;             // trajectory position at t = 0
  FeatureVector desired_px;

  long k = 0;
  long last_tick = 0;
  std::deque<Measurement> pending;
  std::deque<Command> commands;
  bool have_measurement = false;
  Measurement latest{};
  FeatureVector ego_px = FeatureVector::Zero();
  Command active{0, CameraTwist::Zero(), FeatureVector::Zero()};
  ServoSample sample;
  std::vector<ServoSample> trace;

  // True pixel features and depths at time t with the current camera pose.
  void project(double t, FeatureVector& s_px, Eigen::Matrix<double, kPoints, 1>& Z) const {
    const Eigen::Vector2d d = target->position(t) - target_p0;
    vpHomogeneousMatrix wMo;
    wMo[0][3] = d.x();
    wMo[1][3] = d.y();
    const vpHomogeneousMatrix cMo = robot.getPosition().inverse() * wMo;
    for (int i = 0; i < kPoints; ++i) {
      double c[3];
      for (int r = 0; r < 3; ++r)
        c[r] = cMo[r][0] * oP(0, i) + cMo[r][1] * oP(1, i) + cMo[r][2] * oP(2, i) + cMo[r][3];
      Z(i) = c[2];
      s_px(2 * i) = config.camera.u0 + config.camera.px * c[0] / c[2];
      s_px(2 * i + 1) = config.camera.v0 + config.camera.py * c[1] / c[2];
    }
  }

  Eigen::VectorXd toNormalized(const FeatureVector& s_px) const {
    Eigen::VectorXd xy(2 * kPoints);
    for (int i = 0; i < kPoints; ++i) {
      xy(2 * i) = (s_px(2 * i) - config.camera.u0) / config.camera.px;
      xy(2 * i + 1) = (s_px(2 * i + 1) - config.camera.v0) / config.camera.py;
    }
    return xy;
  }

  // L_px v delta at features s_px with depths Z: the image displacement (px) one tick of v causes.
  FeatureVector egoIncrement(const FeatureVector& s_px, const Eigen::Matrix<double, kPoints, 1>& Z,
                             const CameraTwist& v) const {
    const Eigen::VectorXd xy = toNormalized(s_px);
    FeatureVector d;
    for (int i = 0; i < kPoints; ++i) {
      const Eigen::Vector2d dxy = IbvsTask::pointInteraction(xy(2 * i), xy(2 * i + 1), Z(i)) * v;
      d(2 * i) = config.camera.px * dxy.x() * timing.basePeriod();
      d(2 * i + 1) = config.camera.py * dxy.y() * timing.basePeriod();
    }
    return d;
  }

  double trackingError(const FeatureVector& s_px) const {
    double sum = 0.0;
    for (int i = 0; i < kPoints; ++i) sum += (s_px.segment<2>(2 * i) - desired_px.segment<2>(2 * i)).squaredNorm();
    return std::sqrt(sum / kPoints);
  }

  const ServoSample& step() {
    const double t = timing.tickTime(k);
    FeatureVector s_true;
    Eigen::Matrix<double, kPoints, 1> Z_true;
    project(t, s_true, Z_true);

    // Acquisition, then delivery of every frame whose release tick has come.
    if (timing.isAcquisitionTick(k)) {
      Measurement m{t, timing.releaseTick(t), s_true, Z_true, ego_px};
      for (int i = 0; i < 8; ++i) m.z_px(i) = noise.apply(m.z_px(i));
      pending.push_back(m);
    }
    while (!pending.empty() && pending.front().release_tick <= k) {
      const Measurement& m = pending.front();
      const FeatureVector z = compensate ? FeatureVector(m.z_px - m.ego_px) : m.z_px;
      predictor.update(m.t_acq_s, z);
      latest = m;
      have_measurement = true;
      pending.pop_front();
    }

    sample.t_s = t;
    sample.true_px = s_true;
    sample.error_px = trackingError(s_true);
    sample.t_acq_s = have_measurement ? latest.t_acq_s : kNaN;
    sample.measured_px = have_measurement ? latest.z_px : FeatureVector::Constant(kNaN);
    sample.predicted_px = FeatureVector::Constant(kNaN);

    // Control at t_c = t (no command before the first image: the camera waits).
    if (have_measurement) {
      const double t_eff = timing.effectTime(t);
      FeatureVector s_used = latest.z_px;
      Eigen::VectorXd feedforward;
      if (!compensate) {
        s_used = predictor.predictPositions(t_eff);
      } else {
        // E(t_eff): the displacement so far plus that of the queued commands acting before t_eff.
        FeatureVector ego_eff = ego_px;
        const long eff_tick = timing.tickAtOrAfter(t_eff);
        for (const Command& c : commands)
          if (c.apply_tick < eff_tick) ego_eff += c.dego_px;
        const FeatureVector s_hat = FeatureVector(predictor.predictPositions(t_eff)) + ego_eff;
        if (config.forecast != ForecastMode::Feedforward) s_used = s_hat;
        if (config.forecast != ForecastMode::Feature) {
          const FeatureVector rate_px = predictor.predictVelocities(t_eff);
          feedforward.resize(2 * kPoints);
          for (int i = 0; i < kPoints; ++i) {
            feedforward(2 * i) = rate_px(2 * i) / config.camera.px;
            feedforward(2 * i + 1) = rate_px(2 * i + 1) / config.camera.py;
          }
        }
      }
      sample.predicted_px = s_used;
      const CameraTwist v = task->computeVelocity(toNormalized(s_used), latest.Z, feedforward);
      vpColVector v_vp(6);
      for (int i = 0; i < 6; ++i) v_vp[i] = v(i);
      const vpColVector v_sat_vp = vpRobot::saturateVelocities(v_vp, v_max);
      Command c{timing.commandApplyTick(k), CameraTwist::Zero(), FeatureVector::Zero()};
      for (int i = 0; i < 6; ++i) c.v(i) = v_sat_vp[i];
      if (compensate) c.dego_px = egoIncrement(s_used, latest.Z, c.v);
      commands.push_back(c);
    }

    // The command acting over [t, t + delta): the latest whose apply tick has come.
    while (!commands.empty() && commands.front().apply_tick <= k) {
      active = commands.front();
      commands.pop_front();
    }
    vpColVector v_apply(6);
    for (int i = 0; i < 6; ++i) v_apply[i] = active.v(i);
    robot.setVelocity(vpRobot::CAMERA_FRAME, v_apply);
    ego_px += active.dego_px;
    sample.velocity = active.v;
    ++k;
    return sample;
  }
};

ServoLoop::ServoLoop(const ServoConfig& config, Predictor& predictor) {
  requirePositive("duration_s", config.duration_s);
  requirePositive("camera.px", config.camera.px);
  requirePositive("camera.py", config.camera.py);
  requirePositive("target.square_side_m", config.square_side_m);
  requirePositive("target.desired_depth_m", config.desired_depth_m);
  requirePositive("robot.max_translation_mps", config.max_translation_mps);
  requirePositive("robot.max_rotation_radps", config.max_rotation_radps);
  if (!config.initial_pose.allFinite()) throw std::invalid_argument("initial_pose must be finite");
  if (predictor.channels() != 2 * kPoints)
    throw std::invalid_argument("servo loop: predictor '" + predictor.name() + "' has " +
                                std::to_string(predictor.channels()) + " channels, expected 8 (u, v of 4 points)");
  impl_ = std::make_unique<Impl>(config, predictor);
  Impl& m = *impl_;
  m.compensate = config.compensation == Compensation::On ||
                 (config.compensation == Compensation::Auto && predictor.name() != "hold");
  predictor.reset();

  const double a = 0.5 * config.square_side_m;
  m.oP << -a, a, a, -a,  //
      -a, -a, a, a,      //
      0, 0, 0, 0;
  m.target_p0 = m.target->position(0.0);

  // Desired pose: target plane parallel to the image at desired_depth_m, square centred.
  const vpHomogeneousMatrix cdMo(0, 0, config.desired_depth_m, 0, 0, 0);
  Eigen::VectorXd desired_xy(2 * kPoints), desired_Z(kPoints);
  for (int i = 0; i < kPoints; ++i) {
    const double Z = config.desired_depth_m;
    desired_xy(2 * i) = m.oP(0, i) / Z;
    desired_xy(2 * i + 1) = m.oP(1, i) / Z;
    desired_Z(i) = Z;
    m.desired_px(2 * i) = config.camera.u0 + config.camera.px * desired_xy(2 * i);
    m.desired_px(2 * i + 1) = config.camera.v0 + config.camera.py * desired_xy(2 * i + 1);
  }
  m.task = std::make_unique<IbvsTask>(config.task, desired_xy, desired_Z);

  // World frame = target frame at t = 0; the camera starts at initial_pose in the desired frame.
  const Eigen::Matrix<double, 6, 1>& p = config.initial_pose;
  const vpHomogeneousMatrix cdMc0(p(0), p(1), p(2), p(3), p(4), p(5));
  const vpHomogeneousMatrix c0Mo = cdMc0.inverse() * cdMo;
  if (c0Mo[2][3] <= 0.0) throw std::invalid_argument("initial_pose puts the camera behind the target");
  m.robot.setSamplingTime(m.timing.basePeriod());
  // The command is saturated before it is queued; the simulator's own limits sit a hair above
  // so that it neither rescales the twist again nor reports the (rounding-level) excess.
  m.robot.setMaxTranslationVelocity(config.max_translation_mps * (1.0 + kSimulatorLimitMargin));
  m.robot.setMaxRotationVelocity(config.max_rotation_radps * (1.0 + kSimulatorLimitMargin));
  m.robot.setPosition(c0Mo.inverse());
  for (int i = 0; i < 3; ++i) m.v_max[i] = config.max_translation_mps;
  for (int i = 3; i < 6; ++i) m.v_max[i] = config.max_rotation_radps;
  m.last_tick = m.timing.tickAtOrAfter(config.duration_s);
}

ServoLoop::~ServoLoop() = default;

bool ServoLoop::done() const { return impl_->k > impl_->last_tick; }
const ServoSample& ServoLoop::step() { return impl_->step(); }
bool ServoLoop::predictionUsed() const { return impl_->compensate; }
const FeatureVector& ServoLoop::desiredFeatures() const { return impl_->desired_px; }

ServoResult ServoLoop::run() {
  ServoResult r;
  r.predictor = impl_->predictor.name();
  r.prediction_used = impl_->compensate;
  r.desired_px = impl_->desired_px;
  r.trace.reserve(static_cast<size_t>(impl_->last_tick + 1));
  while (!done()) r.trace.push_back(step());
  std::vector<double> ts, es;
  std::vector<Eigen::Matrix<double, 6, 1>> vs;
  for (const auto& s : r.trace) {
    ts.push_back(s.t_s);
    es.push_back(s.error_px);
    vs.push_back(s.velocity);
  }
  r.metrics = computeMetrics(ts, es, impl_->config.metrics, &vs);
  return r;
}

ServoResult runServoLoop(const ServoConfig& config, Predictor& predictor) {
  ServoLoop loop(config, predictor);
  return loop.run();
}

const std::vector<std::string>& servoTraceColumns() {
  static const std::vector<std::string> cols = [] {
    std::vector<std::string> c = {"t_s", "t_acq_s"};
    for (const char* prefix : {"meas_", "pred_", "true_"})
      for (int i = 0; i < kPoints; ++i) {
        c.push_back(std::string(prefix) + "u" + std::to_string(i));
        c.push_back(std::string(prefix) + "v" + std::to_string(i));
      }
    for (const char* n : {"error_px", "vx", "vy", "vz", "wx", "wy", "wz"}) c.push_back(n);
    return c;
  }();
  return cols;
}

std::vector<double> servoTraceRow(const ServoSample& s) {
  std::vector<double> r = {s.t_s, s.t_acq_s};
  for (const FeatureVector* f : {&s.measured_px, &s.predicted_px, &s.true_px})
    for (int i = 0; i < 8; ++i) r.push_back((*f)(i));
  r.push_back(s.error_px);
  for (int i = 0; i < 6; ++i) r.push_back(s.velocity(i));
  return r;
}

}  // namespace predvs
