// predvs app — the outputs of `predvs compare` (leaderboard.{csv,json,md} and the plots; the list
// is in compare_command.h), from the aggregated runs of a plan (compare_plan.h).
#pragma once

#include "compare_command.h"
#include "compare_plan.h"
#include "output_dir.h"

#include <ostream>

namespace predvs {

/// How the runs went, for leaderboard.md.
struct CompareRunInfo {
  double wall_s = 0.0;
  int workers = 1;
};

/// Writes the leaderboard files and, with options.plots, the plots into `dir` (staging).
void writeCompareReport(const Plan& plan, const Results& res, const CompareOptions& options, const CompareRunInfo& info,
                        const StagedOutputDir& dir);

/// The table of every shown variant (report.h: the columns both commands print), means over runs.
void printCompareReport(const Plan& plan, const Results& res, std::ostream& out);

}  // namespace predvs
