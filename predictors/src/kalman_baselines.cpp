#include "predvs/predictors/kalman_baselines.h"

namespace predvs {

HoldPredictor::HoldPredictor(int channels, const Params& params)
    : ChannelPredictor<2>(channels, params.get("r", 1.0, 0.0, 1e12), 0.0, 0.0) {}

void HoldPredictor::step(int c, double /*dt*/, double z) {
  if (!isMeasured(z)) return;
  ChannelState& s = state_[c];
  s.innovation = Innovation{z - s.g.x(0), measurementNoise(c), true};
  s.g.x << z, 0.0;
}

KfCvPredictor::KfCvPredictor(int channels, const Params& params)
    : ChannelPredictor<2>(channels, measurementNoiseParam(params, 1.0), params.get("p0_vel", 1e4, 0.0, 1e12), 0.0),
      q_(processNoiseParam(params, "q", kDefaultQCv, 0.0, 1e12)) {
  readCoastParam(params);
  readShrinkParams(params, kDefaultShrinkSigmasKfCv, /*weigh_velocity=*/true);
  readProcessNoiseAdaptation(params);
  if (isAutoMeasurementNoise(params)) enableAutoNoise();
}

KfCaPredictor::KfCaPredictor(int channels, const Params& params)
    : ChannelPredictor<3>(channels, measurementNoiseParam(params, 1.0), params.get("p0_vel", 1e4, 0.0, 1e12),
                          params.get("p0_acc", 1e4, 0.0, 1e12)),
      q_(processNoiseParam(params, "q", kDefaultQCa, 0.0, 1e15)) {
  readCoastParam(params);
  readShrinkParams(params, kDefaultShrinkSigmasKfCa, kDefaultShrinkVelocityKfCa);
  readProcessNoiseAdaptation(params, kDefaultQWhiteRhoAcceleration);
  if (isAutoMeasurementNoise(params)) enableAutoNoise();
}

}  // namespace predvs
