// Cost of paper 003's reference filtering (its Fig. 7b): the dual-rate EKF/smoother (Algorithm 3,
// N + h - 1 steps) against the single-rate one at the base period (Algorithm 4, h N steps) as a
// function of the prediction horizon h (frames), N = 8, delta = 10 ms, on the (x, y, Z) features of
// 4 points (state 12) at the start of the E10 task (a 300 mm square at 0.38 m, the camera rotated
// 150 deg about its optical axis), J = L(s) for the free-flying camera, Qc = I, Rc = I.
//
//  * BM_ReferenceSmoother/{dr,hf}/h: one pass of each algorithm (what paper Fig. 7b compares).
//  * BM_SmootherCostRatio/h: both passes in one benchmark, timed separately, with the ratio
//    dr / hf and the ratio times N as counters (paper: about 1/N, i.e. ratio_x_N about 1).
//  * BM_LawPerControlPeriod/{dr-ekfs-ibvs,sr-hf-ekfs-ibvs}/h: the whole law per control period, as
//    the loop calls it (a new frame every N periods): the dual-rate law runs its KF, Algorithm 3
//    and the N commands of Algorithm 5 once per frame, the single-rate law Algorithm 4 and one
//    command every period.
#include "predvs/predictors/ekf_smoother.h"
#include "predvs/tasks/reference_filtering_task.h"

#include <benchmark/benchmark.h>

#include <Eigen/Geometry>

#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace {

using namespace predvs;

constexpr double kDelta_s = 0.01;
constexpr int kN = 8;
constexpr double kSide_m = 0.3, kDepth_m = 0.38, kAngle_rad = 150.0 * M_PI / 180.0;

/// Pixels and depths of the square seen from a camera rotated by `angle` about its optical axis.
PointFeatures squareView(const CameraIntrinsics& cam, double angle) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(-angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const double a = kSide_m / 2;
  const Eigen::Vector3d corners[] = {{-a, -a, kDepth_m}, {a, -a, kDepth_m}, {a, a, kDepth_m}, {-a, a, kDepth_m}};
  PointFeatures f;
  f.uv_px.resize(8);
  f.Z_m.resize(4);
  f.seen.assign(4, true);
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d p = R * corners[i];
    f.uv_px(2 * i) = cam.u0 + cam.px * p.x() / p.z();
    f.uv_px(2 * i + 1) = cam.v0 + cam.py * p.y() / p.z();
    f.Z_m(i) = p.z();
  }
  return f;
}

TaskContext e10Context() {
  TaskContext c;
  c.desired_points = squareView(c.camera, 0.0);
  c.command_space = {"camera-twist", {"vx", "vy", "vz", "wx", "wy", "wz"}};
  c.base_period_s = kDelta_s;
  c.frame_period_s = kN * kDelta_s;
  c.nominal_delay_frames = 1.0;
  return c;
}

/// The smoother's inputs at the start of E10.
struct SmootherCase {
  Eigen::Matrix<double, 12, 1> s, s_star, rc;
  Eigen::Matrix<double, 12, 12> JQcJt;
  SmootherCase() {
    const TaskContext ctx = e10Context();
    const ReferenceFilteringTask task(ReferenceFilteringLaw::SrHfEkfsIbvs, Params{}, ctx);
    const PointFeatures start = squareView(ctx.camera, kAngle_rad);
    s = task.toXyz(start.uv_px, start.Z_m);
    s_star = task.desiredXyz();
    const Eigen::MatrixXd J = ReferenceFilteringTask::interactionMatrix(s);
    JQcJt = J * J.transpose();
    rc.setOnes();
  }
};

