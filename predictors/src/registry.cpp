// The predictor registry: adding a predictor is one entry here (and one line in the property
// suite, tests/predictors/property_test.cpp).
#include "predvs/predictors/cs_akf.h"
#include "predvs/predictors/fakf.h"
#include "predvs/predictors/glitch_gate.h"
#include "predvs/predictors/imm.h"
#include "predvs/predictors/kalman_baselines.h"
#include "predvs/predictors/predictor.h"
#include "predvs/predictors/st_akf.h"
#include "predvs/predictors/stkf.h"

#include <functional>
#include <limits>
#include <stdexcept>

namespace predvs {
namespace {

using Factory = std::function<std::unique_ptr<Predictor>(int, const Params&)>;

struct Entry {
  PredictorInfo info;
  Factory make;
};

template <class P>
Factory factory() {
  return [](int channels, const Params& params) { return std::make_unique<P>(channels, params); };
}

const std::vector<Entry>& entries() {
  static const std::vector<Entry> table = {
      {{"hold", "no prediction: the last (delayed) measurement"}, factory<HoldPredictor>()},
      {{"kf-cv", "Kalman filter, constant-velocity model"}, factory<KfCvPredictor>()},
      {{"kf-ca", "Kalman filter, constant-acceleration model"}, factory<KfCaPredictor>()},
      {{"cs-akf", "current-statistical-model KF: Singer Q, Rayleigh variance with fixed a_max"}, factory<CsAkfPredictor>()},
      {{"cs-akf-adaptive", "CS-model KF, variance adapted from successive acceleration estimates"}, factory<CsAkfAdaptivePredictor>()},
      {{"stkf", "self-tuning KF: CA model (model: cv, the paper's, for CV), R from quadratic (line) fit residuals of the last k frames"}, makeStkfPredictor},
      {{"st-akf", "strong-tracking adaptive KF: CA (or model: cv) Kalman filter with fading factors"}, makeStAkfPredictor},
      {{"st-akf-pm", "st-akf re-initialised by the predictive discontinuity monitor"}, makeStAkfPmPredictor},
      {{"fakf-classic", "fuzzy adaptive KF (Escamilla-Ambrosio & Mort): CV (or model: ca), R += fuzzy(C - S)"}, makeFakfClassicPredictor},
      {{"fakf", "improved fuzzy adaptive KF (paper 000): adaptive CS model, R *= fuzzy(E', C - S), fuzzy P inflation"}, factory<FakfPredictor>()},
      {{"imm", "interacting multiple model: CP + CV + CA Kalman filters mixed by mode probabilities"}, factory<ImmPredictor>()},
  };
  return table;
}

}  // namespace

const std::vector<PredictorInfo>& predictorRegistry() {
  static const std::vector<PredictorInfo> infos = [] {
    std::vector<PredictorInfo> out;
    for (const auto& e : entries()) out.push_back(e.info);
    return out;
  }();
  return infos;
}

bool isPredictor(const std::string& name) {
  for (const auto& e : entries())
    if (e.info.name == name) return true;
  return false;
}

double horizonFramesParam(const Params& params) {
  return params.get("horizon_frames", 0.0, 0.0, std::numeric_limits<double>::max());  // any horizon a command takes
}

bool closedLoopParam(const Params& params) {
  const double v = params.get("closed_loop", 0.0, 0.0, 1.0);
  if (v != 0.0 && v != 1.0) throw std::invalid_argument("closed_loop: expected 0 or 1");
  return v == 1.0;
}

std::unique_ptr<Predictor> makePredictor(const std::string& name, int channels, const Params& params) {
  for (const auto& e : entries()) {
    if (e.info.name != name) continue;
    auto p = withGlitchGate(e.make(channels, params), glitchSigmasParam(params));
    horizonFramesParam(params);  // facts about the queries and their use: every predictor takes them (predictor.h)
    closedLoopParam(params);
    params.requireAllUsed("predictor '" + name + "'");
    return p;
  }
  std::string known;
  for (const auto& e : entries()) known += (known.empty() ? "" : ", ") + e.info.name;
  throw std::invalid_argument("unknown predictor '" + name + "' (known: " + known + ")");
}

}  // namespace predvs
