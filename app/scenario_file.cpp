#include "scenario_file.h"

#include "app_error.h"
#include "predvs/servo/data_dir.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>


namespace predvs {
namespace fs = std::filesystem;

std::string scenariosDir() { return dataDir() + "/scenarios"; }

std::string scenarioName(const std::string& path) { return fs::path(path).stem().string(); }

std::string resolveScenario(const std::string& name_or_path) {
  std::error_code ec;
  if (name_or_path.empty()) throw std::invalid_argument("--scenario: expected a scenario name or a .yaml path");
  if (fs::is_regular_file(name_or_path, ec)) return name_or_path;
  if (fs::is_directory(name_or_path, ec))
    throw std::invalid_argument("--scenario: '" + name_or_path + "' is a directory, expected a .yaml file");
  const bool looks_like_path = name_or_path.find('/') != std::string::npos ||
                               fs::path(name_or_path).extension() == ".yaml" ||
                               fs::path(name_or_path).extension() == ".yml";
  if (!looks_like_path) {
    const std::string candidate = scenariosDir() + "/" + name_or_path + ".yaml";
    if (fs::is_regular_file(candidate, ec)) return candidate;
  }
  std::string known;
  for (const auto& s : listScenarios()) known += (known.empty() ? "" : ", ") + s.name;
  if (looks_like_path) throw std::invalid_argument("--scenario: no such file '" + name_or_path + "'");
  throw std::invalid_argument("--scenario: unknown scenario '" + name_or_path + "' (known: " + known +
                              "; or give a path to a .yaml file)");
}

std::vector<ScenarioListing> listScenarios() {
  std::vector<ScenarioListing> out;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(scenariosDir(), ec)) {
    if (entry.path().extension() != ".yaml") continue;
    ScenarioListing s{entry.path().stem().string(), ""};
    try {
      const YAML::Node root = loadYamlFile(entry.path().string());
      if (root.IsMap() && root["description"] && root["description"].IsScalar())
        s.description = root["description"].as<std::string>();
    } catch (const std::exception& e) {
      s.description = std::string("(unreadable: ") + e.what() + ")";
    }
    out.push_back(s);
  }
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  return out;
}

YAML::Node loadYamlFile(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throwAt(path, 0, "cannot open the file (expected a YAML scenario)");
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    throwAt(path, e.mark.line + 1, "YAML syntax error: " + e.msg);
  } catch (const YAML::BadFile&) {
    throwAt(path, 0, "cannot open the file (expected a YAML scenario)");
  }
}

int yamlLine(const YAML::Node& node) {
  if (!node.IsDefined()) return 0;
  const YAML::Mark m = node.Mark();
  return m.line >= 0 ? m.line + 1 : 0;
}

double yamlNumber(const YAML::Node& node, const std::string& file, const std::string& what) {
  if (!node.IsScalar()) throwAt(file, yamlLine(node), what + ": expected a number");
  const std::string s = node.Scalar();
  for (const char* special : {".inf", "+.inf", "-.inf", ".Inf", "+.Inf", "-.Inf", ".INF", "+.INF", "-.INF", ".nan",
                              ".NaN", ".NAN"})
    if (s == special) throwAt(file, yamlLine(node), what + ": expected a finite number, got '" + s + "'");
  const char* begin = s.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (s.empty() || end == begin || *end != '\0')
    throwAt(file, yamlLine(node), what + ": expected a number, got '" + s + "'");
  if (!std::isfinite(v) || errno == ERANGE)
    throwAt(file, yamlLine(node), what + ": expected a finite number, got '" + s + "'");
  return v;
}

YamlSection::YamlSection(const YAML::Node& node, std::string file, std::string section)
    : node_(node), file_(std::move(file)), section_(std::move(section)), line_(yamlLine(node)) {
  if (!node_.IsMap())
    throwAt(file_, line_, (section_.empty() ? std::string("the file") : "'" + section_ + "'") +
                              ": expected a mapping of key: value");
  refuseKeysGivenTwice(node_, file_, section_);
}

