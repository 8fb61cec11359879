// predvs tests — one cell of a generated-track grid (servo/maneuver_tracks.h): the track of a kind
// at a frame rate (Hz), a noise (px, Gaussian standard deviation per coordinate), a duration (s)
// and a seed (and a dropped-frame probability), with the generator's other defaults (2 % dropped frames, start at (320, 240) px), as
// `predvs track-study` builds its grids. Used by the servo grid tests (maneuver_tracks_test.cpp,
// imm_tracks_test.cpp) and the noise-fit tests (tests/calibration/noise_fit_test.cpp).
#pragma once

#include "predvs/servo/maneuver_tracks.h"

#include <cstdint>

namespace predvs {

/// The generated track of that cell (the config's other fields at their defaults; drop_prob, the
/// probability of a dropped frame, at the generator's 2 % unless given, as `track-study --drop`).
inline ManeuverTrack maneuverTrackCell(ManeuverKind kind, double rate_hz, double noise_px, double duration_s,
                                       std::uint64_t seed, double drop_prob = ManeuverTrackConfig{}.drop_prob,
                                       std::uint64_t draw = 0) {
  ManeuverTrackConfig c;
  c.kind = kind;
  c.rate_hz = rate_hz;
  c.noise_px = noise_px;
  c.duration_s = duration_s;
  c.seed = seed;
  c.drop_prob = drop_prob;
  c.draw = draw;  // another draw of the noise and the drops (make-track --draw)
  return generateManeuverTrack(c);
}

}  // namespace predvs
