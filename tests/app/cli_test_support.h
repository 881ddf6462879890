#pragma once
// Running the fovlab command from a test: its exit code, stdout and stderr, and scratch folders.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/support/temp_dir.h"

namespace fovlab::cli_test {

struct CommandResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// A scratch folder of this test process (tests/support/temp_dir.h).
inline std::filesystem::path scratch(const std::string& name) { return testing::scratch_folder(name); }

inline std::string read_all(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Runs `<environment> fovlab <arguments>` through the shell; environment is a command prefix such
// as "env -u DISPLAY" or "FOVLAB_VALIDATION=0", empty for none.
inline CommandResult run(const std::string& arguments, const std::string& environment = "") {
  // Per process, so test processes running side by side do not share them.
  const auto capture = std::filesystem::temp_directory_path() / ("fovlab-cli-" + std::to_string(getpid()));
  const auto out = capture.string() + ".stdout.txt";
  const auto err = capture.string() + ".stderr.txt";
  const std::string command = environment + " " + FOVLAB_BINARY + " " + arguments + " >" + out + " 2>" + err;
  const int status = std::system(command.c_str());
  CommandResult result{WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_all(out), read_all(err)};
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return result;
}

// Bad input: exit code 2 and one line on stderr containing `must_contain`. Progress lines ("preparing
// stimuli: 16 %, ETA 7s", printed when preparing takes a while, as on a loaded machine) are no error.
inline void expect_one_line_error(const CommandResult& result, const std::string& must_contain) {
  EXPECT_EQ(result.exit_code, 2) << result.err;
  EXPECT_NE(result.err.find(must_contain), std::string::npos) << result.err;
  int lines = 0;
  for (size_t start = 0, end; (end = result.err.find('\n', start)) != std::string::npos; start = end + 1)
    lines += result.err.substr(start, end - start).find(" %, ETA ") == std::string::npos ? 1 : 0;
  EXPECT_EQ(lines, 1) << result.err;
}

// An empty folder `name` under `parent`, for a command that works in its working directory.
inline std::filesystem::path fresh_folder(const std::filesystem::path& parent, const std::string& name) {
  const std::filesystem::path dir = parent / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// `run` with `dir` as the working directory (the pre-render cache is stimuli/cache under it) and no
// display, so sessions are headless. `timeout_s` > 0: killed after that long (exit code 124), so a
// command that would hang (a FIFO read without a writer) fails its test instead of hanging it.
inline CommandResult run_in(const std::filesystem::path& dir, const std::string& arguments, int timeout_s = 0) {
  const std::string timeout = timeout_s > 0 ? " timeout -k 5 " + std::to_string(timeout_s) : "";
  return run(arguments, "cd " + dir.string() + " && env -u DISPLAY -u WAYLAND_DISPLAY" + timeout);
}

inline std::filesystem::path write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

}  // namespace fovlab::cli_test
