#include "predvs/calibration/param_file.h"

#include "predvs/predictors/predictor.h"

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <set>
#include <sstream>
#include <stdexcept>

namespace predvs {

std::vector<ParamFileEntry> readParamFile(const std::string& path) {
  if (std::filesystem::is_directory(path)) throw std::invalid_argument(path + ": is a directory, expected a parameter file (YAML)");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw std::invalid_argument(path + ": cannot open the parameter file");
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument(path + ":" + std::to_string(e.mark.line + 1) + ": not valid YAML: " + e.msg);
  }
  const auto at = [&](const YAML::Node& n) { return path + ":" + std::to_string(n.Mark().line + 1) + ": "; };
  if (!root.IsMap() || !root["predictors"] || !root["predictors"].IsSequence())
    throw std::invalid_argument(path + ": expected a mapping with a 'predictors:' list");
  for (const auto& kv : root)
    if (kv.first.as<std::string>() != "predictors")
      throw std::invalid_argument(at(kv.first) + "unknown key '" + kv.first.as<std::string>() + "' (expected predictors)");
  std::vector<ParamFileEntry> entries;
  std::set<std::string> names;
  for (const auto& e : root["predictors"]) {
    if (!e.IsMap() || !e["name"] || !e["name"].IsScalar())
      throw std::invalid_argument(at(e) + "expected {name: PREDICTOR, params: {KEY: VALUE, ...}}");
    ParamFileEntry s;
    s.name = e["name"].as<std::string>();
    if (!isPredictor(s.name)) throw std::invalid_argument(at(e) + "unknown predictor '" + s.name + "'");
    if (!names.insert(s.name).second) throw std::invalid_argument(at(e) + "predictor '" + s.name + "' listed twice");
    for (const auto& kv : e) {
      const std::string key = kv.first.as<std::string>();
      if (key != "name" && key != "params")
        throw std::invalid_argument(at(kv.first) + "unknown key '" + key + "' (expected name, params)");
    }
    if (e["params"]) {
      if (!e["params"].IsMap()) throw std::invalid_argument(at(e["params"]) + "'params' must be a mapping KEY: VALUE");
      std::set<std::string> keys;
      for (const auto& kv : e["params"]) {
        const std::string key = kv.first.as<std::string>();
        if (!keys.insert(key).second)
          throw std::invalid_argument(at(kv.first) + "parameter '" + key + "' of " + s.name + " given twice");
        const std::string text = kv.second.IsScalar() ? kv.second.as<std::string>() : "";
        double v = 0.0;
        const ParamText kind = classifyParamText(text, &v);
        if (kind == ParamText::Number)
          s.params.set(key, v);
        else if (kind == ParamText::Word)
          s.params.setText(key, text);  // a word (r: auto, model: cv): the predictor checks it below
        else
          throw std::invalid_argument(at(kv.second) + "parameter '" + key + "' of " + s.name +
                                      ": expected a number or a word");
      }
    }
    try {
      makePredictor(s.name, 2, s.params);
    } catch (const std::invalid_argument& ex) {
      throw std::invalid_argument(at(e) + ex.what());
    }
    entries.push_back(s);
  }
  if (entries.empty()) throw std::invalid_argument(path + ": the 'predictors:' list is empty");
  return entries;
}

std::string paramFileText(const std::vector<ParamFileEntry>& entries, const std::vector<std::string>& comment) {
  std::ostringstream y;
  for (const auto& c : comment) y << "# " << c << "\n";
  y << "predictors:\n";
  for (const auto& s : entries) {
    y << "  - {name: " << s.name << ", params: {";
    bool first = true;
    for (const auto& kv : s.params.values()) {
      y << (first ? "" : ", ") << kv.first << ": " << std::setprecision(12) << kv.second;
      first = false;
    }
    for (const auto& kv : s.params.texts()) {
      y << (first ? "" : ", ") << kv.first << ": " << kv.second;
      first = false;
    }
    y << "}}\n";
  }
  return y.str();
}

}  // namespace predvs
