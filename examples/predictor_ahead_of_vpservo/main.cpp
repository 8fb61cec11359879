// A predvs predictor ahead of a plain ViSP vpServo IBVS loop: 4 points on a target moving on a
// 5 cm circle, seen with a 2-frame (80 ms) vision delay. The predictor fuses the delayed image
// points (pixels) and predicts them at the current time; the task servoes on the prediction,
// with the feed-forward of the target's own image motion: v = -lambda L^+ e - L^+ (s_dot - L v_seen),
// s_dot the predicted feature velocity, v_seen the camera twist when the newest frame was taken (a P-law alone lags the moving
// target by (image speed) / lambda, whatever the delay).
// Prints the steady-state RMS image error (pixels) without and with the predictor.
// Usage: predictor_ahead_of_vpservo [NAME [KEY=VALUE ...]]   (default kf-cv; KEY=VALUE: the
// predictor's parameters, e.g. `kf-ca q=1000 r=1`, a word for a word key, e.g. `stkf model=cv`; docs/MODELS.md gives each predictor's keys)
#include <predvs/predictors/predictor.h>

#include <visp3/core/vpMeterPixelConversion.h>
#include <visp3/core/vpPixelMeterConversion.h>
#include <visp3/robot/vpSimulatorCamera.h>
#include <visp3/visual_features/vpFeatureBuilder.h>
#include <visp3/vs/vpServo.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

static double runLoop(const std::string& predictor_name, const predvs::Params& params = {}) {  // "" = none
  const double dt_s = 0.04, duration_s = 25.0, radius_m = 0.05, omega_radps = 0.5;
  const int delay_frames = 2;
  const vpCameraParameters cam(800, 800, 320, 240);
  std::vector<vpPoint> points = {{-0.05, -0.05, 0}, {0.05, -0.05, 0}, {0.05, 0.05, 0}, {-0.05, 0.05, 0}};
  auto wMo = [&](double t) { return vpHomogeneousMatrix(radius_m * (std::cos(omega_radps * t) - 1), radius_m * std::sin(omega_radps * t), 0, 0, 0, 0); };
  vpSimulatorCamera robot;
  robot.setSamplingTime(dt_s);
  robot.setPosition(wMo(0) * vpHomogeneousMatrix(0.03, -0.02, 0.4, 0, 0, 0.2).inverse());
  vpServo task;
  task.setServo(vpServo::EYEINHAND_CAMERA);
  task.setInteractionMatrixType(vpServo::CURRENT);
  task.setLambda(1.0);
  std::vector<vpFeaturePoint> p(4), pd(4);
  for (int i = 0; i < 4; ++i) {
    points[i].track(vpHomogeneousMatrix(0, 0, 0.5, 0, 0, 0));
    vpFeatureBuilder::create(pd[i], points[i]);
    task.addFeature(p[i], pd[i]);
  }
  std::unique_ptr<predvs::Predictor> predictor;
  if (!predictor_name.empty()) predictor = predvs::makePredictor(predictor_name, 8, params);
  std::vector<Eigen::VectorXd> measured_px;  // image points at every frame (u0 v0 ... u3 v3)
  std::vector<vpColVector> twists;  // camera twist sent at every step (m/s, rad/s)
  double sum_sq = 0;
  int n = 0;
  for (int k = 0; k * dt_s < duration_s; ++k) {
    const double t_s = k * dt_s;
    const vpHomogeneousMatrix cMo = robot.getPosition().inverse() * wMo(t_s);
    Eigen::VectorXd z(8);
    for (int i = 0; i < 4; ++i) {
      points[i].track(cMo);
      vpMeterPixelConversion::convertPoint(cam, points[i].get_x(), points[i].get_y(), z(2 * i), z(2 * i + 1));
    }
    measured_px.push_back(z);
    const int k_seen = std::max(0, k - delay_frames);  // the newest frame the vision has delivered
    Eigen::VectorXd used = measured_px[k_seen];
    if (predictor) {
      if (k == 0 || k_seen > 0) predictor->update(k_seen * dt_s, measured_px[k_seen]);
      used = predictor->predictPositions(t_s);
    }
    for (int i = 0; i < 4; ++i) {
      double x, y;
      vpPixelMeterConversion::convertPoint(cam, used(2 * i), used(2 * i + 1), x, y);
      points[i].track(cMo);
      p[i].buildFrom(x, y, points[i].get_Z());
    }
    vpColVector v = task.computeControlLaw();
    if (predictor && predictor->extrapolates() && k > delay_frames + 1) {  // hold has no velocity
      const Eigen::VectorXd vel_pxps = predictor->predictVelocities(t_s);
      vpColVector sdot(8);
      for (int j = 0; j < 8; ++j) sdot[j] = vel_pxps(j) / (j % 2 == 0 ? cam.get_px() : cam.get_py());
      v -= task.getTaskJacobianPseudoInverse() * (sdot - task.getInteractionMatrix() * twists[k - delay_frames - 1]);
    }
    robot.setVelocity(vpRobot::CAMERA_FRAME, v);
    twists.push_back(v);
    if (t_s >= duration_s - 10.0) {  // steady state: true current points vs desired, in pixels
      for (int i = 0; i < 4; ++i) {
        double ud, vd;
        vpMeterPixelConversion::convertPoint(cam, pd[i].get_x(), pd[i].get_y(), ud, vd);
        sum_sq += std::pow(z(2 * i) - ud, 2) + std::pow(z(2 * i + 1) - vd, 2);
      }
      ++n;
    }
  }
  return std::sqrt(sum_sq / n);
}

int main(int argc, char** argv) {
  const std::string name = argc > 1 ? argv[1] : "kf-cv";
  predvs::Params params;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    const size_t eq = arg.find('=');
    double value = 0.0;
    const predvs::ParamText kind =
        eq == std::string::npos ? predvs::ParamText::Invalid : predvs::classifyParamText(arg.substr(eq + 1), &value);
    if (eq == 0 || kind == predvs::ParamText::Invalid) {
      std::fprintf(stderr, "predictor_ahead_of_vpservo: '%s': expected KEY=VALUE (a number or a word)\n", arg.c_str());
      return 2;
    }
    if (kind == predvs::ParamText::Number)
      params.set(arg.substr(0, eq), value);
    else
      params.setText(arg.substr(0, eq), arg.substr(eq + 1));  // a word (model=cv): the predictor checks it
  }
  try {
    predvs::makePredictor(name, 8, params);  // an unknown name or parameter is refused before any run
    std::printf("steady-state RMS image error without predictor: %.3f px\n", runLoop(""));
    std::printf("steady-state RMS image error with %s: %.3f px\n", name.c_str(), runLoop(name, params));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "predictor_ahead_of_vpservo: %s\n", e.what());
    return 1;
  }
  return 0;
}
