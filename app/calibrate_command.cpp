// `predvs calibrate camera|latency` (calibrate_command.h).
#include "calibrate_command.h"

#include "app_error.h"
#include "gnuplot.h"
#include "output_dir.h"
#include "plots.h"
#include "report.h"
#include "track_csv.h"

#include "predvs/calibration/calibrated_camera.h"
#include "predvs/calibration/camera_calibration.h"
#include "predvs/calibration/latency_estimation.h"

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <glob.h>
#include <iomanip>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace predvs {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::vector<std::string> imageFiles(const std::string& spec) {
  static const std::set<std::string> kExt = {".pgm", ".ppm", ".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff"};
  std::vector<std::string> files;
  std::error_code ec;
  if (fs::is_directory(spec, ec)) {
    for (const auto& e : fs::directory_iterator(spec, ec)) {
      std::string ext = e.path().extension().string();
      std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
      if (e.is_regular_file() && kExt.count(ext)) files.push_back(e.path().string());
    }
    if (files.empty()) throw std::invalid_argument("--images " + spec + ": no image file (.pgm .png .jpg ...) in this directory");
  } else if (spec.find_first_of("*?[") != std::string::npos) {
    glob_t g{};
    if (::glob(spec.c_str(), 0, nullptr, &g) == 0)
      for (size_t i = 0; i < g.gl_pathc; ++i) files.push_back(g.gl_pathv[i]);
    ::globfree(&g);
    if (files.empty()) throw std::invalid_argument("--images " + spec + ": no file matches this pattern");
  } else {
    if (!fs::exists(spec, ec)) throw std::invalid_argument("--images " + spec + ": no such file or directory");
    files.push_back(spec);
  }
  std::sort(files.begin(), files.end());
  return files;
}

nlohmann::json cameraJson(const CalibratedCamera& c) {
  return {{"fx_px", c.fx_px}, {"fy_px", c.fy_px}, {"cx_px", c.cx_px}, {"cy_px", c.cy_px},
          {"distortion_k1_k2_p1_p2_k3", c.distortion}, {"rms_px", c.rms_px},
          {"width_px", c.width_px}, {"height_px", c.height_px}};
}

void plotResiduals(const CameraCalibrationResult& r, const StagedOutputDir& dir) {
  // One block per image: u v du dv (px), separated by two blank lines (gnuplot `index`).
  double worst = 0.0;
  std::ostringstream dat;
  dat << "# u_px v_px du_px dv_px, one block per image\n";
  for (size_t v = 0; v < r.views.size(); ++v) {
    if (v) dat << "\n\n";
    for (size_t i = 0; i < r.views[v].residual_px.size(); ++i) {
      const auto& p = r.views[v].image_px[i];
      const auto& e = r.views[v].residual_px[i];
      worst = std::max(worst, static_cast<double>(std::hypot(e.x, e.y)));
      dat << datNumber(p.x) << " " << datNumber(p.y) << " " << datNumber(e.x) << " " << datNumber(e.y) << "\n";
    }
  }
  writeTextFile(dir, "residuals.dat", dat.str());
  // Magnify so that the largest residual is drawn 40 px long.
  const double scale = worst > 0.0 ? std::max(1.0, std::floor(40.0 / worst)) : 1.0;
  const int w = r.full.width_px, h = r.full.height_px;
  PlotFigure f;
  f.base = "residuals";
  f.title = "reprojection residuals per image (arrows x" + fixedNumber(scale, 0) + "; overall RMS " + fixedNumber(r.full.rms_px, 3) + " px)";
  for (size_t v = 0; v < r.views.size(); ++v) {
    PlotPanel p;
    p.title = r.views[v].name + ": RMS " + fixedNumber(r.views[v].rms_px, 3) + " px, max " + fixedNumber(r.views[v].max_px, 3) + " px";
    p.xlabel = "u [px]";
    p.ylabel = "v [px] (rows, downwards)";
    p.setup = "set size ratio -1\nset xrange [0:" + std::to_string(w) + "]\nset yrange [" + std::to_string(h) + ":0]\nset key off\n";
    const std::string sel = "index " + std::to_string(v);
    p.lines.push_back({"residuals.dat", "1:2", "points pt 7 ps 0.5", "gray40", "", sel});
    p.lines.push_back({"residuals.dat", "1:2:($3*" + fixedNumber(scale, 0) + "):($4*" + fixedNumber(scale, 0) + ")",
                       "vectors head size 4,20 filled lw 1.5", "#c0392b", "", sel});
    f.panels.push_back(p);
  }
  f.columns = r.views.size() == 1 ? 1 : 2;
  f.panel_width_px = 640;
  f.panel_height_px = 520;
  drawFigure(dir, f);
}

}  // namespace

