// fovlab rays end to end: Table 1 of Polychronakis et al. 2021 through the command's JSON, the printed table, and
// bad input as one line naming the flag, exit code 2 and no JSON written.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/app/cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using fovlab::cli_test::CommandResult;
using fovlab::cli_test::expect_one_line_error;
using fovlab::cli_test::read_all;
using fovlab::cli_test::run;

fs::path scratch() { return fovlab::cli_test::scratch("fovlab-rays-cli-test"); }

const std::string kPaperDisplay = "rays --resolution 1920x1080 --diagonal-in 27 --distance-mm 500 ";
const std::string kTable1Grid = "--foveal-deg 5,10,15,20,25,30 --middle-deg 50,55,60,65,70,75 ";

// Polychronakis et al. 2021, Table 1 (rows foveal 5..30, columns middle 50..75 degrees).
const double kTable1[6][6] = {{4.98, 4.56, 4.19, 3.95, 3.91, 3.91}, {4.60, 4.23, 3.91, 3.70, 3.67, 3.67},
                              {4.07, 3.78, 3.52, 3.35, 3.32, 3.32}, {3.49, 3.28, 3.08, 2.95, 2.93, 2.93},
                              {2.95, 2.79, 2.65, 2.55, 2.53, 2.53}, {2.47, 2.36, 2.25, 2.18, 2.17, 2.17}};

