// Control steps per second of each control law on its own scenario (the scenario files of
// data/scenarios, loaded as `predvs servo` loads them), with the scenario's first predictor that
// extrapolates. One iteration is one full run of the scenario; `steps_per_s` is the figure.
#include "scenario.h"
#include "scenario_file.h"

#include "predvs/predictors/predictor.h"
#include "predvs/servo/servo_loop.h"

#include <benchmark/benchmark.h>

#include <string>

namespace {

using namespace predvs;

// One scenario per law (and per robot where a law runs on several).
constexpr const char* kLawScenarios[] = {"ibvs-moving-target", "e5-line", "e8-vtc", "e9-broyden", "e9-ibvs"};

void BM_Law(benchmark::State& state, const std::string& scenario) {
  const Scenario sc = loadScenario(resolveScenario(scenario));
  std::string name = sc.predictors.front().name;
  Params params = sc.predictors.front().params;
  for (const auto& p : sc.predictors)
    if (makePredictor(p.name, sc.channels, p.params)->extrapolates()) {
      name = p.name;
      params = p.params;
      break;
    }
  auto predictor = makePredictor(name, sc.channels, params);
  long steps = 0;
  for (auto _ : state) {
    ServoLoop loop(sc.closed_loop, *predictor);
    while (!loop.done()) {
      benchmark::DoNotOptimize(loop.step());
      ++steps;
    }
  }
  state.SetLabel(sc.closed_loop.task.name + " on " + sc.closed_loop.robot.name + ", " + name);
  state.counters["steps_per_s"] = benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kIsRate);
}

const bool kRegistered = [] {
  for (const char* s : kLawScenarios)
    benchmark::RegisterBenchmark((std::string("BM_Law/") + s).c_str(), BM_Law, std::string(s))
        ->Unit(benchmark::kMillisecond);
  return true;
}();

}  // namespace