void runCalibrateCamera(const CalibrateCameraOptions& o, std::ostream& out, std::ostream& err) {
  StagedOutputDir::checkReplaceable(o.out_dir, {o.images});
  PatternSpec spec;
  spec.kind = parsePatternKind(o.pattern);
  spec.rows = o.rows;
  spec.cols = o.cols;
  spec.spacing_m = o.spacing_m;
  spec.circle_diameter_m = o.diameter_m;
  spec.tag_size_m = o.tag_size_m;
  if (spec.rows < 2 || spec.cols < 2) throw std::invalid_argument("--rows/--cols: expected at least 2 each");
  if (!(spec.spacing_m > 0.0)) throw std::invalid_argument("--spacing: expected a length > 0 (m)");
  // 0 is "not given" (the defaults); a value given must be of the pattern's kind and in range
  if (o.diameter_m != 0.0 && spec.kind != PatternKind::Circles) throw std::invalid_argument("--diameter: only with --pattern circles");
  if (o.tag_size_m != 0.0 && spec.kind != PatternKind::AprilTag)
    throw std::invalid_argument("--tag-size: only with --pattern apriltag");
  if (o.diameter_m < 0.0 || o.diameter_m >= o.spacing_m) throw std::invalid_argument("--diameter: expected 0 < diameter < spacing (m)");
  if (o.tag_size_m < 0.0 || o.tag_size_m > o.spacing_m) throw std::invalid_argument("--tag-size: expected 0 < size <= spacing (m)");
  if (o.name.empty() || o.name.find_first_of("<>&\"' ") != std::string::npos)
    throw std::invalid_argument("--name: expected a camera name without spaces or XML characters");
  if (o.plots) requireGnuplot();

  const std::vector<std::string> files = imageFiles(o.images);
  std::vector<CalibrationView> views;
  std::vector<std::string> rejected;
  cv::Size size;
  for (const auto& file : files) {
    const cv::Mat g = cv::imread(file, cv::IMREAD_GRAYSCALE);
    if (g.empty()) throw std::invalid_argument(file + ": cannot read this image");
    if (size.area() == 0) size = g.size();
    if (g.size() != size)
      throw std::invalid_argument(file + ": image is " + std::to_string(g.cols) + " x " + std::to_string(g.rows) + ", the first was " +
                                  std::to_string(size.width) + " x " + std::to_string(size.height));
    const std::string name = fs::path(file).filename().string();
    PatternDetection d = detectPattern(g, spec);
    if (!d.found()) {
      rejected.push_back(name);
      continue;
    }
    views.push_back({name, std::move(d)});
  }
  std::string rejected_text;
  for (const auto& n : rejected) rejected_text += (rejected_text.empty() ? "" : ", ") + n;
  if (views.empty())
    throw std::invalid_argument("--images " + o.images + ": the " + patternKindName(spec.kind) + " pattern (" +
                                std::to_string(spec.cols) + " x " + std::to_string(spec.rows) + ") was found in none of the " +
                                std::to_string(files.size()) + " images (" + rejected_text + ")");
  CameraCalibrationResult r;
  try {
    r = calibrateFromViews(views, size, spec);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("--images " + o.images + ": " + e.what() +
                                (rejected.empty() ? std::string() : " (not found in " + rejected_text + ")"));
  }

  StagedOutputDir dir(o.out_dir);
  saveVispCameraXml(dir.file("camera.xml"), o.name, r.pinhole, r.k1_only);
  saveOpenCvYaml(dir.file("camera.yaml"), r.full);
  std::ostringstream csv;
  csv << "image,point,u_px,v_px,du_px,dv_px\n";
  for (const auto& v : r.views)
    for (size_t i = 0; i < v.residual_px.size(); ++i)
      csv << v.name << "," << i << "," << csvNumber(v.image_px[i].x, 8) << "," << csvNumber(v.image_px[i].y, 8) << ","
          << csvNumber(v.residual_px[i].x, 6) << "," << csvNumber(v.residual_px[i].y, 6) << "\n";
  writeTextFile(dir, "residuals.csv", csv.str());
  nlohmann::json j;
  j["command"] = o.command_line;
  j["pattern"] = {{"kind", patternKindName(spec.kind)}, {"rows", spec.rows}, {"cols", spec.cols}, {"spacing_m", spec.spacing_m}};
  j["images_used"] = nlohmann::json::array();
  for (const auto& v : r.views) j["images_used"].push_back({{"image", v.name}, {"rms_px", v.rms_px}, {"max_px", v.max_px}});
  j["images_rejected"] = rejected;
  j["points"] = r.points;
  j["models"] = {{"opencv_5_coefficients", cameraJson(r.full)},
                 {"visp_with_distortion", cameraJson(r.k1_only)},
                 {"visp_without_distortion", cameraJson(r.pinhole)}};
  j["models"]["visp_with_distortion"]["kud"] = r.k1_only.distortion[0];
  j["models"]["visp_with_distortion"]["kdu"] = inverseRadialTerm(r.k1_only);
  j["rms_definition"] = "sqrt(mean over points of the squared 2-D reprojection distance), px";
  writeTextFile(dir, "summary.json", j.dump(2) + "\n");
  if (o.plots) plotResiduals(r, dir);
  dir.commit();
  for (const auto& n : rejected)
    err << "predvs: " << n << ": " << patternKindName(spec.kind) << " pattern " << spec.cols << " x " << spec.rows
        << " not found, image rejected\n";

  out << "calibrate camera: " << patternKindName(spec.kind) << " " << spec.cols << " x " << spec.rows << ", spacing "
      << spec.spacing_m << " m; " << r.views.size() << " of " << files.size() << " images used";
  if (!rejected.empty()) {
    out << " (rejected:";
    for (const auto& n : rejected) out << " " << n;
    out << ")";
  }
  out << "\n";
  size_t w = 5;
  for (const auto& v : r.views) w = std::max(w, v.name.size());
  out << "  " << std::left << std::setw(static_cast<int>(w)) << "image" << std::right << "  points  rms_px  max_px\n";
  for (const auto& v : r.views)
    out << "  " << std::left << std::setw(static_cast<int>(w)) << v.name << std::right << "  " << std::setw(6)
        << v.residual_px.size() << "  " << std::setw(6) << fixedNumber(v.rms_px, 3) << "  " << std::setw(6) << fixedNumber(v.max_px, 3) << "\n";
  auto line = [&](const std::string& what, const CalibratedCamera& c, const std::string& extra) {
    out << "  " << what << ": RMS " << fixedNumber(c.rms_px, 4) << " px  fx " << fixedNumber(c.fx_px, 2) << "  fy " << fixedNumber(c.fy_px, 2)
        << "  cx " << fixedNumber(c.cx_px, 2) << "  cy " << fixedNumber(c.cy_px, 2) << extra << "\n";
  };
  std::ostringstream k;
  k << std::setprecision(4) << "  k1 " << r.full.distortion[0] << " k2 " << r.full.distortion[1] << " p1 " << r.full.distortion[2]
    << " p2 " << r.full.distortion[3] << " k3 " << r.full.distortion[4];
  line("OpenCV k1 k2 p1 p2 k3     ", r.full, k.str());
  std::ostringstream kv;
  kv << std::setprecision(4) << "  kud " << r.k1_only.distortion[0] << " kdu " << inverseRadialTerm(r.k1_only);
  line("ViSP with distortion     ", r.k1_only, kv.str());
  line("ViSP without distortion  ", r.pinhole, "");
  const std::string where = dir.target().string();
  out << "wrote " << where << "/camera.xml (camera '" << o.name << "'), camera.yaml, residuals.csv, summary.json"
      << (o.plots ? ", residuals.png" : "") << "\n";
}

