#include "campaign_html.h"

#include "report.h"
#include "scenario_override.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace predvs {
namespace {

std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

std::string base64(const std::string& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string o;
  o.reserve((in.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(in[i]) << 16) | (static_cast<unsigned char>(in[i + 1]) << 8) |
                       static_cast<unsigned char>(in[i + 2]);
    o += t[(v >> 18) & 63], o += t[(v >> 12) & 63], o += t[(v >> 6) & 63], o += t[v & 63];
  }
  if (i + 1 == in.size()) {
    const unsigned v = static_cast<unsigned char>(in[i]) << 16;
    o += t[(v >> 18) & 63], o += t[(v >> 12) & 63], o += "==";
  } else if (i + 2 == in.size()) {
    const unsigned v = (static_cast<unsigned char>(in[i]) << 16) | (static_cast<unsigned char>(in[i + 1]) << 8);
    o += t[(v >> 18) & 63], o += t[(v >> 12) & 63], o += t[(v >> 6) & 63], o += '=';
  }
  return o;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string cellNumber(double x) {
  if (!std::isfinite(x)) return "";
  std::ostringstream s;
  s.precision(4);
  s << x;
  return s.str();
}

const char* kScript = R"JS(
(function () {
  var table = document.getElementById('leaderboard');
  var body = table.tBodies[0];
  var heads = table.tHead.rows[0].cells;
  var state = {col: -1, dir: 1};
  function key(row, col) {
    var c = row.cells[col], v = c.getAttribute('data-v');
    if (v === null) return c.textContent;
    return v === '' ? NaN : parseFloat(v);
  }
  function sortBy(col) {
    state.dir = state.col === col ? -state.dir : 1;
    state.col = col;
    var rows = Array.prototype.slice.call(body.rows);
    rows.sort(function (a, b) {
      var x = key(a, col), y = key(b, col);
      if (typeof x === 'number' || typeof y === 'number') {
        if (isNaN(x) !== isNaN(y)) return isNaN(x) ? 1 : -1;
        if (isNaN(x)) return 0;
        return (x - y) * state.dir;
      }
      return x < y ? -state.dir : x > y ? state.dir : 0;
    });
    rows.forEach(function (r) { body.appendChild(r); });
    for (var i = 0; i < heads.length; ++i) heads[i].className = i === col ? (state.dir > 0 ? 'asc' : 'desc') : '';
  }
  for (var i = 0; i < heads.length; ++i)
    heads[i].addEventListener('click', (function (c) { return function () { sortBy(c); }; })(i));
  document.body.setAttribute('data-report-ready', String(body.rows.length));
  window.addEventListener('load', function () {
    var ok = 0, imgs = document.images;
    for (var i = 0; i < imgs.length; ++i) if (imgs[i].complete && imgs[i].naturalWidth > 0) ++ok;
    document.body.setAttribute('data-images-loaded', ok + '/' + imgs.length);
  });
})();
)JS";

}  // namespace

