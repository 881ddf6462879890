#pragma once
// A fresh directory under the system temp directory for one test, named after the test (and an
// optional label), removed with everything in it. The one temp-folder helper of the unit tests.
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace fovlab::testing {

class TempDir {
 public:
  explicit TempDir(const std::string& label = "") {
    static std::atomic<int> counter{0};
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = "fovlab_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
    if (!label.empty()) name += "_" + label;
    if (info != nullptr) name += std::string("_") + info->test_suite_name() + "_" + info->name();
    path_ = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::string file(const std::string& file_name) const { return (path_ / file_name).string(); }

  // Writes text (bytes as given) to a file in the directory and returns its path.
  std::string write(const std::string& file_name, const std::string& text) const {
    const std::filesystem::path file = path_ / file_name;
    std::ofstream out(file, std::ios::binary);
    out << text;
    return file.string();
  }

 private:
  std::filesystem::path path_;
};

}  // namespace fovlab::testing