TEST(RaysCli, ReproducesTable1ThroughJson) {
  const fs::path json_path = scratch() / "table1.json";
  const CommandResult result = run(kPaperDisplay + kTable1Grid + "--json " + json_path.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_TRUE(result.err.empty()) << result.err;
  const nlohmann::json cells = nlohmann::json::parse(read_all(json_path));
  ASSERT_TRUE(cells.is_array());
  ASSERT_EQ(cells.size(), 36u);
  const std::vector<double> foveal = {5, 10, 15, 20, 25, 30};
  const std::vector<double> middle = {50, 55, 60, 65, 70, 75};
  for (size_t i = 0; i < cells.size(); ++i) {
    const nlohmann::json& cell = cells[i];
    EXPECT_EQ(cell["foveal_deg"].get<double>(), foveal[i / 6]);
    EXPECT_EQ(cell["middle_deg"].get<double>(), middle[i % 6]);
    const double speedup = cell["speedup"].get<double>();
    EXPECT_NEAR(speedup, kTable1[i / 6][i % 6], 0.02) << cell.dump();
    EXPECT_NEAR(speedup * cell["rays"].get<double>(), 1920.0 * 1080.0, 1e-6);
    EXPECT_EQ(cell["foveal_pixels"].get<int64_t>() + cell["middle_pixels"].get<int64_t>() +
                  cell["outer_pixels"].get<int64_t>(),
              1920 * 1080);
  }
  // The printed table: the full-frame count and the first and last cells, rounded to 2 decimals.
  EXPECT_NE(result.out.find("2073600"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("4.99x"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("2.17x"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find(json_path.string()), std::string::npos) << result.out;
}

TEST(RaysCli, SizeInMillimetresAndGaze) {
  const fs::path by_diagonal = scratch() / "diagonal.json";
  const fs::path by_size = scratch() / "size.json";
  const fs::path corner = scratch() / "corner.json";
  const std::string grid = "--foveal-deg 10 --middle-deg 60 ";
  ASSERT_EQ(run(kPaperDisplay + grid + "--gaze 960,540 --json " + by_diagonal.string()).exit_code, 0);
  const CommandResult sized = run("rays --resolution 1920x1080 --size-mm 597.7265x336.2212 --distance-mm 500 " + grid +
                                  "--json " + by_size.string());
  ASSERT_EQ(sized.exit_code, 0) << sized.err;
  const double diagonal_speedup = nlohmann::json::parse(read_all(by_diagonal))[0]["speedup"].get<double>();
  EXPECT_NEAR(nlohmann::json::parse(read_all(by_size))[0]["speedup"].get<double>(), diagonal_speedup, 1e-3);
  // Gaze at a corner: the zones fall partly off the screen, so fewer pixels need many rays.
  ASSERT_EQ(run(kPaperDisplay + grid + "--gaze 0,0 --json " + corner.string()).exit_code, 0);
  EXPECT_GT(nlohmann::json::parse(read_all(corner))[0]["speedup"].get<double>(), diagonal_speedup);
}

TEST(RaysCli, PrintsWithoutJson) {
  const CommandResult result = run(kPaperDisplay + "--foveal-deg 15 --middle-deg 65");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("3.36x"), std::string::npos) << result.out;
  // A gaze point off the screen is taken (negative coordinates included).
  const CommandResult off_screen = run(kPaperDisplay + "--foveal-deg 15 --middle-deg 65 --gaze -100,-50");
  ASSERT_EQ(off_screen.exit_code, 0) << off_screen.err;
  EXPECT_NE(off_screen.out.find("gaze (-100, -50) px"), std::string::npos) << off_screen.out;
}

TEST(RaysCli, BadInputIsOneLineNamingTheFlag) {
  const fs::path json_path = scratch() / "never.json";
  const std::string out = " --json " + json_path.string();
  const std::string angles = " --foveal-deg 5 --middle-deg 50";
  const std::string display = "rays --resolution 64x36 --diagonal-in 27 --distance-mm 500";
  struct Case {
    std::string arguments;
    std::string must_contain;
  };
  const std::vector<Case> cases = {
      {"rays --resolution 1920 --diagonal-in 27 --distance-mm 500" + angles, "--resolution"},
      {"rays --resolution axb --diagonal-in 27 --distance-mm 500" + angles, "--resolution"},
      {"rays --resolution 0x1080 --diagonal-in 27 --distance-mm 500" + angles, "--resolution"},
      {"rays --resolution 1920x1080x3 --diagonal-in 27 --distance-mm 500" + angles, "--resolution"},
      {"rays --resolution 64x36 --distance-mm 500" + angles, "--diagonal-in, --size-mm"},
      {"rays --resolution 64x36 --diagonal-in 27 --size-mm 600x340 --distance-mm 500" + angles,
       "--diagonal-in, --size-mm"},
      {"rays --resolution 64x36 --diagonal-in 0 --distance-mm 500" + angles, "--diagonal-in"},
      {"rays --resolution 64x36 --diagonal-in inf --distance-mm 500" + angles, "--diagonal-in"},
      {"rays --resolution 64x36 --size-mm 600 --distance-mm 500" + angles, "--size-mm"},
      {"rays --resolution 64x36 --size-mm 600x0 --distance-mm 500" + angles, "--size-mm"},
      {"rays --resolution 64x36 --size-mm nanx340 --distance-mm 500" + angles, "--size-mm"},
      {"rays --resolution 64x36 --diagonal-in 27 --distance-mm 0" + angles, "--distance-mm"},
      {"rays --resolution 64x36 --diagonal-in 27 --distance-mm half" + angles, "--distance-mm"},
      {display + " --foveal-deg 5,-1 --middle-deg 50", "--foveal-deg"},
      {display + " --foveal-deg 5,nan --middle-deg 50", "--foveal-deg"},
      {display + " --foveal-deg 5,,10 --middle-deg 50", "--foveal-deg"},
      {display + " --foveal-deg 5 --middle-deg inf", "--middle-deg"},
      {display + " --foveal-deg 5 --middle-deg 50deg", "--middle-deg"},
      {display + angles + " --gaze 10", "--gaze"},
      {display + angles + " --gaze 10,y", "--gaze"},
      {display + angles + " --gaze 1,inf", "--gaze"},
      {"rays --resolution 64x36 --diagonal-in 27" + angles, "--distance-mm"},  // required
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.arguments);
    const CommandResult result = run(c.arguments + out);
    expect_one_line_error(result, c.must_contain);
    EXPECT_FALSE(fs::exists(json_path));
  }
  // An unwritable JSON path is refused before any work.
  expect_one_line_error(run(display + angles + " --json " + (scratch() / "missing/cells.json").string()), "--json");
}

}  // namespace
