// fovlab bench-present end to end on a tiny FIPR stimulus: the headless row without a display, the
// window row under Xvfb (BenchPresentWindow, run by CTest through xvfb-run); the JSON has every
// field; a window without a display and bad flags exit 2 with one line. Speed is reported, never
// asserted.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/app/cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using fovlab::cli_test::CommandResult;
using fovlab::cli_test::expect_one_line_error;
using fovlab::cli_test::read_all;
using fovlab::cli_test::run;

fs::path scratch() { return fovlab::cli_test::scratch("fovlab-bench-present-cli-test"); }

// One row a frame path: the window's on_device (one device renders and presents) then via_host
// (a second device, the frame through the host); headless: none.
void expect_rows(const nlohmann::json& json, const std::string& presenter) {
  const std::vector<std::string> paths =
      presenter == "headless" ? std::vector<std::string>{"none"} : std::vector<std::string>{"on_device", "via_host"};
  ASSERT_EQ(json["rows"].size(), paths.size());
  for (size_t i = 0; i < paths.size(); ++i) {
    const nlohmann::json& row = json["rows"][i];
    EXPECT_EQ(row["presenter"], presenter);
    EXPECT_EQ(row["frame_path"], paths[i]);
    EXPECT_EQ(row["width"], 64);
    EXPECT_EQ(row["height"], 48);
    EXPECT_EQ(row["refreshes"], 3);
    for (const char* figure : {"median_ms", "p95_ms", "render_median_ms", "present_median_ms", "hash_median_ms"})
      EXPECT_GE(row[figure].get<double>(), 0.0) << figure;
    EXPECT_GE(row["p95_ms"].get<double>(), row["median_ms"].get<double>());
    EXPECT_GE(row["dropped_frames"].get<int>(), 0);
    EXPECT_EQ(row["present_clock"], presenter == "headless" ? "virtual" : "after_queue_present");
  }
  EXPECT_EQ(json["refreshes"], 3);
  EXPECT_EQ(json["stimulus"]["method"], "fipr");
  EXPECT_EQ(json["percentiles"], "nearest rank");
  EXPECT_TRUE(json["render_device"].is_string());
}

TEST(BenchPresentCli, HeadlessTinyRunWritesTheJson) {
  const fs::path json_path = scratch() / "present.json";
  const CommandResult result =
      run("bench-present --presenter headless --width 64 --height 48 --refreshes 3 --json " + json_path.string(),
          "env -u DISPLAY -u WAYLAND_DISPLAY");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("| headless | none | 64x48 |"), std::string::npos) << result.out;
  const nlohmann::json json = nlohmann::json::parse(read_all(json_path));
  expect_rows(json, "headless");
  EXPECT_NE(json["command"].get<std::string>().find("--sizes 64x48 --refreshes 3 --presenter headless"),
            std::string::npos);
}

TEST(BenchPresentCli, AWindowWithoutADisplayAndBadFlagsAreOneLineErrors) {
  CommandResult result = run("bench-present --width 64 --height 48 --refreshes 3", "env -u DISPLAY -u WAYLAND_DISPLAY");
  EXPECT_EQ(result.exit_code, 2);
  expect_one_line_error(result, "xvfb-run -a");
  result = run("bench-present --presenter headless --sizes 64x48,12x9");
  EXPECT_EQ(result.exit_code, 2);
  expect_one_line_error(result, "--sizes: expected WxH with 16 to 4096 pixels a side (e.g. 320x180), got \"12x9\"");
  result = run("bench-present --presenter headless --sizes 64by48");
  EXPECT_EQ(result.exit_code, 2);
  expect_one_line_error(result, "--sizes");
  result = run("bench-present --presenter glass --width 64 --height 48");
  EXPECT_EQ(result.exit_code, 2);
  expect_one_line_error(result, "--presenter glass: expected window, headless or both");
  result = run("bench-present --presenter headless --refreshes 0 --width 64 --height 48");
  EXPECT_EQ(result.exit_code, 2);
  expect_one_line_error(result, "--refreshes 0");
}

// Under Xvfb (CTest: BenchPresentUnderXvfb): the window rows, through the window presenter.
TEST(BenchPresentWindow, WindowRowUnderXvfb) {
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display) {
    if (std::getenv("FOVLAB_REQUIRE_DISPLAY")) FAIL() << "FOVLAB_REQUIRE_DISPLAY set but no DISPLAY";
    GTEST_SKIP() << "no DISPLAY (CTest runs this under xvfb-run)";
  }
  const fs::path json_path = scratch() / "window.json";
  const CommandResult result =
      run("bench-present --presenter window --width 64 --height 48 --refreshes 3 --json " + json_path.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  expect_rows(nlohmann::json::parse(read_all(json_path)), "window");
}

}  // namespace
