#include "scenario_inputs.h"

#include "predvs/calibration/calibrated_camera.h"

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace predvs {
namespace {

/// PATH=VALUE, its text naming where it came from (errors and summary.json show it).
ScenarioOverride makeOverride(const std::string& path, const std::string& value, const std::string& origin) {
  ScenarioOverride o = parseScenarioOverride(path + "=" + value);
  o.text += " (" + origin + ")";
  return o;
}

std::string number(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

void flatten(const YAML::Node& node, const std::string& prefix, const std::string& origin, std::vector<ScenarioOverride>& out) {
  if (node.IsMap() && !prefix.empty() && node.size() == 0) return;
  if (node.IsMap()) {
    for (const auto& kv : node) {
      const std::string key = kv.first.as<std::string>();
      flatten(kv.second, prefix.empty() ? key : prefix + "." + key, origin, out);
    }
    return;
  }
  YAML::Emitter e;
  e << YAML::Flow << node;
  out.push_back(makeOverride(prefix, node.IsNull() ? std::string() : std::string(e.c_str()), origin));
}

}  // namespace

std::vector<ScenarioOverride> cameraOverrides(const std::string& file, const std::string& camera_name) {
  VispCameraFile f;
  try {
    f = loadVispCameraXml(file, camera_name, vpCameraParameters::perspectiveProjWithoutDistortion);
  } catch (const std::exception& e) {
    throw std::invalid_argument("--camera " + std::string(e.what()));
  }
  const std::string origin = "--camera " + file;
  std::vector<ScenarioOverride> o = {makeOverride("camera.px", number(f.camera.get_px()), origin),
                                     makeOverride("camera.py", number(f.camera.get_py()), origin),
                                     makeOverride("camera.u0", number(f.camera.get_u0()), origin),
                                     makeOverride("camera.v0", number(f.camera.get_v0()), origin)};
  if (f.width_px > 0 && f.height_px > 0) {
    o.push_back(makeOverride("camera.width", std::to_string(f.width_px), origin));
    o.push_back(makeOverride("camera.height", std::to_string(f.height_px), origin));
  }
  return o;
}

std::vector<ScenarioOverride> setFileOverrides(const std::string& file) {
  if (std::filesystem::is_directory(file))
    throw std::invalid_argument("--set-file " + file + ": is a directory, expected a YAML file");
  std::ifstream in(file);
  if (!in) throw std::invalid_argument("--set-file " + file + ": cannot open the file");
  YAML::Node doc;
  try {
    doc = YAML::Load(in);
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument("--set-file " + file + ":" + std::to_string(e.mark.line + 1) + ": not valid YAML (" + e.msg + ")");
  }
  if (!doc.IsMap() || doc.size() == 0)
    throw std::invalid_argument("--set-file " + file + ": expected a YAML mapping of scenario keys, such as timing: {...}");
  std::vector<ScenarioOverride> out;
  flatten(doc, "", "--set-file " + file, out);
  return out;
}

}  // namespace predvs
