// predvs app — scenario files: lookup by name, YAML loading with line numbers, strict keys.
//
// A scenario is `data/scenarios/NAME.yaml` (found by name) or any YAML file given by path.
// Every key is validated: a key nobody reads is an error "FILE:LINE: unknown key 'K' in SECTION
// (expected one of: ...)", with LINE from yaml-cpp's Mark (1-based here).
#pragma once

#include "app_error.h"

#include <yaml-cpp/yaml.h>

#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace predvs {

/// The scenarios directory, `dataDir()/scenarios` (predvs/servo/data_dir.h: $PREDVS_DATA_DIR,
/// then <exe>/../share/predvs, which in the build tree links to the source data/).
std::string scenariosDir();

/// Path of a scenario given by name (looked up in scenariosDir()) or by a path to a .yaml file.
/// Throws std::invalid_argument "--scenario: unknown scenario 'X' (known: ...)" if neither exists.
std::string resolveScenario(const std::string& name_or_path);

/// Name shown for a scenario path: the file stem.
std::string scenarioName(const std::string& path);

struct ScenarioListing {
  std::string name;
  std::string description;  ///< the `description:` line, or the parse error
};
/// Every *.yaml in scenariosDir(), sorted by name, with its one-line description.
std::vector<ScenarioListing> listScenarios();

/// Loads a YAML file; syntax errors become std::invalid_argument "FILE:LINE: ...".
YAML::Node loadYamlFile(const std::string& path);

/// 1-based line of a node (0 if unknown).
int yamlLine(const YAML::Node& node);

/// Throws "FILE:LINE: 'SECTION.KEY' given twice" ('KEY' when `section` is empty) at the second of
/// two equal scalar keys of the mapping `map`: YAML leaves a key given twice to the reader, and
/// yaml-cpp keeps both and reads the first.
void refuseKeysGivenTwice(const YAML::Node& map, const std::string& file, const std::string& section);

/// A YAML mapping read with use tracking. Each accessor marks its key as known; finish() throws
/// for the first key that was never asked for. Values are validated (type, finiteness, range)
/// and errors name FILE:LINE and SECTION.KEY.
class YamlSection {
 public:
  /// `node` must be a mapping (else an error naming `section`); `parent_line` is used when
  /// `node` itself has no mark.
  YamlSection(const YAML::Node& node, std::string file, std::string section);

  bool has(const std::string& key) const;
  /// The raw node of `key` (undefined node if absent), marked as known.
  YAML::Node node(const std::string& key);
  double number(const std::string& key, double fallback, double lo, double hi);
  double requiredNumber(const std::string& key, double lo, double hi);
  long integer(const std::string& key, long fallback, long lo, long hi);
  bool boolean(const std::string& key, bool fallback);
  std::string string(const std::string& key, const std::string& fallback);
  std::string requiredString(const std::string& key);
  /// An enum-valued string key: `parse(text)` maps the name to the value and throws
  /// std::invalid_argument for an unknown one, which is reported at the key's line.
  template <class E, class Parse>
  E enumValue(const std::string& key, E fallback, Parse&& parse) {
    if (!has(key)) {
      allow(key);
      return fallback;
    }
    const std::string text = string(key, "");
    try {
      return parse(text);
    } catch (const std::invalid_argument& e) {
      throwAt(file_, yamlLine(get(key)), e.what());
    }
  }
  /// A list of exactly `n` numbers (n = 0: any length >= 1).
  std::vector<double> numbers(const std::string& key, const std::vector<double>& fallback, size_t n);
  /// Marks `key` known without reading it.
  void allow(const std::string& key);
  /// Throws for the first key never asked for.
  void finish() const;

  const std::string& file() const { return file_; }
  const std::string& section() const { return section_; }
  int line() const { return line_; }
  /// "FILE:LINE: " prefix for errors about `key` (the key's own line when present).
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  /// Display name "section.key" (or just key at top level).
  std::string qualified(const std::string& key) const;

 private:
  YAML::Node get(const std::string& key) const {
    const YAML::Node& n = node_;
    return n[key];
  }
  YAML::Node node_;
  std::string file_;
  std::string section_;
  int line_ = 0;
  mutable std::set<std::string> used_;
};

/// Parses a YAML scalar as a finite double; errors name FILE:LINE and `what`.
double yamlNumber(const YAML::Node& node, const std::string& file, const std::string& what);

}  // namespace predvs
