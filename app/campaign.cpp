// Campaigns (campaign.h): records, resume, shards, merge, and the run loop of `predvs compare`
// (threads, or MPI ranks: campaign_mpi.h).
#include "campaign.h"

#include "campaign_html.h"
#include "campaign_mpi.h"
#include "compare_report.h"
#include "gnuplot.h"
#include "output_dir.h"
#include "parallel_runs.h"
#include "report.h"
#include "scenario_file.h"
#include "scenario_override.h"
#include "scenario_run.h"

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

#ifndef PREDVS_VERSION
#define PREDVS_VERSION "unknown"
#endif

namespace fs = std::filesystem;

namespace predvs {
namespace {

constexpr int kRecordFormat = 1;

struct Fnv {
  std::uint64_t h = 1469598103934665603ull;
  void add(const std::string& s) {
    for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
    h = (h ^ 0xffu) * 1099511628211ull;  // separator: ("ab","c") != ("a","bc")
  }
  std::string hex() const {
    char b[17];
    std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(h));
    return b;
  }
};

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw std::invalid_argument(p.string() + ": cannot be read");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Writes atomically: a temporary name in the same directory, then rename.
void writeFileAtomic(const fs::path& p, const std::string& text) {
  const fs::path tmp = p.parent_path() / ("." + p.filename().string() + ".tmp");
  {
    std::ofstream f(tmp, std::ios::binary);
    f << text;
    if (!f) throw std::runtime_error(tmp.string() + ": write failed");
  }
  fs::rename(tmp, p);
}

nlohmann::json number(double x) {
  if (std::isfinite(x)) return x;
  return std::isnan(x) ? "nan" : x > 0 ? "inf" : "-inf";
}

double numberFrom(const nlohmann::json& j) {
  if (j.is_number()) return j.get<double>();
  const std::string s = j.get<std::string>();
  if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
  if (s == "inf") return std::numeric_limits<double>::infinity();
  if (s == "-inf") return -std::numeric_limits<double>::infinity();
  throw std::invalid_argument("not a number: " + s);
}

/// The directory holding the records of DIR: DIR/runs when it exists, else DIR.
fs::path recordsDir(const fs::path& dir) { return fs::is_directory(dir / "runs") ? dir / "runs" : dir; }

std::string sweepText(const ScenarioSweep& sw) {
  std::string values;
  for (const auto& v : sw.values) values += (values.empty() ? "" : ", ") + v;
  return sw.key + "=[" + values + "]";
}

/// What rebuilds the plan of a shard in `predvs merge`.
nlohmann::json optionsJson(const CompareOptions& o) {
  nlohmann::json j;
  j["scenarios"] = o.scenarios;
  j["predictors"] = o.predictors;
  j["runs"] = o.runs;
  j["seed"] = o.seed_given ? nlohmann::json(o.seed) : nlohmann::json(nullptr);
  // Each override as PATH=VALUE (what parseScenarioOverride reads back) and its text as recorded
  // ("camera.px=400 (--camera FILE)" for one from a file, whose file merge need not read again).
  j["overrides"] = nlohmann::json::array();
  for (const auto& ov : o.overrides) {
    std::string path;
    for (const auto& seg : ov.path) path += (path.empty() ? "" : ".") + seg;
    YAML::Emitter e;
    e << YAML::Flow << ov.value;
    j["overrides"].push_back({{"set", path + "=" + (ov.value.IsNull() ? std::string() : std::string(e.c_str()))},
                              {"text", ov.text}});
  }
  j["sweeps"] = nlohmann::json::array();
  for (const auto& sw : o.sweeps) j["sweeps"].push_back(sweepText(sw));
  return j;
}

CompareOptions optionsFrom(const nlohmann::json& j) {
  CompareOptions o;
  o.scenarios = j.at("scenarios").get<std::vector<std::string>>();
  o.predictors = j.at("predictors").get<std::vector<std::string>>();
  o.runs = j.at("runs").get<int>();
  if (!j.at("seed").is_null()) {
    o.seed_given = true;
    o.seed = j.at("seed").get<unsigned long>();
  }
  for (const auto& t : j.at("overrides")) {
    o.overrides.push_back(parseScenarioOverride(t.at("set").get<std::string>()));
    o.overrides.back().text = t.at("text").get<std::string>();
  }
  for (const auto& t : j.at("sweeps")) o.sweeps.push_back(parseSweepOption(t.get<std::string>()));
  return o;
}

/// Writes the outputs of a whole campaign (or, sharded, its records and shard.json) into OUT.
void writeOutputs(const Plan& plan, const CompareOptions& o, const std::vector<Job>& jobs,
                  const std::vector<JobKey>& keys, const std::vector<size_t>& selected,
                  const std::vector<RunRecord>& outcomes, const std::string& fingerprint, int workers, double wall_s,
                  std::ostream& out) {
  StagedOutputDir dir(o.out_dir);
  fs::create_directories(dir.staging() / "runs");
  for (size_t j : selected) {
    std::ofstream f(dir.staging() / "runs" / keys[j].record_name, std::ios::binary);
    f << recordText(plan, jobs[j], keys[j], outcomes[j]);
    if (!f) throw std::runtime_error(dir.file("runs/" + keys[j].record_name) + ": write failed");
  }
  if (o.shard_count > 0) {
    nlohmann::json m;
    m["format"] = kRecordFormat;
    m["predvs_version"] = PREDVS_VERSION;
    m["shard"] = o.shard_index;
    m["of"] = o.shard_count;
    m["campaign"] = fingerprint;
    m["command"] = o.command_line;
    m["options"] = optionsJson(o);
    m["runs_total"] = jobs.size();
    m["runs_in_shard"] = selected.size();
    writeTextFile(dir, "shard.json", m.dump(2) + "\n");
    dir.commit();
    out << "shard " << o.shard_index << "/" << o.shard_count << ": " << selected.size() << " of " << jobs.size()
        << " runs in " << std::fixed << std::setprecision(1) << wall_s << " s on " << workers << " threads"
        << std::defaultfloat << "; wrote " << (dir.target() / "runs").string()
        << "/ and shard.json (predvs merge SHARD_DIRS... --out DIR)\n";
    return;
  }
  const Results res = aggregate(plan, jobs, outcomes);
  CompareRunInfo info;
  info.wall_s = wall_s;
  info.workers = workers;
  writeCompareReport(plan, res, o, info, dir);
  writeReportHtml(plan, res, o, dir);
  dir.commit();
  printCompareReport(plan, res, out);
  out << "\n" << jobs.size() << " runs in " << std::fixed << std::setprecision(1) << wall_s << " s on " << workers
      << (workers == 1 ? " worker" : " workers") << std::defaultfloat << "; wrote "
      << (dir.target() / "leaderboard.md").string() << ", leaderboard.csv, leaderboard.json, report.html"
      << (o.plots ? " and plots" : "") << "; run records in runs/\n";
}

struct StopAfter : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace

ShardSpec parseShard(const std::string& text) {
  const size_t slash = text.find('/');
  auto integer = [&](const std::string& s) {
    if (s.empty() || s.size() > 6 || s.find_first_not_of("0123456789") != std::string::npos)
      throw std::invalid_argument("--shard: expected I/N with 1 <= I <= N (e.g. 2/8), got '" + text + "'");
    return std::stoi(s);
  };
  if (slash == std::string::npos)
    throw std::invalid_argument("--shard: expected I/N with 1 <= I <= N (e.g. 2/8), got '" + text + "'");
  ShardSpec s{integer(text.substr(0, slash)), integer(text.substr(slash + 1))};
  if (s.index < 1 || s.index > s.count || s.count > 100000)
    throw std::invalid_argument("--shard: expected I/N with 1 <= I <= N (e.g. 2/8), got '" + text + "'");
  return s;
}

std::vector<std::string> campaignArgs(const std::vector<std::string>& args) {
  static const std::set<std::string> dropped = {"--out", "--jobs", "--shard", "--resume", "--stop-after"};
  std::vector<std::string> kept;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (dropped.count(a)) {
      ++i;  // and its value
      continue;
    }
    const size_t eq = a.find('=');
    if (a.rfind("--", 0) == 0 && eq != std::string::npos && dropped.count(a.substr(0, eq))) continue;
    kept.push_back(a);
  }
  return kept;
}

