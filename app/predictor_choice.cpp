#include "predictor_choice.h"

#include "predvs/predictors/predictor.h"

#include <cctype>
#include <stdexcept>
#include <vector>

namespace predvs {

PredictorChoice parsePredictorChoice(const std::string& text, const std::string& option) {
  const std::string where = option + " '" + text + "': ";
  std::vector<std::string> parts;
  size_t start = 0;
  for (;;) {
    const size_t colon = text.find(':', start);
    parts.push_back(text.substr(start, colon == std::string::npos ? std::string::npos : colon - start));
    if (colon == std::string::npos) break;
    start = colon + 1;
  }
  PredictorChoice c;
  const std::string& head = parts.front();
  const size_t eq = head.find('=');
  if (eq == std::string::npos) {
    c.type = head;
  } else {
    c.labelled = true;
    c.label = head.substr(0, eq);
    c.type = head.substr(eq + 1);
    if (const std::string why = predictorLabelProblem(c.label, c.type); !why.empty()) throw std::invalid_argument(where + why);
  }
  if (c.type.empty())
    throw std::invalid_argument(where + "expected [LABEL=]TYPE[:KEY=VALUE...], the predictor TYPE is missing");
  c.bare = parts.size() == 1 && !c.labelled;
  if (!isPredictor(c.type) && !(c.bare && predictorLabelProblem(c.type).empty())) {  // a bare word may be a scenario's label
    std::string known;
    for (const auto& q : predictorRegistry()) known += (known.empty() ? "" : ", ") + q.name;
    throw std::invalid_argument(where + "unknown predictor '" + c.type + "' (known: " + known + ")");
  }
  if (!c.labelled) c.label = c.type;
  for (size_t i = 1; i < parts.size(); ++i) {
    const std::string& kv = parts[i];
    const size_t e = kv.find('=');
    if (e == std::string::npos || e == 0 || e + 1 == kv.size())
      throw std::invalid_argument(where + "expected KEY=VALUE after ':', got '" + kv + "'");
    const std::string key = kv.substr(0, e), value = kv.substr(e + 1);
    double x = 0.0;
    const ParamText kind = classifyParamText(value, &x);  // model=cv is a word
    if (kind == ParamText::Invalid)
      throw std::invalid_argument(where + "parameter '" + key + "': expected a number or a word, got '" + value + "'");
    if (c.params.has(key)) throw std::invalid_argument(where + "parameter '" + key + "' given twice");
    if (kind == ParamText::Word)
      c.params.setText(key, value);
    else
      c.params.set(key, x);
  }
  return c;
}

std::string predictorLabelProblem(const std::string& label, const std::string& type) {
  if (label.empty()) return "empty predictor label";
  for (char ch : label)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_')
      return "predictor label '" + label + "': expected letters, digits, '-' and '_' only";
  if (!type.empty() && label != type && isPredictor(label))
    return "predictor label '" + label + "' is the name of another predictor: choose a label of its own for " + type;
  return "";
}

}  // namespace predvs
