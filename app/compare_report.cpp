#include "compare_report.h"

#include "gnuplot.h"
#include "plots.h"
#include "report.h"

#include "predvs/servo/paper_trajectories.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string sigmaText(double sigma) {
  std::ostringstream s;
  s << sigma;
  return s.str();
}

/// The table of variant v: its shown metrics (report.h), predictors ranked by mean rmse.
MetricTable variantTable(const Plan& plan, const Results& res, size_t v) {
  const Variant& var = plan.variants[v];
  MetricTable t;
  t.runs = plan.runs[var.scenario_index];
  t.metrics = tableMetrics(res.metrics[v], *var.scenario);
  for (size_t p : ranking(plan, res, v)) {
    t.rows.push_back(var.scenario->predictors[p].name);
    std::vector<Stats> row;
    for (const auto& m : t.metrics) row.push_back(res.cells[v][p].stats[metricIndex(res, v, m)]);
    t.cells.push_back(row);
  }
  return t;
}

std::string leaderboardCsv(const Plan& plan, const Results& res) {
  std::ostringstream csv;
  csv << "scenario,variant,predictor,metric,n,mean,std,min,max,median\n";
  for (size_t v = 0; v < plan.variants.size(); ++v) {
    const Variant& var = plan.variants[v];
    for (size_t p : ranking(plan, res, v))
      for (size_t m = 0; m < res.metrics[v].size(); ++m) {
        const Stats& s = res.cells[v][p].stats[m];
        csv << var.scenario->name << "," << var.id << "," << var.scenario->predictors[p].name << ","
            << res.metrics[v][m] << "," << s.n << "," << csvNumber(s.mean) << "," << csvNumber(s.std) << ","
            << csvNumber(s.min) << "," << csvNumber(s.max) << "," << csvNumber(s.median) << "\n";
      }
  }
  return csv.str();
}

nlohmann::json sweepValueJson(const std::string& text, double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(text);
}

std::string leaderboardJson(const Plan& plan, const Results& res, const CompareOptions& o) {
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
  j["error_definition"] = {{"open-loop", errorDefinition(ScenarioKind::OpenLoop)},
                           {"closed-loop", errorDefinition(ScenarioKind::ClosedLoop)}};
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
      for (size_t v : variantsOf(plan, i))
        s["sweep"]["values"].push_back(sweepValueJson(plan.variants[v].value, plan.variants[v].x));
    }
    const std::vector<size_t> vs = variantsOf(plan, i);
    s["metric_definitions"] = metricDefinitionsJson(res.metrics[vs.front()], sc);
    s["variants"] = nlohmann::json::array();
    for (size_t v : vs) {
      const Variant& var = plan.variants[v];
      nlohmann::json jv;
      jv["id"] = var.id;
      jv["noise_sigma"] = jsonNumber(var.sigma);
      if (var.swept) jv["sweep_value"] = sweepValueJson(var.value, var.x);
      jv["predictors"] = nlohmann::json::array();
      const auto& preds = var.scenario->predictors;  // a sweep may change their parameters
      for (size_t p : ranking(plan, res, v)) {
        nlohmann::json jp;
        jp["name"] = preds[p].name;
        jp["params"] = paramsJson(preds[p].params);
        for (size_t m = 0; m < res.metrics[v].size(); ++m) {
          const Stats& st = res.cells[v][p].stats[m];
          jp["metrics"][res.metrics[v][m]] = {{"n", st.n},
                                              {"mean", jsonNumber(st.mean)},
                                              {"std", jsonNumber(st.std)},
                                              {"min", jsonNumber(st.min)},
                                              {"max", jsonNumber(st.max)},
                                              {"median", jsonNumber(st.median)}};
        }
        jv["predictors"].push_back(jp);
      }
      s["variants"].push_back(jv);
    }
    j["scenarios"].push_back(s);
  }
  return j.dump(2) + "\n";
}

