#include "compare_plan.h"

#include "scenario_file.h"

#include "predvs/predictors/predictor.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A sweep value as a finite number (NaN when the YAML text is not one).
double numberOf(const std::string& text) {
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0' && std::isfinite(x) ? x : kNaN;
}

/// A sweep value in a variant name: numbers printed plainly (1.0 -> 1, as sigma always was).
std::string valueLabel(const std::string& text) {
  const double x = numberOf(text);
  if (!std::isfinite(x)) return text;
  std::ostringstream s;
  s << x;
  return s.str();
}

std::vector<std::string> predictorNames(const Scenario& sc) {
  std::vector<std::string> names;
  for (const auto& p : sc.predictors) names.push_back(p.name);
  return names;
}

std::vector<std::string> uniqueNames(const std::vector<std::string>& names, const std::string& option) {
  std::set<std::string> seen;
  for (const auto& n : names)
    if (!seen.insert(n).second) throw std::invalid_argument(option + ": '" + n + "' listed twice");
  return names;
}

double noiseSigma(const Scenario& sc) {
  return sc.kind == ScenarioKind::OpenLoop ? sc.open_loop.noise.sigma : sc.closed_loop.noise.sigma;
}

std::vector<std::string> scenarioPaths(const CompareOptions& o) {
  std::vector<std::string> paths;
  if (o.scenarios.size() == 1 && o.scenarios[0] == "all") {
    for (const auto& s : listScenarios()) paths.push_back(resolveScenario(s.name));
    if (paths.empty()) throw std::invalid_argument("--scenarios: no scenario files in " + scenariosDir());
    return paths;
  }
  if (o.scenarios.empty()) throw std::invalid_argument("--scenarios: expected a comma-separated list of scenarios or 'all'");
  for (const auto& s : uniqueNames(o.scenarios, "--scenarios")) {
    if (s == "all") throw std::invalid_argument("--scenarios: 'all' cannot be combined with names");
    try {
      paths.push_back(resolveScenario(s));
    } catch (const std::invalid_argument& e) {  // name our option, not `predvs servo`'s
      std::string msg = e.what();
      if (msg.rfind("--scenario:", 0) == 0) msg = "--scenarios:" + msg.substr(11);
      throw std::invalid_argument(msg);
    }
  }
  return paths;
}

std::vector<std::string> chosenPredictors(const CompareOptions& o) {
  std::vector<std::string> chosen;
  if (o.predictors.size() == 1 && o.predictors[0] == "all") {
    for (const auto& p : predictorRegistry()) chosen.push_back(p.name);
    return chosen;
  }
  std::set<std::string> labels;
  for (const auto& p : o.predictors) {
    if (p == "all") throw std::invalid_argument("--predictors: 'all' cannot be combined with names");
    const PredictorChoice c = parsePredictorChoice(p, "--predictors");  // validated before any file is read
    if (!labels.insert(c.label).second)
      throw std::invalid_argument("--predictors: '" + c.label + "' listed twice (give each its own LABEL=TYPE:...)");
    chosen.push_back(p);
  }
  return chosen;
}

/// The names of the axes in variant ids: the last segment of each key, or the whole keys when two
/// axes share their last segment (task.lambda and predictors.x.params.lambda).
std::vector<std::string> axisLabels(const std::vector<ScenarioSweep>& axes) {
  std::vector<std::string> labels;
  std::set<std::string> seen;
  bool unique = true;
  for (const auto& a : axes) {
    labels.push_back(a.shortKey());
    unique = unique && seen.insert(labels.back()).second;
  }
  if (!unique)
    for (size_t a = 0; a < axes.size(); ++a) labels[a] = axes[a].key;
  return labels;
}

}  // namespace

Plan makePlan(const CompareOptions& o) {
  Plan plan;
  const std::vector<std::string> paths = scenarioPaths(o);
  const std::vector<std::string> chosen = chosenPredictors(o);
  std::set<std::string> names;
  for (const auto& path : paths) {
    Scenario sc = loadScenario(path, o.overrides);
    if (!names.insert(sc.name).second)
      throw std::invalid_argument("--scenarios: two scenarios named '" + sc.name + "'");
    if (!o.sweeps.empty()) setScenarioSweeps(sc, o.sweeps);
    choosePredictors(sc, chosen, "--predictors");
    plan.runs.push_back(o.runs > 0 ? o.runs : sc.runs > 0 ? sc.runs : kDefaultRuns);
    plan.seeds.push_back(o.seed_given ? o.seed : sc.seed());
    plan.scenarios.push_back(std::move(sc));
  }
  for (size_t i = 0; i < plan.scenarios.size(); ++i) {
    const Scenario& sc = plan.scenarios[i];
    if (sc.sweeps.empty()) {
      Variant v;
      v.scenario = &plan.scenarios[i];
      v.scenario_index = i;
      v.id = v.file_id = sc.name;
      v.sigma = noiseSigma(sc);
      plan.variants.push_back(v);
      continue;
    }
    // Each cell: the scenario file loaded again with the --set overrides and KEY=value per axis.
    std::vector<Scenario> at = loadSweepVariants(sc, o.overrides);
    const std::vector<std::string> keys = axisLabels(sc.sweeps);
    for (auto& a : at) choosePredictors(a, chosen, "--predictors");
    // A sweep of predictors.NAME.params.KEY adds NAME when the scenario lacks it: every value does.
    plan.scenarios[i].predictors = at.front().predictors;
    const auto names_at_first = predictorNames(at.front());
    for (size_t k = 0; k < at.size(); ++k) {
      Variant v;
      v.indices = gridIndices(sc.sweeps, k);
      std::string text, label, file;
      for (size_t a = 0; a < sc.sweeps.size(); ++a) {
        v.values.push_back(sc.sweeps[a].values[v.indices[a]]);
        v.xs.push_back(numberOf(v.values.back()));
        text += (a ? ", " : "") + sc.sweeps[a].key + "=" + v.values.back();
        label += (a ? "," : "") + keys[a] + "=" + valueLabel(v.values.back());
        file += "_" + keys[a] + valueLabel(v.values.back());
      }
      if (predictorNames(at[k]) != names_at_first)
        throw std::invalid_argument(sc.sweeps.front().origin + " " + text + " (scenario " + sc.name +
                                    "): the value changes the list of predictors; list them in the "
                                    "scenario or with --predictors");
      plan.variant_scenarios.push_back(std::move(at[k]));
      const Scenario& vs = plan.variant_scenarios.back();
      v.scenario = &vs;
      v.scenario_index = i;
      v.swept = true;
      v.sweep_index = k;
      v.shown = k == 0 || k + 1 == at.size();
      v.value = v.values.front();
      v.x = v.xs.front();
      v.sigma = noiseSigma(vs);
      v.id = sc.name + "@" + label;
      v.file_id = fileSafe(sc.name + file);
      plan.variants.push_back(v);
    }
  }
  return plan;
}

