#include "predvs/servo/maneuver_tracks.h"

#include "predvs/servo/sampled_signal.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A random stream of the track of `seed` for its draw `draw`, one per `stream` tag (the noise and
/// drops of a draw > 0, the glitches of every draw): seeded from all three, so no two share bits.
std::mt19937_64 drawStream(std::uint64_t seed, std::uint64_t draw, std::uint32_t stream) {
  std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                    static_cast<std::uint32_t>(draw), static_cast<std::uint32_t>(draw >> 32), stream};
  return std::mt19937_64(seq);
}

/// The velocity profile of one kind: a state machine advanced in small steps, v(t) in px/s.
class Motion {
 public:
  Motion(ManeuverKind kind, std::mt19937_64& rng) : kind_(kind), rng_(rng) {
    switch (kind_) {
      case ManeuverKind::Smooth:
      case ManeuverKind::Hand:
        for (int axis = 0; axis < 2; ++axis)
          for (int i = 0; i < (kind_ == ManeuverKind::Hand ? 3 : 2); ++i) {
            Wave w;
            if (kind_ == ManeuverKind::Smooth) {
              w.freq_hz = 1.0 / uniform(3.0, 8.0);
              w.amp_px = uniform(40.0, 80.0);  // velocity amplitude 2 pi f A ~ 30..170 px/s
            } else {
              w.freq_hz = uniform(0.2, 0.7);
              w.amp_px = uniform(20.0, 40.0) / (i + 1);
            }
            w.phase = uniform(0.0, 2.0 * kPi);
            waves_[axis].push_back(w);
          }
        if (kind_ == ManeuverKind::Hand)
          for (int axis = 0; axis < 2; ++axis) {
            tremor_[axis].freq_hz = uniform(6.0, 9.0);
            tremor_[axis].amp_px = 0.3;
            tremor_[axis].phase = uniform(0.0, 2.0 * kPi);
          }
        break;
      case ManeuverKind::Turns:
        speed_ = uniform(80.0, 150.0);
        heading_ = uniform(0.0, 2.0 * kPi);
        startLeg(0.0, false);
        break;
      case ManeuverKind::Stops:
        heading_ = uniform(0.0, 2.0 * kPi);
        target_speed_ = uniform(100.0, 200.0);
        seg_end_ = uniform(1.0, 2.0);
        moving_ = true;
        ramp_s_ = 0.06;
        break;
      case ManeuverKind::Bursts:
        heading_ = uniform(0.0, 2.0 * kPi);
        drift_heading_ = uniform(0.0, 2.0 * kPi);
        seg_end_ = uniform(1.0, 3.0);
        moving_ = false;
        ramp_s_ = 0.08;
        break;
      case ManeuverKind::Zigzag:
        vx_ = uniform(30.0, 60.0) * (coin() ? 1.0 : -1.0);
        vy_mag_ = uniform(80.0, 140.0);
        sign_ = coin() ? 1.0 : -1.0;
        prev_sign_ = sign_;
        seg_start_ = -1.0;
        seg_end_ = uniform(0.6, 1.5);
        ramp_s_ = 0.06;
        break;
    }
  }

  /// Velocity at time t (px/s); advance() must have been called up to t.
  void velocity(double t, double& vx, double& vy) const {
    switch (kind_) {
      case ManeuverKind::Smooth:
      case ManeuverKind::Hand: {
        double v[2] = {0.0, 0.0};
        for (int axis = 0; axis < 2; ++axis) {
          for (const Wave& w : waves_[axis]) v[axis] += w.velocity(t);
          if (kind_ == ManeuverKind::Hand) v[axis] += tremor_[axis].velocity(t);
        }
        vx = v[0];
        vy = v[1];
        return;
      }
      case ManeuverKind::Turns:
        vx = speed_ * std::cos(heading_);
        vy = speed_ * std::sin(heading_);
        return;
      case ManeuverKind::Stops: {
        const double s = rampedSpeed(t, moving_ ? target_speed_ : 0.0, moving_ ? 0.0 : prev_speed_);
        vx = s * std::cos(heading_);
        vy = s * std::sin(heading_);
        return;
      }
      case ManeuverKind::Bursts: {
        const double drift = 15.0;
        const double s = rampedSpeed(t, moving_ ? burst_speed_ : 0.0, moving_ ? 0.0 : prev_speed_);
        vx = drift * std::cos(drift_heading_) + s * std::cos(heading_);
        vy = drift * std::sin(drift_heading_) + s * std::sin(heading_);
        return;
      }
      case ManeuverKind::Zigzag: {
        vx = vx_;
        const double w = seg_start_ < 0.0 ? 1.0 : std::min(1.0, (t - seg_start_) / ramp_s_);
        vy = vy_mag_ * ((1.0 - w) * prev_sign_ + w * sign_);
        return;
      }
    }
    vx = vy = 0.0;
  }

