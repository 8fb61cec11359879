// `predvs compare` (compare_command.h): plan (compare_plan.h) -> the runs not yet stored, on a pool
// of threads or over MPI ranks, each stored as a record as it completes (campaign.h) ->
// aggregation in run order, so the leaderboard does not depend on --jobs, ranks, shards or
// resuming -> report (compare_report.h, campaign_html.h).
#include "compare_command.h"

#include "campaign.h"

namespace predvs {

void runCompareCommand(const CompareOptions& o, std::ostream& out, std::ostream& err) { runCampaign(o, out, err); }

}  // namespace predvs
