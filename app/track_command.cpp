#include "track_command.h"

#include "gnuplot.h"
#include "output_dir.h"
#include "plots.h"
#include "report.h"
#include "track_csv.h"

#include "predvs/predictors/glitch_gate.h"
#include "predvs/servo/image_sequence.h"
#include "predvs/servo/image_tracker.h"

#include <visp3/core/vpFont.h>
#include <visp3/core/vpImageConvert.h>
#include <visp3/core/vpImageDraw.h>
#include <visp3/io/vpImageIo.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace predvs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

nlohmann::json statsJson(const TrackErrorStats& s) {
  return {{"rmse_px", jsonNumber(s.rmse_px)}, {"median_px", jsonNumber(s.median_px)}, {"max_px", jsonNumber(s.max_px)}, {"n", s.n}};
}

double seconds(std::chrono::steady_clock::duration d) { return std::chrono::duration<double>(d).count(); }

/// `count` rows spread evenly over `candidates` (sorted), in increasing order.
std::vector<size_t> spread(const std::vector<size_t>& candidates, int count) {
  std::vector<size_t> rows;
  if (candidates.empty() || count <= 0) return rows;
  const size_t k = std::min(candidates.size(), static_cast<size_t>(count));
  for (size_t j = 0; j < k; ++j) rows.push_back(candidates[k == 1 ? 0 : j * (candidates.size() - 1) / (k - 1)]);
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  return rows;
}

vpColor hexColor(const std::string& hex) {
  const auto byte = [&](size_t at) { return static_cast<unsigned char>(std::stoi(hex.substr(at, 2), nullptr, 16)); };
  return vpColor(byte(1), byte(3), byte(5));
}

}  // namespace

TrackErrorStats trackErrorStats(std::vector<double> e) {
  e.erase(std::remove_if(e.begin(), e.end(), [](double x) { return !std::isfinite(x); }), e.end());
  TrackErrorStats s;
  s.n = static_cast<int>(e.size());
  if (e.empty()) {
    s.rmse_px = s.median_px = s.max_px = kNaN;
    return s;
  }
  double sq = 0.0;
  for (double x : e) sq += x * x;
  s.rmse_px = std::sqrt(sq / static_cast<double>(e.size()));
  s.max_px = *std::max_element(e.begin(), e.end());
  std::sort(e.begin(), e.end());
  const size_t m = e.size() / 2;
  s.median_px = e.size() % 2 ? e[m] : 0.5 * (e[m - 1] + e[m]);
  return s;
}

/// runTracking() plus the images of the strip (kept apart: TrackResult holds numbers only).
struct StripImage {
  size_t row;
  vpImage<unsigned char> image;
};

