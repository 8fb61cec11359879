// predvs app — scenario overrides that come from files: `--camera FILE` (a ViSP camera XML) and
// `--set-file FILE` (a YAML fragment such as the timing.yaml `predvs calibrate latency` writes).
//
// Both become ordinary `--set PATH=VALUE` overrides (scenario_override.h), so the strict scenario
// parse validates them like any other, and they are recorded in summary.json / leaderboard.json.
// Order on a command line (choice): --set-file first, then --camera, then every --set, so that an
// explicit --set wins over a file.
//   --camera FILE        the perspectiveProjWithoutDistortion model of the camera named by
//                        --camera-name (default: the first camera in the file) sets camera.px,
//                        camera.py, camera.u0, camera.v0, and camera.width / camera.height when the
//                        file gives the image size. The simulated camera has no distortion: a file
//                        with only a model with distortion is an error. Closed-loop scenarios only
//                        (an open-loop scenario has no camera: its strict parse rejects the key).
//   --set-file FILE      a YAML mapping; every scalar or sequence leaf at a dotted path becomes
//                        PATH=VALUE, in file order (a null leaf, `key: ~`, removes the key, e.g.
//                        timing.delay_frames when the fragment gives the lags instead).
#pragma once

#include "scenario_override.h"

#include <string>
#include <vector>

namespace predvs {

/// Throws std::invalid_argument "--camera FILE: ..." for a missing file, an unknown camera name
/// or a file without a model without distortion.
std::vector<ScenarioOverride> cameraOverrides(const std::string& file, const std::string& camera_name);

/// Throws std::invalid_argument "--set-file FILE: ..." (with the line when YAML gives one) for a
/// missing file, invalid YAML or a document that is not a mapping.
std::vector<ScenarioOverride> setFileOverrides(const std::string& file);

}  // namespace predvs
