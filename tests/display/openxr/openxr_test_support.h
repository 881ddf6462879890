#pragma once
// The OpenXR tests' environment: the test runtime (tests/xr_runtime) named by XR_RUNTIME_JSON and
// the OpenXR core validation layer writing to a file of the test's own, which must stay empty
// (openxr_runtime_test.cpp says why a file).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>

#include "tests/app/cli_test_support.h"
#include "tests/support/temp_dir.h"

namespace fovlab::test {

// Sets an environment variable for the life of the object, then puts back what was there.
class ScopedEnvironment {
 public:
  ScopedEnvironment(std::string name, const std::string& value) : name_(std::move(name)) {
    if (const char* old = std::getenv(name_.c_str())) old_ = old;
    setenv(name_.c_str(), value.c_str(), 1);
  }
  ~ScopedEnvironment() {
    if (old_) {
      setenv(name_.c_str(), old_->c_str(), 1);
    } else {
      unsetenv(name_.c_str());
    }
  }
  ScopedEnvironment(const ScopedEnvironment&) = delete;
  ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

 private:
  std::string name_;
  std::optional<std::string> old_;
};

inline constexpr char kValidationLayer[] = "XR_APILAYER_LUNARG_core_validation";

// The test runtime and the validation layer, for one test; what the layer wrote is checked at the end.
class OpenXrTest : public ::testing::Test {
 protected:
  void TearDown() override {
    const std::string report = cli_test::read_all(validation_file_);
    if (expect_no_validation_messages_) {
      EXPECT_EQ(report, "") << "the OpenXR core validation layer reported";
    }
  }

  std::string validation_report() const { return cli_test::read_all(validation_file_); }

  // For `fovlab devices` in a child process: the same environment as a command prefix.
  std::string child_environment(const std::string& runtime_json) const {
    return "env XR_RUNTIME_JSON=" + runtime_json + " XR_ENABLE_API_LAYERS=" + kValidationLayer +
           " XR_CORE_VALIDATION_EXPORT_TYPE=text XR_CORE_VALIDATION_FILE_NAME=" + validation_file_.string();
  }

  testing::TempDir scratch_{"openxr"};
  std::filesystem::path validation_file_ = scratch_.path() / "core_validation.txt";
  bool expect_no_validation_messages_ = true;
  ScopedEnvironment runtime_{"XR_RUNTIME_JSON", FOVLAB_TEST_XR_RUNTIME_JSON};
  ScopedEnvironment layers_{"XR_ENABLE_API_LAYERS", kValidationLayer};
  ScopedEnvironment export_type_{"XR_CORE_VALIDATION_EXPORT_TYPE", "text"};
  ScopedEnvironment export_file_{"XR_CORE_VALIDATION_FILE_NAME", validation_file_.string()};
};

}  // namespace fovlab::test