static TrackResult trackAndKeep(const TrackOptions& o, std::ostream& log, std::vector<StripImage>* strip) {
  if (o.delay_frames < 0) throw std::invalid_argument("--delay-frames: expected an integer >= 0");
  if (!(o.fps > 0.0) || !std::isfinite(o.fps)) throw std::invalid_argument("--fps: expected a number > 0");
  if (o.predictors.empty()) throw std::invalid_argument("--predictor: expected at least one predictor");
  if (!isImageTracker(o.source)) {
    std::string known;
    for (const auto& t : imageTrackerRegistry()) known += (known.empty() ? "" : ", ") + t.name;
    throw std::invalid_argument("--source: unknown image tracker '" + o.source + "' (known: " + known + ")");
  }
  std::unique_ptr<ImageTracker> tracker;
  try {
    tracker = makeImageTracker(o.source, o.source_params, ImageTrackerContext{});
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("--set: ") + e.what());
  }
  ImageSequenceOptions so;
  so.frame_period_s = 1.0 / o.fps;
  so.max_frames = o.max_frames;
  auto seq = openImageSequence(o.images, so);

  TrackResult r;
  r.images_description = seq->describe();
  r.frame_period_s = so.frame_period_s;
  std::vector<Eigen::VectorXd> uv;  // per row; empty when not measured
  ImageFrame frame;
  std::string why;
  const long expected = seq->size();
  bool all_lost = false;
  std::vector<size_t> wanted;
  size_t stride = 1;
  if (expected > 0) {
    std::vector<size_t> all;
    for (size_t row = static_cast<size_t>(o.delay_frames); row < static_cast<size_t>(expected); ++row) all.push_back(row);
    wanted = spread(all, o.strip_frames);
  }
  using Clock = std::chrono::steady_clock;
  for (;;) {
    const auto t0 = Clock::now();
    const ImageRead status = seq->next(frame, why);
    r.read_s += seconds(Clock::now() - t0);
    if (status == ImageRead::End) break;
    r.t_s.push_back(frame.t_s);
    r.frame_index.push_back(frame.index);
    r.frame_ok.push_back(status == ImageRead::Ok);
    if (o.progress && expected > 0 && (r.rows() % 25 == 0 || static_cast<long>(r.rows()) == expected))
      log << "\rtrack: frame " << r.rows() << "/" << expected << (static_cast<long>(r.rows()) == expected ? "\n" : "")
          << std::flush;
    if (status == ImageRead::Skipped) {
      if (o.progress) log << "\n";
      log << "predvs track: skipped frame " << frame.index << " (" << frame.origin << "): " << why << "\n";
      r.skips.push_back({frame.index, frame.origin, why});
      uv.emplace_back();
      continue;
    }
    const auto t1 = Clock::now();
    const TrackedPoints tp = tracker->track(frame.image);
    r.track_s += seconds(Clock::now() - t1);
    uv.push_back(tp.points.uv_px);
    const int n = tp.points.points();
    if (n == 0) {
      ++r.frames_before_init;
      continue;
    }
    int seen = 0;
    for (bool s : tp.points.seen) seen += s ? 1 : 0;
    if (seen == 0) {
      ++r.frames_all_lost;
      if (!all_lost) {
        if (o.progress) log << "\n";
        log << "predvs track: frame " << frame.index << " (t = " << frame.t_s << " s): every point lost"
            << (tp.note.empty() ? "" : " (" + tp.note + ")") << "\n";
      }
      all_lost = true;
    } else if (all_lost) {
      if (o.progress) log << "\n";
      log << "predvs track: frame " << frame.index << " (t = " << frame.t_s << " s): " << seen << " of " << n
          << " points re-acquired\n";
      all_lost = false;
    }
    // The strip's images: with a known length the rows spread over [H, length); otherwise every
    // stride-th row, the stride doubling whenever more than 4K images are held (bounded memory).
    const size_t row = r.rows() - 1;
    if (strip != nullptr && (expected > 0 ? std::binary_search(wanted.begin(), wanted.end(), row) : row % stride == 0)) {
      strip->push_back({row, frame.image});
      if (expected <= 0 && strip->size() > 4 * static_cast<size_t>(o.strip_frames)) {
        stride *= 2;
        strip->erase(std::remove_if(strip->begin(), strip->end(), [&](const StripImage& x) { return x.row % stride != 0; }),
                     strip->end());
      }
    }
  }
  r.width = seq->width();
  r.height = seq->height();
  const int n = tracker->points();
  if (r.rows() == 0) throw std::invalid_argument("images '" + o.images + "': no frame");
  if (n == 0)
    throw std::invalid_argument("images '" + o.images + "': the '" + o.source + "' tracker found no point in any of the " +
                                std::to_string(r.rows()) + " frames");
  r.point_names = tracker->pointNames();
  r.u_px.assign(static_cast<size_t>(n), std::vector<double>(r.rows(), kNaN));
  r.v_px = r.u_px;
  for (size_t row = 0; row < r.rows(); ++row) {
    if (uv[row].size() != 2 * n) continue;
    for (int p = 0; p < n; ++p) {
      r.u_px[p][row] = uv[row](2 * p);
      r.v_px[p][row] = uv[row](2 * p + 1);
    }
  }

  // Predictions H frames ahead, scored against the measurement H rows later.
  const double horizon_s = o.delay_frames * r.frame_period_s;
  const size_t H = static_cast<size_t>(o.delay_frames);
  FeatureTrack ft;
  ft.path = o.images;
  ft.format = "wide";
  ft.point_names = r.point_names;
  ft.t_s = r.t_s;
  ft.u_px = r.u_px;
  ft.v_px = r.v_px;
  const PredictionReport rep = predictTrack(ft, o.predictors, horizon_s);
  for (const PredictionRun& run : rep.runs) {
    TrackResult::Prediction pred;
    pred.spec = run.spec;
    std::vector<double> pooled;
    for (int p = 0; p < n; ++p) {
      const PointPrediction& pp = run.points[static_cast<size_t>(p)];
      std::vector<double> e;
      for (size_t row = 0; row + H < r.rows(); ++row)
        e.push_back(std::hypot(pp.u_pred_px[row] - r.u_px[p][row + H], pp.v_pred_px[row] - r.v_px[p][row + H]));
      pooled.insert(pooled.end(), e.begin(), e.end());
      pred.per_point.push_back(trackErrorStats(e));
      pred.u_pred_px.push_back(pp.u_pred_px);
      pred.v_pred_px.push_back(pp.v_pred_px);
    }
    pred.pooled = trackErrorStats(pooled);
    pred.tallies = run.tallies;
    r.predictions.push_back(std::move(pred));
  }
  std::stable_sort(r.predictions.begin(), r.predictions.end(), [](const auto& a, const auto& b) {
    const double x = a.pooled.rmse_px, y = b.pooled.rmse_px;
    if (std::isfinite(x) != std::isfinite(y)) return std::isfinite(x);
    return std::isfinite(x) && x < y;
  });

  // Keep only the strip's images.
  if (strip != nullptr) {
    std::vector<size_t> candidates;
    for (const auto& x : *strip)
      if (x.row >= static_cast<size_t>(o.delay_frames)) candidates.push_back(x.row);
    const std::vector<size_t> rows = spread(candidates, o.strip_frames);
    std::vector<StripImage> kept;
    for (auto& s : *strip)
      if (std::find(rows.begin(), rows.end(), s.row) != rows.end()) kept.push_back(std::move(s));
    *strip = std::move(kept);
  }
  return r;
}

