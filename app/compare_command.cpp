// `predvs compare` (compare_command.h): a pool of threads over independent seeded runs, then
// aggregation in a fixed order, so the leaderboard does not depend on --jobs.
#include "compare_command.h"

#include "gnuplot.h"
#include "output_dir.h"
#include "scenario.h"
#include "scenario_file.h"

#include "predvs/predictors/predictor.h"
#include "predvs/servo/channel_experiment.h"
#include "predvs/servo/paper_trajectories.h"
#include "predvs/servo/servo_loop.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <exception>
#include <fstream>
#include <iomanip>
#include <limits>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// One scenario at one sweep value.
struct Variant {
  const Scenario* scenario = nullptr;  ///< the scenario loaded with this sweep value applied
  size_t scenario_index = 0;
  bool swept = false;
  size_t sweep_index = 0;       ///< position of the value in the sweep
  bool shown = true;            ///< in leaderboard.md, the printed table and the error plots
                                ///< (a sweep's first and last value only)
  std::string value;            ///< the swept value as YAML text ("" without a sweep)
  double x = kNaN;              ///< the swept value as a number (NaN when it is not one)
  double sigma = kNaN;          ///< noise.sigma of this variant
  std::string id;               ///< "e6-noise-study@sigma=10", "delay-study@delay_frames=1" or the scenario name
  std::string file_id;          ///< file-name-safe id
  std::vector<std::string> metrics;
};

struct Job {
  size_t variant;
  size_t predictor;  ///< index into the scenario's chosen predictors
  int run;
};

struct Outcome {
  std::vector<double> values;  ///< one per Variant::metrics
  std::vector<double> t_s, error;
};

struct Stats {
  int n = 0;
  double mean = kNaN, std = kNaN, min = kNaN, max = kNaN;
};

Stats stats(const std::vector<double>& xs) {
  Stats s;
  double sum = 0.0;
  for (double x : xs)
    if (std::isfinite(x)) {
      ++s.n;
      sum += x;
      s.min = s.n == 1 ? x : std::min(s.min, x);
      s.max = s.n == 1 ? x : std::max(s.max, x);
    }
  if (s.n == 0) return s;
  s.mean = sum / s.n;
  double ss = 0.0;
  for (double x : xs)
    if (std::isfinite(x)) ss += (x - s.mean) * (x - s.mean);
  s.std = s.n > 1 ? std::sqrt(ss / (s.n - 1)) : 0.0;
  // Identical runs (no noise) differ only by the round-off of the sum: report a spread of 0.
  constexpr double kRoundOffSpread = 1e-9;
  if (s.std <= kRoundOffSpread * std::fabs(s.mean)) s.std = 0.0;
  return s;
}

std::string safeName(const std::string& s) {
  std::string out;
  for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
  return out;
}

std::string num(double x, int precision = 6) {
  if (!std::isfinite(x)) return "";
  std::ostringstream s;
  s << std::setprecision(precision) << x;
  return s.str();
}

std::string dat(double x) { return std::isfinite(x) ? num(x, 8) : "NaN"; }

/// Fixed-point with 3 significant decimals where it matters ("-" for NaN).
std::string pretty(double x) {
  if (!std::isfinite(x)) return "-";
  std::ostringstream s;
  const double a = std::fabs(x);
  if (a != 0.0 && (a >= 1e5 || a < 1e-3))
    s << std::setprecision(3) << std::scientific << x;
  else
    s << std::fixed << std::setprecision(a >= 100 ? 1 : 3) << x;
  return s.str();
}

std::string sigmaText(double sigma) {
  std::ostringstream s;
  s << sigma;
  return s.str();
}

/// A sweep value as a finite number (NaN when the YAML text is not one).
double numberOf(const std::string& text) {
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0' && std::isfinite(x) ? x : kNaN;
}

/// A sweep value in a variant name: numbers printed plainly (1.0 -> 1, as sigma always was).
std::string valueLabel(const std::string& text) {
  const double x = numberOf(text);
  return std::isfinite(x) ? sigmaText(x) : text;
}

// ---------------------------------------------------------------------------------------------
// One run.

/// E7 metrics of one run: RMS and max of the error while the latest delivered frame is lost, and,
/// averaged over the occlusions, the error at the last tick before a frame is delivered again
/// (the extrapolation at its worst), at the first tick after, and its RMS over the next 1 s.
void occlusionMetrics(const ChannelExperimentResult& r, double* occl_rmse, double* occl_max, double* occl_end,
                      double* reacq, double* reacq_1s) {
  double sq = 0.0, mx = kNaN;
  int n = 0;
  std::vector<double> end_errors, reacq_errors, reacq_rms;
  const auto& tr = r.trace;
  for (size_t k = 0; k < tr.size(); ++k) {
    if (!tr[k].measured_valid) {
      if (std::isfinite(tr[k].error)) {
        sq += tr[k].error * tr[k].error;
        ++n;
        mx = std::isfinite(mx) ? std::max(mx, tr[k].error) : tr[k].error;
      }
      continue;
    }
    if (k > 0 && !tr[k - 1].measured_valid) {  // first tick after a frame is delivered again
      end_errors.push_back(tr[k - 1].error);
      reacq_errors.push_back(tr[k].error);
      double s2 = 0.0;
      int m = 0;
      for (size_t j = k; j < tr.size() && tr[j].t_s < tr[k].t_s + 1.0; ++j)
        if (std::isfinite(tr[j].error)) s2 += tr[j].error * tr[j].error, ++m;
      reacq_rms.push_back(m > 0 ? std::sqrt(s2 / m) : kNaN);
    }
  }
  *occl_rmse = n > 0 ? std::sqrt(sq / n) : kNaN;
  *occl_max = mx;
  *occl_end = stats(end_errors).mean;
  *reacq = stats(reacq_errors).mean;
  *reacq_1s = stats(reacq_rms).mean;
}

