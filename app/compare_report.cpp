#include "compare_report.h"

#include "gnuplot.h"
#include "plots.h"
#include "report.h"

#include "predvs/servo/paper_trajectories.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
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

/// A CSV field: quoted (with "" for ") when it holds a comma, a quote or a line break.
std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string q = "\"";
  for (char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string leaderboardCsv(const Plan& plan, const Results& res) {
  std::ostringstream csv;
  csv << "scenario,variant,predictor,metric,n,mean,std,min,max,median\n";
  for (size_t v = 0; v < plan.variants.size(); ++v) {
    const Variant& var = plan.variants[v];
    for (size_t p : ranking(plan, res, v))
      for (size_t m = 0; m < res.metrics[v].size(); ++m) {
        const Stats& s = res.cells[v][p].stats[m];
        csv << var.scenario->name << "," << csvField(var.id) << "," << var.scenario->predictors[p].name << ","
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
  // --sweep, applied to every scenario: its text, a list of them for a grid, null without
  auto optionText = [](const ScenarioSweep& sw) {
    std::string values;
    for (const auto& v : sw.values) values += (values.empty() ? "" : ", ") + v;
    return sw.key + "=[" + values + "]";
  };
  if (o.sweeps.size() == 1) {
    j["sweep"] = optionText(o.sweeps.front());
  } else if (o.sweeps.empty()) {
    j["sweep"] = nullptr;
  } else {
    j["sweep"] = nlohmann::json::array();
    for (const auto& sw : o.sweeps) j["sweep"].push_back(optionText(sw));
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
    // One axis: "sweep" {key, values, from}; several: "grid", a list of them (first axis slowest).
    auto axisJson = [&](const ScenarioSweep& sw) {
      nlohmann::json a = {{"key", sw.key}, {"values", nlohmann::json::array()},
                          {"from", sw.origin == "--sweep" ? "--sweep" : "scenario file"}};
      for (const auto& text : sw.values) {
        char* end = nullptr;
        const double x = std::strtod(text.c_str(), &end);
        a["values"].push_back(end != text.c_str() && *end == '\0' && std::isfinite(x) ? nlohmann::json(x)
                                                                                       : nlohmann::json(text));
      }
      return a;
    };
    if (sc.sweeps.size() == 1) {
      s["sweep"] = axisJson(sc.sweeps.front());
    } else if (sc.sweeps.size() > 1) {
      s["grid"] = nlohmann::json::array();
      for (const auto& sw : sc.sweeps) s["grid"].push_back(axisJson(sw));
    }
    const std::vector<size_t> vs = variantsOf(plan, i);
    s["metric_definitions"] = metricDefinitionsJson(res.metrics[vs.front()], sc);
    s["variants"] = nlohmann::json::array();
    for (size_t v : vs) {
      const Variant& var = plan.variants[v];
      nlohmann::json jv;
      jv["id"] = var.id;
      jv["noise_sigma"] = jsonNumber(var.sigma);
      if (var.swept && sc.sweeps.size() == 1) jv["sweep_value"] = sweepValueJson(var.value, var.x);
      if (var.swept && sc.sweeps.size() > 1)
        for (size_t a = 0; a < sc.sweeps.size(); ++a)
          jv["grid_values"][sc.sweeps[a].key] = sweepValueJson(var.values[a], var.xs[a]);
      jv["predictors"] = nlohmann::json::array();
      const auto& preds = var.scenario->predictors;  // a sweep may change their parameters
      for (size_t p : ranking(plan, res, v)) {
        nlohmann::json jp;
        jp["name"] = preds[p].name;
        jp["type"] = preds[p].typeName();
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

// No wall time or thread count here (the terminal has them): the outputs of a campaign are
// byte-identical however it was spread (threads, MPI ranks, shards, resumed; campaign.h).
std::string leaderboardMarkdown(const Plan& plan, const Results& res, const CompareOptions& o,
                                const CompareRunInfo&) {
  std::ostringstream md;
  md << "# predvs compare: leaderboard\n\n"
     << "Command: `" << o.command_line << "`.\n\n"
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
    const bool lone_sigma = sc.sweeps.size() == 1 && sc.sweeps.front().key == "noise.sigma";
    if (var.swept && !lone_sigma)
      for (size_t a = 0; a < sc.sweeps.size(); ++a) md << ", " << sc.sweeps[a].key << " = " << var.values[a];
    md << ", error in " << errorUnits(sc);
    if (var.swept)
      md << (lone_sigma ? std::string(" (every sigma in leaderboard.csv)")
                        : sc.sweeps.size() == 1 ? " (every " + sc.sweeps.front().key + " in leaderboard.csv)"
                                                : " (every cell of the " + sweepKeysText(sc.sweeps) +
                                                      " grid in leaderboard.csv and grid_" + fileSafe(sc.name) + ".csv)");
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
    // Runs that fail at t = 0 (metrics.outcome) have no error samples: no plot for such a variant.
    bool any = false;
    for (const auto& c : res.cells[v])
      for (double e : c.mean_error) any = any || std::isfinite(e);
    if (!any) continue;
    const std::string base = "error_" + var.file_id;
    const auto& cells = res.cells[v];
    size_t len = 0;
    for (const auto& c : cells) len = std::max(len, c.t_s.size());
    {
      std::ostringstream d;
      d << "# t_s then the mean over runs of the error of each predictor:";
      for (const auto& p : sc.predictors) d << " " << p.name;
      d << "\n";
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
    // About 20 markers per curve: a predictor that coincides with another (st-akf under st-akf-pm
    // on E12, stkf under stkf-plain on E6) shows its own between the other's.
    p.marker_rows = std::max<size_t>(1, len / 20);
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
  const ScenarioSweep& sweep = sc.sweeps.front();
  const std::string key = sweep.shortKey();
  const std::string base = "rmse_vs_" + fileSafe(key) + "_" + fileSafe(sc.name);
  bool positive = true;  // every run's rmse > 0: a log axis, so that large and small errors both read
  bool any = false;      // some rmse at all (every run of a metrics.outcome sweep may fail)
  for (size_t v : vs)
    for (const auto& cell : res.cells[v]) {
      const Stats& st = cell.stats[metricIndex(res, v, "rmse")];
      positive = positive && (st.n == 0 || st.min > 0.0);
      any = any || st.n > 0;
    }
  if (!any) return;
  {
    std::ostringstream d;
    d << "# one block per predictor (separated by two blank lines): " << sweep.key
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
  f.title = sc.name + ": steady-window rmse versus " + sweep.key + ", median over " +
            std::to_string(plan.runs[i]) + " runs, bars from the best to the worst run";
  PlotPanel p;
  p.xlabel = sweep.key;
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

/// The Stats of metric `name` of variant v and predictor p (empty Stats when the variant has no
/// such figure, e.g. the outcome without metrics.outcome).
Stats metricStats(const Results& res, size_t v, size_t p, const std::string& name) {
  const auto& m = res.metrics[v];
  const auto at = std::find(m.begin(), m.end(), name);
  return at == m.end() ? Stats{} : res.cells[v][p].stats[static_cast<size_t>(at - m.begin())];
}

/// grid_<scenario>.csv: one row per cell (variant) and predictor, the outcome of the cell's runs
/// (fractions are means of the runs' 0/1 values; medians over the runs where the figure is finite).
void writeGridCsv(const Plan& plan, const Results& res, const StagedOutputDir& dir, size_t i) {
  const Scenario& sc = plan.scenarios[i];
  std::ostringstream csv;
  csv << "scenario,variant";
  for (const auto& axis : sc.sweeps) csv << "," << csvField(axis.key);
  csv << ",predictor,n,converged_fraction,convergence_time_median_s,failed_fraction,fail_behind_fraction,"
         "fail_image_fraction,fail_robot_fraction,rmse_median,rmse_n\n";
  for (size_t v : variantsOf(plan, i)) {
    const Variant& var = plan.variants[v];
    for (size_t p = 0; p < var.scenario->predictors.size(); ++p) {
      csv << csvField(sc.name) << "," << csvField(var.id);
      for (const auto& value : var.values) csv << "," << csvField(value);
      const Stats rmse = metricStats(res, v, p, "rmse");
      csv << "," << csvField(var.scenario->predictors[p].name) << "," << plan.runs[i] << ","
          << csvNumber(metricStats(res, v, p, "converged").mean) << ","
          << csvNumber(metricStats(res, v, p, "convergence_time_s").median) << ","
          << csvNumber(metricStats(res, v, p, "failed").mean) << ","
          << csvNumber(metricStats(res, v, p, "fail_behind").mean) << ","
          << csvNumber(metricStats(res, v, p, "fail_image").mean) << ","
          << csvNumber(metricStats(res, v, p, "fail_robot").mean) << "," << csvNumber(rmse.median) << "," << rmse.n
          << "\n";
    }
  }
  writeTextFile(dir, "grid_" + fileSafe(sc.name) + ".csv", csv.str());
}

/// A number for a heat-map label: two significant digits ("2.3", "0.56", "12").
std::string shortNumber(double x) {
  std::ostringstream s;
  s << std::setprecision(2) << x;
  return s.str();
}

/// heatmap_<scenario>[_<KEY><value>...].png for a grid of two or more axes (paper 003 Fig. 4
/// analogue): the first axis across, the second up, one panel per predictor; every combination of
/// the further axes' values is its own figure. Colour: the median over the converged runs of the
/// convergence time; grey: no run converged; a cross: some runs failed. Each cell's label gives
/// the median time and, when not every run converged, the failed (F) and not converged (NC) runs.
/// Values are placed at their index (a grid is rarely uniform), labelled with their text.
void plotGridHeatMaps(const Plan& plan, const Results& res, const StagedOutputDir& dir, size_t i) {
  const Scenario& sc = plan.scenarios[i];
  const std::vector<ScenarioSweep>& axes = sc.sweeps;
  const std::vector<size_t> vs = variantsOf(plan, i);
  const size_t nx = axes[0].values.size(), ny = axes[1].values.size();
  // Cells are ordered with the first axis slowest (gridIndices); group them by the values of
  // the axes after the second.
  std::vector<std::vector<size_t>> figures;  // variant indices per combination of the further axes
  std::vector<std::string> suffixes, titles;
  for (size_t v : vs) {
    const Variant& var = plan.variants[v];
    std::string suffix, title;
    for (size_t a = 2; a < axes.size(); ++a) {
      suffix += "_" + axes[a].shortKey() + var.values[a];
      title += ", " + axes[a].key + " = " + var.values[a];
    }
    const auto at = std::find(suffixes.begin(), suffixes.end(), suffix);
    if (at == suffixes.end()) {
      suffixes.push_back(suffix);
      titles.push_back(title);
      figures.push_back({v});
    } else {
      figures[static_cast<size_t>(at - suffixes.begin())].push_back(v);
    }
  }
  const int runs = plan.runs[i];
  const size_t n_pred = sc.predictors.size();
  for (size_t f = 0; f < figures.size(); ++f) {
    const std::string base = "heatmap_" + fileSafe(sc.name + suffixes[f]);
    double t_max = 0.0;
    std::ostringstream d;
    d << "# one block per predictor (separated by two blank lines): index of " << axes[0].key << ", index of "
      << axes[1].key << ", median convergence time over the converged runs (s), converged fraction, failed "
         "fraction, label of the time, label of the runs that did not converge\n";
    for (size_t p = 0; p < n_pred; ++p) {
      d << "# " << sc.predictors[p].name << "\n";
      for (size_t v : figures[f]) {
        const Variant& var = plan.variants[v];
        const double t = metricStats(res, v, p, "convergence_time_s").median;
        const double conv = metricStats(res, v, p, "converged").mean;
        const double fail = metricStats(res, v, p, "failed").mean;
        if (std::isfinite(t)) t_max = std::max(t_max, t);
        const long n_fail = std::isfinite(fail) ? std::lround(fail * runs) : 0;
        const long n_nc = std::isfinite(conv) ? runs - std::lround(conv * runs) - n_fail : 0;
        std::string other;
        if (n_fail > 0) other += "F " + std::to_string(n_fail) + "/" + std::to_string(runs);
        if (n_nc > 0) other += (other.empty() ? "" : " ") + std::string("NC ") + std::to_string(n_nc) + "/" + std::to_string(runs);
        d << var.indices[0] << " " << var.indices[1] << " " << datNumber(t) << " " << datNumber(conv) << " "
          << datNumber(fail) << " \"" << (std::isfinite(t) ? shortNumber(t) : "-") << "\" \"" << other << "\"\n";
      }
      d << "\n\n";
    }
    writeTextFile(dir, base + ".dat", d.str());

    const size_t cols = std::min<size_t>(n_pred, 3), rows = (n_pred + cols - 1) / cols;
    constexpr int kTitleWidthPx = 880;  // the two title lines fit
    const int pw = static_cast<int>(std::max<size_t>(560, 70 * nx + 220));
    const int ph = static_cast<int>(std::max<size_t>(400, 50 * ny + 180));
    auto tics = [](const ScenarioSweep& axis) {
      std::string t = "(";
      for (size_t k = 0; k < axis.values.size(); ++k) t += (k ? ", " : "") + gnuplotQuote(axis.values[k]) + " " + std::to_string(k);
      return t + ")";
    };
    std::ostringstream gp;
    gp << "# Regenerate with: gnuplot " << base << ".gp\n"
       << "set terminal pngcairo size " << std::max(static_cast<int>(cols) * pw, kTitleWidthPx) << ","
       << static_cast<int>(rows) * ph + 70
       << " noenhanced font 'Sans,10'\nset output '" << base << ".png'\n"
       << "set datafile missing 'NaN'\nunset key\nset style fill solid 1.0 noborder\n"
       // One-directional (a time: faster is lighter), light enough for the black labels on every cell.
       << "set palette defined (0 '#fff7bc', 0.5 '#fec44f', 1 '#d95f0e')\n"
       << "set cbrange [0:" << (t_max > 0.0 ? t_max : 1.0) << "]\nset cblabel 'median convergence time [s]' offset 1.5,0\n"
       << "set xrange [-0.5:" << nx - 0.5 << "]\nset yrange [-0.5:" << ny - 0.5 << "]\n"
       << "set xtics " << tics(axes[0]) << "\nset ytics " << tics(axes[1]) << "\n"
       << "set xlabel " << gnuplotQuote(axes[0].key) << "\nset ylabel " << gnuplotQuote(axes[1].key) << "\n";
    // Two title lines: gnuplot turns \n inside a double-quoted string into a line break.
    const std::string line1 = gnuplotQuote(sc.name + titles[f] + ": median convergence time of the converged runs, " +
                                           std::to_string(runs) + " runs per cell");
    const std::string line2 = gnuplotQuote(
        "light grey: none converged; dark grey: none converged, some failed; x: some failed "
        "(F failed, NC not converged, of the runs)");
    gp << "set multiplot layout " << rows << "," << cols << " title " << line1.substr(0, line1.size() - 1) << "\\n"
       << line2.substr(1) << "\n";
    for (size_t p = 0; p < n_pred; ++p) {
      const std::string data = "'" + base + ".dat' index " + std::to_string(p);
      gp << "set title " << gnuplotQuote(sc.predictors[p].name) << "\n"
         << "plot " << data << " using ($4 > 0 || $5 > 0 ? 1/0 : $1):2:(0.5):(0.5) with boxxyerror lc rgb '#e5e5e5', \\\n"
         << "     " << data << " using ($4 > 0 || $5 == 0 ? 1/0 : $1):2:(0.5):(0.5) with boxxyerror lc rgb '#666666', \\\n"
         // (cells without a converged run skipped: gnuplot paints a NaN colour value grey over the fills)
         << "     " << data << " using ($3 == $3 ? $1 : 1/0):2:(0.5):(0.5):3 with boxxyerror lc palette, \\\n"
         << "     " << data << " using ($1 + 0.36):($5 > 0 ? $2 + 0.3 : 1/0) with points pt 2 ps 1.2 lw 1.5 lc rgb 'black', \\\n"
         << "     " << data << " using 1:2:6 with labels offset 0,0.5 font ',9', \\\n"
         << "     " << data << " using 1:2:7 with labels offset 0,-0.6 font ',8'\n";
    }
    gp << "unset multiplot\n";
    writeTextFile(dir, base + ".gp", gp.str());
    runGnuplot(dir.staging().string(), base + ".gp");
  }
}

}  // namespace

void writeCompareReport(const Plan& plan, const Results& res, const CompareOptions& o, const CompareRunInfo& info,
                        const StagedOutputDir& dir) {
  writeTextFile(dir, "leaderboard.csv", leaderboardCsv(plan, res));
  writeTextFile(dir, "leaderboard.json", leaderboardJson(plan, res, o));
  writeTextFile(dir, "leaderboard.md", leaderboardMarkdown(plan, res, o, info));
  for (size_t i = 0; i < plan.scenarios.size(); ++i)
    if (!plan.scenarios[i].sweeps.empty()) writeGridCsv(plan, res, dir, i);
  if (!o.plots) return;
  plotErrors(plan, res, dir);
  for (size_t i = 0; i < plan.scenarios.size(); ++i) {
    const Scenario& sc = plan.scenarios[i];
    if (sc.sweeps.empty()) continue;
    if (sc.sweeps.size() > 1)
      plotGridHeatMaps(plan, res, dir, i);
    else if (sc.sweeps.front().key == "noise.sigma" && sc.kind == ScenarioKind::OpenLoop && !sc.sigma_sweep.empty())
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
