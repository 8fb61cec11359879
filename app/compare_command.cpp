// `predvs compare` (compare_command.h): plan (compare_plan.h) -> a pool of threads over the
// independent seeded runs (parallel_runs.h; each run is runScenarioOnce(), scenario_run.h) ->
// aggregation in run order, so the leaderboard does not depend on --jobs -> report
// (compare_report.h).
#include "compare_command.h"

#include "compare_plan.h"
#include "compare_report.h"
#include "gnuplot.h"
#include "output_dir.h"
#include "parallel_runs.h"
#include "scenario_run.h"

#include <algorithm>
#include <chrono>
#include <iomanip>
#include <thread>

namespace predvs {

void runCompareCommand(const CompareOptions& o, std::ostream& out, std::ostream& err) {
  ParallelOptions par;
  par.start = std::chrono::steady_clock::now();
  const Plan plan = makePlan(o);
  if (o.plots) requireGnuplot();

  const std::vector<Job> jobs = planJobs(plan);
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  const int threads = o.jobs > 0 ? o.jobs : static_cast<int>(hw);
  par.workers = static_cast<int>(std::min<size_t>(static_cast<size_t>(threads), std::max<size_t>(1, jobs.size())));
  par.progress_bar = o.progress_bar;
  err << "predvs: compare: " << plan.scenarios.size() << " scenarios (" << plan.variants.size() << " variants), "
      << jobs.size() << " runs on " << par.workers << " threads\n";

  std::vector<RunRecord> outcomes(jobs.size());
  runParallel(
      jobs.size(),
      [&](size_t i) {
        const Job& job = jobs[i];
        const Scenario& sc = *plan.variants[job.variant].scenario;
        outcomes[i] = runScenarioOnce(sc, sc.predictors[job.predictor], jobSeed(plan, job), false);
        if (!plan.variants[job.variant].shown) {  // only shown variants plot their error: keep a big grid small
          std::vector<double>().swap(outcomes[i].t_s);
          std::vector<double>().swap(outcomes[i].error);
        }
      },
      par, err);

  const Results res = aggregate(plan, jobs, outcomes);
  CompareRunInfo info;
  info.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - par.start).count();
  info.workers = par.workers;
  StagedOutputDir dir(o.out_dir);
  writeCompareReport(plan, res, o, info, dir);
  dir.commit();

  printCompareReport(plan, res, out);
  out << "\n" << jobs.size() << " runs in " << std::fixed << std::setprecision(1) << info.wall_s << " s on "
      << par.workers << " threads" << std::defaultfloat << "; wrote " << (dir.target() / "leaderboard.md").string()
      << ", leaderboard.csv, leaderboard.json" << (o.plots ? " and plots" : "") << "\n";
}

}  // namespace predvs
