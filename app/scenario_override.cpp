#include "scenario_override.h"

#include "scenario_file.h"

#include <algorithm>
#include <cctype>

namespace predvs {
namespace {

[[noreturn]] void fail(const ScenarioOverride& o, const std::string& what) {
  throw OverrideError("--set " + o.text + ": " + what);
}

std::string joined(const std::vector<std::string>& parts, size_t begin, size_t end) {
  std::string s;
  for (size_t i = begin; i < end; ++i) s += (i == begin ? "" : ".") + parts[i];
  return s;
}

bool isIndex(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c) != 0; });
}

/// Name of a list element: the scalar itself or the `name:` of a mapping ("" otherwise).
std::string elementName(const YAML::Node& element) {
  if (element.IsScalar()) return element.Scalar();
  if (element.IsMap() && element["name"] && element["name"].IsScalar()) return element["name"].Scalar();
  return "";
}

YAML::Node namedMap(const std::string& name) {
  YAML::Node m(YAML::NodeType::Map);
  m["name"] = name;
  return m;
}

/// Short rendering of a scalar for an error message.
std::string shown(const YAML::Node& scalar) {
  std::string s = scalar.Scalar();
  if (s.size() > 40) s = s.substr(0, 37) + "...";
  return "'" + s + "'";
}

}  // namespace

ScenarioOverride parseScenarioOverride(const std::string& text) {
  const auto eq = text.find('=');
  const std::string usage = "--set: expected PATH=VALUE with a dotted YAML path such as task.lambda=2, got '" + text + "'";
  if (eq == std::string::npos || eq == 0) throw OverrideError(usage);
  ScenarioOverride o;
  o.text = text;
  const std::string path = text.substr(0, eq);
  size_t start = 0;
  while (true) {
    const auto dot = path.find('.', start);
    const std::string seg = path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (seg.empty() || seg.find_first_of(" \t") != std::string::npos)
      throw OverrideError(usage + " (empty or blank path segment)");
    o.path.push_back(seg);
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  const std::string value = text.substr(eq + 1);
  try {
    o.value = value.empty() ? YAML::Node(YAML::NodeType::Null) : YAML::Load(value);
  } catch (const YAML::Exception& e) {
    throw OverrideError("--set " + text + ": VALUE is not valid YAML (" + e.msg + ")");
  }
  return o;
}

void applyScenarioOverride(YAML::Node& document, const ScenarioOverride& o) {
  // yaml-cpp nodes are references: `cur.reset(n)` rebinds cur, `cur[k] = v` writes into the document.
  YAML::Node cur;
  cur.reset(document);
  std::string where;  // the path walked so far, for messages
  size_t i = 0;
  while (true) {
    if (cur.IsMap()) {
      const YAML::Node& view = cur;
      size_t take = 1;
      for (size_t n = o.path.size() - i; n > 1; --n)
        if (view[joined(o.path, i, i + n)]) {
          take = n;
          break;
        }
      const std::string key = joined(o.path, i, i + take);
      i += take;
      where += (where.empty() ? "" : ".") + key;
      if (i == o.path.size()) {
        cur[key] = YAML::Clone(o.value);
        return;
      }
      const YAML::Node existing = view[key];  // invalid (not just undefined) when absent
      if (!existing || existing.IsNull()) {
        cur[key] = YAML::Node(YAML::NodeType::Map);
      } else if (existing.IsScalar()) {
        fail(o, "'" + where + "' is a value (" + shown(existing) + "), not a mapping, so it has no key '" + o.path[i] +
                    "'");
      }
      const YAML::Node next = cur[key];
      cur.reset(next);
    } else if (cur.IsSequence()) {
      const std::string seg = o.path[i++];
      size_t index = cur.size();
      bool by_name = false;
      if (isIndex(seg)) {
        index = std::stoul(seg);
        if (index >= cur.size())
          fail(o, "'" + where + "' has " + std::to_string(cur.size()) + " element(s), index " + seg + " is out of range");
      } else {
        by_name = true;
        for (size_t k = 0; k < cur.size(); ++k)
          if (elementName(cur[k]) == seg) {
            index = k;
            break;
          }
        if (index == cur.size()) cur.push_back(namedMap(seg));
      }
      where += "." + seg;
      if (i == o.path.size()) {
        cur[index] = YAML::Clone(o.value);
        return;
      }
      const YAML::Node next = cur[index];
      if (next.IsScalar() && by_name) {
        cur[index] = namedMap(seg);
      } else if (next.IsScalar()) {
        fail(o, "'" + where + "' is a value (" + shown(next) + "), not a mapping, so it has no key '" + o.path[i] + "'");
      } else if (next.IsNull()) {
        cur[index] = YAML::Node(YAML::NodeType::Map);
      }
      const YAML::Node element = cur[index];
      cur.reset(element);
    } else if (cur.IsScalar()) {
      fail(o, "'" + where + "' is a value (" + shown(cur) + "), not a mapping, so it has no key '" + o.path[i] + "'");
    } else {
      fail(o, "'" + (where.empty() ? std::string("the document") : where) + "' is not a mapping");
    }
  }
}

std::vector<std::string> overrideTexts(const std::vector<ScenarioOverride>& overrides) {
  std::vector<std::string> out;
  for (const auto& o : overrides) out.push_back(o.text);
  return out;
}

std::string overrideErrorMessage(const ScenarioOverride& o, const std::string& file, const std::string& message) {
  std::string what = message;
  if (what.rfind(file + ":", 0) == 0) {
    what = what.substr(file.size() + 1);
    size_t digits = 0;
    while (digits < what.size() && std::isdigit(static_cast<unsigned char>(what[digits])) != 0) ++digits;
    if (digits > 0 && digits < what.size() && what[digits] == ':') what = what.substr(digits + 1);
    while (!what.empty() && what.front() == ' ') what.erase(what.begin());
  }
  return "--set " + o.text + " (scenario " + scenarioName(file) + "): " + what;
}

}  // namespace predvs