std::vector<JobKey> jobKeys(const Plan& plan, const CompareOptions& o, const std::vector<Job>& jobs) {
  std::map<std::string, std::string> file_text;  // scenario path -> bytes
  std::vector<JobKey> keys;
  std::set<std::string> names;
  for (const Job& job : jobs) {
    const Variant& var = plan.variants[job.variant];
    const Scenario& sc = *var.scenario;
    const ScenarioPredictor& p = sc.predictors[job.predictor];
    const std::string& path = plan.scenarios[var.scenario_index].path;
    if (!file_text.count(path)) file_text[path] = readFile(path);
    Fnv h;
    h.add(file_text[path]);
    for (const auto& t : overrideTexts(o.overrides)) h.add(t);
    const auto& axes = plan.scenarios[var.scenario_index].sweeps;
    for (size_t a = 0; a < var.values.size() && a < axes.size(); ++a) h.add(axes[a].key + "=" + var.values[a]);
    h.add(p.name);
    h.add(p.typeName());
    for (const auto& kv : p.params.values()) {
      std::ostringstream s;
      s << std::setprecision(17) << kv.first << "=" << kv.second;
      h.add(s.str());
    }
    for (const auto& kv : p.params.texts()) h.add(kv.first + "=" + kv.second);
    JobKey k;
    k.scenario_hash = h.hex();
    k.record_name = fileSafe(var.id + "__" + p.name + "__seed" + std::to_string(jobSeed(plan, job))) + ".json";
    if (!names.insert(k.record_name).second)
      throw std::logic_error("two runs of the campaign share the record name " + k.record_name);
    keys.push_back(std::move(k));
  }
  return keys;
}