TrackResult runTracking(const TrackOptions& options, std::ostream& log) { return trackAndKeep(options, log, nullptr); }

namespace {

void writeCsvs(const TrackResult& r, int delay_frames, const StagedOutputDir& dir) {
  const size_t n = r.point_names.size();
  {
    std::ofstream csv(dir.file("tracks.csv"));
    csv << "t,point,u,v\n";
    for (size_t row = 0; row < r.rows(); ++row)
      for (size_t p = 0; p < n; ++p)
        csv << csvCell(r.t_s[row]) << "," << p << "," << csvCell(r.u_px[p][row]) << "," << csvCell(r.v_px[p][row]) << "\n";
    if (!csv) throw std::runtime_error(dir.file("tracks.csv") + ": write failed");
  }
  {
    std::ofstream csv(dir.file("tracks_wide.csv"));
    csv << "t";
    for (size_t p = 0; p < n; ++p) csv << ",u" << p << ",v" << p;
    csv << "\n";
    for (size_t row = 0; row < r.rows(); ++row) {
      csv << csvCell(r.t_s[row]);
      for (size_t p = 0; p < n; ++p) csv << "," << csvCell(r.u_px[p][row]) << "," << csvCell(r.v_px[p][row]);
      csv << "\n";
    }
    if (!csv) throw std::runtime_error(dir.file("tracks_wide.csv") + ": write failed");
  }
  {
    std::ofstream csv(dir.file("predictions.csv"));
    csv << "t,point,u,v,t_target";
    for (const auto& pr : r.predictions) csv << "," << pr.spec.shownName() << ".u_pred," << pr.spec.shownName() << ".v_pred";
    csv << "\n";
    const double horizon_s = delay_frames * r.frame_period_s;
    for (size_t row = 0; row < r.rows(); ++row)
      for (size_t p = 0; p < n; ++p) {
        csv << csvCell(r.t_s[row]) << "," << p << "," << csvCell(r.u_px[p][row]) << "," << csvCell(r.v_px[p][row]) << ","
            << csvCell(r.t_s[row] + horizon_s);
        for (const auto& pr : r.predictions) csv << "," << csvCell(pr.u_pred_px[p][row]) << "," << csvCell(pr.v_pred_px[p][row]);
        csv << "\n";
      }
    if (!csv) throw std::runtime_error(dir.file("predictions.csv") + ": write failed");
  }
  {
    std::ofstream csv(dir.file("leaderboard.csv"));
    csv << "predictor,point,rmse_px,median_px,max_px,n\n";
    for (const auto& pr : r.predictions) {
      csv << pr.spec.shownName() << ",all," << csvCell(pr.pooled.rmse_px) << "," << csvCell(pr.pooled.median_px) << ","
          << csvCell(pr.pooled.max_px) << "," << pr.pooled.n << "\n";
      for (size_t p = 0; p < n; ++p)
        csv << pr.spec.shownName() << "," << p << "," << csvCell(pr.per_point[p].rmse_px) << "," << csvCell(pr.per_point[p].median_px)
            << "," << csvCell(pr.per_point[p].max_px) << "," << pr.per_point[p].n << "\n";
    }
    if (!csv) throw std::runtime_error(dir.file("leaderboard.csv") + ": write failed");
  }
}

const char* kErrorDefinition =
    "the prediction made at frame r for t_r + H / fps is compared with the measurement of the same point at frame r + H "
    "(skipped frames count as frames); e = pixel distance; rmse_px = sqrt(mean e^2), median_px, max_px over the scored "
    "pairs (n); 'all' pools every point";

nlohmann::json predictorsJson(const TrackResult& r) {
  nlohmann::json arr = nlohmann::json::array();
  for (const auto& pr : r.predictions) {
    nlohmann::json j;
    j["name"] = pr.spec.shownName();
    if (!pr.spec.label.empty()) j["type"] = pr.spec.name;  // a labelled entry: its registry name
    j["params"] = paramsJson(pr.spec.params);
    j["all"] = statsJson(pr.pooled);
    if (!pr.tallies.empty()) j["tallies"] = namedValuesJson(pr.tallies);
    j["per_point"] = nlohmann::json::array();
    for (size_t p = 0; p < pr.per_point.size(); ++p) {
      nlohmann::json q = statsJson(pr.per_point[p]);
      q["point"] = p;
      q["name"] = r.point_names[p];
      j["per_point"].push_back(q);
    }
    arr.push_back(j);
  }
  return arr;
}

void writeJsons(const TrackResult& r, const TrackOptions& o, const StagedOutputDir& dir) {
  nlohmann::json lb;
  lb["delay_frames"] = o.delay_frames;
  lb["horizon_s"] = o.delay_frames * r.frame_period_s;
  lb["error_definition"] = kErrorDefinition;
  lb["predictors"] = predictorsJson(r);
  writeTextFile(dir, "leaderboard.json", lb.dump(2) + "\n");

  nlohmann::json s;
  s["command"] = o.command_line;
  s["images"] = o.images;
  s["images_description"] = r.images_description;
  s["width"] = r.width;
  s["height"] = r.height;
  s["fps"] = o.fps;
  s["frame_period_s"] = r.frame_period_s;
  s["source"] = o.source;
  s["source_params"] = paramsJson(o.source_params);
  long ok = 0;
  for (bool b : r.frame_ok) ok += b ? 1 : 0;
  s["frames"] = {{"rows", r.rows()}, {"read", ok}, {"skipped", r.skips.size()},
                 {"before_initialisation", r.frames_before_init}, {"all_points_lost", r.frames_all_lost}};
  s["skipped"] = nlohmann::json::array();
  for (const auto& k : r.skips) s["skipped"].push_back({{"index", k.index}, {"origin", k.origin}, {"reason", k.reason}});
  s["points"] = r.point_names.size();
  s["point_names"] = r.point_names;
  nlohmann::json lost = nlohmann::json::array();
  for (size_t p = 0; p < r.point_names.size(); ++p) {
    long l = 0;
    for (size_t row = 0; row < r.rows(); ++row)
      if (r.frame_ok[row] && !std::isfinite(r.u_px[p][row])) ++l;
    lost.push_back(l);
  }
  s["lost_frames_per_point"] = lost;
  s["delay_frames"] = o.delay_frames;
  s["horizon_s"] = o.delay_frames * r.frame_period_s;
  s["error_definition"] = kErrorDefinition;
  s["predictors"] = predictorsJson(r);
  const double frames = static_cast<double>(std::max<long>(ok, 1));
  s["timing"] = {{"read_ms_per_frame", 1e3 * r.read_s / static_cast<double>(std::max<size_t>(r.rows(), 1))},
                 {"track_ms_per_frame", 1e3 * r.track_s / frames},
                 {"note", "wall time of this run on this machine (not a benchmark: see docs/PERFORMANCE.md)"}};
  writeTextFile(dir, "summary.json", s.dump(2) + "\n");
}

void writeStrip(const TrackResult& r, const std::vector<StripImage>& strip, int delay_frames,
                const StagedOutputDir& dir) {
  if (strip.empty() || r.width == 0) return;
  const unsigned W = r.width, H = r.height, gap = 4;
  const unsigned line_h = 14;
  const size_t legend_rows = r.predictions.size() + 2;
  const unsigned cols_legend = std::max<unsigned>(1, static_cast<unsigned>(strip.size()));
  const unsigned legend_h = static_cast<unsigned>((legend_rows + cols_legend - 1) / cols_legend) * line_h + 22;
  const unsigned total_w = static_cast<unsigned>(strip.size()) * (W + gap) - gap;
  vpImage<vpRGBa> canvas(H + legend_h, total_w, vpRGBa(255, 255, 255));
  vpFont font(12, vpFont::GENERIC_MONOSPACE);
  const vpColor measured_color(0, 200, 0);
  for (size_t k = 0; k < strip.size(); ++k) {
    const StripImage& s = strip[k];
    vpImage<vpRGBa> rgb;
    vpImageConvert::convert(s.image, rgb);
    if (rgb.getWidth() != W || rgb.getHeight() != H) continue;
    const size_t row = s.row;
    for (size_t pi = 0; pi < r.predictions.size(); ++pi) {
      const auto& pr = r.predictions[pi];
      const vpColor c = hexColor(seriesColor(pi));
      for (size_t p = 0; p < r.point_names.size(); ++p) {
        if (row < static_cast<size_t>(delay_frames)) continue;
        const double u = pr.u_pred_px[p][row - delay_frames], v = pr.v_pred_px[p][row - delay_frames];
        if (std::isfinite(u) && std::isfinite(v)) vpImageDraw::drawCircle(rgb, vpImagePoint(v, u), 4, c, 1);
      }
    }
    for (size_t p = 0; p < r.point_names.size(); ++p) {
      const double u = r.u_px[p][row], v = r.v_px[p][row];
      if (!std::isfinite(u) || !std::isfinite(v)) continue;
      vpImageDraw::drawCross(rgb, vpImagePoint(v, u), 9, measured_color, 1);
      font.drawText(rgb, std::to_string(p), vpImagePoint(v + 5, u + 5), measured_color);
    }
    std::ostringstream title;
    title << "frame " << r.frame_index[row] << "  t=" << std::fixed << std::setprecision(3) << r.t_s[row] << " s";
    font.drawText(rgb, title.str(), vpImagePoint(3, 3), vpColor::yellow, vpColor::black);
    const unsigned x0 = static_cast<unsigned>(k) * (W + gap);
    for (unsigned i = 0; i < H; ++i)
      for (unsigned j = 0; j < W; ++j) canvas[i][x0 + j] = rgb[i][j];
  }
  // Legend below: measured, then one line per predictor in its colour.
  std::vector<std::pair<std::string, vpColor>> legend;
  legend.push_back({"+ measured (point number)", vpColor(0, 140, 0)});
  std::ostringstream what;
  what << "o predicted " << delay_frames << " frame(s) earlier:";
  legend.push_back({what.str(), vpColor::black});
  for (size_t pi = 0; pi < r.predictions.size(); ++pi)
    legend.push_back({"o " + r.predictions[pi].spec.shownName(), hexColor(seriesColor(pi))});
  const size_t per_col = (legend.size() + cols_legend - 1) / cols_legend;
  for (size_t i = 0; i < legend.size(); ++i) {
    const unsigned col = static_cast<unsigned>(i / per_col), line = static_cast<unsigned>(i % per_col);
    font.drawText(canvas, legend[i].first, vpImagePoint(H + 8 + line * line_h, 6 + col * (W + gap)), legend[i].second);
  }
  vpImageIo::write(canvas, dir.file("strip.png"));
}

/// Draws tracks.png (when there are two rows or more) and errors.png (when some prediction was
/// scored): gnuplot refuses a figure without a valid point. Returns the names drawn.
std::vector<std::string> writePlots(const TrackResult& r, int delay_frames, const StagedOutputDir& dir) {
  std::vector<std::string> drawn;
  const size_t n = r.point_names.size();
  if (r.rows() < 2) return drawn;
  {
    std::ofstream dat(dir.file("tracks_plot.dat"));
    dat << "# t_s";
    for (size_t p = 0; p < n; ++p) dat << " u" << p << "_px v" << p << "_px";
    dat << "\n" << std::setprecision(10);
    for (size_t row = 0; row < r.rows(); ++row) {
      dat << r.t_s[row];
      for (size_t p = 0; p < n; ++p)
        dat << " " << (std::isfinite(r.u_px[p][row]) ? csvCell(r.u_px[p][row]) : "NaN") << " "
            << (std::isfinite(r.v_px[p][row]) ? csvCell(r.v_px[p][row]) : "NaN");
      dat << "\n";
    }
  }
  PlotFigure tracks;
  tracks.base = "tracks";
  tracks.title = "Tracked points (" + std::to_string(n) + ")";
  for (int axis = 0; axis < 2; ++axis) {
    PlotPanel panel;
    panel.title = axis == 0 ? "u (image column)" : "v (image row)";
    panel.ylabel = axis == 0 ? "u [px]" : "v [px]";
    for (size_t p = 0; p < n; ++p)
      panel.lines.push_back({"tracks_plot.dat", "1:" + std::to_string(2 + 2 * p + axis), "lines lw 1.2", seriesColor(p),
                             r.point_names[p], ""});
    tracks.panels.push_back(panel);
  }
  drawFigure(dir, tracks);
  drawn.push_back("tracks.png");
  bool scored = false;
  for (const auto& pr : r.predictions) scored = scored || pr.pooled.n > 0;
  if (!scored) return drawn;

  // Error per predictor and frame: the mean over the points scored at that frame (target time);
  // then, per predictor, its RMS over the frames of the last kWindowS seconds.
  constexpr double kWindowS = 1.0;
  const size_t k_count = r.predictions.size();
  {
    std::ofstream dat(dir.file("errors_plot.dat"));
    dat << "# t_target_s";
    for (const auto& pr : r.predictions) dat << " " << pr.spec.shownName();
    for (const auto& pr : r.predictions) dat << " rms_" << pr.spec.shownName();
    dat << "\n" << std::setprecision(8);
    const size_t H = static_cast<size_t>(delay_frames);
    std::vector<double> sum_sq(k_count, 0.0);
    std::vector<int> in_window(k_count, 0);
    std::vector<std::vector<double>> frame_error(k_count, std::vector<double>(r.rows(), std::nan("")));
    size_t oldest = H;  // first row inside the window
    for (size_t row = H; row < r.rows(); ++row) {
      for (size_t k = 0; k < k_count; ++k) {
        const auto& pr = r.predictions[k];
        double sum = 0.0;
        int count = 0;
        for (size_t p = 0; p < n; ++p) {
          const double e = std::hypot(pr.u_pred_px[p][row - H] - r.u_px[p][row], pr.v_pred_px[p][row - H] - r.v_px[p][row]);
          if (std::isfinite(e)) {
            sum += e;
            ++count;
          }
        }
        if (count) {
          frame_error[k][row] = sum / count;
          sum_sq[k] += frame_error[k][row] * frame_error[k][row];
          ++in_window[k];
        }
      }
      for (; r.t_s[oldest] <= r.t_s[row] - kWindowS; ++oldest)
        for (size_t k = 0; k < k_count; ++k)
          if (std::isfinite(frame_error[k][oldest])) {
            sum_sq[k] -= frame_error[k][oldest] * frame_error[k][oldest];
            --in_window[k];
          }
      dat << r.t_s[row];
      for (size_t k = 0; k < k_count; ++k) dat << " " << (std::isfinite(frame_error[k][row]) ? csvCell(frame_error[k][row]) : "NaN");
      for (size_t k = 0; k < k_count; ++k)
        dat << " " << (in_window[k] > 0 ? csvCell(std::sqrt(std::max(0.0, sum_sq[k]) / in_window[k])) : "NaN");
      dat << "\n";
    }
  }
  PlotFigure errors;
  errors.base = "errors";
  errors.title = "Prediction error " + std::to_string(delay_frames) + " frame(s) ahead (mean over points, vs measurement)";
  PlotPanel panel;
  panel.ylabel = "error [px] (log scale)";
  panel.xlabel = "time of the predicted frame t [s]";
  // Log y: a hand-held sequence's few jumps (and the start-up) are ten times its steady error, which
  // a linear axis squeezes into the bottom tenth. Past six predictors, dashes tell the colours apart.
  panel.log_y = true;
  panel.title = "per frame";
  PlotPanel rms;
  rms.title = "RMS over the last " + csvNumber(kWindowS) + " s";
  rms.ylabel = "RMS of the error [px] (log scale)";
  rms.log_y = true;  // the start-up's 10-20 px beside a steady 1 px
  rms.xlabel = panel.xlabel;
  for (size_t k = 0; k < k_count; ++k) {
    const std::string style = " dt " + std::to_string(dashType(k / 6));
    panel.lines.push_back({"errors_plot.dat", "1:" + std::to_string(2 + k), "lines lw 1" + style, seriesColor(k),
                           r.predictions[k].spec.shownName(), ""});
    rms.lines.push_back({"errors_plot.dat", "1:" + std::to_string(2 + k_count + k), "lines lw 2" + style, seriesColor(k),
                         r.predictions[k].spec.shownName(), ""});
  }
  errors.panels.push_back(panel);
  errors.panels.push_back(rms);
  errors.panel_height_px = 430;
  drawFigure(dir, errors);
  drawn.push_back("errors.png");
  return drawn;
}

/// The printed table shows the per-point RMSE of at most this many points (a tag board has dozens).
constexpr size_t kPrintedPoints = 10;

void printLeaderboard(const TrackResult& r, int delay_frames, std::ostream& out) {
  size_t w = 9;
  for (const auto& pr : r.predictions) w = std::max(w, pr.spec.shownName().size());
  out << "Prediction " << delay_frames << " frame(s) ahead vs the measurement " << delay_frames
      << " frame(s) later, px (all points pooled; per-point RMSE"
      << (r.point_names.size() > kPrintedPoints ? " of the first " + std::to_string(kPrintedPoints) + ", every point in leaderboard.csv" : "")
      << "):\n";
  out << std::left << std::setw(4) << "#" << std::setw(static_cast<int>(w)) << "predictor" << std::right
      << std::setw(9) << "rmse" << std::setw(9) << "median" << std::setw(9) << "max" << std::setw(9) << "n";
  const size_t shown = std::min(r.point_names.size(), kPrintedPoints);
  for (size_t p = 0; p < shown; ++p) out << std::setw(8) << r.point_names[p];
  out << "\n";
  for (size_t k = 0; k < r.predictions.size(); ++k) {
    const auto& pr = r.predictions[k];
    out << std::left << std::setw(4) << (k + 1) << std::setw(static_cast<int>(w)) << pr.spec.shownName() << std::right
        << std::setw(9) << fixedNumber(pr.pooled.rmse_px, 3) << std::setw(9) << fixedNumber(pr.pooled.median_px, 3) << std::setw(9)
        << fixedNumber(pr.pooled.max_px, 2) << std::setw(9) << pr.pooled.n;
    for (size_t p = 0; p < shown && p < pr.per_point.size(); ++p) out << std::setw(8) << fixedNumber(pr.per_point[p].rmse_px, 3);
    out << "\n";
  }
}

}  // namespace

