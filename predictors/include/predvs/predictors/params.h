// predvs — named numeric parameters with use tracking (Eigen-free, used by every layer).
#pragma once

#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace predvs {

/// Named parameters of a predictor, trajectory, noise model, task, robot or feature source, with
/// use tracking so that a misspelt key in a scenario file is reported instead of silently ignored.
/// Values are numbers; a few keys take a word (a task's `interaction: current`), stored as text:
/// reading a text key as a number (or a number as text) throws naming the key.
class Params {
 public:
  Params() = default;
  Params(std::initializer_list<std::pair<const std::string, double>> values) : values_(values) {}

  void set(const std::string& key, double value) { values_[key] = value; }
  void setText(const std::string& key, const std::string& value) { texts_[key] = value; }
  bool has(const std::string& key) const { return values_.count(key) != 0 || texts_.count(key) != 0; }
  /// set(key, value) unless `key` is given already (a number or a word): a caller's default on top
  /// of what the user or a file gave.
  void setUnlessGiven(const std::string& key, double value) {
    if (!has(key)) set(key, value);
  }
  /// Removes `key` (number or word); nothing when absent.
  void erase(const std::string& key) {
    values_.erase(key);
    texts_.erase(key);
  }
  /// Sets every number and word of `over` (each replacing the one of its kind given here for the same
  /// key): a variant's or a file's overrides on top of these.
  void setAll(const Params& over) {
    for (const auto& kv : over.values_) values_[kv.first] = kv.second;
    for (const auto& kv : over.texts_) texts_[kv.first] = kv.second;
  }
  /// The value of `key`, or `fallback` when absent. Marks the key as known.
  double get(const std::string& key, double fallback) const;
  /// Same, and throws std::invalid_argument unless lo <= value <= hi (naming the key).
  double get(const std::string& key, double fallback, double lo, double hi) const;
  /// The word given for `key`, or `fallback` when absent. Marks the key as known; throws
  /// std::invalid_argument when the key holds a number.
  std::string text(const std::string& key, const std::string& fallback) const;
  /// Keys that were set but never read by get() or text(): unknown to whoever consumed them.
  std::vector<std::string> unusedKeys() const;
  /// Throws std::invalid_argument "unknown parameter 'KEY' for WHAT" if a key was never read.
  void requireAllUsed(const std::string& what) const;
  const std::map<std::string, double>& values() const { return values_; }
  const std::map<std::string, std::string>& texts() const { return texts_; }

 private:
  std::map<std::string, double> values_;
  std::map<std::string, std::string> texts_;
  mutable std::set<std::string> used_;
};

/// How a parameter value given as text (a command line, a scenario or parameter file) reads:
/// a Number when the whole text is a finite number (stored in *number), a Word when it starts with
/// a letter and no number can be read from its start (auto, cv, zero: a word key's value, checked
/// by whoever reads the key), Invalid otherwise (empty, "1e", "-x", "nan", "inf", ...): the caller
/// reports that with its own one-line message.
enum class ParamText { Number, Word, Invalid };
ParamText classifyParamText(const std::string& text, double* number);

/// Named values in a fixed order (metrics of a run, per-tick diagnostics of a control law).
using NamedValues = std::vector<std::pair<std::string, double>>;

}  // namespace predvs
