#pragma once
// The temp-folder helpers of the tests: TempDir, a fresh directory for one test, and scratch_folder,
// one for a test process. Both are per process (the pid is in the name), so tests that CTest runs
// side by side (ctest -j) never share or empty each other's folders, and both are removed with
// everything in them.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <vector>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include <gtest/gtest.h>

namespace fovlab::testing {

// temp/<name>-<pid>, emptied the first time this process asks for it and removed when the process
// exits: for folders that several tests of a process (or fixtures made once) share.
inline std::filesystem::path scratch_folder(const std::string& name) {
  struct Folders {
    std::set<std::filesystem::path> paths;
    ~Folders() {
      std::error_code ignored;
      for (const auto& path : paths) std::filesystem::remove_all(path, ignored);
    }
  };
  static Folders made;
  std::string folder_name = name;  // appended, not name + "-" + ...: GCC 12 warns falsely (-Wrestrict) on that
  folder_name.append("-").append(std::to_string(::getpid()));
  const auto path = std::filesystem::temp_directory_path() / folder_name;
  if (made.paths.insert(path).second) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  return path;
}

// The same folder, emptied on every call: for a test that must start from nothing.
inline std::filesystem::path fresh_scratch_folder(const std::string& name) {
  const std::filesystem::path path = scratch_folder(name);
  std::filesystem::remove_all(path);
  std::filesystem::create_directories(path);
  return path;
}

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

// The names in a folder, sorted.
inline std::vector<std::string> names_in(const std::filesystem::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(folder))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// A pid no process has now: a child's, after it exited and was reaped (the temporaries of a
// "killed" writer carry it).
inline pid_t pid_of_a_finished_process() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return child;
}

}  // namespace fovlab::testing
