#include "number_text.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace predvs {

Stats stats(const std::vector<double>& xs) {
  Stats s;
  double sum = 0.0;
  for (double x : xs)
    if (std::isfinite(x)) {
      ++s.n;
      sum += x;
      s.min = s.n == 1 ? x : std::min(s.min, x);
      s.max = s.n == 1 ? x : std::max(s.max, x);
    }
  if (s.n == 0) return s;
  s.mean = sum / s.n;
  double ss = 0.0;
  for (double x : xs)
    if (std::isfinite(x)) ss += (x - s.mean) * (x - s.mean);
  s.std = s.n > 1 ? std::sqrt(ss / (s.n - 1)) : 0.0;
  std::vector<double> finite;
  finite.reserve(static_cast<size_t>(s.n));
  for (double x : xs)
    if (std::isfinite(x)) finite.push_back(x);
  std::sort(finite.begin(), finite.end());
  const size_t h = finite.size() / 2;
  s.median = finite.size() % 2 ? finite[h] : 0.5 * (finite[h - 1] + finite[h]);
  // Identical runs (no noise) differ only by the round-off of the sum: report a spread of 0.
  constexpr double kRoundOffSpread = 1e-9;
  if (s.std <= kRoundOffSpread * std::fabs(s.mean)) s.std = 0.0;
  return s;
}

std::string csvNumber(double x, int precision) {
  if (!std::isfinite(x)) return "";
  std::ostringstream s;
  s << std::setprecision(precision) << x;
  return s.str();
}

std::string csvCell(double x) { return csvNumber(x, 10); }

std::string fixedNumber(double x, int decimals) {
  if (!std::isfinite(x)) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(decimals) << x;
  return s.str();
}

std::string datNumber(double x) { return std::isfinite(x) ? csvNumber(x, 8) : "NaN"; }

std::string tableNumber(double x) {
  if (!std::isfinite(x)) return "-";
  std::ostringstream s;
  const double a = std::fabs(x);
  if (a != 0.0 && (a >= 1e5 || a < 1e-3))
    s << std::setprecision(3) << std::scientific << x;
  else
    s << std::fixed << std::setprecision(a >= 100 ? 1 : 3) << x;
  return s.str();
}

nlohmann::json jsonNumber(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

std::string fileSafe(const std::string& s) {
  std::string out;
  for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
  return out;
}

nlohmann::json paramsJson(const Params& params) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& kv : params.values()) j[kv.first] = kv.second;
  for (const auto& kv : params.texts()) j[kv.first] = kv.second;  // words: model: ca, r: auto
  return j;
}

nlohmann::json namedValuesJson(const NamedValues& values) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& kv : values) j[kv.first] = kv.second;
  return j;
}

void writeTextFile(const StagedOutputDir& dir, const std::string& name, const std::string& text) {
  std::ofstream f(dir.file(name));
  f << text;
  if (!f) throw std::runtime_error(dir.file(name) + ": write failed");
}

}  // namespace predvs
