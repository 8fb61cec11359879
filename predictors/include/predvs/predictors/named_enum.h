// predvs — enumerations that scenario files spell as words (noise.model, timing.pipeline,
// task.interaction, servo.forecast, ...): one table of (value, name) pairs per enumeration serves
// both directions and words the error the same way everywhere. Header-only, no dependency; it
// sits in the lowest layer, beside params.h, so that every layer can use it.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

namespace predvs {

template <class E>
using EnumName = std::pair<E, const char*>;

/// The value called `name` in `names`. Otherwise throws std::invalid_argument
/// "<key> must be 'a', 'b' or 'c', got '<name>'" (key: the scenario key, e.g. "servo.forecast").
template <class E, std::size_t N>
E enumFromName(const EnumName<E> (&names)[N], const std::string& key, const std::string& name) {
  for (const auto& n : names)
    if (name == n.second) return n.first;
  std::string expected;
  for (std::size_t i = 0; i < N; ++i)
    expected += std::string(i == 0 ? "" : i + 1 == N ? " or " : ", ") + "'" + names[i].second + "'";
  throw std::invalid_argument(key + " must be " + expected + ", got '" + name + "'");
}

/// The name of `value` in `names` ("?" if the table lacks it).
template <class E, std::size_t N>
std::string enumToName(const EnumName<E> (&names)[N], E value) {
  for (const auto& n : names)
    if (n.first == value) return n.second;
  return "?";
}

}  // namespace predvs
