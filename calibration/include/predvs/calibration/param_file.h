// predvs calibration — the predictor parameter file: what `predvs fit-noise` and the Python
// module's fit_noise write, and what `predict / servo / compare --params FILE` and
// predvs.read_params() read.
//
// Format (YAML), the same shape as a scenario's `predictors:` list:
//   # comment lines: what was fitted, on which track, the likelihood before/after
//   predictors:
//     - {name: kf-cv, params: {q: 123.4, r: 2.25}}
// Every name must be a registered predictor and every value a number (or the word `auto`, kept as
// text: the start-up estimate of r); each entry is checked by building its predictor
// (makePredictor(name, 2, params)), so an unknown or out-of-range key is reported with the line of
// its entry. Numbers are written with 12 significant digits.
//
// Moved here from app/fit_command (issue 13 item 3) so that the Python module can link it; the
// app keeps readParamsFile/paramsFileText as thin wrappers, with the same messages.
#pragma once

#include "predvs/predictors/params.h"

#include <string>
#include <vector>

namespace predvs {

/// One entry of a parameter file: a registered predictor and its params.
struct ParamFileEntry {
  std::string name;
  Params params;
};

/// Reads a parameter file (format above). Throws std::invalid_argument "FILE: ..." or
/// "FILE:LINE: ..." on any defect, "FILE: cannot open the parameter file" when it cannot be read.
std::vector<ParamFileEntry> readParamFile(const std::string& path);

/// The YAML text of a parameter file for `entries`, each line of `comment` first as "# LINE".
std::string paramFileText(const std::vector<ParamFileEntry>& entries, const std::vector<std::string>& comment);

}  // namespace predvs
