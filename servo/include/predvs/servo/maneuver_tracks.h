// predvs — seeded maneuvering 2-D image tracks with truth (issue 11: defaults that hold, imm,
// noise fitting), and the open-loop score `predvs predict` uses on them.
//
// A track is a target moving in the image, sampled at a fixed frame rate with Gaussian pixel
// noise and randomly dropped frames. The motion is a velocity profile v(t) (px/s) drawn from the
// seed, integrated exactly enough (sub-steps of at most 1 ms, trapezoid rule) to give the true
// position at every frame time t_k = k / rate_hz. Kinds (speeds in px/s, accelerations in px/s^2):
//
//   smooth   a Lissajous drift: two sinusoids per axis, periods 3..8 s, amplitudes 40..80 px
//            (velocity amplitude 30..170 px/s per component)
//   turns    constant speed 80..150 px/s; straight legs of 0.8..2 s alternate with coordinated
//            turns at 1.5..3 rad/s lasting 0.4..1.2 s (centripetal acceleration up to ~450)
//   stops    move 1..2 s at 100..200 px/s along a random heading, stop hard (speed ramps to 0 in
//            60 ms, ~3000 px/s^2), rest 0.4..1.2 s, start again as hard on a new heading
//   bursts   slow drift at 15 px/s with bursts of 250..400 px/s lasting 0.4..0.8 s every 1..3 s
//            (ramps of 80 ms), as a target that is suddenly pushed (a burst shorter than ~4 frames
//            at 10 Hz is over before any predictor with a 2-frame delay has seen it)
//   zigzag   constant v_x = 30..60 px/s, v_y = +-80..140 px/s flipping sign every 0.6..1.5 s
//            (ramp of 60 ms)
//   hand     hand-held camera: a sway of 3 sinusoids per axis at 0.2..0.7 Hz (amplitudes 20..40,
//            10..20, 7..13 px) plus a small tremor at 6..9 Hz (0.3 px): smooth but never straight.
//            The sway stays below 0.7 Hz so that a 2-frame horizon at the slowest rate (0.2 s at
//            10 Hz) is under 1/7 of its period: faster sway is not predictable at 10 Hz by any
//            model and would only measure noise (the tremor is there as such an unpredictable part)
//
// Speeds are those of the tracks of issue 11 (hold 4.9 px at 30 Hz and 1.5 px noise, 2 frames
// ahead: ~65 px/s rms) and above: on a target that moves less over the horizon than the noise,
// no predictor can beat `hold` (measured: hand sway at 40 px/s rms, 10 Hz, 3 px: hold 9.3 px,
// the best kf-cv q 9.8 px), so such tracks would not test a predictor.
//
// Sampling: rate_hz in [1, 1000]; noise n ~ N(0, noise_px^2) per coordinate; a frame is dropped
// (u, v empty) with probability drop_prob, and with probability drop_prob / 5 an occlusion of
// 0.1..0.3 s (at least 2 consecutive frames) begins. The first frame is never dropped. Truth is kept for
// every frame. The same config gives the same track (std::mt19937_64 seeded with `seed`).
#pragma once

#include "predvs/predictors/predictor.h"

#include <cstdint>
#include <string>
#include <vector>

namespace predvs {

enum class ManeuverKind { Smooth, Turns, Stops, Bursts, Zigzag, Hand };

/// Every kind, in display order.
const std::vector<ManeuverKind>& maneuverKinds();
/// "smooth", "turns", "stops", "bursts", "zigzag", "hand".
std::string maneuverKindName(ManeuverKind kind);
/// Inverse of maneuverKindName; throws std::invalid_argument "unknown track kind 'x' (known: ...)".
ManeuverKind parseManeuverKind(const std::string& name);

struct ManeuverTrackConfig {
  ManeuverKind kind = ManeuverKind::Turns;
  double rate_hz = 30.0;     ///< frame rate, [1, 1000]
  double noise_px = 1.0;     ///< Gaussian noise standard deviation per coordinate, >= 0
  double duration_s = 20.0;  ///< > 0; frames at k / rate_hz for k = 0 .. floor(duration * rate)
  double drop_prob = 0.02;   ///< probability of a dropped frame, [0, 0.5]
  double u0_px = 320.0, v0_px = 240.0;  ///< start position
  std::uint64_t seed = 1;     ///< the motion's seed; also the noise's and the drops' when draw = 0
  /// Which draw of the noise and the dropped frames over the motion of `seed`: 0 = the track's own
  /// (seeded from seed alone, as before draws existed); d > 0 = another, independent draw of them
  /// over the same motion and truth (`predvs make-track --draw`, `track-study --draws`).
  std::uint64_t draw = 0;
  /// Probability that a measured frame (after the first) is a tracker glitch: its u, v displaced by
  /// glitch_px in a uniformly drawn direction, for that frame only; [0, 0.5], default 0 (none). The
  /// glitches have their own random stream, so the noise and the drops are those of glitch_prob 0.
  double glitch_prob = 0.0;
  double glitch_px = 15.0;  ///< size of a glitch, px (> 0)
};

/// A generated track: measured u, v (NaN = dropped frame) and truth, per frame.
struct ManeuverTrack {
  std::vector<double> t_s;
  std::vector<double> u_px, v_px;
  std::vector<double> u_true_px, v_true_px;
  size_t glitches = 0;  ///< measured frames displaced by a glitch (ManeuverTrackConfig::glitch_prob)
  size_t size() const { return t_s.size(); }
};

/// Generates a track. Throws std::invalid_argument naming the field on a bad config.
ManeuverTrack generateManeuverTrack(const ManeuverTrackConfig& config);

/// Open-loop score of one predictor on a track, the rule of `predvs predict` (app/predict_command.h):
/// the predictor (2 channels, reset first) is updated with every row (predict-only on a dropped
/// frame) and asked for the position at t_i + horizon_s; that prediction is compared with the
/// measurement (rmse_meas_px) and with the truth (rmse_truth_px), each linearly interpolated at
/// t_i + horizon_s between the nearest finite samples; rows whose target time is outside the span
/// are skipped. rmse = sqrt(mean(du^2 + dv^2)). n = rows scored against the truth.
struct TrackScore {
  double rmse_meas_px = 0.0;
  double rmse_truth_px = 0.0;
  int n = 0;
};
/// Scores rows i >= first_scored_row only (the predictor still sees every row from 0): used to
/// score a predictor fitted on the first part of a track on the rest.
TrackScore scoreOnTrack(const ManeuverTrack& track, Predictor& predictor, double horizon_s,
                        size_t first_scored_row = 0);

}  // namespace predvs
