// `predvs servo` (servo_command.h): load the scenario -> one run per predictor on the same seed
// (runScenarioOnce(), scenario_run.h: the same runs as `predvs compare`) -> report
// (servo_report.h). The runs happen before the output directory is staged, and the directory is
// renamed into place only when every file is written, so a failing run leaves nothing behind.
#include "servo_command.h"

#include "gnuplot.h"
#include "output_dir.h"
#include "scenario.h"
#include "scenario_file.h"
#include "scenario_run.h"
#include "servo_report.h"

#include <chrono>
#include <iomanip>

namespace predvs {

void runScenarioCommand(const ScenarioRunOptions& o, std::ostream& out, std::ostream& err) {
  const std::string path = resolveScenario(o.scenario);
  Scenario sc = loadScenario(path, o.overrides);
  if (o.seed_given) sc.setSeed(o.seed);
  choosePredictors(sc, o.predictors, "--predictors");
  if (o.plots) requireGnuplot();
  const std::string out_dir = o.out_dir.empty() ? "out/" + sc.name : o.out_dir;
  std::vector<std::string> inputs = o.inputs;
  inputs.push_back(path);
  StagedOutputDir::checkReplaceable(out_dir, inputs);
  if (!sc.sweeps.empty())
    err << "predvs: " << sc.name << ": the sweep over " << sweepKeysText(sc.sweeps)
        << " is not run by `predvs servo`, which runs the scenario with the value its file gives; run the sweep with "
           "`predvs compare --scenarios "
        << sc.name << "`\n";

  ServoReport report;
  report.scenario = &sc;
  report.command_line = o.command_line;
  report.overrides = o.overrides;
  const size_t n = sc.predictors.size();
  for (size_t i = 0; i < n; ++i) {
    err << "predvs: [" << (i + 1) << "/" << n << "] " << sc.name << ": " << sc.predictors[i].name << " ..." << std::flush;
    const auto start = std::chrono::steady_clock::now();
    report.runs.push_back(runScenarioOnce(sc, sc.predictors[i], sc.seed(), true));
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    err << " " << report.runs.back().rows.size() << " steps in " << std::fixed << std::setprecision(2) << secs
        << " s\n"
        << std::defaultfloat;
  }

  StagedOutputDir dir(out_dir);
  const std::vector<std::string> written = writeServoReport(report, o.plots, dir);
  dir.commit();

  out << sc.name << " (" << scenarioKindName(sc.kind) << ", seed " << sc.seed() << ", " << sc.durationS()
      << " s): " << (sc.kind == ScenarioKind::OpenLoop ? "prediction error" : "tracking error") << " per predictor\n";
  printServoReport(report, out);
  const std::string where = dir.target().string();
  out << "wrote ";
  for (size_t i = 0; i < written.size(); ++i) out << (i ? ", " : "") << where << "/" << written[i];
  out << "\n";
}

}  // namespace predvs
