#include "predvs/predictors/predictor.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace predvs {

double Params::get(const std::string& key, double fallback) const {
  used_.insert(key);
  const auto t = texts_.find(key);
  if (t != texts_.end())
    throw std::invalid_argument("parameter '" + key + "' expects a number, got '" + t->second + "'");
  const auto it = values_.find(key);
  return it == values_.end() ? fallback : it->second;
}

double Params::get(const std::string& key, double fallback, double lo, double hi) const {
  const double v = get(key, fallback);
  if (!(v >= lo && v <= hi)) {
    std::ostringstream msg;
    msg << "parameter '" << key << "' = " << v << " is out of range [" << lo << ", " << hi << "]";
    throw std::invalid_argument(msg.str());
  }
  return v;
}

ParamText classifyParamText(const std::string& text, double* number) {
  if (text.empty()) return ParamText::Invalid;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (*end == '\0' && std::isfinite(v)) {
    *number = v;
    return ParamText::Number;
  }
  // A word: no number prefix at all (so "nan", "inf" and "infx" are not words) and a letter first.
  return end == text.c_str() && std::isalpha(static_cast<unsigned char>(text[0])) ? ParamText::Word
                                                                                  : ParamText::Invalid;
}

std::string Params::text(const std::string& key, const std::string& fallback) const {
  used_.insert(key);
  if (values_.count(key)) {
    std::ostringstream msg;
    msg << "parameter '" << key << "' expects a word, got the number " << values_.at(key);
    throw std::invalid_argument(msg.str());
  }
  const auto it = texts_.find(key);
  return it == texts_.end() ? fallback : it->second;
}

void Params::requireAllUsed(const std::string& what) const {
  const auto unknown = unusedKeys();
  if (!unknown.empty()) throw std::invalid_argument("unknown parameter '" + unknown.front() + "' for " + what);
}

std::vector<std::string> Params::unusedKeys() const {
  std::vector<std::string> out;
  for (const auto& kv : values_)
    if (!used_.count(kv.first)) out.push_back(kv.first);
  for (const auto& kv : texts_)
    if (!used_.count(kv.first)) out.push_back(kv.first);
  return out;
}

Predictor::Predictor(int channels) : channels_(channels), t_last_(std::numeric_limits<double>::quiet_NaN()) {
  if (channels <= 0) throw std::invalid_argument("a predictor needs at least one channel");
}

void Predictor::update(double t_s) {
  update(t_s, Eigen::VectorXd::Constant(channels_, std::numeric_limits<double>::quiet_NaN()));
}

double Predictor::advanceClock(double t_s, const Eigen::Ref<const Eigen::VectorXd>& z) {
  if (z.size() != channels())
    throw std::invalid_argument(name() + ": measurement has " + std::to_string(z.size()) + " entries, expected " +
                                std::to_string(channels()));
  return advanceClock(t_s);
}

double Predictor::advanceClock(double t_s) {
  if (!std::isfinite(t_s)) throw std::invalid_argument(name() + ": update time is not finite");
  if (std::isnan(t_last_)) {
    t_last_ = t_s;
    return 0.0;
  }
  if (!(t_s > t_last_)) {
    std::ostringstream msg;
    msg << name() << ": update time " << t_s << " s is not after the previous one (" << t_last_ << " s)";
    throw std::invalid_argument(msg.str());
  }
  const double dt = t_s - t_last_;
  t_last_ = t_s;
  return dt;
}

void Predictor::resetClock() { t_last_ = std::numeric_limits<double>::quiet_NaN(); }

Eigen::VectorXd Predictor::predictPositions(double t_s) const {
  Eigen::VectorXd out(channels_);
  predictPositions(t_s, out);
  return out;
}

void Predictor::predictPositions(double t_s, Eigen::Ref<Eigen::VectorXd> out) const {
  if (out.size() != channels_)
    throw std::invalid_argument(name() + ": predictPositions into " + std::to_string(out.size()) +
                                " entries, expected " + std::to_string(channels_));
  for (int c = 0; c < channels_; ++c) out(c) = predictPosition(c, t_s);
}

Eigen::VectorXd Predictor::predictVelocities(double t_s) const {
  Eigen::VectorXd out(channels_);
  for (int c = 0; c < channels_; ++c) out(c) = predictVelocity(c, t_s);
  return out;
}

Eigen::VectorXd Predictor::feedforwardVelocities(double t_s) const {
  Eigen::VectorXd out(channels_);
  for (int c = 0; c < channels_; ++c) out(c) = feedforwardVelocity(c, t_s);
  return out;
}

}  // namespace predvs
