// predvs app — `--set PATH=VALUE`: a change to a scenario's YAML document made on the command line.
//
// PATH is a dotted path into the document (`timing.delay_frames`, `task.lambda`, `servo.forecast`,
// `noise.sigma`, `predictors.cs-akf.params.a_max`); VALUE is parsed as YAML, so `0.5`, `feature`,
// `[1, 2]` and `{lambda: 2}` all work, and an empty VALUE is null (the key's default, as if absent).
// The change is made to the loaded document BEFORE the strict parse (scenario.h), so the usual
// validation decides whether the key and the value are allowed; loadScenario() then reports an
// error caused by an override as "--set PATH=VALUE (scenario NAME): <what was expected>".
//
// Walking PATH (each step names the document node reached so far):
//   mapping   the longest run of the remaining segments that is an existing key (so a key that
//             contains a dot, like sweep's `noise.sigma`, is found), else the next segment; a
//             missing or null intermediate becomes an empty mapping, a scalar intermediate is an
//             error (it has no keys)
//   list      a segment of digits is a 0-based index (out of range: an error); any other segment
//             selects the element that is that name or a mapping with `name:` that name, as in a
//             scenario's `predictors:` list; a bare name element becomes {name: NAME} when PATH goes
//             deeper, and a missing name is appended as {name: NAME} (so `predictors.cs-akf.params.
//             a_max=100` on a scenario without cs-akf adds cs-akf with that parameter)
//   scalar    an error: nothing can be set inside a value
// The last step replaces (or adds) the value. Overrides are applied in command-line order.
#pragma once

#include <yaml-cpp/yaml.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace predvs {

struct ScenarioOverride {
  std::string text;               ///< "PATH=VALUE" as given (quoted in errors, recorded in outputs)
  std::vector<std::string> path;  ///< PATH split at its dots (none empty)
  YAML::Node value;               ///< VALUE parsed as YAML (null when VALUE is empty)
};

/// A structural `--set` error (malformed argument, scalar intermediate, index out of range): its
/// message already starts with "--set", so loadScenario() passes it on unchanged.
class OverrideError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Parses "PATH=VALUE". Throws OverrideError "--set: expected PATH=VALUE ..., got '...'" when there
/// is no '=', PATH is empty or has an empty segment, or VALUE is not valid YAML.
ScenarioOverride parseScenarioOverride(const std::string& text);

/// Applies one override to a scenario document (a mapping; a copy of the value is stored, so one
/// override can be applied to many documents). Throws OverrideError "--set TEXT: ..." for a
/// scalar intermediate or a list index out of range.
void applyScenarioOverride(YAML::Node& document, const ScenarioOverride& override_);

/// The texts of `overrides`, in order (for summary.json / leaderboard.json).
std::vector<std::string> overrideTexts(const std::vector<ScenarioOverride>& overrides);

/// Turns an error "FILE:LINE: WHAT" raised while parsing `file` with `override_` applied into
/// "--set TEXT (scenario NAME): WHAT" (the line would point into the file, not at the override).
std::string overrideErrorMessage(const ScenarioOverride& override_, const std::string& file,
                                 const std::string& message);

}  // namespace predvs