  /// Moves the state machine from t to t + dt (segment switches, heading integration).
  void advance(double t, double dt) {
    const double t1 = t + dt;
    switch (kind_) {
      case ManeuverKind::Turns:
        heading_ += omega_ * dt;
        if (t1 >= seg_end_) startLeg(t1, !turning_);
        return;
      case ManeuverKind::Stops:
        if (t1 >= seg_end_) {
          seg_start_ = t1;
          if (moving_) {
            prev_speed_ = target_speed_;
            moving_ = false;
            seg_end_ = t1 + uniform(0.4, 1.2);
          } else {
            heading_ = uniform(0.0, 2.0 * kPi);
            target_speed_ = uniform(100.0, 200.0);
            moving_ = true;
            seg_end_ = t1 + uniform(1.0, 2.0);
          }
        }
        return;
      case ManeuverKind::Bursts:
        if (t1 >= seg_end_) {
          seg_start_ = t1;
          if (moving_) {
            prev_speed_ = burst_speed_;
            moving_ = false;
            seg_end_ = t1 + uniform(1.0, 3.0);
          } else {
            heading_ = uniform(0.0, 2.0 * kPi);
            burst_speed_ = uniform(250.0, 400.0);
            moving_ = true;
            seg_end_ = t1 + uniform(0.4, 0.8);
          }
        }
        return;
      case ManeuverKind::Zigzag:
        if (t1 >= seg_end_) {
          seg_start_ = t1;
          prev_sign_ = sign_;
          sign_ = -sign_;
          seg_end_ = t1 + uniform(0.6, 1.5);
        }
        return;
      default:
        return;
    }
  }

 private:
  struct Wave {
    double freq_hz = 0.0, amp_px = 0.0, phase = 0.0;
    /// Derivative of amp sin(2 pi f t + phase).
    double velocity(double t) const { return amp_px * 2.0 * kPi * freq_hz * std::cos(2.0 * kPi * freq_hz * t + phase); }
  };

  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  bool coin() { return std::uniform_int_distribution<int>(0, 1)(rng_) == 1; }

  /// Linear ramp from `from` (at seg_start_) to `to` over ramp_s_.
  double rampedSpeed(double t, double to, double from) const {
    if (moving_) from = 0.0;
    const double w = std::clamp((t - seg_start_) / ramp_s_, 0.0, 1.0);
    return (1.0 - w) * from + w * to;
  }

  void startLeg(double t, bool turn) {
    turning_ = turn;
    if (turn) {
      omega_ = uniform(1.5, 3.0) * (coin() ? 1.0 : -1.0);
      seg_end_ = t + uniform(0.4, 1.2);
    } else {
      omega_ = 0.0;
      seg_end_ = t + uniform(0.8, 2.0);
    }
  }

  ManeuverKind kind_;
  std::mt19937_64& rng_;
  std::vector<Wave> waves_[2];
  Wave tremor_[2];
  double speed_ = 0.0, heading_ = 0.0, omega_ = 0.0, drift_heading_ = 0.0;
  double target_speed_ = 0.0, burst_speed_ = 0.0, prev_speed_ = 0.0;
  double vx_ = 0.0, vy_mag_ = 0.0, sign_ = 1.0, prev_sign_ = 1.0;
  double seg_start_ = -1e9, seg_end_ = 0.0, ramp_s_ = 0.06;
  bool turning_ = false, moving_ = false;
};

}  // namespace

const std::vector<ManeuverKind>& maneuverKinds() {
  static const std::vector<ManeuverKind> kinds = {ManeuverKind::Smooth, ManeuverKind::Turns,  ManeuverKind::Stops,
                                                  ManeuverKind::Bursts, ManeuverKind::Zigzag, ManeuverKind::Hand};
  return kinds;
}

std::string maneuverKindName(ManeuverKind kind) {
  switch (kind) {
    case ManeuverKind::Smooth: return "smooth";
    case ManeuverKind::Turns: return "turns";
    case ManeuverKind::Stops: return "stops";
    case ManeuverKind::Bursts: return "bursts";
    case ManeuverKind::Zigzag: return "zigzag";
    case ManeuverKind::Hand: return "hand";
  }
  return "?";
}

ManeuverKind parseManeuverKind(const std::string& name) {
  std::string known;
  for (ManeuverKind k : maneuverKinds()) {
    if (maneuverKindName(k) == name) return k;
    known += (known.empty() ? "" : ", ") + maneuverKindName(k);
  }
  throw std::invalid_argument("unknown track kind '" + name + "' (known: " + known + ")");
}

