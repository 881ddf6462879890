// The fovlab command end to end: outputs on success; exit code 2, one line naming the problem and
// no output file on bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/app/cli_test_support.h"

namespace {

using fovlab::cli_test::CommandResult;
using fovlab::cli_test::expect_one_line_error;
using fovlab::cli_test::read_all;
using fovlab::cli_test::run;

std::filesystem::path scratch() { return fovlab::cli_test::scratch("fovlab-cli-test"); }

const std::string kSmall = " --width 48 --height 32 ";

TEST(Cli, RenderWritesImageHeatMapAndStats) {
  const auto image = scratch() / "frame.png";
  const auto steps = scratch() / "steps.png";
  const auto stats = scratch() / "stats.json";
  const CommandResult result =
      run("render --scene primitives --method ipr" + kSmall + "--spp 4 --time 1.5 --out " + image.string() +
          " --steps-out " + steps.string() + " --stats-json " + stats.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_TRUE(std::filesystem::exists(image));
  EXPECT_TRUE(std::filesystem::exists(steps));
  const nlohmann::json json = nlohmann::json::parse(read_all(stats));
  for (const char* key : {"method", "width", "height", "spp", "total_steps", "steps_per_pixel", "gpu_ms", "wall_ms",
                          "device", "capped_rays", "levels"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_EQ(json["method"], "ipr");
  EXPECT_EQ(json["spp"], 4);
  EXPECT_GT(json["total_steps"].get<uint64_t>(), 0u);
  EXPECT_TRUE(json["gpu_ms"].contains("total"));
  EXPECT_TRUE(json["gpu_ms"]["passes"].contains("trace_level2"));
}

TEST(Cli, CompareIdenticalAndDifferentImages) {
  const auto gt = scratch() / "cmp_gt.png";
  const auto ipr = scratch() / "cmp_ipr.exr";
  ASSERT_EQ(run("render --scene columns --method gt" + kSmall + "--out " + gt.string()).exit_code, 0);
  ASSERT_EQ(run("render --scene columns --method ipr" + kSmall + "--out " + ipr.string()).exit_code, 0);
  const CommandResult same = run("compare " + gt.string() + " " + gt.string() + " --json");
  ASSERT_EQ(same.exit_code, 0) << same.err;
  const nlohmann::json same_json = nlohmann::json::parse(same.out);
  EXPECT_TRUE(same_json["psnr_db"].is_null());
  EXPECT_EQ(same_json["ssim"], 1.0);
  EXPECT_EQ(same_json["flip"], 0.0);
  EXPECT_EQ(same_json["flip_pixels_per_degree"], 67.0);  // FLIP's default without a display
  EXPECT_TRUE(same_json["fpsnr_db"].is_null());
  const CommandResult different = run("compare " + gt.string() + " " + ipr.string());
  ASSERT_EQ(different.exit_code, 0) << different.err;
  EXPECT_NE(different.out.find("PSNR "), std::string::npos);
  EXPECT_NE(different.out.find("SSIM 0.9"), std::string::npos) << different.out;
  EXPECT_NE(different.out.find("FLIP 0.0"), std::string::npos) << different.out;

  // With the display: FLIP at its pixels per degree, and FPSNR around the gaze.
  const std::string display = " --diagonal-in 27 --distance-mm 500";
  const CommandResult centred = run("compare " + gt.string() + " " + ipr.string() + display + " --json");
  ASSERT_EQ(centred.exit_code, 0) << centred.err;
  const nlohmann::json centred_json = nlohmann::json::parse(centred.out);
  EXPECT_GT(centred_json["flip_pixels_per_degree"].get<double>(), 0.0);
  EXPECT_NE(centred_json["flip_pixels_per_degree"].get<double>(), 67.0);
  ASSERT_TRUE(centred_json["fpsnr_db"].is_number()) << centred.out;
  EXPECT_GE(centred_json["fpsnr_db"].get<double>(), 0.0);
  const CommandResult cornered = run("compare " + gt.string() + " " + ipr.string() + display + " --gaze 0,0 --json");
  ASSERT_EQ(cornered.exit_code, 0) << cornered.err;
  const nlohmann::json cornered_json = nlohmann::json::parse(cornered.out);
  EXPECT_EQ(cornered_json["gaze"], nlohmann::json::array({0.0, 0.0}));
  EXPECT_EQ(cornered_json["psnr_db"], centred_json["psnr_db"]);  // the gaze changes FPSNR only
  EXPECT_EQ(cornered_json["flip"], centred_json["flip"]);
  expect_one_line_error(run("compare " + gt.string() + " " + ipr.string() + " --gaze 3,4"), "--gaze");
  expect_one_line_error(run("compare " + gt.string() + " " + ipr.string() + " --diagonal-in 27"), "--distance-mm");
  expect_one_line_error(run("compare " + gt.string() + " " + ipr.string() + display + " --gaze a,b"), "--gaze");
}

TEST(Cli, BenchPrintsATableAndWritesJson) {
  const auto json_path = scratch() / "bench.json";
  const CommandResult result =
      run("bench --scenes primitives --spp 1 --width 48 --height 32 --repeats 1 --json " + json_path.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("| primitives | 1 |"), std::string::npos) << result.out;
  const nlohmann::json json = nlohmann::json::parse(read_all(json_path));
  ASSERT_EQ(json["rows"].size(), 1u);
  EXPECT_GT(json["rows"][0]["speedup"].get<double>(), 0.0);
  // The one-step floor: every sample one step from where GT stopped, then shaded; IPR's time over it.
  EXPECT_GT(json["rows"][0]["floor"]["median_gpu_ms"].get<double>(), 0.0);
  EXPECT_LE(json["rows"][0]["floor"]["steps_per_sample"].get<double>(), 1.0);
  EXPECT_GT(json["rows"][0]["ipr_over_floor"].get<double>(), 0.0);
  EXPECT_NE(json["command"].get<std::string>().find("fovlab bench --scenes primitives"), std::string::npos);
  // No --coarse-test or --min-filter given: IPR takes its own defaults (the cone without the min
  // filter since log schema 10), the command leaves them out and the JSON gives IPR's.
  EXPECT_EQ(json["command"].get<std::string>().find("--coarse-test"), std::string::npos);
  EXPECT_EQ(json["coarse_test"], (nlohmann::json{{"ipr", "cone"}}));
  EXPECT_EQ(json["min_filter_size"], (nlohmann::json{{"ipr", 1}}));
}

TEST(Cli, DevicesListsLavapipeOrAGpu) {
  const CommandResult result = run("devices");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("default: "), std::string::npos);
}

TEST(Cli, BadInputExitsTwoWithOneLineAndWritesNothing) {
  const auto out = scratch() / "never.png";
  const std::string render = "render --scene primitives --out " + out.string();
  expect_one_line_error(run("render --scene nope" + kSmall + "--out " + out.string()), "nope");
  expect_one_line_error(run(render + " --width 0 --height 32"), "--width 0");
  expect_one_line_error(run(render + " --width 99999 --height 32"), "--width 99999");
  expect_one_line_error(run(render + kSmall + "--spp 3"), "--spp 3");
  expect_one_line_error(run(render + kSmall + "--method ipr --coarse-test wide"), "--coarse-test");
  // The renderer names its settings' fields; render words them as its flags.
  expect_one_line_error(run(render + kSmall + "--levels 6"), "--levels 6: expected 2 to 5 pyramid levels");
  // A method's parameter flags take what a study config takes (its descriptor's range and values).
  expect_one_line_error(run(render + kSmall + "--method fipr --levels 2"), "--levels 2: expected a value in [3, 5]");
  expect_one_line_error(run(render + kSmall + "--max-steps 5000"), "--max-steps 5000: expected a value in [1, 4096]");
  // A float flag quoted as given, not as the float's 17 digits (9.9999997473787516e-06).
  expect_one_line_error(run(render + kSmall + "--hit-threshold 0.00001"), "--hit-threshold 1e-05: expected a value in");
  expect_one_line_error(run(render + kSmall + "--method fipr --fovea-deg 200"),
                        "--fovea-deg 200: expected a value in [0, 180]");
  expect_one_line_error(run(render + kSmall + "--method ipr --min-filter 2"), "--min-filter 2: expected one of 1 3 5");
  expect_one_line_error(run(render + kSmall + "--method rtx"), "--method");
  expect_one_line_error(run(render + kSmall + "--steps-out " + (scratch() / "steps.foo").string()), "steps.foo");
  expect_one_line_error(run("render --scene primitives" + kSmall + "--out /nonexistent-folder/x.png"),
                        "/nonexistent-folder");
  expect_one_line_error(
      run(render + kSmall, "VK_ICD_FILENAMES=/nonexistent/icd.json VK_DRIVER_FILES=/nonexistent/icd.json"),
      "no Vulkan");
  expect_one_line_error(run("compare " + out.string() + " " + out.string()), "never.png");
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(Cli, VersionAndUnknownSubcommands) {
  const CommandResult version = run("--version");
  EXPECT_EQ(version.exit_code, 0) << version.err;
  EXPECT_EQ(version.out.rfind("fovlab ", 0), 0u) << version.out;
  expect_one_line_error(run("frobnicate"), "unknown subcommand \"frobnicate\": expected one of render, ");
  const CommandResult none = run("");
  EXPECT_EQ(none.exit_code, 2) << none.err;
}

TEST(Cli, SceneCompileErrorNamesFileAndLine) {
  const auto scene = scratch() / "broken.glsl";
  std::ofstream(scene) << "// a scene with a typo\nconst vec3 SCENE_BOUNDS_MIN = vec3(0.0)\nfloat x;\n";
  const auto out = scratch() / "broken.png";
  const CommandResult result = run("render --scene " + scene.string() + kSmall + "--out " + out.string());
  // The missing semicolon of line 2 is reported at the next token, on line 3.
  expect_one_line_error(result, scene.string() + ":3: ");
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(Cli, RejectedRenderKeepsAnExistingOutput) {
  const auto out = scratch() / "keep.png";
  std::ofstream(out) << "an earlier result";
  EXPECT_EQ(run("render --scene primitives" + kSmall + "--spp 2 --out " + out.string()).exit_code, 2);
  EXPECT_EQ(read_all(out), "an earlier result");
}

}  // namespace
