#include "predvs/predictors/glitch_gate.h"

#include "predvs/predictors/kalman_math.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace predvs {

double glitchSigmasParam(const Params& params) {
  return params.get("glitch_sigmas", kDefaultGlitchSigmas, 0.0, 1e6);
}

GlitchGate::GlitchGate(std::unique_ptr<Predictor> inner, double g)
    : Predictor(inner ? inner->channels() : 0), inner_(std::move(inner)), g_(g) {
  if (!inner_) throw std::invalid_argument("glitch gate: no predictor");
  if (!(g_ > 0.0)) throw std::invalid_argument("glitch gate: glitch_sigmas must be > 0");
  lines_.resize(static_cast<size_t>(channels()));
}

std::unique_ptr<Predictor> GlitchGate::clone() const {
  auto copy = std::make_unique<GlitchGate>(inner_->clone(), g_);
  copy->coasted_ = coasted_ ? coasted_->clone() : nullptr;
  copy->lines_ = lines_;
  copy->n_glitch_ = n_glitch_;
  copy->n_step_ = n_step_;
  if (!std::isnan(time())) copy->advanceClock(time());
  return copy;
}

void GlitchGate::reset() {
  resetClock();
  inner_->reset();
  coasted_.reset();
  for (Line& l : lines_) l = Line{};
  n_glitch_ = n_step_ = 0;
}

bool GlitchGate::test(Line& line, double t, double z) const {
  if (line.kept < 2) {
    line.keep(t, z);
    return false;
  }
  const double h1 = line.t1 - line.t2, h = t - line.t1;
  if (!(h <= kGlitchPeriodRatio * h1 && h1 <= kGlitchPeriodRatio * h)) {  // not a steady period: no test
    line.kept = 0;
    line.keep(t, z);
    return false;
  }
  const double step = line.z1 - line.z2;
  const double d = z - (line.z1 + step * (h / h1));
  const double d2 = d * d;
  if (line.samples >= kGlitchWarmup) {
    const double floor2 = kGlitchFloor * kGlitchFloor * line.m2;
    const double s = line.s > floor2 ? line.s : floor2;
    if (d2 > g_ * g_ * s) return true;  // in doubt: neither learnt nor kept until settled
    if (h != line.keep_h) {  // the forgetting of the last interval, kept: a steady clock repeats it
      line.keep_h = h;
      line.keep_factor = std::exp(-h / kGlitchScaleTauS);
    }
    const double keep = line.keep_factor;
    const double clip = kGlitchClip * kGlitchClip * line.s;
    line.s = keep * line.s + (1.0 - keep) * (d2 < clip ? d2 : clip);
    line.m2 = keep * line.m2 + (1.0 - keep) * step * step;
  } else {
    const double n = line.samples;
    line.m2 = (n * line.m2 + step * step) / (n + 1.0);
    line.warm[static_cast<size_t>(line.samples)] = d2;
    if (line.samples + 1 == kGlitchWarmup) {  // all but the kGlitchTrimmed largest (file comment)
      std::array<double, kGlitchWarmup> w = line.warm;
      std::sort(w.begin(), w.end());
      double sum = 0.0;
      for (int i = 0; i < kGlitchWarmup - kGlitchTrimmed; ++i) sum += w[static_cast<size_t>(i)];
      line.s = sum / (kGlitchWarmup - kGlitchTrimmed) / kGlitchTrimmedMean;
    }
  }
  ++line.samples;
  line.keep(t, z);
  return false;
}

void GlitchGate::settle(double t_s, const Eigen::Ref<const Eigen::VectorXd>& z) {
  double err_a = 0.0, err_b = 0.0;
  bool any = false;
  for (int c = 0; c < channels(); ++c) {
    if (!lines_[static_cast<size_t>(c)].doubt || !isMeasured(z(c))) continue;
    const double ea = z(c) - inner_->predictPosition(c, t_s),
                 eb = z(c) - coasted_->predictPosition(c, t_s);
    err_a += ea * ea;
    err_b += eb * eb;
    any = true;
  }
  const bool glitch = any && err_b < err_a;
  if (glitch) {
    inner_ = std::move(coasted_);
    ++n_glitch_;
  } else {
    ++n_step_;
  }
  coasted_.reset();
  for (Line& l : lines_) {
    if (!l.doubt) continue;
    l.doubt = false;
    // A glitch leaves the line as it was before it; a step starts the line anew
    // from its frame, so that the frame after it is not tested against the
    // jump's slope.
    if (!glitch) {
      l.kept = 0;
      l.keep(l.t_doubt, l.z_doubt);
    }
  }
}

void GlitchGate::update(double t_s, const Eigen::Ref<const Eigen::VectorXd>& z) {
  advanceClock(t_s, z);
  if (coasted_) settle(t_s, z);
  bool doubt = false;
  for (int c = 0; c < channels(); ++c) {
    Line& l = lines_[static_cast<size_t>(c)];
    if (!isMeasured(z(c))) {
      l.kept = 0;  // the next test needs two measured frames in a row again
      continue;
    }
    if (test(l, t_s, z(c))) {
      l.doubt = true;
      l.t_doubt = t_s;
      l.z_doubt = z(c);
      doubt = true;
    }
  }
  if (doubt) {
    coasted_ = inner_->clone();
    Eigen::VectorXd zb = z;
    for (int c = 0; c < channels(); ++c)
      if (lines_[static_cast<size_t>(c)].doubt) zb(c) = std::numeric_limits<double>::quiet_NaN();
    coasted_->update(t_s, zb);
  }
  inner_->update(t_s, z);
}

ChannelEstimate GlitchGate::predict(int channel, double t_s) const {
  ChannelEstimate a = inner_->predict(channel, t_s);
  if (!coasted_ || !lines_.at(static_cast<size_t>(channel)).doubt) return a;
  const ChannelEstimate b = coasted_->predict(channel, t_s);
  const double p = glitchShare();
  ChannelEstimate m;
  m.x = p * b.x + (1.0 - p) * a.x;
  const ChannelVector da = a.x - m.x, db = b.x - m.x;
  m.P = p * (b.P + db * db.transpose()) + (1.0 - p) * (a.P + da * da.transpose());
  return m;
}

double GlitchGate::mixed(double (Predictor::*of)(int, double) const, int c, double t_s) const {
  const double a = ((*inner_).*of)(c, t_s);
  if (!coasted_ || !lines_[static_cast<size_t>(c)].doubt) return a;
  const double p = glitchShare();
  return p * ((*coasted_).*of)(c, t_s) + (1.0 - p) * a;
}

double GlitchGate::predictPosition(int channel, double t_s) const {
  return mixed(&Predictor::predictPosition, channel, t_s);
}

double GlitchGate::predictVelocity(int channel, double t_s) const {
  return mixed(&Predictor::predictVelocity, channel, t_s);
}

double GlitchGate::feedforwardVelocity(int channel, double t_s) const {
  return mixed(&Predictor::feedforwardVelocity, channel, t_s);
}

NamedValues GlitchGate::tallies() const {
  NamedValues out = inner_->tallies();
  out.emplace_back("glitches", n_glitch_);
  out.emplace_back("steps", n_step_);
  return out;
}

std::unique_ptr<Predictor> withGlitchGate(std::unique_ptr<Predictor> inner, double g) {
  if (!(g > 0.0) || !inner || !inner->extrapolates()) return inner;
  if (!inner->clone()) return inner;
  return std::make_unique<GlitchGate>(std::move(inner), g);
}

}  // namespace predvs
