// The predictor parameter file (calibration/param_file.h): round trip and errors naming file and line.
#include "predvs/calibration/param_file.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

namespace predvs {
namespace {

std::string writeTemp(const std::string& name, const std::string& text) {
  const auto path = (std::filesystem::temp_directory_path() / ("predvs_param_file_test_" + name)).string();
  std::ofstream(path) << text;
  return path;
}

std::string errorOf(const std::string& path) {
  try {
    readParamFile(path);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ParamFile, TextReadsBackWithNumbersAndAuto) {
  // GIVEN two entries, one with a number and the word auto, one with no params
  ParamFileEntry a{"kf-cv", {}}, b{"fakf", {}};
  a.params.set("q", 123.456789012345);
  a.params.setText("r", "auto");
  // WHEN written and read back
  const std::string text = paramFileText({a, b}, {"fitted by a test"});
  EXPECT_EQ(text.rfind("# fitted by a test\npredictors:\n", 0), 0u) << text;
  const auto path = writeTemp("ok.yaml", text);
  const auto entries = readParamFile(path);
  std::remove(path.c_str());
  // THEN the same names and values (12 significant digits), auto kept as text
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[0].name, "kf-cv");
  EXPECT_NEAR(entries[0].params.values().at("q"), 123.456789012345, 1e-9);
  EXPECT_EQ(entries[0].params.texts().at("r"), "auto");
  EXPECT_EQ(entries[1].name, "fakf");
  EXPECT_TRUE(entries[1].params.values().empty());
}

TEST(ParamFile, ErrorsNameTheFileAndLine) {
  const auto missing = (std::filesystem::temp_directory_path() / "predvs_param_file_test_none.yaml").string();
  EXPECT_EQ(errorOf(missing), missing + ": cannot open the parameter file");
  const auto key = writeTemp("key.yaml", "predictors:\n  - {name: kf-ca, params: {q: 1}}\n  - {name: kf-cv, params: {qq: 2}}\n");
  EXPECT_EQ(errorOf(key), key + ":3: unknown parameter 'qq' for predictor 'kf-cv'");
  // a predictor or a parameter given twice (the reader would keep one silently)
  const auto twice = writeTemp("twice.yaml", "predictors:\n  - {name: kf-cv, params: {q: 1}}\n  - {name: kf-cv, params: {q: 2}}\n");
  EXPECT_EQ(errorOf(twice), twice + ":3: predictor 'kf-cv' listed twice");
  const auto key2 = writeTemp("key2.yaml", "predictors:\n  - {name: kf-cv, params: {q: 1, q: 2}}\n");
  EXPECT_EQ(errorOf(key2), key2 + ":2: parameter 'q' of kf-cv given twice");
  const auto word = writeTemp("word.yaml", "predictors:\n  - {name: kf-cv, params: {q: fast}}\n");
  EXPECT_EQ(errorOf(word), word + ":2: parameter 'q' expects a number or 'auto', got 'fast'");  // kf-cv's own word check
  const auto notword = writeTemp("notword.yaml", "predictors:\n  - {name: kf-cv, params: {q: 1x}}\n");
  EXPECT_EQ(errorOf(notword), notword + ":2: parameter 'q' of kf-cv: expected a number or a word");
  const auto name = writeTemp("name.yaml", "predictors:\n  - {name: kf-xx}\n");
  EXPECT_EQ(errorOf(name), name + ":2: unknown predictor 'kf-xx'");
  const auto empty = writeTemp("empty.yaml", "predictors: []\n");
  EXPECT_EQ(errorOf(empty), empty + ": the 'predictors:' list is empty");
  for (const auto& p : {key, word, name, empty}) std::remove(p.c_str());
}

}  // namespace
}  // namespace predvs