std::string campaignFingerprint(const std::vector<JobKey>& keys) {
  Fnv h;
  for (const auto& k : keys) {
    h.add(k.record_name);
    h.add(k.scenario_hash);
  }
  return h.hex();
}

std::string recordText(const Plan& plan, const Job& job, const JobKey& key, const RunRecord& run) {
  const Variant& var = plan.variants[job.variant];
  nlohmann::json j;
  j["format"] = kRecordFormat;
  j["predvs_version"] = PREDVS_VERSION;
  j["scenario"] = plan.scenarios[var.scenario_index].name;
  j["variant"] = var.id;
  j["predictor"] = var.scenario->predictors[job.predictor].name;
  j["seed"] = jobSeed(plan, job);
  j["run"] = job.run;
  j["scenario_hash"] = key.scenario_hash;
  j["values"] = nlohmann::json::array();
  for (const auto& kv : run.values) j["values"].push_back({kv.first, number(kv.second)});
  j["t_s"] = nlohmann::json::array();
  j["error"] = nlohmann::json::array();
  if (var.shown) {
    for (double x : run.t_s) j["t_s"].push_back(number(x));
    for (double x : run.error) j["error"].push_back(number(x));
  }
  return j.dump() + "\n";
}

bool parseRecord(const std::string& text, const Plan& plan, const Job& job, const JobKey& key, RunRecord& run,
                 std::string& why) {
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    const Variant& var = plan.variants[job.variant];
    if (j.at("format").get<int>() != kRecordFormat) return why = "record format", false;
    if (j.at("predvs_version").get<std::string>() != PREDVS_VERSION)
      return why = "predvs version " + j.at("predvs_version").get<std::string>() + " (this is " + PREDVS_VERSION + ")",
             false;
    if (j.at("variant").get<std::string>() != var.id ||
        j.at("predictor").get<std::string>() != var.scenario->predictors[job.predictor].name ||
        j.at("seed").get<std::uint64_t>() != jobSeed(plan, job))
      return why = "another run's record", false;
    if (j.at("scenario_hash").get<std::string>() != key.scenario_hash)
      return why = "scenario content changed (hash " + j.at("scenario_hash").get<std::string>() + ", now " +
                   key.scenario_hash + ")",
             false;
    RunRecord r;
    r.predictor = j.at("predictor").get<std::string>();
    for (const auto& kv : j.at("values")) r.values.emplace_back(kv.at(0).get<std::string>(), numberFrom(kv.at(1)));
    for (const auto& x : j.at("t_s")) r.t_s.push_back(numberFrom(x));
    for (const auto& x : j.at("error")) r.error.push_back(numberFrom(x));
    if (r.t_s.size() != r.error.size()) return why = "t_s and error differ in length", false;
    run = std::move(r);
    return true;
  } catch (const std::exception& e) {
    why = std::string("unreadable (") + e.what() + ")";
    return false;
  }
}

