// predvs app — `predvs servo`: run a scenario file and write log.csv, summary.json and plots.
#pragma once

#include "scenario_override.h"

#include <ostream>
#include <string>
#include <vector>

namespace predvs {

struct ScenarioRunOptions {
  std::string scenario = "ibvs-moving-target";  ///< name in data/scenarios or a .yaml path
  std::vector<std::string> predictors;           ///< overrides the scenario's list when not empty
  bool seed_given = false;
  unsigned long seed = 0;                        ///< overrides the scenario's seed when seed_given
  std::vector<ScenarioOverride> overrides;       ///< --set PATH=VALUE, applied before validation
  std::string out_dir;                           ///< empty: out/<scenario name>
  bool plots = true;
  std::string command_line;                      ///< recorded in summary.json
};

/// Loads, runs and reports a scenario. Throws std::invalid_argument / std::runtime_error for bad
/// input (the output directory is then not created).
void runScenarioCommand(const ScenarioRunOptions& options, std::ostream& out, std::ostream& err);

}  // namespace predvs