std::vector<std::string> variantMetrics(const Scenario& sc) {
  std::vector<std::string> m = {"rmse", "final", "peak", "iae", "settling_s"};
  if (sc.kind == ScenarioKind::ClosedLoop) {
    m.push_back("effort");
    // Per-feature errors (metrics.per_feature) and the law's own run figures
    // (e.g. jacobian_error_final, lyap_bound_positive_fraction).
    auto hold = makePredictor("hold", sc.channels);
    const ServoLoop probe(sc.closed_loop, *hold);
    const std::set<std::string> listed(m.begin(), m.end());
    for (const auto& name : probe.valueNames())
      if (!listed.count(name) && name != "max") m.push_back(name);
    return m;
  }
  const auto traj = makeChannelTrajectory(sc.trajectory, sc.trajectory_params);
  for (const auto& c : traj->channelNames()) m.push_back("pos_mse_" + c);
  for (const auto& c : traj->channelNames()) m.push_back("vel_mse_" + c);
  if (!sc.open_loop.occlusions.empty())
    for (const char* k : {"occl_rmse", "occl_max", "occl_end_error", "reacq_error", "reacq_1s_rmse"}) m.push_back(k);
  m.push_back("alarms");
  m.push_back("false_alarms_per_min");
  if (traj->onsetTime() > 0.0) {  // an onset at or before the first frame cannot be seen
    m.push_back("detected");
    m.push_back("detect_delay_frames");
  }
  if (traj->manoeuvre().exists())
    for (const char* k : {"resp_max_lag", "resp_overshoot", "resp_mean_3s", "resp_time_s"}) m.push_back(k);
  return m;
}

/// ResponseMetrics of an open-loop run to the trajectory's manoeuvre, on the effect-time axis
/// (the prediction for t_pred is scored against the truth at t_pred, so the change is at t_pred =
/// manoeuvre time).
ResponseMetrics responseMetrics(const ChannelExperimentResult& r, const Manoeuvre& man, const MetricsOptions& opt) {
  std::vector<double> t, e, s;
  for (const auto& row : r.trace) {
    t.push_back(row.t_pred_s);
    e.push_back(row.error);
    s.push_back((row.predicted - row.truth).dot(man.direction));
  }
  return computeResponse(t, e, s, man.t_s, opt);
}

Outcome runOne(const Variant& v, const ScenarioPredictor& sp, std::uint64_t seed) {
  const Scenario& sc = *v.scenario;
  Outcome o;
  const Metrics* metrics = nullptr;
  if (sc.kind == ScenarioKind::ClosedLoop) {
    ServoConfig cfg = sc.closed_loop;
    cfg.seed = seed;
    auto predictor = makePredictor(sp.name, sc.channels, sp.params);
    const ServoResult r = runServoLoop(cfg, *predictor);
    for (const auto& s : r.trace) o.t_s.push_back(s.t_s), o.error.push_back(s.error);
    for (const auto& name : v.metrics) {
      double x = kNaN;
      for (const auto& kv : r.values)
        if (kv.first == name) x = kv.second;
      o.values.push_back(x);
    }
    return o;
  }
  PredictionExperimentConfig cfg = sc.open_loop;
  cfg.seed = seed;
  const auto traj = makeChannelTrajectory(sc.trajectory, sc.trajectory_params);
  auto predictor = makePredictor(sp.name, traj->channels(), sp.params);
  const ChannelExperimentResult r = runChannelExperiment(cfg, *traj, *predictor);
  for (const auto& s : r.trace) o.t_s.push_back(s.t_s), o.error.push_back(s.error);
  metrics = &r.metrics;
  o.values = {metrics->rmse, metrics->final_error, metrics->peak_error, metrics->iae, metrics->settling_time_s};
  for (int c = 0; c < r.position_mse.size(); ++c) o.values.push_back(r.position_mse(c));
  for (int c = 0; c < r.velocity_mse.size(); ++c) o.values.push_back(r.velocity_mse(c));
  if (!cfg.occlusions.empty()) {
    double a, b, c, d, e;
    occlusionMetrics(r, &a, &b, &c, &d, &e);
    o.values.insert(o.values.end(), {a, b, c, d, e});
  }
  const double onset = traj->onsetTime();
  const double frame_s = TimingModel(cfg.timing).framePeriod();
  double delay = kNaN;
  if (onset > 0.0) {
    const double first_frame = std::ceil(onset / frame_s - 1e-9) * frame_s;
    for (double t : r.alarm_t_acq_s)
      if (t >= first_frame - 1e-9 && t < onset + kDetectWindowS) {
        delay = std::round((t - first_frame) / frame_s);
        break;
      }
  }
  const double alarms = static_cast<double>(r.alarm_t_acq_s.size());
  const double minutes = cfg.duration_s / 60.0;
  o.values.push_back(alarms);
  o.values.push_back((alarms - (std::isfinite(delay) ? 1.0 : 0.0)) / minutes);
  if (onset > 0.0) {
    o.values.push_back(std::isfinite(delay) ? 1.0 : 0.0);
    o.values.push_back(delay);
  }
  const Manoeuvre man = traj->manoeuvre();
  if (man.exists()) {
    const ResponseMetrics resp = responseMetrics(r, man, cfg.metrics);
    o.values.insert(o.values.end(), {resp.max_lag, resp.overshoot, resp.mean_after, resp.response_s});
  }
  return o;
}

