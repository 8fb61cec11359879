// dataDir(): PREDVS_DATA_DIR overrides; a PREDVS_DATA_DIR that is not a folder is an error naming
// it; unset, the test binary (build/tests/) finds build/share/predvs, the link to the source data/.
#include "predvs/servo/data_dir.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>

namespace {
namespace fs = std::filesystem;

class ScopedEnv {
 public:
  explicit ScopedEnv(const char* value) {
    if (const char* old = std::getenv("PREDVS_DATA_DIR")) old_ = old;
    if (value) setenv("PREDVS_DATA_DIR", value, 1); else unsetenv("PREDVS_DATA_DIR");
  }
  ~ScopedEnv() {
    if (old_) setenv("PREDVS_DATA_DIR", old_->c_str(), 1); else unsetenv("PREDVS_DATA_DIR");
  }

 private:
  std::optional<std::string> old_;
};

TEST(DataDir, EnvironmentVariableOverrides) {
  const fs::path dir = fs::temp_directory_path();
  ScopedEnv env(dir.c_str());
  EXPECT_EQ(fs::path(predvs::dataDir()), dir.lexically_normal());
}

TEST(DataDir, EnvironmentVariableNotAFolderIsAnErrorNamingIt) {
  ScopedEnv env("/nonexistent/predvs-data");
  try {
    predvs::dataDir();
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("PREDVS_DATA_DIR=/nonexistent/predvs-data"), std::string::npos) << e.what();
  }
}

TEST(DataDir, UnsetFindsTheBuildTreeLinkToTheSourceData) {
  ScopedEnv env(nullptr);
  const fs::path found = predvs::dataDir();
  EXPECT_EQ(found, fs::path(PREDVS_BINARY_DIR "/share/predvs").lexically_normal());
  EXPECT_TRUE(fs::equivalent(found, fs::path(PREDVS_SOURCE_DIR "/data")));
  EXPECT_TRUE(fs::is_regular_file(found / "scenarios" / "ibvs-moving-target.yaml"));
}

}  // namespace