void refuseKeysGivenTwice(const YAML::Node& map, const std::string& file, const std::string& section) {
  std::set<std::string> seen;
  for (const auto& kv : map)
    if (kv.first.IsScalar() && !seen.insert(kv.first.Scalar()).second)
      throwAt(file, yamlLine(kv.first), "'" + (section.empty() ? "" : section + ".") + kv.first.Scalar() + "' given twice");
}

std::string YamlSection::qualified(const std::string& key) const {
  return section_.empty() ? key : section_ + "." + key;
}

void YamlSection::fail(const std::string& key, const std::string& what) const {
  const YAML::Node n = get(key);
  throwAt(file_, n.IsDefined() ? yamlLine(n) : line_, "'" + qualified(key) + "': " + what);
}

bool YamlSection::has(const std::string& key) const { return get(key).IsDefined() && !get(key).IsNull(); }

YAML::Node YamlSection::node(const std::string& key) {
  used_.insert(key);
  return get(key);
}

void YamlSection::allow(const std::string& key) { used_.insert(key); }

double YamlSection::number(const std::string& key, double fallback, double lo, double hi) {
  used_.insert(key);
  if (!has(key)) return fallback;
  const double v = yamlNumber(get(key), file_, "'" + qualified(key) + "'");
  if (!(v >= lo && v <= hi)) {
    std::ostringstream msg;
    msg << "expected a number in [" << lo << ", " << hi << "], got " << v;
    fail(key, msg.str());
  }
  return v;
}

double YamlSection::requiredNumber(const std::string& key, double lo, double hi) {
  if (!has(key)) throwAt(file_, line_, "missing required key '" + qualified(key) + "' (a number)");
  return number(key, 0.0, lo, hi);
}

long YamlSection::integer(const std::string& key, long fallback, long lo, long hi) {
  used_.insert(key);
  if (!has(key)) return fallback;
  const double v = yamlNumber(get(key), file_, "'" + qualified(key) + "'");
  if (v != std::floor(v) || v < static_cast<double>(lo) || v > static_cast<double>(hi)) {
    std::ostringstream msg;
    msg << "expected an integer in [" << lo << ", " << hi << "], got " << get(key).Scalar();
    fail(key, msg.str());
  }
  return static_cast<long>(v);
}

bool YamlSection::boolean(const std::string& key, bool fallback) {
  used_.insert(key);
  if (!has(key)) return fallback;
  bool v = false;
  if (!get(key).IsScalar() || !YAML::convert<bool>::decode(get(key), v))
    fail(key, "expected true or false");
  return v;
}

std::string YamlSection::string(const std::string& key, const std::string& fallback) {
  used_.insert(key);
  if (!has(key)) return fallback;
  if (!get(key).IsScalar()) fail(key, "expected a string");
  return get(key).Scalar();
}

std::string YamlSection::requiredString(const std::string& key) {
  if (!has(key)) throwAt(file_, line_, "missing required key '" + qualified(key) + "' (a string)");
  return string(key, "");
}

std::vector<double> YamlSection::numbers(const std::string& key, const std::vector<double>& fallback, size_t n) {
  used_.insert(key);
  if (!has(key)) return fallback;
  const YAML::Node list = get(key);
  if (!list.IsSequence() || (n > 0 && list.size() != n) || list.size() == 0)
    fail(key, n > 0 ? "expected a list of " + std::to_string(n) + " numbers" : "expected a list of numbers");
  std::vector<double> out;
  for (size_t i = 0; i < list.size(); ++i)
    out.push_back(yamlNumber(list[i], file_, "'" + qualified(key) + "[" + std::to_string(i) + "]'"));
  return out;
}

void YamlSection::finish() const {
  std::vector<std::string> known(used_.begin(), used_.end());
  for (const auto& kv : node_) {
    const std::string key = kv.first.Scalar();
    if (used_.count(key)) continue;
    std::string expected;
    for (const auto& k : known) expected += (expected.empty() ? "" : ", ") + k;
    throwAt(file_, yamlLine(kv.first),
            "unknown key '" + qualified(key) + "'" + (expected.empty() ? "" : " (expected one of: " + expected + ")"));
  }
}

}  // namespace predvs