// ---------------------------------------------------------------------------------------------
// Progress on stderr.

class Progress {
 public:
  Progress(std::ostream& err, size_t total, bool bar) : err_(err), total_(total), bar_(bar) {}
  void show(size_t done, double elapsed_s) {
    if (bar_) {
      constexpr int kWidth = 40;
      const int filled = total_ ? static_cast<int>(kWidth * done / total_) : kWidth;
      const double eta = done ? elapsed_s * static_cast<double>(total_ - done) / static_cast<double>(done) : 0.0;
      err_ << "\rpredvs compare [" << std::string(static_cast<size_t>(filled), '#')
           << std::string(static_cast<size_t>(kWidth - filled), '.') << "] " << done << "/" << total_ << " runs, "
           << std::fixed << std::setprecision(0) << elapsed_s << " s, eta " << eta << " s   " << std::defaultfloat
           << std::flush;
      if (done == total_) err_ << "\n";
      return;
    }
    // Not a terminal: a line at every quarter.
    const size_t quarter = total_ ? 4 * done / total_ : 4;
    if (quarter > last_quarter_ || (done == total_ && !finished_)) {
      last_quarter_ = quarter;
      finished_ = done == total_;
      err_ << "predvs: compare: " << done << "/" << total_ << " runs (" << std::fixed << std::setprecision(1)
           << elapsed_s << " s)\n"
           << std::defaultfloat << std::flush;
    }
  }

 private:
  std::ostream& err_;
  size_t total_;
  bool bar_;
  size_t last_quarter_ = 0;
  bool finished_ = false;
};

// ---------------------------------------------------------------------------------------------
// Plan, validation.

struct Plan {
  std::vector<Scenario> scenarios;         ///< as loaded (with --set, --sweep and --predictors applied)
  std::vector<int> runs;                   ///< per scenario
  std::vector<std::uint64_t> seeds;        ///< base seed per scenario
  std::deque<Scenario> variant_scenarios;  ///< per swept variant: the scenario at that value
  std::vector<Variant> variants;
};

/// Replaces the scenario's predictor list by `chosen` (each with the parameters the scenario gives
/// it, its defaults otherwise); no-op when `chosen` is empty.
void choosePredictors(Scenario& sc, const std::vector<std::string>& chosen) {
  if (chosen.empty()) return;
  std::vector<ScenarioPredictor> ps;
  for (const auto& name : chosen) {
    ScenarioPredictor p{name, {}, 0};
    for (const auto& own : sc.predictors)
      if (own.name == name) p = own;
    try {
      makePredictor(p.name, sc.channels, p.params);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(sc.path + ": " + e.what());
    }
    ps.push_back(p);
  }
  sc.predictors = ps;
}

std::vector<std::string> predictorNames(const Scenario& sc) {
  std::vector<std::string> names;
  for (const auto& p : sc.predictors) names.push_back(p.name);
  return names;
}

std::vector<std::string> splitNames(const std::vector<std::string>& names, const std::string& option) {
  std::set<std::string> seen;
  for (const auto& n : names)
    if (!seen.insert(n).second) throw std::invalid_argument(option + ": '" + n + "' listed twice");
  return names;
}

Plan makePlan(const CompareOptions& o) {
  Plan plan;
  std::vector<std::string> paths;
  if (o.scenarios.size() == 1 && o.scenarios[0] == "all") {
    for (const auto& s : listScenarios()) paths.push_back(resolveScenario(s.name));
    if (paths.empty()) throw std::invalid_argument("--scenarios: no scenario files in " + scenariosDir());
  } else {
    if (o.scenarios.empty()) throw std::invalid_argument("--scenarios: expected a comma-separated list of scenarios or 'all'");
    for (const auto& s : splitNames(o.scenarios, "--scenarios")) {
      if (s == "all") throw std::invalid_argument("--scenarios: 'all' cannot be combined with names");
      try {
        paths.push_back(resolveScenario(s));
      } catch (const std::invalid_argument& e) {  // name our option, not `predvs servo`'s
        std::string msg = e.what();
        if (msg.rfind("--scenario:", 0) == 0) msg = "--scenarios:" + msg.substr(11);
        throw std::invalid_argument(msg);
      }
    }
  }
  std::vector<std::string> chosen;
  if (o.predictors.size() == 1 && o.predictors[0] == "all") {
    for (const auto& p : predictorRegistry()) chosen.push_back(p.name);
  } else {
    for (const auto& p : splitNames(o.predictors, "--predictors")) {
      if (p == "all") throw std::invalid_argument("--predictors: 'all' cannot be combined with names");
      if (!isPredictor(p)) {
        std::string known;
        for (const auto& q : predictorRegistry()) known += (known.empty() ? "" : ", ") + q.name;
        throw std::invalid_argument("--predictors: unknown predictor '" + p + "' (known: " + known + ")");
      }
      chosen.push_back(p);
    }
  }
  std::set<std::string> names;
  for (const auto& path : paths) {
    Scenario sc = loadScenario(path, o.overrides);
    if (!names.insert(sc.name).second)
      throw std::invalid_argument("--scenarios: two scenarios named '" + sc.name + "'");
    if (!o.sweep.empty()) setScenarioSweep(sc, o.sweep);
    choosePredictors(sc, chosen);
    plan.runs.push_back(o.runs > 0 ? o.runs : sc.runs > 0 ? sc.runs : kDefaultRuns);
    plan.seeds.push_back(o.seed_given ? o.seed : sc.seed());
    plan.scenarios.push_back(std::move(sc));
  }
  auto noiseSigma = [](const Scenario& sc) {
    return sc.kind == ScenarioKind::OpenLoop ? sc.open_loop.noise.sigma : sc.closed_loop.noise.sigma;
  };
  for (size_t i = 0; i < plan.scenarios.size(); ++i) {
    const Scenario& sc = plan.scenarios[i];
    if (sc.sweep.empty()) {
      Variant v;
      v.scenario = &plan.scenarios[i];
      v.scenario_index = i;
      v.id = v.file_id = sc.name;
      v.sigma = noiseSigma(sc);
      v.metrics = variantMetrics(sc);
      plan.variants.push_back(v);
      continue;
    }
    // Each value: the scenario file loaded again with the --set overrides and KEY=value.
    std::vector<Scenario> at = loadSweepVariants(sc, o.overrides);
    const std::string key = sc.sweep.shortKey();
    for (auto& a : at) choosePredictors(a, chosen);
    // A sweep of predictors.NAME.params.KEY adds NAME when the scenario lacks it: every value does.
    plan.scenarios[i].predictors = at.front().predictors;
    const auto names_at_first = predictorNames(at.front());
    for (size_t k = 0; k < at.size(); ++k) {
      if (predictorNames(at[k]) != names_at_first)
        throw std::invalid_argument(sc.sweep.origin + " " + sc.sweep.key + "=" + sc.sweep.values[k] + " (scenario " +
                                    sc.name + "): the value changes the list of predictors; list them in the "
                                    "scenario or with --predictors");
      plan.variant_scenarios.push_back(std::move(at[k]));
      const Scenario& vs = plan.variant_scenarios.back();
      Variant v;
      v.scenario = &vs;
      v.scenario_index = i;
      v.swept = true;
      v.sweep_index = k;
      v.shown = k == 0 || k + 1 == at.size();
      v.value = sc.sweep.values[k];
      v.x = numberOf(v.value);
      v.sigma = noiseSigma(vs);
      v.id = sc.name + "@" + key + "=" + valueLabel(v.value);
      v.file_id = safeName(sc.name + "_" + key + valueLabel(v.value));
      v.metrics = variantMetrics(vs);
      plan.variants.push_back(v);
    }
  }
  return plan;
}

