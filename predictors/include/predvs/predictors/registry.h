// predvs — a registry by name: the one shape of every extension point (predictors, tasks, robots,
// feature sources). Each kind keeps one table of {name, summary, factory} in its registry file;
// adding an implementation is one line there. Header-only, no dependency.
#pragma once

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace predvs {

/// One entry as `predvs list` shows it.
struct RegistryInfo {
  std::string name;
  std::string summary;  ///< one line
};

template <class Product, class... Args>
class Registry {
 public:
  using Factory = std::function<std::unique_ptr<Product>(Args...)>;
  struct Entry {
    RegistryInfo info;
    Factory make;
  };

  /// `what` names the kind in errors ("robot", "task", "feature source").
  Registry(std::string what, std::vector<Entry> entries) : what_(std::move(what)), entries_(std::move(entries)) {
    for (const auto& e : entries_) infos_.push_back(e.info);
  }

  /// A factory that constructs T from the arguments.
  template <class T>
  static Factory factory() {
    return [](Args... args) { return std::make_unique<T>(args...); };
  }

  const std::vector<RegistryInfo>& infos() const { return infos_; }
  bool has(const std::string& name) const {
    for (const auto& e : entries_)
      if (e.info.name == name) return true;
    return false;
  }
  /// Builds `name`; throws std::invalid_argument "unknown WHAT 'x' (known: a, b)".
  std::unique_ptr<Product> make(const std::string& name, Args... args) const {
    for (const auto& e : entries_)
      if (e.info.name == name) return e.make(args...);
    std::string known;
    for (const auto& e : entries_) known += (known.empty() ? "" : ", ") + e.info.name;
    throw std::invalid_argument("unknown " + what_ + " '" + name + "' (known: " + known + ")");
  }

 private:
  std::string what_;
  std::vector<Entry> entries_;
  std::vector<RegistryInfo> infos_;
};

}  // namespace predvs
