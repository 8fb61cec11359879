// predvs app — the outputs of `predvs servo` (one run per predictor on one seed); the file list
// and their columns are in servo_command.h.
#pragma once

#include "output_dir.h"
#include "scenario.h"
#include "scenario_override.h"
#include "scenario_run.h"

#include <ostream>
#include <string>
#include <vector>

namespace predvs {

struct ServoReport {
  const Scenario* scenario = nullptr;  ///< as run (predictors chosen, seed set)
  std::vector<RunRecord> runs;         ///< one per scenario predictor, in order, with their traces
  std::string command_line;
  std::vector<ScenarioOverride> overrides;
};

/// Writes log.csv, summary.json and, with `plots`, the figures into `dir` (staging). Returns the
/// names of the files written that a user reads first (log.csv, summary.json, the PNGs).
std::vector<std::string> writeServoReport(const ServoReport& report, bool plots, const StagedOutputDir& dir);

/// The metrics table of the runs (report.h: the columns both commands print).
void printServoReport(const ServoReport& report, std::ostream& out);

}  // namespace predvs