// ---------------------------------------------------------------------------------------------
namespace {

struct ParsedLog {
  LatencyLog log;
  std::string predictor;
  std::vector<std::string> features, commands;
  bool has_stamps = false;
};

ParsedLog readServoLog(const CalibrateLatencyOptions& o) {
  if (fs::is_directory(o.log)) throw std::invalid_argument(o.log + ": is a directory, expected a servo log (CSV)");
  std::ifstream in(o.log);
  if (!in) throw std::invalid_argument(o.log + ": cannot open the log");
  std::string line;
  int line_no = 0;
  if (!std::getline(in, line)) throwAt(o.log, 1, "the log is empty (expected a header row t_s,...,meas_...,vx,...)");
  ++line_no;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  const std::vector<std::string> header = splitCsvLine(line);
  std::map<std::string, size_t> col;
  for (size_t i = 0; i < header.size(); ++i) {
    if (col.count(header[i])) throwAt(o.log, 1, "column '" + header[i] + "' appears twice");
    col[header[i]] = i;
  }
  if (!col.count("t_s")) throwAt(o.log, 1, "no t_s column (the control tick times, s)");
  ParsedLog p;
  p.has_stamps = col.count("t_acq_s") > 0;
  std::vector<size_t> fcols, ccols;
  for (size_t i = 0; i < header.size(); ++i)
    if (header[i].rfind("meas_", 0) == 0) fcols.push_back(i), p.features.push_back(header[i]);
  if (fcols.empty()) throwAt(o.log, 1, "no meas_<feature> column (the delivered features)");
  std::vector<std::string> wanted;
  if (!o.commands.empty()) {
    std::stringstream ss(o.commands);
    std::string c;
    while (std::getline(ss, c, ','))
      if (!c.empty()) wanted.push_back(c);
    for (const auto& c : wanted)
      if (!col.count(c)) throwAt(o.log, 1, "--commands: no column '" + c + "'");
  } else {
    for (const char* c : {"vx", "vy", "vz", "wx", "wy", "wz"})
      if (col.count(c)) wanted.push_back(c);
    if (wanted.empty()) throwAt(o.log, 1, "no camera-twist column (vx .. wz): name the command columns with --commands");
  }
  for (const auto& c : wanted) ccols.push_back(col[c]), p.commands.push_back(c);
  const bool has_pred = col.count("predictor") > 0;
  p.predictor = o.predictor;
  std::vector<double> last_meas;
  double last_acq = kNaN;
  bool any_row = false, seen_predictor = false;
  std::set<std::string> predictors;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    const std::vector<std::string> cells = splitCsvLine(line);
    if (cells.size() != header.size())
      throwAt(o.log, line_no, "expected " + std::to_string(header.size()) + " cells, got " + std::to_string(cells.size()));
    if (has_pred) {
      const std::string& name = cells[col["predictor"]];
      predictors.insert(name);
      if (p.predictor.empty()) p.predictor = name;
      if (name != p.predictor) continue;
      seen_predictor = true;
    }
    any_row = true;
    const double t = parseCell(cells[col["t_s"]], o.log, line_no, "t_s", false);
    if (!p.log.tick_t_s.empty() && !(t > p.log.tick_t_s.back())) throwAt(o.log, line_no, "t_s is not strictly increasing");
    p.log.tick_t_s.push_back(t);
    std::vector<double> u;
    for (size_t k = 0; k < ccols.size(); ++k) {
      const double v = parseCell(cells[ccols[k]], o.log, line_no, p.commands[k], true);
      u.push_back(std::isfinite(v) ? v : 0.0);  // no command (before the first image): at rest
    }
    p.log.command.push_back(u);
    std::vector<double> s;
    for (size_t k = 0; k < fcols.size(); ++k) s.push_back(parseCell(cells[fcols[k]], o.log, line_no, p.features[k], true));
    bool new_frame = false;
    double acq = kNaN;
    if (p.has_stamps) {
      acq = parseCell(cells[col["t_acq_s"]], o.log, line_no, "t_acq_s", true);
      new_frame = std::isfinite(acq) && !(acq == last_acq);
    } else {
      bool finite = false, differs = last_meas.empty();
      for (size_t k = 0; k < s.size(); ++k) {
        finite = finite || std::isfinite(s[k]);
        if (!last_meas.empty() && !(s[k] == last_meas[k]) && (std::isfinite(s[k]) || std::isfinite(last_meas[k]))) differs = true;
      }
      new_frame = finite && differs;
    }
    if (new_frame) {
      p.log.frame_delivery_s.push_back(t);
      if (p.has_stamps) p.log.frame_acquisition_s.push_back(acq);
      p.log.features.push_back(s);
      last_acq = acq;
    }
    last_meas = s;
  }
  if (has_pred && !o.predictor.empty() && !seen_predictor) {
    std::string known;
    for (const auto& n : predictors) known += (known.empty() ? "" : ", ") + n;
    throw std::invalid_argument("--predictor: no run of '" + o.predictor + "' in " + o.log + " (it has: " + known + ")");
  }
  if (!any_row) throwAt(o.log, 0, "the log has a header but no data row");
  return p;
}