void runTrackCommand(const TrackOptions& o, std::ostream& out, std::ostream& err) {
  if (o.plots) requireGnuplot();
  std::vector<StripImage> strip;
  const TrackResult r = trackAndKeep(o, err, o.strip_frames > 0 ? &strip : nullptr);

  StagedOutputDir dir(o.out_dir);
  writeCsvs(r, o.delay_frames, dir);
  writeJsons(r, o, dir);
  writeStrip(r, strip, o.delay_frames, dir);
  const std::vector<std::string> plots = o.plots ? writePlots(r, o.delay_frames, dir) : std::vector<std::string>{};
  dir.commit();

  long ok = 0;
  for (bool b : r.frame_ok) ok += b ? 1 : 0;
  printLeaderboard(r, o.delay_frames, out);
  out << r.images_description << ": " << ok << " frames tracked, " << r.skips.size() << " skipped; "
      << r.point_names.size() << " points (" << o.source << ")";
  if (r.frames_all_lost > 0) out << ", every point lost in " << r.frames_all_lost << " frames";
  long lost = 0;
  for (size_t p = 0; p < r.point_names.size(); ++p)
    for (size_t row = 0; row < r.rows(); ++row)
      if (r.frame_ok[row] && !std::isfinite(r.u_px[p][row])) ++lost;
  out << ", " << lost << " point-frames lost\n";
  double gate = 0.0;  // the glitch gate of the specs (--glitch-sigmas), when one has it on
  for (const auto& spec : o.predictors) gate = std::max(gate, glitchSigmasParam(spec.params));
  if (gate > 0.0) {  // with the doubts each predictor settled as glitches / steps (its tallies)
    out << "glitch gate at " << gate << " sigmas (docs/MODELS.md §16; --glitch-sigmas 0: off), doubts settled as glitches/steps:";
    for (const auto& pr : r.predictions) {
      double glitches = -1.0, steps = -1.0;
      for (const auto& kv : pr.tallies) {
        if (kv.first == "glitches") glitches = kv.second;
        if (kv.first == "steps") steps = kv.second;
      }
      if (glitches >= 0.0 && steps >= 0.0) out << " " << pr.spec.shownName() << " " << glitches << "/" << steps;
    }
    out << "\n";
  }
  out << "wrote " << dir.target().string() << "/: tracks.csv, tracks_wide.csv, predictions.csv, leaderboard.csv/.json, "
      << (strip.empty() ? "" : "strip.png, ");
  for (const auto& p : plots) out << p << ", ";
  out << "summary.json\n";
}

}  // namespace predvs