// ---------------------------------------------------------------------------------------------
// Results.

struct Cell {  ///< one (variant, predictor)
  std::vector<Stats> stats;            ///< per metric
  std::vector<double> t_s, mean_error; ///< mean over runs per tick
};

struct Results {
  std::vector<std::vector<Cell>> cells;  ///< [variant][predictor]
};

Results aggregate(const Plan& plan, const std::vector<Job>& tasks, const std::vector<Outcome>& outcomes) {
  Results res;
  res.cells.resize(plan.variants.size());
  for (size_t v = 0; v < plan.variants.size(); ++v)
    res.cells[v].resize(plan.variants[v].scenario->predictors.size());
  // Group outcome indices by cell, in task order (which is run order).
  std::vector<std::vector<std::vector<size_t>>> idx(plan.variants.size());
  for (size_t v = 0; v < plan.variants.size(); ++v) idx[v].resize(res.cells[v].size());
  for (size_t i = 0; i < tasks.size(); ++i) idx[tasks[i].variant][tasks[i].predictor].push_back(i);
  for (size_t v = 0; v < plan.variants.size(); ++v)
    for (size_t p = 0; p < res.cells[v].size(); ++p) {
      Cell& cell = res.cells[v][p];
      const auto& ids = idx[v][p];
      for (size_t m = 0; m < plan.variants[v].metrics.size(); ++m) {
        std::vector<double> xs;
        for (size_t i : ids) xs.push_back(outcomes[i].values.at(m));
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

std::string errorUnits(const Scenario& sc) {
  if (sc.kind == ScenarioKind::ClosedLoop) return "px (RMS over the 4 points of ||s - s*||)";
  if (sc.trajectory == "onset-sinusoid") return "scenario units (mm in the E12 scenarios)";
  return "px";
}

/// Predictor order of a variant: by mean rmse, NaN last, ties by name.
std::vector<size_t> ranking(const Plan& plan, const Results& res, size_t v) {
  std::vector<size_t> order(res.cells[v].size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  const auto& preds = plan.variants[v].scenario->predictors;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const double x = res.cells[v][a].stats[0].mean, y = res.cells[v][b].stats[0].mean;
    if (std::isfinite(x) != std::isfinite(y)) return std::isfinite(x);
    if (std::isfinite(x) && x != y) return x < y;
    return preds[a].name < preds[b].name;
  });
  return order;
}

void writeCsv(const Plan& plan, const Results& res, const StagedOutputDir& dir) {
  std::ofstream csv(dir.file("leaderboard.csv"));
  csv << "scenario,variant,predictor,metric,n,mean,std,min,max\n";
  for (size_t v = 0; v < plan.variants.size(); ++v) {
    const Variant& var = plan.variants[v];
    for (size_t p : ranking(plan, res, v))
      for (size_t m = 0; m < var.metrics.size(); ++m) {
        const Stats& s = res.cells[v][p].stats[m];
        csv << var.scenario->name << "," << var.id << "," << var.scenario->predictors[p].name << "," << var.metrics[m]
            << "," << s.n << "," << num(s.mean) << "," << num(s.std) << "," << num(s.min) << "," << num(s.max) << "\n";
      }
  }
  if (!csv) throw std::runtime_error(dir.file("leaderboard.csv") + ": write failed");
}

nlohmann::json jsonNumber(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

void writeJson(const Plan& plan, const Results& res, const CompareOptions& o, const StagedOutputDir& dir) {
  nlohmann::json j;
  j["command"] = o.command_line;
  j["overrides"] = overrideTexts(o.overrides);
  if (!o.sweep.empty()) {
    std::string values;
    for (const auto& v : o.sweep.values) values += (values.empty() ? "" : ", ") + v;
    j["sweep"] = o.sweep.key + "=[" + values + "]";  // --sweep, applied to every scenario
  } else {
    j["sweep"] = nullptr;
  }
  j["error_definition"] = {
      {"open-loop", "||predicted - true|| over the channels at the effect time, in the scenario's units"},
      {"closed-loop", "RMS over the 4 points of ||s - s*|| (px)"}};
  j["scenarios"] = nlohmann::json::array();
  for (size_t i = 0; i < plan.scenarios.size(); ++i) {
    const Scenario& sc = plan.scenarios[i];
    nlohmann::json s;
    s["name"] = sc.name;
    s["file"] = sc.path;
    s["description"] = sc.description;
    s["kind"] = scenarioKindName(sc.kind);
    s["runs"] = plan.runs[i];
    s["seeds"] = {plan.seeds[i], plan.seeds[i] + static_cast<std::uint64_t>(plan.runs[i]) - 1};
    s["error_units"] = errorUnits(sc);
    if (!sc.sweep.empty()) {
      s["sweep"] = {{"key", sc.sweep.key}, {"values", nlohmann::json::array()},
                    {"from", sc.sweep.origin == "--sweep" ? "--sweep" : "scenario file"}};
      for (const auto& v : sc.sweep.values) {
        const double x = numberOf(v);
        s["sweep"]["values"].push_back(std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(v));
      }
    }
    s["variants"] = nlohmann::json::array();
    for (size_t v = 0; v < plan.variants.size(); ++v) {
      const Variant& var = plan.variants[v];
      if (var.scenario_index != i) continue;
      nlohmann::json jv;
      jv["id"] = var.id;
      jv["noise_sigma"] = jsonNumber(var.sigma);
      if (var.swept) jv["sweep_value"] = std::isfinite(var.x) ? nlohmann::json(var.x) : nlohmann::json(var.value);
      jv["predictors"] = nlohmann::json::array();
      const auto& preds = var.scenario->predictors;  // a sweep may change their parameters
      for (size_t p : ranking(plan, res, v)) {
        nlohmann::json jp;
        jp["name"] = preds[p].name;
        jp["params"] = nlohmann::json::object();
        for (const auto& kv : preds[p].params.values()) jp["params"][kv.first] = kv.second;
        for (size_t m = 0; m < var.metrics.size(); ++m) {
          const Stats& st = res.cells[v][p].stats[m];
          jp["metrics"][var.metrics[m]] = {{"n", st.n},
                                           {"mean", jsonNumber(st.mean)},
                                           {"std", jsonNumber(st.std)},
                                           {"min", jsonNumber(st.min)},
                                           {"max", jsonNumber(st.max)}};
        }
        jv["predictors"].push_back(jp);
      }
      s["variants"].push_back(jv);
    }
    j["scenarios"].push_back(s);
  }
  std::ofstream js(dir.file("leaderboard.json"));
  js << j.dump(2) << "\n";
  if (!js) throw std::runtime_error(dir.file("leaderboard.json") + ": write failed");
}

/// Metrics shown in the markdown table of a variant (the rest are in the CSV / JSON).
std::vector<size_t> shownMetrics(const Variant& v) {
  const Scenario& sc = *v.scenario;
  std::vector<size_t> shown;
  const bool mse = (sc.sweep.key == "noise.sigma" && sc.kind == ScenarioKind::OpenLoop) || (sc.kind == ScenarioKind::OpenLoop && sc.channels != 2);
  for (size_t m = 0; m < v.metrics.size(); ++m) {
    const std::string& k = v.metrics[m];
    const bool base = k == "rmse" || k == "final" || k == "peak" || k == "iae" || k == "effort";
    const bool is_mse = k.rfind("pos_mse_", 0) == 0 || k.rfind("vel_mse_", 0) == 0;
    const bool occl = k == "occl_rmse" || k == "occl_end_error" || k == "reacq_error" || k == "reacq_1s_rmse";
    const bool monitor = sc.trajectory == "onset-sinusoid" &&
                         (k == "detected" || k == "detect_delay_frames" || k == "false_alarms_per_min");
    const bool response = k.rfind("resp_", 0) == 0;
    if (base || (mse && is_mse) || occl || monitor || response) shown.push_back(m);
  }
  return shown;
}

std::string markdown(const Plan& plan, const Results& res, const CompareOptions& o, double wall_s, int jobs) {
  std::ostringstream md;
  md << "# predvs compare: leaderboard\n\n"
     << "Command: `" << o.command_line << "` (" << jobs << " worker threads, wall time " << std::fixed
     << std::setprecision(1) << wall_s << " s)" << std::defaultfloat << ".\n\n"
     << "Each cell is mean ± std over the runs (min and max in leaderboard.csv / leaderboard.json); run r uses seed "
        "S + r for every predictor. Predictors are ranked by mean rmse (steady-window RMS error). Metric definitions: "
        "app/compare_command.h.\n";
  for (size_t v = 0; v < plan.variants.size(); ++v) {
    const Variant& var = plan.variants[v];
    const Scenario& sc = *var.scenario;
    const size_t i = var.scenario_index;
    // For a sweep, only the first and last value go into the markdown.
    if (!var.shown) continue;
    md << "\n## " << var.id << "\n\n"
       << sc.description << "  \n"
       << scenarioKindName(sc.kind) << ", " << plan.runs[i] << " runs, seeds " << plan.seeds[i] << ".."
       << plan.seeds[i] + static_cast<std::uint64_t>(plan.runs[i]) - 1 << ", noise sigma " << sigmaText(var.sigma);
    if (var.swept && sc.sweep.key != "noise.sigma") md << ", " << sc.sweep.key << " = " << var.value;
    md << ", error in " << errorUnits(sc);
    if (var.swept)
      md << (sc.sweep.key == "noise.sigma" ? std::string(" (every sigma in leaderboard.csv)")
                                           : " (every " + sc.sweep.key + " in leaderboard.csv)");
    md << "\n\n";
    const auto shown = shownMetrics(var);
    md << "| # | predictor |";
    for (size_t m : shown) md << " " << var.metrics[m] << " |";
    md << "\n|---|---|";
    for (size_t k = 0; k < shown.size(); ++k) md << "---:|";
    md << "\n";
    int rank = 0;
    for (size_t p : ranking(plan, res, v)) {
      md << "| " << ++rank << " | " << sc.predictors[p].name << " |";
      for (size_t m : shown) {
        const Stats& s = res.cells[v][p].stats[m];
        md << " " << pretty(s.mean);
        if (s.n > 1 && std::isfinite(s.std)) md << " ± " << pretty(s.std);
        if (s.n < plan.runs[i] && s.n > 0) md << " (" << s.n << "/" << plan.runs[i] << ")";
        md << " |";
      }
      md << "\n";
    }
  }
  return md.str();
}

void printBoard(const Plan& plan, const Results& res, std::ostream& out) {
  for (size_t v = 0; v < plan.variants.size(); ++v) {
    const Variant& var = plan.variants[v];
    const Scenario& sc = *var.scenario;
    if (!var.shown) continue;
    const auto shown = shownMetrics(var);
    size_t w = 9;
    for (const auto& p : sc.predictors) w = std::max(w, p.name.size());
    out << "\n" << var.id << " (" << plan.runs[var.scenario_index] << " runs; mean over runs)\n"
        << std::left << std::setw(static_cast<int>(w)) << "predictor";
    for (size_t m : shown) out << std::right << std::setw(std::max<int>(11, static_cast<int>(var.metrics[m].size()) + 2)) << var.metrics[m];
    out << "\n";
    for (size_t p : ranking(plan, res, v)) {
      out << std::left << std::setw(static_cast<int>(w)) << sc.predictors[p].name;
      for (size_t m : shown)
        out << std::right << std::setw(std::max<int>(11, static_cast<int>(var.metrics[m].size()) + 2))
            << pretty(res.cells[v][p].stats[m].mean);
      out << "\n";
    }
  }
}

/// error_<variant>: mean error versus time, one line per predictor, for every shown variant.
void writeErrorPlots(const Plan& plan, const Results& res, const StagedOutputDir& dir) {
  for (size_t v = 0; v < plan.variants.size(); ++v) {
    const Variant& var = plan.variants[v];
    const Scenario& sc = *var.scenario;
    if (!var.shown) continue;
    const std::string base = "error_" + var.file_id;
    {
      std::ofstream d(dir.file(base + ".dat"));
      d << "# t_s then the mean over runs of the error of each predictor:";
      for (const auto& p : sc.predictors) d << " " << p.name;
      d << "\n";
      const auto& cells = res.cells[v];
      size_t len = 0;
      for (const auto& c : cells) len = std::max(len, c.t_s.size());
      for (size_t k = 0; k < len; ++k) {
        double t = kNaN;
        for (const auto& c : cells)
          if (k < c.t_s.size() && std::isfinite(c.t_s[k])) t = c.t_s[k];
        d << dat(t);
        for (const auto& c : cells) d << " " << dat(k < c.mean_error.size() ? c.mean_error[k] : kNaN);
        d << "\n";
      }
    }
    std::ofstream gp(dir.file(base + ".gp"));
    const bool closed = sc.kind == ScenarioKind::ClosedLoop;
    const int runs = plan.runs[var.scenario_index];
    gp << "# Regenerate with: gnuplot " << base << ".gp\n"
       << "set terminal pngcairo size 1200,700 enhanced font 'Sans,11'\nset output '" << base << ".png'\n"
       << "set datafile missing 'NaN'\nset grid\nset autoscale xfix\nset logscale y\nset format y '%g'\n"
       << "set key outside right top\nset xlabel 'time t [s]'\n"
       << "set ylabel " << gnuplotQuote(closed ? "image error, RMS over 4 points [px]" : "||predicted - true|| [" + std::string(sc.trajectory == "onset-sinusoid" ? "mm" : "px") + "]") << "\n"
       << "set title " << gnuplotQuote(var.id + ": mean over " + std::to_string(runs) + " runs of the " +
                                       (closed ? "tracking error" : "prediction error at the effect time"))
       << "\n";
    for (const auto& o : sc.open_loop.occlusions)
      if (!closed)
        gp << "set object rect from " << o.start_s << ", graph 0 to " << o.end_s
           << ", graph 1 fc rgb 'gray90' fs solid behind\n";
    const double onset = closed ? kNaN : makeChannelTrajectory(sc.trajectory, sc.trajectory_params)->onsetTime();
    if (onset > 0.0)
      gp << "set arrow from " << onset << ", graph 0 to " << onset << ", graph 1 nohead dt 2 lc rgb 'black'\n"
         << "set label 'onset' at " << onset << ", graph 0.97 offset 0.5,0\n";
    if (!closed && !sc.open_loop.occlusions.empty())
      gp << "set label 'occlusion (shaded)' at " << sc.open_loop.occlusions.front().start_s << ", graph 0.97 offset 0.5,0\n";
    gp << "plot ";
    for (size_t p = 0; p < sc.predictors.size(); ++p)
      gp << (p ? ", \\\n     " : "") << "'" << base << ".dat' using 1:" << (p + 2) << " with lines lw "
         << (p < 6 ? "1.6" : "1.6 dt 2") << " lc rgb '" << seriesColor(p) << "' title "
         << gnuplotQuote(sc.predictors[p].name);
    gp << "\n";
    gp.close();
    runGnuplot(dir.staging().string(), base + ".gp");
  }
}

/// Variants of scenario i, in sweep order.
std::vector<size_t> variantsOf(const Plan& plan, size_t i) {
  std::vector<size_t> vs;
  for (size_t v = 0; v < plan.variants.size(); ++v)
    if (plan.variants[v].scenario_index == i) vs.push_back(v);
  return vs;
}

/// mse_vs_sigma_<scenario>: an open-loop noise.sigma sweep, position and velocity MSE per channel
/// versus sigma_n, one line per predictor (paper 001 Fig. 8 analogue).
void writeMseVsSigmaPlot(const Plan& plan, const Results& res, const StagedOutputDir& dir, size_t i) {
  {
    const Scenario& sc = plan.scenarios[i];
    const auto traj = makeChannelTrajectory(sc.trajectory, sc.trajectory_params);
    const auto& chans = traj->channelNames();
    const std::string base = "mse_vs_sigma_" + safeName(sc.name);
    const std::vector<size_t> vs = variantsOf(plan, i);
    const auto& metrics = plan.variants[vs.front()].metrics;
    {
      std::ofstream d(dir.file(base + ".dat"));
      d << "# one block per predictor (separated by two blank lines): sigma_n, then mean pos_mse and vel_mse per channel\n";
      for (size_t p = 0; p < sc.predictors.size(); ++p) {
        d << "# " << sc.predictors[p].name << "\n";
        for (size_t v : vs) {
          d << dat(plan.variants[v].sigma);
          for (const std::string kind : {"pos_mse_", "vel_mse_"})
            for (const auto& c : chans) {
              const size_t m = static_cast<size_t>(std::find(metrics.begin(), metrics.end(), kind + c) - metrics.begin());
              d << " " << dat(res.cells[v][p].stats[m].mean);
            }
          d << "\n";
        }
        d << "\n\n";
      }
    }
    std::ofstream gp(dir.file(base + ".gp"));
    const size_t nc = chans.size();
    gp << "# Regenerate with: gnuplot " << base << ".gp\n"
       << "set terminal pngcairo size " << (nc * 500 + 280) << ",1000 enhanced font 'Sans,11'\nset output '" << base
       << ".png'\nset datafile missing 'NaN'\nset grid\nset logscale y\nset format y '%g'\n"
       << "set xlabel 'noise amplitude {/Symbol s}_n [px]'\n"
       << "set multiplot layout 2," << nc << " margins 0.06,0.84,0.07,0.91 spacing 0.07,0.12 title "
       << gnuplotQuote(sc.name + ": MSE versus noise, mean over " + std::to_string(plan.runs[i]) +
                       " runs (paper 001 Fig. 8 analogue)")
       << "\n";
    for (int kind = 0; kind < 2; ++kind)
      for (size_t c = 0; c < nc; ++c) {
        const bool last = kind == 1 && c == nc - 1;
        gp << "set title " << gnuplotQuote((kind ? "velocity MSE of " : "position MSE of ") + chans[c]) << "\n"
           << "set ylabel " << gnuplotQuote(kind ? "MSE [(px/s)^2]" : "MSE [px^2]") << "\n"
           << (last ? "set key at screen 0.995,0.5 right center box opaque reverse Left\n" : "unset key\n") << "plot ";
        for (size_t p = 0; p < sc.predictors.size(); ++p)
          gp << (p ? ", \\\n     " : "") << "'" << base << ".dat' index " << p << " using 1:"
             << (2 + static_cast<size_t>(kind) * nc + c) << " with linespoints lw 1.6 pt 7 ps 0.6 "
             << (p < 6 ? "" : "dt 2 ") << "lc rgb '" << seriesColor(p) << "' title " << gnuplotQuote(sc.predictors[p].name);
        gp << "\n";
      }
    gp << "unset multiplot\n";
    gp.close();
    runGnuplot(dir.staging().string(), base + ".gp");
  }
}

/// rmse_vs_<key>_<scenario>: any other sweep, mean ± std over the runs of the steady-window rmse
/// versus the swept value, one line per predictor. Numeric values are the x axis; otherwise the
/// values are placed at 0, 1, ... with their text as tic labels.
void writeRmseVsKeyPlot(const Plan& plan, const Results& res, const StagedOutputDir& dir, size_t i) {
  const Scenario& sc = plan.scenarios[i];
  const std::vector<size_t> vs = variantsOf(plan, i);
  bool numeric = true;
  for (size_t v : vs) numeric = numeric && std::isfinite(plan.variants[v].x);
  const std::string key = sc.sweep.shortKey();
  const std::string base = "rmse_vs_" + safeName(key) + "_" + safeName(sc.name);
  bool positive = true;  // every mean - std > 0: a log axis, so that large and small errors both read
  for (size_t v : vs)
    for (const auto& cell : res.cells[v]) positive = positive && cell.stats[0].mean - cell.stats[0].std > 0.0;
  {
    std::ofstream d(dir.file(base + ".dat"));
    d << "# one block per predictor (separated by two blank lines): " << sc.sweep.key
      << (numeric ? "" : " (as its index)") << ", mean rmse, std rmse over the runs\n";
    for (size_t p = 0; p < sc.predictors.size(); ++p) {
      d << "# " << sc.predictors[p].name << "\n";
      for (size_t k = 0; k < vs.size(); ++k) {
        const Variant& var = plan.variants[vs[k]];
        const Stats& st = res.cells[vs[k]][p].stats[0];  // metric 0 is rmse for every kind
        d << dat(numeric ? var.x : static_cast<double>(k)) << " " << dat(st.mean) << " " << dat(st.std) << "\n";
      }
      d << "\n\n";
    }
  }
  const bool closed = sc.kind == ScenarioKind::ClosedLoop;
  std::ofstream gp(dir.file(base + ".gp"));
  gp << "# Regenerate with: gnuplot " << base << ".gp\n"
     << "set terminal pngcairo size 1100,650 enhanced font 'Sans,11'\nset output '" << base << ".png'\n"
     << "set datafile missing 'NaN'\nset grid\nset key outside right top\nset offsets graph 0.03, graph 0.03, 0, 0\n"
     << (positive ? "set logscale y\nset format y '%g'\n" : "")
     << "set xlabel " << gnuplotQuote(sc.sweep.key) << " noenhanced\n"
     << "set ylabel " << gnuplotQuote(closed ? "steady rmse of the image error [px]"
                                             : "steady rmse of ||predicted - true|| [" + errorUnits(sc) + "]")
     << "\n"
     << "set title " << gnuplotQuote(sc.name + ": steady-window rmse versus " + sc.sweep.key + ", mean ± std over " +
                                     std::to_string(plan.runs[i]) + " runs")
     << " noenhanced\n";
  if (!numeric) {
    gp << "set xtics (";
    for (size_t k = 0; k < vs.size(); ++k)
      gp << (k ? ", " : "") << gnuplotQuote(plan.variants[vs[k]].value) << " " << k;
    gp << ")\n";
  }
  gp << "plot ";
  for (size_t p = 0; p < sc.predictors.size(); ++p)
    gp << (p ? ", \\\n     " : "") << "'" << base << ".dat' index " << p
       << " using 1:2:3 with yerrorlines lw 1.6 pt 7 ps 0.6 " << (p < 6 ? "" : "dt 2 ") << "lc rgb '" << seriesColor(p)
       << "' title " << gnuplotQuote(sc.predictors[p].name);
  gp << "\n";
  gp.close();
  runGnuplot(dir.staging().string(), base + ".gp");
}

void writePlots(const Plan& plan, const Results& res, const StagedOutputDir& dir) {
  writeErrorPlots(plan, res, dir);
  for (size_t i = 0; i < plan.scenarios.size(); ++i) {
    const Scenario& sc = plan.scenarios[i];
    if (sc.sweep.empty()) continue;
    if (sc.sweep.key == "noise.sigma" && sc.kind == ScenarioKind::OpenLoop && !sc.sigma_sweep.empty())
      writeMseVsSigmaPlot(plan, res, dir, i);
    else
      writeRmseVsKeyPlot(plan, res, dir, i);
  }
}

}  // namespace

void runCompareCommand(const CompareOptions& o, std::ostream& out, std::ostream& err) {
  const auto start = std::chrono::steady_clock::now();
  const Plan plan = makePlan(o);
  if (o.plots) requireGnuplot();

  std::vector<Job> tasks;
  for (size_t v = 0; v < plan.variants.size(); ++v) {
    const size_t i = plan.variants[v].scenario_index;
    for (size_t p = 0; p < plan.scenarios[i].predictors.size(); ++p)
      for (int r = 0; r < plan.runs[i]; ++r) tasks.push_back({v, p, r});
  }
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  const int jobs = o.jobs > 0 ? o.jobs : static_cast<int>(hw);
  const int workers = static_cast<int>(std::min<size_t>(static_cast<size_t>(jobs), std::max<size_t>(1, tasks.size())));
  err << "predvs: compare: " << plan.scenarios.size() << " scenarios (" << plan.variants.size() << " variants), "
      << tasks.size() << " runs on " << workers << " threads\n";

  std::vector<Outcome> outcomes(tasks.size());
  std::atomic<size_t> next{0}, done{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&] {
    for (;;) {
      const size_t i = next.fetch_add(1);
      if (i >= tasks.size() || failed) return;
      const Job& t = tasks[i];
      const Variant& v = plan.variants[t.variant];
      try {
        outcomes[i] = runOne(v, v.scenario->predictors[t.predictor],
                             plan.seeds[v.scenario_index] + static_cast<std::uint64_t>(t.run));
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        failed = true;
      }
      ++done;
    }
  };
  std::vector<std::thread> pool;
  for (int w = 0; w < workers; ++w) pool.emplace_back(work);
  Progress progress(err, tasks.size(), o.progress_bar);
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  while (done < tasks.size() && !failed) {
    progress.show(done, elapsed());
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
  progress.show(done, elapsed());

  const Results res = aggregate(plan, tasks, outcomes);
  const double run_s = elapsed();
  StagedOutputDir dir(o.out_dir);
  writeCsv(plan, res, dir);
  writeJson(plan, res, o, dir);
  {
    std::ofstream md(dir.file("leaderboard.md"));
    md << markdown(plan, res, o, run_s, workers);
    if (!md) throw std::runtime_error(dir.file("leaderboard.md") + ": write failed");
  }
  if (o.plots) writePlots(plan, res, dir);
  dir.commit();

  printBoard(plan, res, out);
  out << "\n" << tasks.size() << " runs in " << std::fixed << std::setprecision(1) << run_s << " s on " << workers
      << " threads" << std::defaultfloat << "; wrote " << (dir.target() / "leaderboard.md").string()
      << ", leaderboard.csv, leaderboard.json" << (o.plots ? " and plots" : "") << "\n";
}

}  // namespace predvs
