// kf-cv as a plain CV Kalman filter, as the scenario files pin it (data/scenarios/
// ibvs-moving-target.yaml: q and r fixed, no significance weighting, no blend with hold): the
// like-for-like of ViSP's and OpenCV's filters (predictor_bench.cpp) and the loop figure of the
// scenarios (servo_bench.cpp).
#pragma once

#include "predvs/predictors/params.h"

namespace predvs {

inline constexpr double kPlainKfCvQ = 100.0;  ///< white-acceleration density, px^2/s^3
inline constexpr double kPlainKfCvR = 1.0;    ///< measurement variance, px^2

inline Params plainKfCvParams() {
  return Params{{"q", kPlainKfCvQ}, {"r", kPlainKfCvR}, {"shrink_sigmas", 0.0}, {"hold_blend_tau_s", 0.0}};
}

}  // namespace predvs