std::string leaderboardMarkdown(const Plan& plan, const Results& res, const CompareOptions& o,
                                const CompareRunInfo& info) {
  std::ostringstream md;
  md << "# predvs compare: leaderboard\n\n"
     << "Command: `" << o.command_line << "` (" << info.workers << " worker threads, wall time " << std::fixed
     << std::setprecision(1) << info.wall_s << " s)" << std::defaultfloat << ".\n\n"
     << "Each cell is mean ± std over the runs (min and max in leaderboard.csv / leaderboard.json); run r uses seed "
        "S + r for every predictor. Predictors are ranked by mean rmse (steady-window RMS error). Metric definitions: "
        "leaderboard.json (metric_definitions) and servo/include/predvs/servo/run_metrics.h.\n";
  for (size_t v = 0; v < plan.variants.size(); ++v) {
    const Variant& var = plan.variants[v];
    const Scenario& sc = *var.scenario;
    const size_t i = var.scenario_index;
    if (!var.shown) continue;  // for a sweep, only the first and last value go into the markdown
    md << "\n## " << var.id << "\n\n"
       << sc.description << "  \n"
       << scenarioKindName(sc.kind) << ", " << plan.runs[i] << " runs, seeds " << plan.seeds[i] << ".."
       << plan.seeds[i] + static_cast<std::uint64_t>(plan.runs[i]) - 1 << ", noise sigma " << sigmaText(var.sigma);
    if (var.swept && sc.sweep.key != "noise.sigma") md << ", " << sc.sweep.key << " = " << var.value;
    md << ", error in " << errorUnits(sc);
    if (var.swept)
      md << (sc.sweep.key == "noise.sigma" ? std::string(" (every sigma in leaderboard.csv)")
                                           : " (every " + sc.sweep.key + " in leaderboard.csv)");
    md << "\n\n" << markdownMetricTable(variantTable(plan, res, v));
  }
  return md.str();
}

/// error_<variant>: mean error versus time, one line per predictor, for every shown variant.
void plotErrors(const Plan& plan, const Results& res, const StagedOutputDir& dir) {
  for (size_t v = 0; v < plan.variants.size(); ++v) {
    const Variant& var = plan.variants[v];
    const Scenario& sc = *var.scenario;
    if (!var.shown) continue;
    const std::string base = "error_" + var.file_id;
    {
      std::ostringstream d;
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
        d << datNumber(t);
        for (const auto& c : cells) d << " " << datNumber(k < c.mean_error.size() ? c.mean_error[k] : kNaN);
        d << "\n";
      }
      writeTextFile(dir, base + ".dat", d.str());
    }
    const bool closed = sc.kind == ScenarioKind::ClosedLoop;
    PlotFigure f;
    f.base = base;
    f.title = var.id + ": mean over " + std::to_string(plan.runs[var.scenario_index]) + " runs of the " +
              (closed ? "tracking error" : "prediction error at the effect time");
    f.setup = eventMarks(runEvents(sc));
    PlotPanel p;
    p.ylabel = closed ? "tracking error e [px]" : "||predicted - true|| [" + errorUnitLabel(sc) + "]";
    p.log_y = true;
    p.setup = "set key outside right top noopaque\n";
    for (size_t k = 0; k < sc.predictors.size(); ++k)
      p.lines.push_back({base + ".dat", "1:" + std::to_string(k + 2), k < 6 ? "lines lw 1.6" : "lines lw 1.6 dt 2",
                         seriesColor(k), sc.predictors[k].name, ""});
    f.panels.push_back(p);
    f.panel_width_px = 1200;
    f.panel_height_px = 700;
    drawFigure(dir, f);
  }
}