void runCampaign(const CompareOptions& o, std::ostream& out, std::ostream& err) {
  const auto start = std::chrono::steady_clock::now();
  const MpiWorld world = mpiWorld();
  const bool root = world.rank == 0;
  if (world.size > 1 && o.shard_count > 0)
    throw std::invalid_argument("--shard: not under mpirun (a shard is one process; mpirun spreads a whole campaign)");
  const Plan plan = makePlan(o);
  std::vector<std::string> inputs = o.inputs;
  for (const std::string& s : o.scenarios)
    if (s != "all") inputs.push_back(resolveScenario(s));
  StagedOutputDir::checkReplaceable(o.out_dir, inputs);
  const bool sharded = o.shard_count > 0;
  if (o.plots && !sharded) requireGnuplot();
  const std::vector<Job> jobs = planJobs(plan);
  const std::vector<JobKey> keys = jobKeys(plan, o, jobs);
  std::vector<size_t> selected;
  for (size_t j = 0; j < jobs.size(); ++j)
    if (!sharded || static_cast<int>(j % static_cast<size_t>(o.shard_count)) == o.shard_index - 1) selected.push_back(j);

  std::vector<RunRecord> outcomes(jobs.size());
  std::vector<size_t> to_compute;
  const fs::path journal = fs::path(o.out_dir).string() + ".partial";
  const fs::path journal_runs = journal / "runs";
  size_t reused = 0, stale = 0;
  std::exception_ptr before;  // rank 0's failure before the hand-out: the other ranks are released first
  if (root) {
    try {
      std::vector<char> have(jobs.size(), 0);
      if (!o.resume_dir.empty()) {
        if (!fs::is_directory(o.resume_dir))
          throw std::invalid_argument("--resume: " + o.resume_dir + " is not a directory");
        const fs::path from = recordsDir(o.resume_dir);
        for (size_t j : selected) {
          const fs::path p = from / keys[j].record_name;
          if (!fs::exists(p)) continue;
          std::string why;
          if (parseRecord(readFile(p), plan, jobs[j], keys[j], outcomes[j], why)) {
            have[j] = 1;
            ++reused;
          } else {
            ++stale;
            if (stale <= 3) err << "predvs: compare: not reusing " << p.string() << ": " << why << "\n";
          }
        }
      }
      for (size_t j : selected)
        if (!have[j]) to_compute.push_back(j);
      fs::create_directories(journal_runs);
      if (reused > 0 && fs::absolute(recordsDir(o.resume_dir)).lexically_normal() !=
                            fs::absolute(journal_runs).lexically_normal())
        for (size_t j : selected)  // the journal holds every record of the campaign so far
          if (have[j]) writeFileAtomic(journal_runs / keys[j].record_name, recordText(plan, jobs[j], keys[j], outcomes[j]));
    } catch (...) {
      before = std::current_exception();
      to_compute.clear();
    }
  }

  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  // Under mpirun, --jobs is per rank and defaults to 1 (one rank per core is mpirun's habit).
  const int threads = o.jobs > 0 ? o.jobs : world.size > 1 ? 1 : static_cast<int>(hw);
  int workers = threads * world.size;
  if (root && !before) {
    err << "predvs: compare: " << plan.scenarios.size() << " scenarios (" << plan.variants.size() << " variants), "
        << jobs.size() << " runs";
    if (sharded) err << ", shard " << o.shard_index << "/" << o.shard_count << ": " << selected.size() << " runs";
    if (!o.resume_dir.empty())
      err << "; " << reused << " from the records in " << o.resume_dir << (stale ? " (" + std::to_string(stale) + " stale, not reused)" : "");
    err << "; computing " << to_compute.size() << " on ";
    if (world.size > 1) err << world.size << " MPI ranks x " << threads << " threads\n";
    else err << std::min<size_t>(static_cast<size_t>(threads), std::max<size_t>(1, to_compute.size())) << " threads\n";
  }

  std::mutex store_mutex;
  int stored = 0;
  auto compute = [&](size_t j) {
    const Job& job = jobs[j];
    const Scenario& sc = *plan.variants[job.variant].scenario;
    const RunRecord r = runScenarioOnce(sc, sc.predictors[job.predictor], jobSeed(plan, job), false);
    return recordText(plan, job, keys[j], r);  // drops the error series of variants not plotted
  };
  // Rank 0, one call at a time: parse (so every path reads its runs back the same way), journal.
  double store_s = 0.0;  // rank 0's time in `done` (parse + journal), for the coordination figures
  auto done = [&](size_t j, const std::string& text) {
    const auto t0 = std::chrono::steady_clock::now();
    struct Clock {  // adds the time of this call to store_s however it leaves
      double& total;
      std::chrono::steady_clock::time_point t0;
      ~Clock() { total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); }
    } clock{store_s, t0};
    std::string why;
    if (!parseRecord(text, plan, jobs[j], keys[j], outcomes[j], why))
      throw std::logic_error("run record of " + keys[j].record_name + ": " + why);
    writeFileAtomic(journal_runs / keys[j].record_name, text);
    ++stored;
    if (o.stop_after > 0 && stored >= o.stop_after)
      throw StopAfter("--stop-after " + std::to_string(o.stop_after) + ": stopped after " + std::to_string(stored) +
                      " stored runs (test hook)");
  };
  try {
    if (world.size > 1) {
      mpiRunJobs(world, to_compute, threads, compute, done, err);
      if (!root) return;
    } else if (!before) {
      ParallelOptions par;
      par.start = start;
      par.workers = static_cast<int>(std::min<size_t>(static_cast<size_t>(threads), std::max<size_t>(1, to_compute.size())));
      par.progress_bar = o.progress_bar;
      workers = par.workers;
      runParallel(
          to_compute.size(),
          [&](size_t i) {
            const std::string text = compute(to_compute[i]);
            std::lock_guard<std::mutex> lock(store_mutex);
            done(to_compute[i], text);
          },
          par, err);
    }
    if (before) std::rethrow_exception(before);
  } catch (...) {
    if (root && !before && fs::exists(journal_runs))
      err << "predvs: compare: the runs stored so far are in " << journal.string() << " (continue with --resume "
          << journal.string() << ")\n";
    throw;
  }

  if (stored > 0)
    err << "predvs: compare: rank 0 stored " << stored << " run records, " << std::setprecision(3)
        << 1e3 * store_s / stored << " ms each (parse + journal write)\n" << std::setprecision(6);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  writeOutputs(plan, o, jobs, keys, selected, outcomes, campaignFingerprint(keys), workers, wall_s, out);
  std::error_code ec;
  fs::remove_all(journal, ec);
}

