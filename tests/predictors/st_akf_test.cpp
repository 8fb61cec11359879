#include "predvs/predictors/kalman_baselines.h"
#include "predvs/predictors/monitor.h"
#include "predvs/predictors/st_akf.h"

#include "predictors/model_switch_scenario.h"
#include "predictors/paper_trajectories.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <random>
#include <stdexcept>

namespace predvs {
namespace {

Eigen::VectorXd vec1(double v) { return Eigen::VectorXd::Constant(1, v); }

/// The manoeuvre that makes a filter fade: 2 s at rest (50 frames, 25 Hz, z = 0), then a 100 px jump.
void jumpAfterRest(Predictor& f) {
  for (int n = 0; n < 50; ++n) f.update(0.04 * n, vec1(0.0));
  f.update(50 * 0.04, vec1(100.0));
}

TEST(StAkf, NoFadingOnAModelMatchedSignalFadingAfterAManoeuvre) {
  // GIVEN a noise-free constant-acceleration signal, exactly the filter's model
  const double T = 0.04;
  StAkfPredictor<3> f(1, {{"q", 1.0}, {"r", 1.0}});
  int n = 0;
  double max_lambda_smooth = 0.0;
  for (; n < 200; ++n) {
    const double t = n * T;
    f.update(t, vec1(5.0 + 30.0 * t + 0.5 * 8.0 * t * t));
    // THEN once the start-up transient is over, every fading factor is exactly 1
    if (n >= 10) max_lambda_smooth = std::max(max_lambda_smooth, f.fadingFactors(0).maxCoeff());
  }
  EXPECT_EQ(max_lambda_smooth, 1.0);
  // WHEN the target jumps by 50 units (a manoeuvre the model does not predict)
  const double t = n * T;
  f.update(t, vec1(5.0 + 30.0 * t + 0.5 * 8.0 * t * t + 50.0));
  // THEN the fading factor rises well above 1 (tr N / tr M grows with the innovation squared)
  const double lambda_jump = f.fadingFactors(0)(0);
  std::printf("[ st-akf ] lambda after a 50-unit jump: %.1f\n", lambda_jump);
  EXPECT_GT(lambda_jump, 10.0);
}

TEST(StAkf, TheFirstMeasurementAfterAGapDoesNotFadeWhileCoasting) {
  // GIVEN a target moving at 300 px/s, 60 Hz, 2 px of noise (r fixed: the fading is on from the
  // start), then 10 frames without a measurement: the coasted velocity decays (coast_tau_s 0.2 s),
  // the target does not, so the first measurement after the gap is far from the coasted forecast
  const double T = 1.0 / 60.0;
  const auto run = [&](const Params& params, double* lambda_after, double* lambda_next) {
    StAkfPredictor<3> f(1, params);
    std::mt19937 rng(3);
    std::normal_distribution<double> noise(0.0, 2.0);
    int k = 0;
    for (; k < 120; ++k) f.update(k * T, vec1(300.0 * k * T + noise(rng)));
    for (int g = 0; g < 10; ++g, ++k) f.update(k * T, vec1(std::nan("")));
    f.update(k * T, vec1(300.0 * k * T + noise(rng)));
    *lambda_after = f.fadingFactors(0).maxCoeff();
    ++k;
    f.update(k * T, vec1(300.0 * k * T + noise(rng)));
    *lambda_next = f.fadingFactors(0).maxCoeff();
  };
  double def_after = 0.0, def_next = 0.0, old_after = 0.0, old_next = 0.0;
  double plain_after = 0.0, plain_next = 0.0, plain_old_after = 0.0, plain_old_next = 0.0;
  // WHEN st-akf runs with its defaults, with adapt_after_gap: 1 (before), and without coasting
  run(Params{{"r", 4.0}}, &def_after, &def_next);
  run(Params{{"r", 4.0}, {"adapt_after_gap", 1.0}}, &old_after, &old_next);
  run(Params{{"r", 4.0}, {"coast_tau_s", 0.0}}, &plain_after, &plain_next);
  run(Params{{"r", 4.0}, {"coast_tau_s", 0.0}, {"adapt_after_gap", 1.0}}, &plain_old_after, &plain_old_next);
  std::printf("[ st-akf ] lambda at / after the first measurement after a gap: default %.2f / %.2f, "
              "adapt_after_gap 1: %.2f / %.2f\n", def_after, def_next, old_after, old_next);
  // THEN with the defaults that measurement does not fade P, nor does the one after it (its
  // innovation never entered V0); with adapt_after_gap: 1 the coast's own error faded both
  EXPECT_EQ(def_after, 1.0);
  EXPECT_EQ(def_next, 1.0);
  EXPECT_GT(old_after, 2.0);
  EXPECT_GT(old_next, 1.0);
  // AND without coasting every measured frame fades as in the paper: the key changes nothing
  EXPECT_EQ(plain_after, plain_old_after);
  EXPECT_EQ(plain_next, plain_old_next);
}

TEST(StAkf, MultipleFactorsFollowThePresetRatios) {
  // GIVEN preset ratios a = (1, 2, 4) and a manoeuvre that makes the filter fade
  // (r given: with `r: auto` there is no fading until the estimate is frozen, after 53 frames)
  StAkfPredictor<3> f(1, {{"q", 1.0}, {"r", 1.0}, {"a1", 1.0}, {"a2", 2.0}, {"a3", 4.0}});
  jumpAfterRest(f);
  // THEN lambda_i = a_i c once a_1 c > 1
  const Vec<3> l = f.fadingFactors(0);
  ASSERT_GT(l(0), 1.0);
  EXPECT_NEAR(l(1), 2.0 * l(0), 1e-9 * l(1));
  EXPECT_NEAR(l(2), 4.0 * l(0), 1e-9 * l(2));
  // AND the covariance stays symmetric (Joseph form, symmetric fading)
  const Mat<3>& P = f.gaussian(0).P;
  EXPECT_LT((P - P.transpose()).cwiseAbs().maxCoeff(), 1e-12 * P.cwiseAbs().maxCoeff());
}

TEST(StAkf, SteadyStateCaIsTheLimitOfTheCaKalmanFilter) {
  // GIVEN the steady-state CA filter and an ordinary kf-ca with the same q, r, dt
  const double q = 10.0, r = 1e-6, dt = 0.04;
  const SteadyStateCa ss = steadyStateCa(q, r, dt);
  KfCaPredictor kf(1, {{"q", q}, {"r", r}, {"p0_vel", 100.0}, {"p0_acc", 1e3}});
  std::mt19937 rng(2);
  std::normal_distribution<double> noise(0.0, 1e-3);
  for (int n = 0; n < 2000; ++n) kf.update(n * dt, vec1(noise(rng)));
  // THEN the kf-ca covariance converges to the steady-state P_post (relative, Riccati converged)
  const Mat<3>& P = kf.gaussian(0).P;
  EXPECT_LT((P - ss.P_post).cwiseAbs().maxCoeff(), 1e-6 * ss.P_post.cwiseAbs().maxCoeff());
  // AND the gain is the one that P implies: K = P_pred H' / (H P_pred H' + r)
  const Mat<3> F = caTransition(dt);
  const Mat<3> Pp = F * ss.P_post * F.transpose() + caProcessNoise(q, dt);
  const Vec<3> K = Pp.col(0) / (Pp(0, 0) + r);
  EXPECT_LT((K - ss.K).cwiseAbs().maxCoeff(), 1e-9 * K.cwiseAbs().maxCoeff());
}

TEST(DiscontinuityMonitor, BandNeedsAFullWindowThenFiresOnAnOutlier) {
  // GIVEN a band monitor, n = 5, lambda_b = 4, fed alternating +-1 errors (sigma_n = 1)
  MonitorConfig cfg;
  cfg.window = 5;
  cfg.band_factor = 4.0;
  DiscontinuityMonitor m(cfg);
  for (int k = 0; k < 5; ++k) EXPECT_FALSE(m.observe(k, k % 2 ? 1.0 : -1.0));  // warming up
  EXPECT_FALSE(m.observe(5, 1.0));
  // WHEN an error of 10 arrives (centre near 0, band half-width 4 * 1)
  EXPECT_TRUE(m.observe(6, 10.0));
  // THEN it is counted with its time, and restart() keeps the counters
  EXPECT_EQ(m.alarms(), 1);
  EXPECT_EQ(m.lastAlarmTime(), 6.0);
  m.restart();
  EXPECT_FALSE(m.observe(7, 100.0));
  EXPECT_EQ(m.alarms(), 1);
  m.reset();
  EXPECT_EQ(m.alarms(), 0);
}

TEST(DiscontinuityMonitor, ChiSquareComparesNormalisedInnovation) {
  MonitorConfig cfg;
  cfg.statistic = MonitorConfig::Statistic::kChiSquare;
  cfg.chi2_threshold = 9.0;
  cfg.warmup = 0;
  DiscontinuityMonitor m(cfg);
  EXPECT_FALSE(m.observe(0.0, 2.9, 1.0));  // 8.41 < 9
  EXPECT_TRUE(m.observe(0.1, 6.1, 4.0));   // 9.30 >= 9
  EXPECT_EQ(m.alarms(), 1);
}

TEST(StrongTrackingAndSelfTuning, RegisteredResetReproducesARunAndBadParamsAreNamed) {
  for (const char* name : {"stkf", "st-akf", "st-akf-pm"}) {
    // GIVEN a registered predictor run on a noisy ramp with a step and a gap
    auto f = makePredictor(name, 2, {});
    auto run = [&f] {
      std::mt19937 rng(9);
      std::normal_distribution<double> noise(0.0, 2.0);
      Eigen::VectorXd out(2);
      for (int n = 0; n < 120; ++n) {
        Eigen::VectorXd z(2);
        z << 10.0 * n * 0.04 + (n > 60 ? 50.0 : 0.0) + noise(rng), n % 7 == 0 ? std::nan("") : noise(rng);
        f->update(n * 0.04, z);
      }
      out << f->predict(0, 5.0).position(), f->predict(1, 5.0).position();
      return out;
    };
    const Eigen::VectorXd first = run();
    // WHEN it is reset and run again on the same data
    f->reset();
    const Eigen::VectorXd second = run();
    // THEN the result is bit-identical (no adaptive state survives reset())
    EXPECT_EQ(first, second) << name;
    EXPECT_TRUE(first.allFinite()) << name;
    // AND a misspelt parameter is reported by name
    EXPECT_THROW(makePredictor(name, 1, {{"windw", 3.0}}), std::invalid_argument) << name;
  }
  EXPECT_THROW(makePredictor("st-akf-pm", 1, {{"pm_window", 2.5}}), std::invalid_argument);
  EXPECT_THROW(makePredictor("stkf", 1, {{"window", 2}}), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Monitor on st-akf-pm: false alarms on smooth noisy motion, detection delay on a real step.

// Metres throughout. Measurement noise sigma = 1 mm; q, r, P_0 chosen for a target moving at
// metres per second (choice for these studies, not from the paper, which gives no values).
constexpr double kNoiseM = 1e-3;
Params pmParams(int monitor, int on_alarm = 0) {
  return {{"q", 10.0},       {"r", kNoiseM * kNoiseM}, {"p0_vel", 100.0},
          {"p0_acc", 1e3},   {"monitor", monitor},     {"pm_on_alarm", on_alarm}};
}

// ---------------------------------------------------------------------------------------------
// The motion model (`model: cv | ca`, issue 11 item 3).

using namespace model_switch;

TEST(StAkfModel, DefaultModelGivesTheNumbersOfBeforeTheModelKey) {
  // GIVEN st-akf and st-akf-pm with their defaults, with and without `model: ca` spelt out
  // (reference: the same scenario through main at b41f742, before `model` existed, %.17g)
  const struct {
    const char* name;
    Pinned channel[2];
    int alarms;
  } expected[] = {
      {"st-akf",
       {{275.08929370236802, 7.6253739840617358, 3.3789935209516258},
        {3224.2296337247371, 580.2118858778997, 4.6072319863853908}},
       0},
      {"st-akf-pm",
       {{275.08929370236814, 7.6253739840625574, 3.3789935209516258},
        {3222.7857681269315, 563.58304590767057, 32.436529592276912}},
       2},
  };
  for (const auto& e : expected) {
    for (bool spelt : {false, true}) {
      SCOPED_TRACE(std::string(e.name) + (spelt ? " model: ca" : " default"));
      // pinned before the weighted, blended forecast and the no-fading frame after a gap
      Params params{{"shrink_sigmas", 0.0}, {"hold_blend_tau_s", 0.0}, {"adapt_after_gap", 1.0}};
      if (spelt) params.setText("model", "ca");
      auto f = makePredictor(e.name, 2, params);
      // WHEN they filter the scenario THEN the 2-frame predictions and the alarms are the pinned ones
      expectPinned(*f, e.channel, 3);
      EXPECT_EQ(f->monitorAlarms(), e.alarms);
    }
  }
}

TEST(StAkfModel, WithoutFadingEachModelIsThePlainKalmanFilterOfThatModel) {
  // GIVEN st-akf and st-akf-pm whose fading never fires (beta = 1e6: N = V0 - q - 1e6 R < 0 on this
  // 2 px noise and 40 px jump) and whose monitor never alarms (band of 1e6 sigma), on each model,
  // and kf-cv / kf-ca with the same q, r, P_0 and forecast weighting (shrink_sigmas 1)
  for (const char* model : {"cv", "ca"}) {
    const bool cv = std::string(model) == "cv";
    const double q = cv ? 2e3 : 5e4;
    for (const char* name : {"st-akf", "st-akf-pm"}) {
      Params params{{"q", q}, {"r", 1.5}, {"p0_vel", 300.0}, {"p0_acc", 700.0}, {"beta", 1e6}, {"shrink_sigmas", 1.0}};
      params.setText("model", model);
      if (std::string(name) == "st-akf-pm") params.set("pm_band", 1e6);
      auto st = makePredictor(name, 2, params);
      Params kf_params{{"q", q}, {"r", 1.5}, {"p0_vel", 300.0}, {"shrink_sigmas", 1.0}};
      if (!cv) kf_params.set("p0_acc", 700.0);
      auto kf = makePredictor(cv ? "kf-cv" : "kf-ca", 2, kf_params);
      // WHEN both filter the same scenario THEN they agree: the model is wired right
      SCOPED_TRACE(std::string(name) + " model " + model);
      expectSameFilter(*st, *kf);
      EXPECT_EQ(st->monitorAlarms(), 0);
    }
  }
}

TEST(StAkfModel, CvFadingFollowsThePresetRatiosOnTwoFactors) {
  // GIVEN the CV filter with ratios a = (1, 3) (a3 accepted and unused on cv) and a manoeuvre
  StAkfPredictor<2> f(1, {{"q", 1.0}, {"r", 1.0}, {"a1", 1.0}, {"a2", 3.0}, {"a3", 4.0}});
  jumpAfterRest(f);
  // THEN lambda_p = c > 1 and lambda_v = 3 c, and P stays symmetric
  const Vec<2> l = f.fadingFactors(0);
  ASSERT_GT(l(0), 1.0);
  EXPECT_NEAR(l(1), 3.0 * l(0), 1e-9 * l(1));
  const Mat<2>& P = f.gaussian(0).P;
  EXPECT_LT(std::abs(P(0, 1) - P(1, 0)), 1e-12 * P.cwiseAbs().maxCoeff());
}

TEST(StAkfModel, StructuralVariantsAreCvAndCaAndEachBuildsAndRuns) {
  for (const char* name : {"st-akf", "st-akf-pm"}) {
    SCOPED_TRACE(name);
    // GIVEN the variants of the default predictor WHEN a predictor is built from each alone (plus
    // r) and runs THEN it has that model's state and noise keys, its default q, and a finite forecast
    expectModelVariantsBuildAndRun(name, kDefaultQStAkfCv, kDefaultQStAkf);
  }
}

TEST(StAkfModel, ABadModelIsAOneLineErrorNamingTheKey) {
  for (const char* name : {"st-akf", "st-akf-pm"}) expectBadModelRejected(name);
}

TEST(StAkfModel, SteadyStateCvIsTheLimitOfTheCvKalmanFilter) {
  // GIVEN the steady-state CV filter and kf-cv with the same q, r, dt
  const double q = 50.0, r = 0.5, dt = 0.04;
  const SteadyStateKf<2> ss = steadyStateKf<2>(q, r, dt);
  KfCvPredictor kf(1, {{"q", q}, {"r", r}, {"p0_vel", 100.0}});
  for (int n = 0; n < 2000; ++n) kf.update(n * dt, vec1(0.0));
  // THEN kf-cv's covariance converges to P_post (relative: the Riccati recursion converged)
  const Mat<2>& P = kf.gaussian(0).P;
  EXPECT_LT((P - ss.P_post).cwiseAbs().maxCoeff(), 1e-9 * ss.P_post.cwiseAbs().maxCoeff());
}

TEST(StAkfModel, MonitorOnTheCvFilterDetectsAStepAndItsSteadyStatePhaseRuns) {
  for (int on_alarm : {0, 1}) {
    for (int monitor : {0, 1}) {
      // GIVEN st-akf-pm on the CV model tracking a target at rest (1 mm noise, T = 0.04 s), with a
      // white-acceleration density of 0.1 m^2/s^3 (pmParams' q = 10 is a jerk density: as an
      // acceleration density it sets the gain near 1, the two-step errors then have a sigma of
      // ~3 mm and a 2 cm step is inside the 6-sigma band)
      Params p = pmParams(monitor, on_alarm);
      p.setText("model", "cv");
      p.set("q", 0.1);
      auto f = makePredictor("st-akf-pm", 1, p);
      std::mt19937 rng(5);
      std::normal_distribution<double> noise(0.0, kNoiseM);
      const double T = 0.04;
      int n = 0;
      for (; n < 50; ++n) f->update(n * T, vec1(noise(rng)));
      ASSERT_EQ(f->monitorAlarms(), 0) << "monitor " << monitor;
      // WHEN it steps by 2 cm (20 sigma)
      const int step_frame = n;
      int detected = -1;
      for (; n < step_frame + 40; ++n) {
        f->update(n * T, vec1(0.02 + noise(rng)));
        if (detected < 0 && f->monitorAlarms() > 0) detected = n - step_frame;
      }
      // THEN the alarm comes within 2 frames, and after the steady-state phase (25 frames) the
      // filter is back on the step
      EXPECT_GE(detected, 0) << "monitor " << monitor << " on_alarm " << on_alarm;
      EXPECT_LE(detected, 2) << "monitor " << monitor << " on_alarm " << on_alarm;
      EXPECT_NEAR(f->predictPosition(0, n * T), 0.02, 5.0 * kNoiseM) << "monitor " << monitor << " on_alarm " << on_alarm;
    }
  }
}

struct SmoothRun {
  int alarms = 0;
  double minutes = 0.0;
};

// Ten minutes of a smooth sinusoid (amplitude 0.5 m, period 6 s) with Gaussian noise, T = 0.04 s.
SmoothRun smoothRun(int monitor, unsigned seed) {
  StAkfPmPredictor<3> f(1, pmParams(monitor));
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, kNoiseM);
  const double T = 0.04;
  const int frames = static_cast<int>(600.0 / T);
  for (int n = 0; n < frames; ++n) {
    const double t = n * T;
    f.update(t, vec1(0.5 * std::sin(2.0 * M_PI * t / 6.0) + noise(rng)));
  }
  return {f.monitorAlarms(), 10.0};
}

TEST(StAkfPm, FewFalseAlarmsOnSmoothNoisyMotion) {
  for (int monitor : {0, 1}) {
    int alarms = 0;
    double minutes = 0.0;
    for (unsigned seed : {11u, 12u, 13u}) {
      const SmoothRun r = smoothRun(monitor, seed);
      alarms += r.alarms;
      minutes += r.minutes;
    }
    std::printf("[ st-akf-pm ] monitor=%d (%s): %d false alarms in %.0f min = %.2f / min (T = 0.04 s)\n", monitor,
                monitor ? "chi-square" : "band", alarms, minutes, alarms / minutes);
    // THEN fewer than one false alarm per minute (1500 frames) on 30 minutes of smooth motion
    EXPECT_LT(alarms / minutes, 1.0) << "monitor " << monitor;
  }
}

TEST(StAkfPm, DetectsAPositionStepWithinAFewFrames) {
  for (int monitor : {0, 1}) {
    // GIVEN a target at rest with 1 mm noise, tracked for 2 s at T = 0.04 s
    StAkfPmPredictor<3> f(1, pmParams(monitor));
    std::mt19937 rng(5);
    std::normal_distribution<double> noise(0.0, kNoiseM);
    const double T = 0.04;
    int n = 0;
    for (; n < 50; ++n) f.update(n * T, vec1(noise(rng)));
    ASSERT_EQ(f.monitorAlarms(), 0);
    // WHEN it steps by 2 cm (20 sigma)
    const int step_frame = n;
    int detected = -1;
    for (; n < step_frame + 20 && detected < 0; ++n) {
      f.update(n * T, vec1(0.02 + noise(rng)));
      if (f.monitorAlarms() > 0) detected = n - step_frame;
    }
    std::printf("[ st-akf-pm ] monitor=%d: 2 cm step detected %d frame(s) after it\n", monitor, detected);
    // THEN the alarm comes within 2 frames (the step is first seen in frame 0)
    EXPECT_GE(detected, 0);
    EXPECT_LE(detected, 2);
  }
}

// ---------------------------------------------------------------------------------------------
// E12 (paper 004 §5): target at rest, then a sudden sinusoid (period 3 s, amplitude 2 m).

struct E12Result {
  int delay_frames = -1;      // frames from the start of the motion to the first alarm (-1: none)
  int alarms_at_rest = 0;
  int alarms_total = 0;
  double iae_m_s = 0.0;       // integral of |x(k|k) - x(k)| dt from the start of the motion (m s)
  double iae_pred_m_s = 0.0;  // same for the one-frame-ahead prediction x(k+1|k)
  double iae_onset_m_s = 0.0; // filtered IAE over the first 0.5 s of motion only
};

// One E12 run over rest (1 s) + two periods of the sinusoid, 1 mm noise, frame period Th.
E12Result runE12(const std::string& name, int monitor, double Th, unsigned seed, int on_alarm = 0) {
  const paper::E12Config cfg;
  const double duration = cfg.t_start_s + 2.0 * cfg.period_s;
  Params p = pmParams(monitor, on_alarm);
  if (name != "st-akf-pm") p = {{"q", 10.0}, {"r", kNoiseM * kNoiseM}, {"p0_vel", 100.0}, {"p0_acc", 1e3}};
  auto f = makePredictor(name, 1, p);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, kNoiseM);
  E12Result r;
  const int frames = static_cast<int>(std::lround(duration / Th));
  for (int n = 0; n <= frames; ++n) {
    const double t = n * Th;
    f->update(t, vec1(paper::e12Position(cfg, t) + noise(rng)));
    const int alarms = f->monitorAlarms();  // 0 for a filter without a monitor
    if (t < cfg.t_start_s) r.alarms_at_rest = alarms;
    if (t >= cfg.t_start_s) {
      if (r.delay_frames < 0 && alarms > r.alarms_at_rest)
        r.delay_frames = static_cast<int>(std::lround((t - cfg.t_start_s) / Th));
      const double err = std::abs(f->predict(0, t).position() - paper::e12Position(cfg, t)) * Th;
      r.iae_m_s += err;
      if (t < cfg.t_start_s + 0.5) r.iae_onset_m_s += err;
      r.iae_pred_m_s += std::abs(f->predict(0, t + Th).position() - paper::e12Position(cfg, t + Th)) * Th;
    }
    r.alarms_total = alarms;
  }
  return r;
}

TEST(StAkfE12, MonitorDetectsTheStartOfMotion) {
  // Detected "quickly" = within this many frames of the first moving frame.
  constexpr int kQuickFrames = 3;
  constexpr unsigned kSeeds = 5;
  for (double Th : {0.04, 0.002}) {
    double iae_ca = 0.0, iae_ca_pred = 0.0, iae_st = 0.0, iae_st_pred = 0.0, onset_ca = 0.0, onset_st = 0.0;
    for (unsigned s = 0; s < kSeeds; ++s) {
      const E12Result a = runE12("kf-ca", 0, Th, 100 + s), b = runE12("st-akf", 0, Th, 100 + s);
      iae_ca += a.iae_m_s / kSeeds;
      iae_ca_pred += a.iae_pred_m_s / kSeeds;
      iae_st += b.iae_m_s / kSeeds;
      iae_st_pred += b.iae_pred_m_s / kSeeds;
      onset_ca += a.iae_onset_m_s / kSeeds;
      onset_st += b.iae_onset_m_s / kSeeds;
    }
    std::printf("[ E12 ] Th=%.3f s, %u seeds, mean IAE filtered / 1-step predicted (first 0.5 s filtered) in m s: "
                "kf-ca %.5f / %.5f (%.5f), st-akf %.5f / %.5f (%.5f)\n",
                Th, kSeeds, iae_ca, iae_ca_pred, onset_ca, iae_st, iae_st_pred, onset_st);
    for (int variant = 0; variant < 4; ++variant) {
      const int monitor = variant % 2, on_alarm = variant / 2;
      double iae = 0.0, iae_pred = 0.0, onset = 0.0;
      int quick = 0, worst = 0, at_rest = 0, total = 0;
      for (unsigned s = 0; s < kSeeds; ++s) {
        const E12Result r = runE12("st-akf-pm", monitor, Th, 100 + s, on_alarm);
        iae += r.iae_m_s / kSeeds;
        iae_pred += r.iae_pred_m_s / kSeeds;
        onset += r.iae_onset_m_s / kSeeds;
        const bool is_quick = r.delay_frames >= 0 && r.delay_frames <= kQuickFrames;
        quick += is_quick ? 1 : 0;
        worst = std::max(worst, r.delay_frames < 0 ? 1 << 30 : r.delay_frames);
        at_rest += r.alarms_at_rest;
        total += r.alarms_total;
        // THEN the monitor never fires while the target is at rest
        EXPECT_EQ(r.alarms_at_rest, 0) << "Th " << Th << " monitor " << monitor;
        // AND at Th = 0.04 s both monitors detect the start quickly in every seed. At Th = 0.002 s
        // the first moving frame is displaced by only ~8 noise sigmas and the strong-tracking
        // filter absorbs the change within 1-2 frames, so the monitors can miss the start there
        // (measured and reported, not asserted).
        if (Th > 0.01) {
          EXPECT_TRUE(is_quick) << "Th " << Th << " monitor " << monitor;
        }
      }
      std::printf("[ E12 ]   st-akf-pm %-10s %-12s IAE %.5f / %.5f (%.5f); start detected within %d frames in %d/%u "
                  "seeds (worst delay %s%d), alarms at rest %d, alarms in total %d\n",
                  monitor ? "chi-square" : "band", on_alarm ? "steady-state" : "reinit", iae, iae_pred, onset, kQuickFrames, quick, kSeeds,
                  worst == 1 << 30 ? "none: " : "", worst == 1 << 30 ? -1 : worst, at_rest, total);
    }
  }
}

}  // namespace
}  // namespace predvs