void writeReportHtml(const Plan& plan, const Results& res, const CompareOptions& o, const StagedOutputDir& dir) {
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>predvs compare: report</title>\n"
    << "<style>body{font-family:sans-serif;margin:1.5em;max-width:1400px}table{border-collapse:collapse;font-size:"
       "13px}th,td{border:1px solid #ccc;padding:2px 6px;text-align:right}td.t,th.t{text-align:left}th{cursor:"
       "pointer;background:#eee;position:sticky;top:0}th.asc:after{content:' \\25B2'}th.desc:after{content:' "
       "\\25BC'}img{max-width:100%;border:1px solid #ddd;margin:4px 0}pre{background:#f6f6f6;padding:6px;"
       "overflow:auto;font-size:12px}code{background:#f6f6f6}</style>\n</head>\n<body>\n"
    << "<h1>predvs compare: report</h1>\n<p>Command: <code id=\"command\">" << esc(o.command_line) << "</code></p>\n"
    << "<p>Each cell: the mean over the runs (run r uses seed S + r for every predictor); leaderboard.csv and "
       "leaderboard.json have n, std, min, max and median. Click a column header to sort by it.</p>\n";

  // Leaderboard: the union of the table columns of every variant, in order of first appearance.
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> per_variant(plan.variants.size());
  for (size_t v = 0; v < plan.variants.size(); ++v) {
    per_variant[v] = tableMetrics(res.metrics[v], *plan.variants[v].scenario);
    for (const auto& m : per_variant[v])
      if (std::find(columns.begin(), columns.end(), m) == columns.end()) columns.push_back(m);
  }
  h << "<h2>Leaderboard</h2>\n<table id=\"leaderboard\">\n<thead><tr><th class=\"t\">scenario</th><th class=\"t\">"
       "variant</th><th class=\"t\">predictor</th><th>rank</th><th>runs</th>";
  for (const auto& c : columns) h << "<th>" << esc(c) << "</th>";
  h << "</tr></thead>\n<tbody>\n";
  for (size_t v = 0; v < plan.variants.size(); ++v) {
    const Variant& var = plan.variants[v];
    const std::vector<size_t> order = ranking(plan, res, v);
    for (size_t r = 0; r < order.size(); ++r) {
      const size_t p = order[r];
      h << "<tr><td class=\"t\">" << esc(plan.scenarios[var.scenario_index].name) << "</td><td class=\"t\">"
        << esc(var.id) << "</td><td class=\"t\">" << esc(var.scenario->predictors[p].name) << "</td><td data-v=\""
        << r + 1 << "\">" << r + 1 << "</td><td data-v=\"" << plan.runs[var.scenario_index] << "\">"
        << plan.runs[var.scenario_index] << "</td>";
      for (const auto& c : columns) {
        if (std::find(per_variant[v].begin(), per_variant[v].end(), c) == per_variant[v].end()) {
          h << "<td data-v=\"\"></td>";
          continue;
        }
        const double x = res.cells[v][p].stats[metricIndex(res, v, c)].mean;
        const std::string text = cellNumber(x);
        h << "<td data-v=\"" << (std::isfinite(x) ? csvNumber(x, 17) : "") << "\">" << text << "</td>";
      }
      h << "</tr>\n";
    }
  }
  h << "</tbody>\n</table>\n";

  // Plots: every PNG written so far, heat maps first, by name.
  std::vector<std::string> heat, other;
  for (const auto& e : fs::directory_iterator(dir.staging()))
    if (e.path().extension() == ".png")
      (e.path().filename().string().rfind("heatmap_", 0) == 0 ? heat : other).push_back(e.path().filename().string());
  std::sort(heat.begin(), heat.end());
  std::sort(other.begin(), other.end());
  auto images = [&](const std::vector<std::string>& names) {
    for (const auto& n : names)
      h << "<figure><img alt=\"" << esc(n) << "\" src=\"data:image/png;base64," << base64(slurp(dir.staging() / n))
        << "\"><figcaption>" << esc(n) << "</figcaption></figure>\n";
  };
  if (!heat.empty()) {
    h << "<h2>Grids</h2>\n<p>Median convergence time per cell and predictor (grid_&lt;scenario&gt;.csv has every "
         "figure).</p>\n";
    images(heat);
  }
  if (!other.empty()) {
    h << "<h2>Plots</h2>\n";
    images(other);
  }
  if (!o.plots) h << "<p>Plots were not drawn (--no-plots).</p>\n";

  h << "<h2>Scenarios</h2>\n";
  const auto overrides = overrideTexts(o.overrides);
  for (size_t i = 0; i < plan.scenarios.size(); ++i) {
    const Scenario& sc = plan.scenarios[i];
    h << "<h3>" << esc(sc.name) << "</h3>\n<p>" << esc(sc.description) << "</p>\n<ul><li>file: <code>"
      << esc(fs::path(sc.path).filename().string()) << "</code></li><li>kind: " << esc(scenarioKindName(sc.kind))
      << "</li><li>runs: " << plan.runs[i] << ", seeds " << plan.seeds[i] << " to "
      << plan.seeds[i] + static_cast<std::uint64_t>(plan.runs[i]) - 1 << "</li><li>predictors:";
    for (const auto& p : sc.predictors) h << " " << esc(p.name);
    h << "</li>";
    for (const auto& sw : sc.sweeps) {
      h << "<li>" << (sc.sweeps.size() > 1 ? "grid axis " : "sweep ") << "<code>" << esc(sw.key) << "</code>:";
      for (const auto& v : sw.values) h << " " << esc(v);
      h << "</li>";
    }
    if (!overrides.empty()) {
      h << "<li>overrides:";
      for (const auto& t : overrides) h << " <code>" << esc(t) << "</code>";
      h << "</li>";
    }
    h << "</ul>\n<details><summary>scenario file</summary><pre>" << esc(slurp(sc.path)) << "</pre></details>\n";
  }
  h << "<script>" << kScript << "</script>\n</body>\n</html>\n";
  writeTextFile(dir, "report.html", h.str());
}

}  // namespace predvs
