// fovlab bench-fpt end to end on a tiny frame: every figure of the emulated foveated path tracer is
// in the JSON and in the printed table, the upsampling agrees with the reference and with
// OpenImageIO; bad flags exit 2 with one line and write nothing. Speed is reported, never asserted.
#include <gtest/gtest.h>

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

fs::path scratch() { return fovlab::cli_test::scratch("fovlab-bench-fpt-cli-test"); }

const std::string kTiny =
    "bench-fpt --scene primitives --width 64 --height 48 --repeats 2 --path-width 16 --path-height 8 --path-samples 2 "
    "--path-bounces 4 ";

TEST(BenchFptCli, TinyRunWritesEveryFigure) {
  const fs::path json_path = scratch() / "fpt.json";
  const CommandResult result = run(kTiny + "--json " + json_path.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("| Lanczos-3, 32x24 to 64x48"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("| Lanczos-3, 16x12 to 64x48"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("blend to the sRGB8 frame (sessions), against a copy shader"), std::string::npos);
  EXPECT_NE(result.out.find("samples/s on the GPU clock"), std::string::npos) << result.out;

  const nlohmann::json json = nlohmann::json::parse(read_all(json_path));
  EXPECT_NE(json["command"].get<std::string>().find("--width 64 --height 48 --repeats 2"), std::string::npos);
  for (const char* factor : {"upsample_factor_2", "upsample_factor_4"}) {
    const nlohmann::json& upsample = json[factor];
    EXPECT_GE(upsample["gpu_median_ms"].get<double>(), 0.0) << factor;  // 0 where the queue has no timestamps
    EXPECT_GT(upsample["openimageio_median_wall_ms"].get<double>(), 0.0) << factor;
    EXPECT_EQ(upsample["repeats"].get<int>(), 2);
    const double high = upsample["input_range"][1].get<double>();
    EXPECT_LT(upsample["largest_difference"]["gpu_vs_reference"].get<double>(), 1e-4 * high) << factor;
    EXPECT_LT(upsample["largest_difference"]["openimageio_vs_reference"].get<double>(), 1e-4 * high) << factor;
  }
  const nlohmann::json& blend = json["blend"];
  for (const char* figure : {"display_blend_gpu_ms", "linear_blend_gpu_ms", "copy_shader_gpu_ms", "copy_buffer_gpu_ms"})
    EXPECT_GE(blend[figure].get<double>(), 0.0) << figure;
  EXPECT_GT(blend["refresh_wall_ms"].get<double>(), 0.0);
  EXPECT_EQ(blend["bounds_deg"]["middle"].get<double>(), 62.5);  // the default: foveal + 52.5
  EXPECT_EQ(blend["frame_pixels"].get<uint32_t>(), 64u * 48u);
  EXPECT_GT(blend["band_pixels"].get<uint32_t>(), 0u);  // the foveal band: 10 degrees on a 64x48 frame of 27"
  EXPECT_LT(blend["band_pixels"].get<uint32_t>(), 64u * 48u);
  EXPECT_GE(json["zone_buffers_gpu_ms"].get<double>(), 0.0);
  EXPECT_NE(result.out.find("an animation frame's zone buffers"), std::string::npos) << result.out;
  const nlohmann::json& path = json["path_tracer"];
  EXPECT_EQ(path["samples"].get<uint64_t>(), 16u * 8u * 2u);
  EXPECT_GT(path["samples_per_s_wall"].get<double>(), 0.0);
}

TEST(BenchFptCli, BadFlagsExitTwoWithOneLineAndWriteNothing) {
  const fs::path json_path = scratch() / "never.json";
  const std::string json = " --json " + json_path.string();
  expect_one_line_error(run("bench-fpt --width 30 --height 48" + json), "--width/--height 30x48");
  expect_one_line_error(run("bench-fpt --repeats 0" + json), "--repeats 0");
  expect_one_line_error(run("bench-fpt --path-scene nowhere" + json), "--path-scene nowhere");
  expect_one_line_error(run("bench-fpt --path-scene " + (scratch() / "missing.obj").string() + json), "missing.obj");
  expect_one_line_error(run("bench-fpt --path-samples 0" + json), "samples");
  expect_one_line_error(run("bench-fpt --gaze 1,x" + json), "--gaze");
  expect_one_line_error(run("bench-fpt --scene nowhere" + json), "nowhere");
  expect_one_line_error(run("bench-fpt --json " + (scratch() / "no-such-folder" / "fpt.json").string()), "--json");
  EXPECT_FALSE(fs::exists(json_path));
}

}  // namespace
