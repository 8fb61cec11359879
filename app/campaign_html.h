// predvs app — report.html of a `predvs compare` campaign (issue #12): one self-contained page,
// no server, no network: the leaderboard as a sortable table (every variant and predictor: the
// mean over runs of the columns leaderboard.md shows; a click on a header sorts by it, again to
// reverse; a few lines of inline JavaScript, no library), the grids' heat maps and every other PNG
// plot of the output directory embedded as data: URIs (base64), the scenario set-ups (file,
// description, runs, seeds, overrides, sweep or grid, and the scenario file's text) and the
// campaign command (campaign.h: without --out, --jobs, --shard, --resume). The script marks
// <body data-report-ready="ROWS"> once it has run, and data-images-loaded="OK/ALL" (images decoded
// with a non-zero width / images) at the load event, so a headless browser can tell that it ran
// without error and showed every plot. Nothing in it depends on wall time, threads or ranks.
#pragma once

#include "compare_command.h"
#include "compare_plan.h"
#include "output_dir.h"

namespace predvs {

/// Writes report.html into `dir` (staging), after the plots (it embeds the PNGs found there).
void writeReportHtml(const Plan& plan, const Results& res, const CompareOptions& options, const StagedOutputDir& dir);

}  // namespace predvs