ManeuverTrack generateManeuverTrack(const ManeuverTrackConfig& c) {
  if (!(c.rate_hz >= 1.0 && c.rate_hz <= 1000.0)) throw std::invalid_argument("track rate_hz must be in [1, 1000]");
  if (!(c.noise_px >= 0.0 && std::isfinite(c.noise_px))) throw std::invalid_argument("track noise_px must be >= 0");
  if (!(c.duration_s > 0.0 && c.duration_s <= 1e6)) throw std::invalid_argument("track duration_s must be > 0");
  if (!(c.drop_prob >= 0.0 && c.drop_prob <= 0.5)) throw std::invalid_argument("track drop_prob must be in [0, 0.5]");
  if (!(c.glitch_prob >= 0.0 && c.glitch_prob <= 0.5)) throw std::invalid_argument("track glitch_prob must be in [0, 0.5]");
  if (!(c.glitch_px > 0.0 && std::isfinite(c.glitch_px))) throw std::invalid_argument("track glitch_px must be > 0");

  std::mt19937_64 motion_rng(c.seed);
  std::mt19937_64 noise_rng(c.seed ^ 0x9e3779b97f4a7c15ULL);
  if (c.draw != 0) noise_rng = drawStream(c.seed, c.draw, 0x6472u);  // another draw: the motion's rng is untouched
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::mt19937_64 glitch_rng = drawStream(c.seed, c.draw, 0x676cu);  // the glitches' own (glitch_prob > 0 only)
  Motion motion(c.kind, motion_rng);

  const double T = 1.0 / c.rate_hz;
  const auto frames = static_cast<size_t>(std::floor(c.duration_s * c.rate_hz + 1e-9)) + 1;
  const int sub = std::max(1, static_cast<int>(std::ceil(T / 1e-3)));
  const double h = T / sub;

  ManeuverTrack track;
  track.t_s.reserve(frames);
  double x = c.u0_px, y = c.v0_px, t = 0.0;
  int drop_left = 0;
  for (size_t k = 0; k < frames; ++k) {
    const double tk = static_cast<double>(k) * T;
    if (k > 0) {
      for (int s = 0; s < sub; ++s) {
        double vx0, vy0, vx1, vy1;
        motion.velocity(t, vx0, vy0);
        motion.advance(t, h);
        t += h;
        motion.velocity(t, vx1, vy1);
        x += 0.5 * h * (vx0 + vx1);
        y += 0.5 * h * (vy0 + vy1);
      }
      t = tk;
    }
    track.t_s.push_back(tk);
    track.u_true_px.push_back(x);
    track.v_true_px.push_back(y);
    const double nu = c.noise_px * normal(noise_rng), nv = c.noise_px * normal(noise_rng);
    bool dropped = false;
    if (k > 0) {
      const double r = unit(noise_rng);
      if (drop_left > 0) {
        dropped = true;
        --drop_left;
      } else if (r < c.drop_prob / 5.0) {
        // an occlusion of 0.1..0.3 s (at least 2 frames), this frame included
        const double len_s = 0.1 + 0.2 * unit(noise_rng);
        drop_left = std::max(1, static_cast<int>(std::lround(len_s * c.rate_hz)) - 1);
        dropped = true;
      } else if (r < c.drop_prob) {
        dropped = true;
      }
    }
    double gu = 0.0, gv = 0.0;
    if (k > 0 && !dropped && c.glitch_prob > 0.0 && unit(glitch_rng) < c.glitch_prob) {
      const double angle = 2.0 * kPi * unit(glitch_rng);
      gu = c.glitch_px * std::cos(angle);
      gv = c.glitch_px * std::sin(angle);
      ++track.glitches;
    }
    track.u_px.push_back(dropped ? kNaN : x + nu + gu);
    track.v_px.push_back(dropped ? kNaN : y + nv + gv);
  }
  return track;
}

TrackScore scoreOnTrack(const ManeuverTrack& track, Predictor& predictor, double horizon_s, size_t first_scored_row) {
  if (predictor.channels() != 2) throw std::invalid_argument("scoreOnTrack: the predictor needs 2 channels");
  predictor.reset();
  TrackScore score;
  double sm = 0.0, st = 0.0;
  int nm = 0;
  Eigen::Vector2d z;
  for (size_t i = 0; i < track.size(); ++i) {
    z << track.u_px[i], track.v_px[i];
    predictor.update(track.t_s[i], z);
    if (i < first_scored_row) continue;
    const double t = track.t_s[i] + horizon_s;
    const Eigen::VectorXd p = predictor.predictPositions(t);
    if (!std::isfinite(p(0)) || !std::isfinite(p(1))) continue;
    const double um = interpolateAt(track.t_s, track.u_px, t), vm = interpolateAt(track.t_s, track.v_px, t);
    if (std::isfinite(um) && std::isfinite(vm)) {
      sm += (p(0) - um) * (p(0) - um) + (p(1) - vm) * (p(1) - vm);
      ++nm;
    }
    const double ut = interpolateAt(track.t_s, track.u_true_px, t), vt = interpolateAt(track.t_s, track.v_true_px, t);
    if (std::isfinite(ut) && std::isfinite(vt)) {
      st += (p(0) - ut) * (p(0) - ut) + (p(1) - vt) * (p(1) - vt);
      ++score.n;
    }
  }
  score.rmse_meas_px = nm > 0 ? std::sqrt(sm / nm) : kNaN;
  score.rmse_truth_px = score.n > 0 ? std::sqrt(st / score.n) : kNaN;
  return score;
}

}  // namespace predvs