std::vector<Job> planJobs(const Plan& plan) {
  std::vector<Job> jobs;
  for (size_t v = 0; v < plan.variants.size(); ++v) {
    const size_t i = plan.variants[v].scenario_index;
    for (size_t p = 0; p < plan.scenarios[i].predictors.size(); ++p)
      for (int r = 0; r < plan.runs[i]; ++r) jobs.push_back({v, p, r});
  }
  return jobs;
}

std::uint64_t jobSeed(const Plan& plan, const Job& job) {
  return plan.seeds[plan.variants[job.variant].scenario_index] + static_cast<std::uint64_t>(job.run);
}

Results aggregate(const Plan& plan, const std::vector<Job>& jobs, const std::vector<RunRecord>& outcomes) {
  Results res;
  const size_t nv = plan.variants.size();
  res.metrics.resize(nv);
  res.cells.resize(nv);
  // Outcome indices by cell, in job order (which is run order).
  std::vector<std::vector<std::vector<size_t>>> idx(nv);
  for (size_t v = 0; v < nv; ++v) {
    res.cells[v].resize(plan.variants[v].scenario->predictors.size());
    idx[v].resize(res.cells[v].size());
  }
  for (size_t i = 0; i < jobs.size(); ++i) {
    const Job& j = jobs[i];
    idx[j.variant][j.predictor].push_back(i);
    if (res.metrics[j.variant].empty())  // every run of a variant has the same names (run_metrics.h)
      for (const auto& kv : outcomes[i].values) res.metrics[j.variant].push_back(kv.first);
  }
  for (size_t v = 0; v < nv; ++v)
    for (size_t p = 0; p < res.cells[v].size(); ++p) {
      Cell& cell = res.cells[v][p];
      const auto& ids = idx[v][p];
      for (const auto& name : res.metrics[v]) {
        std::vector<double> xs;
        for (size_t i : ids) {
          double x = kNaN;
          for (const auto& kv : outcomes[i].values)
            if (kv.first == name) x = kv.second;
          xs.push_back(x);
        }
        cell.stats.push_back(stats(xs));
      }
      size_t len = 0;
      for (size_t i : ids) len = std::max(len, outcomes[i].t_s.size());
      cell.t_s.assign(len, kNaN);
      cell.mean_error.assign(len, kNaN);
      for (size_t k = 0; k < len; ++k) {
        double sum = 0.0;
        int n = 0;
        for (size_t i : ids)
          if (k < outcomes[i].t_s.size()) {
            cell.t_s[k] = outcomes[i].t_s[k];
            if (std::isfinite(outcomes[i].error[k])) sum += outcomes[i].error[k], ++n;
          }
        cell.mean_error[k] = n > 0 ? sum / n : kNaN;
      }
    }
  return res;
}

size_t metricIndex(const Results& res, size_t v, const std::string& name) {
  const auto& m = res.metrics[v];
  const auto at = std::find(m.begin(), m.end(), name);
  if (at == m.end()) throw std::logic_error("variant " + std::to_string(v) + " has no metric '" + name + "'");
  return static_cast<size_t>(at - m.begin());
}

std::vector<size_t> ranking(const Plan& plan, const Results& res, size_t v) {
  std::vector<size_t> order(res.cells[v].size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  const auto& preds = plan.variants[v].scenario->predictors;
  const size_t m = metricIndex(res, v, "rmse");
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const double x = res.cells[v][a].stats[m].mean, y = res.cells[v][b].stats[m].mean;
    if (std::isfinite(x) != std::isfinite(y)) return std::isfinite(x);
    if (std::isfinite(x) && x != y) return x < y;
    return preds[a].name < preds[b].name;
  });
  return order;
}

std::vector<size_t> variantsOf(const Plan& plan, size_t i) {
  std::vector<size_t> vs;
  for (size_t v = 0; v < plan.variants.size(); ++v)
    if (plan.variants[v].scenario_index == i) vs.push_back(v);
  return vs;
}

}  // namespace predvs
