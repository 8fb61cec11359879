#include "predvs/predictors/fakf.h"

#include <algorithm>
#include <stdexcept>

namespace predvs {

InnovationWindow::InnovationWindow(int length) {
  if (length < 1) throw std::invalid_argument("innovation window length must be >= 1");
  buf_.assign(static_cast<size_t>(length), 0.0);
}

void InnovationWindow::push(double eps) {
  buf_[static_cast<size_t>(next_)] = eps;
  next_ = (next_ + 1) % length();
  count_ = std::min(count_ + 1, length());
}

void InnovationWindow::clear() {
  std::fill(buf_.begin(), buf_.end(), 0.0);
  next_ = 0;
  count_ = 0;
}

// Sums are recomputed over the (short) window rather than kept as running sums, which would
// accumulate rounding over long runs.
double InnovationWindow::mean() const {
  if (count_ == 0) return 0.0;
  double s = 0.0;
  for (int i = 0; i < count_; ++i) s += buf_[static_cast<size_t>(i)];
  return s / count_;
}

double InnovationWindow::meanSquare() const {
  if (count_ == 0) return 0.0;
  double s = 0.0;
  for (int i = 0; i < count_; ++i) s += buf_[static_cast<size_t>(i)] * buf_[static_cast<size_t>(i)];
  return s / count_;
}

namespace {

fuzzy::DomSystemConfig domConfig(const Params& p) {
  fuzzy::DomSystemConfig c;
  c.dom_range = p.get("dom_range", c.dom_range, 1e-9, 1e9);
  c.dr_max = p.get("dr_max", c.dr_max, 1e-12, 1e9);
  return c;
}

}  // namespace

FakfClassicPredictor::FakfClassicPredictor(int channels, const Params& params)
    : ChannelPredictor<2>(channels, params.get("r", 1.0, 1e-12, 1e12), params.get("p0_vel", 1e4, 0.0, 1e12), 0.0),
      q_(params.get("q", 100.0, 0.0, 1e12)),
      r_min_(params.get("r_min", 1e-3, 1e-12, 1e12)),
      r_max_(params.get("r_max", 1e4, 1e-12, 1e12)),
      window_length_(static_cast<int>(params.get("window", 10.0, 2.0, 1000.0))),
      dom_(fuzzy::makeFakfDomSystem(domConfig(params))) {
  if (!(r_min_ <= r0_ && r0_ <= r_max_))
    throw std::invalid_argument("fakf-classic: need r_min <= r <= r_max");
  resetAdaptation();
}

void FakfClassicPredictor::resetAdaptation() {
  r_.assign(static_cast<size_t>(channels()), r0_);
  window_.assign(static_cast<size_t>(channels()), InnovationWindow(window_length_));
}

void FakfClassicPredictor::step(int c, double dt, double z) {
  ChannelState& s = state_[static_cast<size_t>(c)];
  timeUpdate(s.g, transition(c, dt), processNoise(c, dt));
  if (!isMeasured(z)) return;
  double& R = r_[static_cast<size_t>(c)];
  InnovationWindow& win = window_[static_cast<size_t>(c)];
  const double eps = z - s.g.x(0);
  const double S = s.g.P(0, 0) + R;  // theoretical innovation power with R(k-1)
  win.push(eps);
  if (win.full()) {
    const double dom = win.meanSquare() - S;
    R = std::clamp(R + dom_.evaluate(dom), r_min_, r_max_);
  }
  s.innovation = measurementUpdate(s.g, z, R);
}

}  // namespace predvs
