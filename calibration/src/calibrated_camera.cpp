#include "predvs/calibration/calibrated_camera.h"

#include <visp3/core/vpXmlParserCamera.h>

#include <opencv2/core.hpp>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

namespace predvs {

vpCameraParameters toVispWithoutDistortion(const CalibratedCamera& c) {
  vpCameraParameters cam;
  cam.initPersProjWithoutDistortion(c.fx_px, c.fy_px, c.cx_px, c.cy_px);
  return cam;
}

double inverseRadialTerm(const CalibratedCamera& c) {
  const double kud = c.distortion[0];
  double num = 0.0, den = 0.0;
  const int n = 20;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double u = (i + 0.5) * c.width_px / n, v = (j + 0.5) * c.height_px / n;
      const double xd = (u - c.cx_px) / c.fx_px, yd = (v - c.cy_px) / c.fy_px;
      const double rd2 = xd * xd + yd * yd;
      // Undistort: xd = x (1 + kud r^2), fixed-point on the scale factor.
      double x = xd, y = yd;
      for (int it = 0; it < 50; ++it) {
        const double s = 1.0 + kud * (x * x + y * y);
        x = xd / s, y = yd / s;
      }
      // x = xd (1 + kdu rd2): residual (x - xd) - kdu xd rd2, same for y.
      num += (x - xd) * xd * rd2 + (y - yd) * yd * rd2;
      den += (xd * xd + yd * yd) * rd2 * rd2;
    }
  return den > 0.0 ? num / den : 0.0;
}

vpCameraParameters toVispWithDistortion(const CalibratedCamera& c) {
  vpCameraParameters cam;
  cam.initPersProjWithDistortion(c.fx_px, c.fy_px, c.cx_px, c.cy_px, c.distortion[0], inverseRadialTerm(c));
  return cam;
}

void saveVispCameraXml(const std::string& path, const std::string& name, const CalibratedCamera& pinhole,
                       const CalibratedCamera& k1_only) {
  // vpXmlParserCamera::save adds to an existing file; start from none.
  std::remove(path.c_str());
  vpXmlParserCamera xml;
  const unsigned w = static_cast<unsigned>(pinhole.width_px), h = static_cast<unsigned>(pinhole.height_px);
  // The parser reports on std::cout ("Found camera with name ..."): keep the command's output clean.
  std::ostringstream quiet;
  std::streambuf* const saved = std::cout.rdbuf(quiet.rdbuf());
  const bool ok = xml.save(toVispWithoutDistortion(pinhole), path, name, w, h) == vpXmlParserCamera::SEQUENCE_OK &&
                  xml.save(toVispWithDistortion(k1_only), path, name, w, h) == vpXmlParserCamera::SEQUENCE_OK;
  std::cout.rdbuf(saved);
  if (!ok) throw std::runtime_error(path + ": cannot write the ViSP camera XML");
}

VispCameraFile loadVispCameraXml(const std::string& path, const std::string& name,
                                 vpCameraParameters::vpCameraParametersProjType model) {
  std::string text;
  {
    if (std::filesystem::is_directory(path)) throw std::invalid_argument(path + ": is a directory, expected a camera file (XML)");
    std::ifstream in(path);
    if (!in) throw std::invalid_argument(path + ": cannot open the camera file");
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  // ViSP's parser needs the name: without one, take the first camera's.
  std::string wanted = name;
  if (wanted.empty()) {
    const auto cam = text.find("<camera>");
    const auto open = cam == std::string::npos ? cam : text.find("<name>", cam);
    const auto close = open == std::string::npos ? open : text.find("</name>", open);
    if (close == std::string::npos) throw std::invalid_argument(path + ": no <camera> with a <name> in this ViSP camera XML");
    wanted = text.substr(open + 6, close - open - 6);
    while (!wanted.empty() && std::isspace(static_cast<unsigned char>(wanted.back()))) wanted.pop_back();
    while (!wanted.empty() && std::isspace(static_cast<unsigned char>(wanted.front()))) wanted.erase(wanted.begin());
  }
  vpXmlParserCamera xml;
  VispCameraFile f;
  int status = vpXmlParserCamera::SEQUENCE_ERROR;
  std::ostringstream quiet;
  std::streambuf* const saved = std::cout.rdbuf(quiet.rdbuf());
  try {
    status = xml.parse(f.camera, path, wanted, model);
  } catch (const std::exception& e) {
    std::cout.rdbuf(saved);
    throw std::invalid_argument(path + ": not a ViSP camera XML (" + e.what() + ")");
  }
  std::cout.rdbuf(saved);
  const std::string what = model == vpCameraParameters::perspectiveProjWithoutDistortion
                               ? "perspectiveProjWithoutDistortion"
                               : "perspectiveProjWithDistortion";
  if (status != vpXmlParserCamera::SEQUENCE_OK)
    throw std::invalid_argument(path + ": no camera " + (name.empty() ? std::string("") : "'" + name + "' ") +
                                "with a " + what + " model in this ViSP camera XML");
  f.width_px = xml.getWidth();
  f.height_px = xml.getHeight();
  f.name = xml.getCameraName();
  return f;
}

void saveOpenCvYaml(const std::string& path, const CalibratedCamera& c) {
  cv::FileStorage fs(path, cv::FileStorage::WRITE);
  if (!fs.isOpened()) throw std::runtime_error(path + ": cannot write the OpenCV YAML");
  const cv::Mat K = (cv::Mat_<double>(3, 3) << c.fx_px, 0.0, c.cx_px, 0.0, c.fy_px, c.cy_px, 0.0, 0.0, 1.0);
  const cv::Mat D = (cv::Mat_<double>(1, 5) << c.distortion[0], c.distortion[1], c.distortion[2], c.distortion[3],
                     c.distortion[4]);
  fs << "image_width" << c.width_px << "image_height" << c.height_px;
  fs << "camera_matrix" << K << "distortion_coefficients" << D;
  fs << "distortion_model" << "opencv_k1_k2_p1_p2_k3";
  fs << "reprojection_rms_px" << c.rms_px;
  fs.release();
}

}  // namespace predvs
