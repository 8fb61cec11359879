// predvs — fuzzy adaptive Kalman filters (METHODS §3, paper 000 §4).
//
// Both filters watch the innovation sequence of each channel over a sliding window of N_w frames,
//   E'(k) = (1/N_w) sum eps(i),   C(k) = (1/N_w) sum eps(i)^2,   i = k-N_w+1 .. k,
// and compare the actual innovation power C with the filter's own S(k) = P(k|k-1)(0,0) + R(k-1).
// When the filter matches the data, E' ~ 0 and C ~ S. The windowed statistics include the current
// innovation, and R(k) is adapted BEFORE the measurement update of frame k, so that update already
// uses the new R (as in Escamilla-Ambrosio & Mort and paper 000: R(k) is then used in K(k)).
// Adaptation starts once the window is full (the first N_w innovations only fill it), so a few
// noisy innovations after initialisation do not swing R.
//
// R is kept finite and positive for every input: after each adaptation R is clamped to
// [r_min, r_max] (parameters, px^2). This is what the property suite relies on (no NaN, P PSD).
#pragma once

#include "predvs/predictors/channel_predictor.h"
#include "predvs/predictors/fuzzy.h"

#include <vector>

namespace predvs {

/// Sliding window of the last N_w innovations of one channel: E' (mean) and C (mean square).
class InnovationWindow {
 public:
  explicit InnovationWindow(int length = 10);
  void push(double eps);
  void clear();
  int length() const { return static_cast<int>(buf_.size()); }
  int count() const { return count_; }
  bool full() const { return count_ == length(); }
  /// E' = mean of the stored innovations (0 when empty).
  double mean() const;
  /// C = mean of the squared stored innovations (0 when empty).
  double meanSquare() const;

 private:
  std::vector<double> buf_;
  int next_ = 0;
  int count_ = 0;
};

/// `fakf-classic`: the traditional fuzzy adaptive KF of Escamilla-Ambrosio & Mort, the baseline
/// paper 000 compares against (METHODS §3). Constant-velocity state x = [p, v] per channel
/// (same model and defaults as kf-cv), no CS model, no P inflation. Per frame, once the window is
/// full:
///   DoM(k) = C(k) - S(k)                  (actual minus theoretical innovation power)
///   dR(k)  = fuzzy(DoM): N -> decrease, ZE -> keep, P -> increase (fuzzy::makeFakfDomSystem)
///   R(k)   = clamp(R(k-1) + dR(k), r_min, r_max)
/// Parameters: q (100 px^2/s^3), r (initial R, 1 px^2), p0_vel (1e4), window (N_w, 10),
/// dom_range (DoM universe half-width, 10 px^2), dr_max (dR universe half-width, 0.5 px^2 per
/// frame; choice: the original paper's ranges are not in paper 000), r_min (1e-3 px^2),
/// r_max (1e4 px^2).
class FakfClassicPredictor : public ChannelPredictor<2> {
 public:
  FakfClassicPredictor(int channels, const Params& params);
  std::string name() const override { return "fakf-classic"; }

  /// Current (adapted) measurement variance of channel c, px^2.
  double adaptedR(int c) const { return measurementNoise(c); }

 protected:
  Mat<2> transition(int, double dt) const override { return cvTransition(dt); }
  Mat<2> processNoise(int, double dt) const override { return cvProcessNoise(q_, dt); }
  double measurementNoise(int c) const override { return r_.at(static_cast<size_t>(c)); }
  void resetAdaptation() override;
  void step(int c, double dt, double z) override;

 private:
  double q_;
  double r_min_, r_max_;
  int window_length_;
  fuzzy::MamdaniSystem dom_;
  std::vector<double> r_;
  std::vector<InnovationWindow> window_;
};

}  // namespace predvs
