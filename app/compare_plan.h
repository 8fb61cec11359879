// predvs app — what `predvs compare` runs (the plan: scenarios, sweep variants, predictors, runs,
// seeds; compare_command.h) and the aggregation of the runs' figures over runs.
#pragma once

#include "compare_command.h"
#include "report.h"
#include "scenario.h"
#include "scenario_run.h"

#include <cstdint>
#include <deque>
#include <limits>
#include <string>
#include <vector>

namespace predvs {

/// One scenario at one sweep value, or at one cell of a grid (one value per axis).
struct Variant {
  const Scenario* scenario = nullptr;  ///< the scenario loaded with this sweep value (cell) applied
  size_t scenario_index = 0;
  bool swept = false;
  size_t sweep_index = 0;  ///< position of the value in the sweep (of the cell in the grid, gridIndices())
  bool shown = true;       ///< in leaderboard.md, the printed table and the error plots
                           ///< (a sweep's first and last value, a grid's first and last cell, only)
  std::vector<size_t> indices;      ///< per axis: the index of the cell's value
  std::vector<std::string> values;  ///< per axis: the value as YAML text
  std::vector<double> xs;           ///< per axis: the value as a number (NaN when it is not one)
  std::string value;       ///< the first axis' value as YAML text ("" without a sweep)
  double x = std::numeric_limits<double>::quiet_NaN();      ///< the first axis' value as a number (NaN when it is not one)
  double sigma = std::numeric_limits<double>::quiet_NaN();  ///< noise.sigma of this variant
  /// "e6-noise-study@sigma=10", "delay-study@delay_frames=1", "e10@lambda=1.4,frame_period_n=8" (the
  /// last segment of each key; the whole keys when two axes share it) or the scenario name
  std::string id;
  std::string file_id;  ///< file-name-safe id
};

struct Plan {
  std::vector<Scenario> scenarios;         ///< as loaded (with --set, --sweep and --predictors applied)
  std::vector<int> runs;                   ///< per scenario
  std::vector<std::uint64_t> seeds;        ///< base seed per scenario
  std::deque<Scenario> variant_scenarios;  ///< per swept variant: the scenario at that value
  std::vector<Variant> variants;
};

/// Loads and validates every scenario, sweep value and predictor (nothing runs). Throws
/// std::invalid_argument naming the option, file or override at fault.
Plan makePlan(const CompareOptions& options);

/// One seeded run: variant, predictor (index into the variant's scenario predictors), run r.
struct Job {
  size_t variant;
  size_t predictor;
  int run;
};
/// Every run of the plan: variants in order, then predictors, then runs. A run is identified by
/// (scenario, cell values, predictor, seed) and computed from them alone, so any subset of the
/// jobs can run anywhere, in any order (the grid of issue #9: shards, resume).
std::vector<Job> planJobs(const Plan& plan);
/// The seed of a job: the scenario's base seed S + r.
std::uint64_t jobSeed(const Plan& plan, const Job& job);

struct Cell {                            ///< one (variant, predictor)
  std::vector<Stats> stats;              ///< per metric of the variant
  std::vector<double> t_s, mean_error;   ///< mean over runs per tick
};

struct Results {
  std::vector<std::vector<std::string>> metrics;  ///< [variant]: the runs' figure names, in order
  std::vector<std::vector<Cell>> cells;           ///< [variant][predictor]
};

/// Summarises the runs (outcomes[i] is the run of jobs[i]) per variant and predictor, in run
/// order, so that the result does not depend on which thread ran what.
Results aggregate(const Plan& plan, const std::vector<Job>& jobs, const std::vector<RunRecord>& outcomes);

/// Predictor order of a variant: by mean rmse, NaN last, ties by name.
std::vector<size_t> ranking(const Plan& plan, const Results& res, size_t v);
/// Variants of scenario i, in sweep order.
std::vector<size_t> variantsOf(const Plan& plan, size_t i);
/// Index of metric `name` of variant v (std::logic_error if it has none).
size_t metricIndex(const Results& res, size_t v, const std::string& name);

}  // namespace predvs
