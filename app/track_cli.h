// predvs app — the subcommands on feature tracks: predict, fit-noise, make-track, track-study.
// They need the predictors, the noise fit and the track generator, and none of ViSP's image,
// robot or detection libraries nor OpenCV's codecs, whose 300 shared libraries take a quarter of
// a second to load. So the `predvs` executable (app/main.cpp) is linked with these alone and runs
// them itself; every other command line it hands to `predvs-all` beside it (app/all_main.cpp,
// runCli of cli.h, which has every subcommand, these four included, with the same definitions).
#pragma once

#include "predict_command.h"  // PredictorSpec

#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace predvs {

/// Adds the four subcommands to `app` (their options, help and footers) and runs the one parsed.
class TrackSubcommands {
 public:
  explicit TrackSubcommands(CLI::App& app);
  ~TrackSubcommands();
  TrackSubcommands(const TrackSubcommands&) = delete;
  TrackSubcommands& operator=(const TrackSubcommands&) = delete;

  /// After `app` parsed: the exit status of the one of these it parsed (0; errors throw
  /// std::invalid_argument / std::runtime_error naming the option or file), or std::nullopt when
  /// it parsed another subcommand. `command_line` is recorded in the outputs (commandLine()).
  std::optional<int> run(const std::string& command_line, std::ostream& out, std::ostream& err) const;

  /// The subcommands' names, in the order they are added.
  static std::vector<std::string> names();

 private:
  struct State;
  std::unique_ptr<State> s_;
};

/// --predictor of predict and track: 'all' or a comma list of [LABEL=]NAME[:KEY=VALUE...]
/// (parsePredictorSpecs, predict_command.h).
std::vector<PredictorSpec> predictorSpecs(const std::string& text);

/// The command line of the four alone (`args` without the program name), as runCli() runs it:
/// the same exit statuses, outputs and one-line errors.
int runTrackCli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace predvs