/// The value of a lag in the scenario's timing model: rounded to the nearest base period (the
/// loop delivers and applies on ticks), not negative.
double onTicks(double lag_s, double base_s) { return std::max(0.0, std::round(lag_s / base_s) * base_s); }

}  // namespace

void runCalibrateLatency(const CalibrateLatencyOptions& o, std::ostream& out, std::ostream&) {
  StagedOutputDir::checkReplaceable(o.out_dir, {o.log, o.camera});
  if (!(o.max_delay_s > 0.0)) throw std::invalid_argument("--max-delay-s: expected a time > 0 (s)");
  if (!(o.window_s > 0.0)) throw std::invalid_argument("--window-s: expected a time > 0 (s)");
  if (o.plots) requireGnuplot();
  if (!o.camera.empty() && !o.intrinsics.empty()) throw std::invalid_argument("--camera / --intrinsics: give one of them");
  if (!o.camera_name.empty() && o.camera.empty()) throw std::invalid_argument("--camera-name: needs --camera FILE");
  LatencyOptions lo;
  lo.max_delay_s = o.max_delay_s;
  lo.window_s = o.window_s;
  if (!o.camera.empty()) {
    VispCameraFile f;
    try {
      f = loadVispCameraXml(o.camera, o.camera_name, vpCameraParameters::perspectiveProjWithoutDistortion);
    } catch (const std::exception& e) {
      throw std::invalid_argument("--camera " + std::string(e.what()));
    }
    lo.point_model = true;
    lo.px = f.camera.get_px(), lo.py = f.camera.get_py(), lo.u0 = f.camera.get_u0(), lo.v0 = f.camera.get_v0();
  } else if (!o.intrinsics.empty()) {
    std::vector<double> v;
    bool numbers = true;
    std::stringstream ss(o.intrinsics);
    std::string item;
    while (std::getline(ss, item, ',')) {
      char* end = nullptr;
      const double x = std::strtod(item.c_str(), &end);
      numbers = numbers && !item.empty() && *end == '\0' && std::isfinite(x);
      v.push_back(x);
    }
    if (!numbers || v.size() != 4 || !(v[0] > 0.0) || !(v[1] > 0.0))
      throw std::invalid_argument("--intrinsics: expected PX,PY,U0,V0 in pixels with PX, PY > 0, got '" + o.intrinsics + "'");
    lo.point_model = true;
    lo.px = v[0], lo.py = v[1], lo.u0 = v[2], lo.v0 = v[3];
  }
  const ParsedLog p = readServoLog(o);
  LatencyResult r;
  try {
    r = estimateLatency(p.log, lo);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(o.log + (p.predictor.empty() ? "" : " (predictor " + p.predictor + ")") + ": " + e.what());
  }
  const double base = r.base_period_s;
  const int n = std::max(1, static_cast<int>(std::lround(r.frame_period_s / base)));
  const double vision = onTicks(r.vision_delay_s, base);
  const double actuation = r.has_actuation ? onTicks(r.actuation.delay_s, base) : 0.0;

  std::ostringstream y;
  y << "# predvs calibrate latency: scenario fragment measured from " << o.log
    << (p.predictor.empty() ? "" : " (predictor " + p.predictor + ")") << "\n"
    << "# use: predvs servo --set-file timing.yaml (or compare). Estimates (s): vision delay "
    << fixedNumber(r.vision_delay_s, 4) << " +- " << fixedNumber(r.vision_sigma_s, 4);
  if (r.has_actuation) y << ", actuation lag " << fixedNumber(r.actuation.delay_s, 4) << " +- " << fixedNumber(r.actuation.sigma_s, 4);
  y << "; the lags below are rounded to the nearest base period and the vision delay split evenly\n"
    << "# between acquisition and processing (the timing model needs only their sum, and a parallel\n"
    << "# pipeline needs each at most one frame period).\n"
    << "timing:\n"
    << "  base_period_s: " << csvNumber(base, 10) << "\n"
    << "  frame_period_n: " << n << "\n"
    << "  delay_frames: ~\n"
    << "  acquisition_lag_s: " << csvNumber(0.5 * vision, 10) << "\n"
    << "  processing_lag_s: " << csvNumber(0.5 * vision, 10) << "\n";
  if (r.has_actuation) y << "  controller_lag_s: " << csvNumber(actuation, 10) << "\n";

  auto est = [](const DelayEstimate& e) {
    return nlohmann::json{{"delay_s", e.delay_s}, {"sigma_s", e.sigma_s}, {"interval_s", {e.lo_s, e.hi_s}},
                          {"frames", e.frames}, {"directions", e.directions}, {"explained_fraction", e.explained}};
  };
  nlohmann::json j;
  j["command"] = o.command_line;
  j["log"] = o.log;
  j["predictor"] = p.predictor;
  j["features"] = p.features;
  j["commands"] = p.commands;
  j["base_period_s"] = base;
  j["frame_period_s"] = r.frame_period_s;
  j["delivery_fit"] = est(r.total);
  if (r.has_actuation) {
    j["acquisition_fit"] = est(r.actuation);
    j["stamped_delay_s"] = r.stamped_delay_s;
  }
  j["vision_delay_s"] = r.vision_delay_s;
  j["vision_sigma_s"] = r.vision_sigma_s;
  j["method"] = lo.point_model ? "point model: image points of a camera driven by a camera twist, depths and target "
                                 "velocities fitted per window over the whole run, profiled over the delay "
                                 "(calibration/latency_estimation.h)"
                               : "least-squares fit of the features on the integrated command around the start of motion, "
                                 "profiled over the delay (calibration/latency_estimation.h)";
  if (lo.point_model) j["intrinsics_px"] = {lo.px, lo.py, lo.u0, lo.v0};

  StagedOutputDir dir(o.out_dir);
  writeTextFile(dir, "timing.yaml", y.str());
  writeTextFile(dir, "latency.json", j.dump(2) + "\n");
  if (o.plots) {
    std::ostringstream dat;
    dat << "# delay_ms rss_delivery" << (r.has_actuation ? " rss_acquisition" : "") << "\n";
    for (size_t g = 0; g < r.total.grid_s.size(); ++g) {
      dat << datNumber(r.total.grid_s[g] * 1000.0) << " " << datNumber(r.total.rss[g]);
      if (r.has_actuation) dat << " " << datNumber(g < r.actuation.rss.size() ? r.actuation.rss[g] : kNaN);
      dat << "\n";
    }
    writeTextFile(dir, "profile.dat", dat.str());
    PlotFigure f;
    f.base = "profile";
    f.title = "latency fit: residual sum of squares versus the delay (" + o.log + ")";
    PlotPanel panel;
    panel.xlabel = "delay candidate L [ms]";
    panel.ylabel = "RSS [px^2]";
    // The estimate, its +-1 sigma band and, with stamps, the stamped delivery - acquisition, in ms as
    // the text output gives them.
    const double d_ms = r.total.delay_s * 1000.0, s_ms = r.total.sigma_s * 1000.0;
    panel.setup = "set object rect from " + datNumber(d_ms - s_ms) + ", graph 0 to " + datNumber(d_ms + s_ms) +
                  ", graph 1 fc rgb '#dbe9f6' fs solid noborder behind\n" + "set arrow from " + datNumber(d_ms) + ", graph 0 to " +
                  datNumber(d_ms) + ", graph 1 nohead dt 2 lc rgb '#1f77b4'\n" + "set label " +
                  gnuplotQuote("estimate " + fixedNumber(d_ms, 1) + " +- " + fixedNumber(s_ms, 1) + " ms") + " at " +
                  datNumber(d_ms) + ", graph 0.06 offset 0.5,0 textcolor rgb '#1f77b4'\n";
    if (r.has_actuation && std::isfinite(r.stamped_delay_s))
      panel.setup += "set arrow from " + datNumber(r.stamped_delay_s * 1000.0) + ", graph 0 to " +
                     datNumber(r.stamped_delay_s * 1000.0) + ", graph 1 nohead dt 3 lc rgb 'black'\n" + "set label " +
                     gnuplotQuote("stamped " + fixedNumber(r.stamped_delay_s * 1000.0, 1) + " ms") + " at " +
                     datNumber(r.stamped_delay_s * 1000.0) + ", graph 0.12 offset 0.5,0\n";
    panel.lines.push_back({"profile.dat", "1:2", "lines lw 2", "#1f77b4", "delivered features (vision + actuation)", ""});
    if (r.has_actuation)
      panel.lines.push_back({"profile.dat", "1:3", "lines lw 2", "#d62728", "features at acquisition (actuation)", ""});
    f.panels.push_back(panel);
    drawFigure(dir, f);
  }
  dir.commit();

  out << "calibrate latency: " << o.log << (p.predictor.empty() ? "" : " (predictor " + p.predictor + ")") << ": "
      << p.log.tick_t_s.size() << " ticks of " << fixedNumber(base * 1000.0, 2) << " ms, " << p.log.frame_delivery_s.size()
      << " frames every " << fixedNumber(r.frame_period_s * 1000.0, 2) << " ms, " << p.features.size() << " features, commands";
  for (const auto& c : p.commands) out << " " << c;
  out << "\n  delivery fit (command as logged -> delivered features): " << fixedNumber(r.total.delay_s * 1000.0, 1) << " +- "
      << fixedNumber(r.total.sigma_s * 1000.0, 1) << " ms (" << r.total.frames
      << (lo.point_model ? " frames, point model over the whole run)\n" : " frames around the start of motion)\n");
  if (r.has_actuation)
    out << "  acquisition fit (command as logged -> features at acquisition): " << fixedNumber(r.actuation.delay_s * 1000.0, 1)
        << " +- " << fixedNumber(r.actuation.sigma_s * 1000.0, 1) << " ms; stamped delivery - acquisition: median "
        << fixedNumber(r.stamped_delay_s * 1000.0, 1) << " ms\n";
  out << "  vision delay: " << fixedNumber(r.vision_delay_s * 1000.0, 1) << " +- " << fixedNumber(r.vision_sigma_s * 1000.0, 1) << " ms ("
      << fixedNumber(r.vision_delay_s / r.frame_period_s, 2) << " frames); fragment: acquisition_lag_s = processing_lag_s = "
      << csvNumber(0.5 * vision, 6) << " s";
  if (r.has_actuation) out << ", controller_lag_s = " << csvNumber(actuation, 6) << " s";
  out << "\n";
  if (vision > 2.0 * n * base + 1e-12)
    out << "  note: a vision delay over two frame periods cannot be expressed with the parallel pipeline (each lag at "
           "most one frame period): the fragment will be rejected by a scenario\n";
  out << "wrote " << dir.target().string() << "/timing.yaml, latency.json" << (o.plots ? ", profile.png" : "") << "\n";
}

}  // namespace predvs