void BM_ReferenceSmoother(benchmark::State& state, bool dual) {
  const int h = static_cast<int>(state.range(0));
  const SmootherCase c;
  ReferenceSmoother<12> smoother;
  for (auto _ : state) {
    if (dual)
      smoother.runDualRate(c.s, c.s_star, c.JQcJt, c.rc, kDelta_s, kN, h);
    else
      smoother.runSingleRate(c.s, c.s_star, c.JQcJt, c.rc, kDelta_s, h * kN);
    benchmark::DoNotOptimize(smoother.reference(1).data());
  }
  state.counters["steps"] = smoother.steps();
  state.SetLabel(dual ? "Algorithm 3 (DR-EKFS)" : "Algorithm 4 at delta (HF-EKFS)");
}

void BM_SmootherCostRatio(benchmark::State& state) {
  const int h = static_cast<int>(state.range(0));
  const SmootherCase c;
  ReferenceSmoother<12> dr, hf;
  double dr_s = 0.0, hf_s = 0.0;
  using Clock = std::chrono::steady_clock;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    dr.runDualRate(c.s, c.s_star, c.JQcJt, c.rc, kDelta_s, kN, h);
    benchmark::DoNotOptimize(dr.reference(1).data());
    const auto t1 = Clock::now();
    hf.runSingleRate(c.s, c.s_star, c.JQcJt, c.rc, kDelta_s, h * kN);
    benchmark::DoNotOptimize(hf.reference(1).data());
    const auto t2 = Clock::now();
    dr_s += std::chrono::duration<double>(t1 - t0).count();
    hf_s += std::chrono::duration<double>(t2 - t1).count();
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["dr_us"] = 1e6 * dr_s / n;
  state.counters["hf_us"] = 1e6 * hf_s / n;
  state.counters["ratio"] = dr_s / hf_s;
  state.counters["ratio_x_N"] = kN * dr_s / hf_s;
  state.counters["step_ratio"] = static_cast<double>(kN + h - 1) / (h * kN);
}

void BM_LawPerControlPeriod(benchmark::State& state, const std::string& law) {
  const int h = static_cast<int>(state.range(0));
  const TaskContext ctx = e10Context();
  Params p{{"lambda", 1.4}, {"horizon", static_cast<double>(h)}};
  auto task = makeTask(law, p, ctx);
  const PointFeatures f = squareView(ctx.camera, kAngle_rad);
  const Eigen::MatrixXd Jc = Eigen::MatrixXd::Identity(6, 6);
  const Eigen::VectorXd q = Eigen::VectorXd::Zero(6), no_rate;
  const Eigen::MatrixXd no_truth;
  long k = 0;
  for (auto _ : state) {
    // A frame acquired every N periods, delivered one frame later (E10's latency).
    const double t = (k + kN) * kDelta_s, t_acq = (k / kN) * kN * kDelta_s;
    const TaskInput in{t, t_acq, f.uv_px, f.uv_px, no_rate, f.Z_m, Jc, q, no_truth};
    benchmark::DoNotOptimize(task->computeCommand(in).data());
    ++k;
  }
  state.SetLabel(law + ", per control period (delta = 10 ms, N = 8)");
}

const bool kRegistered = [] {
  for (const int h : {1, 2, 4, 8, 16, 32, 64}) {
    benchmark::RegisterBenchmark("BM_ReferenceSmoother/dr", BM_ReferenceSmoother, true)->Arg(h);
    benchmark::RegisterBenchmark("BM_ReferenceSmoother/hf", BM_ReferenceSmoother, false)->Arg(h);
    benchmark::RegisterBenchmark("BM_SmootherCostRatio", BM_SmootherCostRatio)->Arg(h);
  }
  for (const int h : {2, 8, 32}) {
    benchmark::RegisterBenchmark("BM_LawPerControlPeriod/dr-ekfs-ibvs", BM_LawPerControlPeriod,
                                 std::string("dr-ekfs-ibvs"))
        ->Arg(h);
    benchmark::RegisterBenchmark("BM_LawPerControlPeriod/sr-hf-ekfs-ibvs", BM_LawPerControlPeriod,
                                 std::string("sr-hf-ekfs-ibvs"))
        ->Arg(h);
  }
  return true;
}();

}  // namespace
