// predvs app — campaigns of `predvs compare` beyond one process (issue #12): one stored record per
// run, resuming from the records, deterministic shards and their merge.
//
// Run record: every finished run of a campaign is stored as one small JSON file
//   runs/<variant id>__<predictor label>__seed<S>.json  (file-safe: fileSafe(), report.h)
//   {"format": 1, "predvs_version", "scenario", "variant", "predictor", "seed", "run",
//    "scenario_hash", "values": [[name, x], ...], "t_s": [...], "error": [...]}
// keyed by (variant id = scenario and sweep cell, predictor label, seed). t_s / error (the error
// versus time) only for the variants whose error is plotted (Variant::shown), empty otherwise.
// Numbers: finite ones as JSON numbers in the shortest text that reads back to the same double,
// non-finite ones as the strings "nan", "inf", "-inf"; so an output computed from records read
// back is byte-identical to one computed from runs in memory.
// scenario_hash: FNV-1a 64 (hex) over the scenario file's bytes, the --set overrides (their
// texts; --camera / --set-file arrive as overrides), the sweep cell (KEY=value per axis) and the
// predictor entry (label, type, parameters). Files a scenario refers to (images) are not hashed.
// A record is reused only when its key, predvs_version (PROJECT_VERSION) and scenario_hash all
// match the run's; otherwise it is "stale" and the run is computed again.
//
// Journal: while a campaign runs, each record is written (to a temporary name, then renamed, so
// a kill never leaves half a record) into OUT.partial/runs/ as its run completes. On success the
// output directory OUT gets runs/ with the record of every run of the campaign (or shard) and
// OUT.partial is removed; after an interruption OUT.partial stays, and `--resume OUT.partial`
// (or `--resume DIR` of any earlier campaign or shard: DIR/runs/ or DIR itself) reuses its records.
//
// Shards: `--shard I/N` (1 <= I <= N) runs the jobs j (planJobs() order, 0-based) with
// j mod N = I - 1 (round robin, so that the costly cells of a grid spread over the shards) and
// writes OUT/runs/ and OUT/shard.json {"format", "predvs_version", "shard", "of", "campaign"
// (FNV-1a 64 over every job's record name and scenario hash, in job order), "command", "options"
// (what rebuilds the plan: scenarios, predictors, runs, seed, overrides, sweeps), "runs_total",
// "runs_in_shard"}; no leaderboard. `predvs merge DIR... --out OUT` checks that the DIRs are the
// shards 1..N of one campaign, each exactly once (an error names a missing or duplicated shard),
// rebuilds the plan from "options", checks its fingerprint (the scenario files did not change),
// reads every run's record and writes the outputs of the campaign as a single run would.
//
// Command: the leaderboards and report.html record the campaign command without the options that
// only say where and how it ran (--out, --jobs, --shard, --resume, --stop-after), so the outputs
// do not depend on them.
#pragma once

#include "compare_command.h"
#include "compare_plan.h"

#include <cstdint>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace predvs {

/// --shard I/N parsed; count 0 = not sharded.
struct ShardSpec {
  int index = 0;  ///< 1-based
  int count = 0;
};
/// Parses "I/N"; throws std::invalid_argument "--shard: ..." unless 1 <= I <= N <= 100000.
ShardSpec parseShard(const std::string& text);

/// `args` (a `predvs compare` command line, without the program) without --out, --jobs, --shard,
/// --resume, --stop-after and their values (both "--opt V" and "--opt=V").
std::vector<std::string> campaignArgs(const std::vector<std::string>& args);

/// The identity of each job of a plan (planJobs() order).
struct JobKey {
  std::string record_name;    ///< file name of its record (with .json)
  std::string scenario_hash;  ///< 16 hex digits
};
std::vector<JobKey> jobKeys(const Plan& plan, const CompareOptions& options, const std::vector<Job>& jobs);
/// FNV-1a 64 over the job keys, in order (hex).
std::string campaignFingerprint(const std::vector<JobKey>& keys);

/// The record of job `job` holding `run` (t_s / error dropped unless the variant is shown).
std::string recordText(const Plan& plan, const Job& job, const JobKey& key, const RunRecord& run);
/// Reads a record; false (with `why`) when it is unreadable or not the record of (job, key) of
/// this predvs version.
bool parseRecord(const std::string& text, const Plan& plan, const Job& job, const JobKey& key, RunRecord& run,
                 std::string& why);

/// Validates, runs (threads, MPI ranks under mpirun, a shard, resuming), writes the outputs and
/// prints the leaderboard (runCompareCommand()).
void runCampaign(const CompareOptions& options, std::ostream& out, std::ostream& err);

struct MergeOptions {
  std::vector<std::string> dirs;  ///< shard output directories
  std::string out_dir = "out/compare";
  bool plots = true;
};
/// `predvs merge`: the outputs of a campaign from its shards. Throws std::invalid_argument naming
/// the directory, shard or record at fault (nothing is written then).
void runMergeCommand(const MergeOptions& options, std::ostream& out, std::ostream& err);

}  // namespace predvs