/// mse_vs_sigma_<scenario>: an open-loop noise.sigma sweep, position and velocity MSE per channel
/// versus sigma_n, one line per predictor (paper 001 Fig. 8 analogue).
void plotMseVsSigma(const Plan& plan, const Results& res, const StagedOutputDir& dir, size_t i) {
  const Scenario& sc = plan.scenarios[i];
  const auto chans = makeChannelTrajectory(sc.trajectory, sc.trajectory_params)->channelNames();
  const std::string base = "mse_vs_sigma_" + fileSafe(sc.name);
  const std::vector<size_t> vs = variantsOf(plan, i);
  {
    std::ostringstream d;
    d << "# one block per predictor (separated by two blank lines): sigma_n, then mean pos_mse and vel_mse per channel\n";
    for (size_t p = 0; p < sc.predictors.size(); ++p) {
      d << "# " << sc.predictors[p].name << "\n";
      for (size_t v : vs) {
        d << datNumber(plan.variants[v].sigma);
        for (const std::string kind : {"pos_mse_", "vel_mse_"})
          for (const auto& c : chans) d << " " << datNumber(res.cells[v][p].stats[metricIndex(res, v, kind + c)].mean);
        d << "\n";
      }
      d << "\n\n";
    }
    writeTextFile(dir, base + ".dat", d.str());
  }
  const size_t nc = chans.size();
  std::ostringstream gp;
  gp << "# Regenerate with: gnuplot " << base << ".gp\n"
     << "set terminal pngcairo size " << (nc * 500 + 280) << ",1000 enhanced font 'Sans,11'\nset output '" << base
     << ".png'\nset datafile missing 'NaN'\nset grid\nset logscale y\nset format y '%g'\n"
     << "set xlabel 'noise amplitude {/Symbol s}_n [px]'\n"
     << "set multiplot layout 2," << nc << " margins 0.06,0.84,0.07,0.91 spacing 0.07,0.12 title "
     << gnuplotQuote(sc.name + ": MSE versus noise, mean over " + std::to_string(plan.runs[i]) +
                     " runs (paper 001 Fig. 8 analogue)")
     << " noenhanced\n";
  for (int kind = 0; kind < 2; ++kind)
    for (size_t c = 0; c < nc; ++c) {
      const bool last = kind == 1 && c == nc - 1;
      gp << "set title " << gnuplotQuote((kind ? "velocity MSE of " : "position MSE of ") + chans[c]) << " noenhanced\n"
         << "set ylabel " << gnuplotQuote(kind ? "MSE [(px/s)^2]" : "MSE [px^2]") << "\n"
         << (last ? "set key at screen 0.995,0.5 right center box opaque reverse Left\n" : "unset key\n") << "plot ";
      for (size_t p = 0; p < sc.predictors.size(); ++p)
        gp << (p ? ", \\\n     " : "") << "'" << base << ".dat' index " << p << " using 1:"
           << (2 + static_cast<size_t>(kind) * nc + c) << " with linespoints lw 1.6 pt 7 ps 0.6 "
           << (p < 6 ? "" : "dt 2 ") << "lc rgb '" << seriesColor(p) << "' title " << gnuplotQuote(sc.predictors[p].name)
           << " noenhanced";
      gp << "\n";
    }
  gp << "unset multiplot\n";
  writeTextFile(dir, base + ".gp", gp.str());
  runGnuplot(dir.staging().string(), base + ".gp");
}