void runMergeCommand(const MergeOptions& mo, std::ostream& out, std::ostream& err) {
  const auto start = std::chrono::steady_clock::now();
  if (mo.dirs.empty()) throw std::invalid_argument("merge: expected the shard directories");
  StagedOutputDir::checkReplaceable(mo.out_dir, mo.dirs);
  struct Shard {
    std::string dir;
    nlohmann::json manifest;
  };
  std::map<int, Shard> shards;
  int count = 0;
  std::string fingerprint;
  for (const auto& d : mo.dirs) {
    const fs::path m = fs::path(d) / "shard.json";
    if (!fs::exists(m)) throw std::invalid_argument("merge: " + d + ": no shard.json (not the output of compare --shard I/N)");
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(readFile(m));
      j.at("shard").get<int>();
      j.at("of").get<int>();
      j.at("campaign").get<std::string>();
      j.at("predvs_version").get<std::string>();
    } catch (const nlohmann::json::exception& e) {
      throw std::invalid_argument("merge: " + m.string() + ": malformed (" + e.what() + ")");
    }
    const int i = j["shard"].get<int>(), n = j["of"].get<int>();
    const std::string tag = std::to_string(i) + "/" + std::to_string(n);
    if (j["predvs_version"].get<std::string>() != PREDVS_VERSION)
      throw std::invalid_argument("merge: " + d + ": shard " + tag + " was written by predvs " +
                                  j["predvs_version"].get<std::string>() + " (this is " + PREDVS_VERSION + ")");
    if (count == 0) {
      count = n;
      fingerprint = j["campaign"].get<std::string>();
    } else if (n != count || j["campaign"].get<std::string>() != fingerprint) {
      throw std::invalid_argument("merge: " + d + ": shard " + tag + " is of another campaign than " +
                                  shards.begin()->second.dir + " (shard " + std::to_string(shards.begin()->first) +
                                  "/" + std::to_string(count) + ")");
    }
    if (shards.count(i))
      throw std::invalid_argument("merge: shard " + tag + " given twice: " + shards[i].dir + " and " + d);
    shards[i] = {d, j};
  }
  std::string missing;
  for (int i = 1; i <= count; ++i)
    if (!shards.count(i)) missing += (missing.empty() ? "" : ", ") + std::to_string(i) + "/" + std::to_string(count);
  if (!missing.empty()) throw std::invalid_argument("merge: shard " + missing + " missing (give every shard's directory)");

  const nlohmann::json& first = shards.begin()->second.manifest;
  CompareOptions o = optionsFrom(first.at("options"));
  o.command_line = first.at("command").get<std::string>();
  o.out_dir = mo.out_dir;
  o.plots = mo.plots;
  const Plan plan = makePlan(o);
  if (o.plots) requireGnuplot();
  const std::vector<Job> jobs = planJobs(plan);
  const std::vector<JobKey> keys = jobKeys(plan, o, jobs);
  if (campaignFingerprint(keys) != fingerprint)
    throw std::invalid_argument("merge: the campaign of the shards (" + fingerprint +
                                ") differs from what its scenario files give now (" + campaignFingerprint(keys) +
                                "): a scenario file changed since the shards ran");
  std::vector<RunRecord> outcomes(jobs.size());
  std::vector<size_t> all;
  for (size_t j = 0; j < jobs.size(); ++j) {
    const Shard& s = shards[static_cast<int>(j % static_cast<size_t>(count)) + 1];
    const fs::path p = fs::path(s.dir) / "runs" / keys[j].record_name;
    if (!fs::exists(p)) throw std::invalid_argument("merge: " + p.string() + ": missing run record");
    std::string why;
    if (!parseRecord(readFile(p), plan, jobs[j], keys[j], outcomes[j], why))
      throw std::invalid_argument("merge: " + p.string() + ": " + why);
    all.push_back(j);
  }
  err << "predvs: merge: " << count << " shards, " << jobs.size() << " runs\n";
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  writeOutputs(plan, o, jobs, keys, all, outcomes, fingerprint, 1, wall_s, out);
}

}  // namespace predvs
