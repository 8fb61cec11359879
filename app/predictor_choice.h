// predvs app — one element of a predictor list on the command line, `[LABEL=]TYPE[:KEY=VALUE...]`
// (`--predictors` of servo, compare and track-study; `--predictor` of predict and track). Needs
// the predictor registry only, so the track commands (track_cli.h) use it without the scenarios.
#pragma once

#include "predvs/predictors/params.h"

#include <string>

namespace predvs {

/// One element of `--predictors` (compare, servo): `[LABEL=]TYPE[:KEY=VALUE[:KEY=VALUE...]]`.
///   kf-cv                         the registry predictor kf-cv under its own name
///   kf-cv-paper=kf-cv:r=5:q=20    kf-cv labelled kf-cv-paper, with r = 5 and q = 20
///   st-akf-pm:pm_band=4           st-akf-pm (label st-akf-pm) with pm_band = 4
/// ',' separates elements, ':' the parameters of one, '=' a label from its type and a key from its
/// value: none of the three can occur in a label, a type or a key, so the syntax is unambiguous.
/// VALUEs are numbers. LABEL: letters, digits, '-' and '_' (it names files and `--set` paths).
struct PredictorChoice {
  std::string label;  ///< the name shown in leaderboards, plots and traces
  std::string type;   ///< registry name
  Params params;      ///< the KEY=VALUE given (on top of the scenario's own, see choosePredictors)
  bool labelled = false;  ///< LABEL= given
  /// A bare word (no '=', no ':'): a registry name or a label of the scenario's own list (then
  /// resolved by choosePredictors; parsePredictorChoice accepts any well-formed word here).
  bool bare = false;
};
/// Parses one element; throws std::invalid_argument "OPTION: ..." naming the element and what was
/// expected (unknown type, empty or malformed label, key or value, a key twice).
PredictorChoice parsePredictorChoice(const std::string& text, const std::string& option);

/// Why `label` cannot name a predictor entry ("" when it can): it must be non-empty and made of
/// letters, digits, '-' and '_' (it appears in file names, `--set predictors.LABEL...` paths and
/// the `--predictors` syntax, whose separators are ',', ':' and '='). With `type`: nor may it be
/// the name of another registered predictor (`hold=kf-cv` would show kf-cv's figures as hold's).
std::string predictorLabelProblem(const std::string& label, const std::string& type = "");

}  // namespace predvs