/// rmse_vs_<key>_<scenario>: any other sweep, the median over the runs of the steady-window rmse
/// with bars from the smallest to the largest run, versus the swept value, one line per predictor
/// (the median, because a run that diverges would make the mean and its spread say nothing about
/// the others; the bars still show it). Numeric values are the x axis; otherwise the
/// values are placed at 0, 1, ... with their text as tic labels.
void plotRmseVsKey(const Plan& plan, const Results& res, const StagedOutputDir& dir, size_t i) {
  const Scenario& sc = plan.scenarios[i];
  const std::vector<size_t> vs = variantsOf(plan, i);
  bool numeric = true;
  for (size_t v : vs) numeric = numeric && std::isfinite(plan.variants[v].x);
  const std::string key = sc.sweep.shortKey();
  const std::string base = "rmse_vs_" + fileSafe(key) + "_" + fileSafe(sc.name);
  bool positive = true;  // every run's rmse > 0: a log axis, so that large and small errors both read
  for (size_t v : vs)
    for (const auto& cell : res.cells[v]) positive = positive && cell.stats[metricIndex(res, v, "rmse")].min > 0.0;
  {
    std::ostringstream d;
    d << "# one block per predictor (separated by two blank lines): " << sc.sweep.key
      << (numeric ? "" : " (as its index)") << ", median, min and max rmse over the runs\n";
    for (size_t p = 0; p < sc.predictors.size(); ++p) {
      d << "# " << sc.predictors[p].name << "\n";
      for (size_t k = 0; k < vs.size(); ++k) {
        const Variant& var = plan.variants[vs[k]];
        const Stats& st = res.cells[vs[k]][p].stats[metricIndex(res, vs[k], "rmse")];
        d << datNumber(numeric ? var.x : static_cast<double>(k)) << " " << datNumber(st.median) << " "
          << datNumber(st.min) << " " << datNumber(st.max) << "\n";
      }
      d << "\n\n";
    }
    writeTextFile(dir, base + ".dat", d.str());
  }
  PlotFigure f;
  f.base = base;
  f.title = sc.name + ": steady-window rmse versus " + sc.sweep.key + ", median over " +
            std::to_string(plan.runs[i]) + " runs, bars from the best to the worst run";
  PlotPanel p;
  p.xlabel = sc.sweep.key;
  p.ylabel = sc.kind == ScenarioKind::ClosedLoop ? "steady rmse of the tracking error [px]"
                                                 : "steady rmse of ||predicted - true|| [" + errorUnits(sc) + "]";
  p.log_y = positive;
  p.setup = "set key outside right top noopaque\nset offsets graph 0.03, graph 0.03, 0, 0\nset autoscale x\n";
  if (!numeric) {
    p.setup += "set xtics (";
    for (size_t k = 0; k < vs.size(); ++k)
      p.setup += (k ? ", " : "") + gnuplotQuote(plan.variants[vs[k]].value) + " " + std::to_string(k);
    p.setup += ")\n";
  }
  for (size_t k = 0; k < sc.predictors.size(); ++k)
    p.lines.push_back({base + ".dat", "1:2:3:4", std::string("yerrorlines lw 1.6 pt 7 ps 0.6") + (k < 6 ? "" : " dt 2"),
                       seriesColor(k), sc.predictors[k].name, "index " + std::to_string(k)});
  f.panels.push_back(p);
  f.panel_height_px = 650;
  drawFigure(dir, f);
}

}  // namespace

void writeCompareReport(const Plan& plan, const Results& res, const CompareOptions& o, const CompareRunInfo& info,
                        const StagedOutputDir& dir) {
  writeTextFile(dir, "leaderboard.csv", leaderboardCsv(plan, res));
  writeTextFile(dir, "leaderboard.json", leaderboardJson(plan, res, o));
  writeTextFile(dir, "leaderboard.md", leaderboardMarkdown(plan, res, o, info));
  if (!o.plots) return;
  plotErrors(plan, res, dir);
  for (size_t i = 0; i < plan.scenarios.size(); ++i) {
    const Scenario& sc = plan.scenarios[i];
    if (sc.sweep.empty()) continue;
    if (sc.sweep.key == "noise.sigma" && sc.kind == ScenarioKind::OpenLoop && !sc.sigma_sweep.empty())
      plotMseVsSigma(plan, res, dir, i);
    else
      plotRmseVsKey(plan, res, dir, i);
  }
}

void printCompareReport(const Plan& plan, const Results& res, std::ostream& out) {
  for (size_t v = 0; v < plan.variants.size(); ++v) {
    const Variant& var = plan.variants[v];
    if (!var.shown) continue;
    out << "\n" << var.id << " (" << plan.runs[var.scenario_index] << " runs; mean over runs)\n";
    printMetricTable(variantTable(plan, res, v), out);
  }
}

}  // namespace predvs
