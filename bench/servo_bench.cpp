// Closed-loop throughput: the predvs loop with a predictor (kf-cv with its defaults, or as the
// scenario files pin it: q and r fixed, no blend with hold; ego-motion compensation and
// feed-forward) versus a bare vpServo + vpSimulatorCamera loop on the same scenario (default
// ServoConfig: 4 points, 80 ms latency, 0.5 px noise, circle target), to measure the predictor's
// overhead (target <= 10 %). Each iteration is one full run (25 s of simulated time, 626 ticks);
// the `steps_per_s` counter is the figure to compare.
#include "plain_kf_cv.h"
#include "predvs/predictors/predictor.h"
#include "predvs/servo/noise.h"
#include "predvs/servo/servo_loop.h"
#include "predvs/servo/timing_model.h"
#include "predvs/servo/trajectory.h"

#include <benchmark/benchmark.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/core/vpPoint.h>
#include <visp3/robot/vpSimulatorCamera.h>
#include <visp3/visual_features/vpFeaturePoint.h>
#include <visp3/vs/vpServo.h>

#include <deque>
#include <vector>

namespace {

using namespace predvs;

void runPredvs(benchmark::State& state, const char* predictor_name, const Params& params = {}) {
  const ServoConfig config;
  auto predictor = makePredictor(predictor_name, 8, params);
  long steps = 0;
  for (auto _ : state) {
    ServoLoop loop(config, *predictor);
    while (!loop.done()) {
      benchmark::DoNotOptimize(loop.step());
      ++steps;
    }
  }
  state.counters["steps_per_s"] = benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kIsRate);
}

void BM_ServoLoopKfCv(benchmark::State& state) { runPredvs(state, "kf-cv"); }
/// kf-cv as data/scenarios/ibvs-moving-target.yaml pins it (the figures of the scenario files).
void BM_ServoLoopKfCvPlain(benchmark::State& state) {
  runPredvs(state, "kf-cv", plainKfCvParams());
}
void BM_ServoLoopHold(benchmark::State& state) { runPredvs(state, "hold"); }

// What a plain ViSP user writes: project, add noise, delay by the vision latency, IBVS on the
// delayed features, saturate and integrate. Same scenario and timing model as ServoConfig{}.
void BM_BareViSPLoop(benchmark::State& state) {
  const ServoConfig c;
  const TimingModel timing(c.timing);
  const auto target = makeTrajectory(c.scene.trajectory, c.scene.trajectory_params);
  const double a = 0.5 * c.scene.square_side_m;
  const double oP[4][2] = {{-a, -a}, {a, -a}, {a, a}, {-a, a}};
  const long last_tick = timing.tickAtOrAfter(c.duration_s);
  long steps = 0;
  for (auto _ : state) {
    NoiseModel noise(c.noise, c.seed);
    vpSimulatorCamera robot;
    robot.setSamplingTime(timing.basePeriod());
    const vpHomogeneousMatrix cdMo(0, 0, c.scene.desired_depth_m, 0, 0, 0);
    const auto& p = c.initial_pose;
    const vpHomogeneousMatrix cdMc0(p(0), p(1), p(2), p(3), p(4), p(5));
    robot.setPosition((cdMc0.inverse() * cdMo).inverse());
    vpServo task;
    task.setServo(vpServo::EYEINHAND_CAMERA);
    task.setInteractionMatrixType(vpServo::CURRENT);
    task.setLambda(1.0);  // ibvs default lambda
    vpFeaturePoint s[4], sd[4];
    for (int i = 0; i < 4; ++i) {
      sd[i].buildFrom(oP[i][0] / c.scene.desired_depth_m, oP[i][1] / c.scene.desired_depth_m, c.scene.desired_depth_m);
      s[i] = sd[i];
      task.addFeature(s[i], sd[i]);
    }
    struct Frame {
      long release;
      double xyZ[4][3];
    };
    std::deque<Frame> pending;
    bool have = false;
    const Eigen::Vector2d p0 = target->position(0.0);
    for (long k = 0; k <= last_tick; ++k) {
      const double t = timing.tickTime(k);
      if (timing.isAcquisitionTick(k)) {
        const Eigen::Vector2d d = target->position(t) - p0;
        vpHomogeneousMatrix wMo;
        wMo[0][3] = d.x();
        wMo[1][3] = d.y();
        const vpHomogeneousMatrix cMo = robot.getPosition().inverse() * wMo;
        Frame f{timing.releaseTick(t), {}};
        for (int i = 0; i < 4; ++i) {
          vpPoint P(oP[i][0], oP[i][1], 0);
          P.track(cMo);
          f.xyZ[i][0] = P.get_x() + noise.sample() / c.camera.px;
          f.xyZ[i][1] = P.get_y() + noise.sample() / c.camera.py;
          f.xyZ[i][2] = P.get_Z();
        }
        pending.push_back(f);
      }
      while (!pending.empty() && pending.front().release <= k) {
        for (int i = 0; i < 4; ++i) s[i].buildFrom(pending.front().xyZ[i][0], pending.front().xyZ[i][1], pending.front().xyZ[i][2]);
        pending.pop_front();
        have = true;
      }
      vpColVector v(6, 0.0);
      if (have) v = task.computeControlLaw();
      robot.setVelocity(vpRobot::CAMERA_FRAME, v);
      benchmark::DoNotOptimize(v);
      ++steps;
    }
  }
  state.counters["steps_per_s"] = benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kIsRate);
}

BENCHMARK(BM_BareViSPLoop)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ServoLoopHold)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ServoLoopKfCv)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ServoLoopKfCvPlain)->Unit(benchmark::kMillisecond);

}  // namespace
