// fovlab bench --headset (issue 42): each eye measured at its size from its head-locked view. The
// bench's GT frame of an eye is the sphere tracer's GT frame of that eye's view, rendered here
// directly (bit for bit after the sRGB PNG's 8 bits); the eyes' frames differ; the JSON says which
// eye and its size; a config that is not a headset's, and flags the config decides, are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/colour.h"
#include "core/image_io.h"
#include "renderer/scene/eye_view.h"
#include "renderer/scene/scene_source.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "tests/app/cli_test_support.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;

using cli_test::CommandResult;
using cli_test::expect_one_line_error;
using cli_test::read_all;
using cli_test::run;

fs::path scratch() { return cli_test::scratch("fovlab-bench-headset-test"); }

// experiments/fipr_main_hmd.toml with eyes of 48x40 pixels (its angles and 63 mm IPD kept).
fs::path small_headset_config() {
  std::string text = read_all(fs::path(FOVLAB_SOURCE_DIR) / "experiments/fipr_main_hmd.toml");
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"eye_width_px = 1440", "eye_width_px = 48"},
                                 std::pair<std::string, std::string>{"eye_height_px = 1600", "eye_height_px = 40"}}) {
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  }
  const fs::path path = scratch() / "hmd_48x40.toml";
  std::ofstream(path) << text;
  return path;
}

// The config's eye, as the bench must render it: at -/+ 31.5 mm along the head's x, its angles.
EyeView config_eye(bool left) {
  EyeView view;
  view.position_in_head = {left ? -0.0315 : 0.0315, 0.0, 0.0};
  view.field_of_view = left ? field_of_view_from_deg(-54, 49, 54, -56) : field_of_view_from_deg(-49, 54, 54, -56);
  return view;
}

// Pixels whose 8-bit sRGB value differs on some channel.
int pixels_differing(const Image& a, const Image& b) {
  int differing = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      bool differs = false;
      for (int c = 0; c < 3; ++c) differs |= std::lround(a.at(x, y, c) * 255.0f) != std::lround(b.at(x, y, c) * 255.0f);
      differing += differs ? 1 : 0;
    }
  return differing;
}

class BenchHeadset : public test::VulkanTest {};

TEST_F(BenchHeadset, EachEyesGroundTruthIsTheTracersFrameOfThatEyesView) {
  const fs::path config = small_headset_config();
  const fs::path out_dir = scratch() / "eyes";
  const fs::path json_path = scratch() / "eyes.json";
  const CommandResult result =
      run("bench --headset " + config.string() + " --scenes primitives --spp 1 --repeats 1 --methods gt,ipr --json " +
          json_path.string() + " --out-dir " + out_dir.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("left eye 48x40"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("right eye 48x40"), std::string::npos) << result.out;

  const nlohmann::json json = nlohmann::json::parse(read_all(json_path));
  ASSERT_EQ(json["eyes"].size(), 2u);
  SphereTracer tracer(context(), load_scene("primitives"));
  Image frames[2];
  for (int index = 0; index < 2; ++index) {
    const bool left = index == 0;
    const std::string name = left ? "left" : "right";
    const nlohmann::json& eye = json["eyes"][index];
    EXPECT_EQ(eye["eye"]["name"], name);
    EXPECT_EQ(eye["eye"]["width_px"], 48);
    EXPECT_EQ(eye["eye"]["height_px"], 40);
    EXPECT_NEAR(eye["eye"]["position_m"][0].get<double>(), left ? -0.0315 : 0.0315, 1e-12);
    EXPECT_NE(eye["command"].get<std::string>().find("--headset " + config.string()), std::string::npos);
    EXPECT_NE(eye["command"].get<std::string>().find("--eye " + name), std::string::npos);
    // The gaze, left out, is at the eye's principal point: tan(left) / (tan(left) - tan(right)) across.
    const EyeView view = config_eye(left);
    const DisplayGeometry display = eye_display(view, 48, 40);
    EXPECT_NEAR(eye["metrics"]["gaze_px"][0].get<double>(), display.principal_point_x_px(), 1e-9);
    EXPECT_NEAR(eye["metrics"]["gaze_px"][1].get<double>(), display.principal_point_y_px(), 1e-9);

    SphereTraceSettings settings;
    settings.width = 48;
    settings.height = 40;
    settings.samples_per_pixel = 1;
    settings.method = TraceMethod::ground_truth;
    settings.eye = view;
    const Image expected = encode_srgb(tracer.render(settings).colour_linear);
    frames[index] = read_image(out_dir / name / "primitives_spp1_gt.png");
    ASSERT_EQ(frames[index].width, 48);
    ASSERT_EQ(frames[index].height, 40);
    EXPECT_EQ(pixels_differing(frames[index], expected), 0) << name;
  }
  // The eyes see the scene from 63 mm apart through different angles.
  EXPECT_GT(pixels_differing(frames[0], frames[1]), 48 * 40 / 20);
}

TEST(BenchHeadsetCli, OneEyeIsOneSweepOfThatEye) {
  const fs::path json_path = scratch() / "right.json";
  const CommandResult result =
      run("bench --headset " + small_headset_config().string() +
          " --eye right --scenes primitives --spp 1 --repeats 1 --methods gt --json " + json_path.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const nlohmann::json json = nlohmann::json::parse(read_all(json_path));
  EXPECT_FALSE(json.contains("eyes"));
  EXPECT_EQ(json["eye"]["name"], "right");
  EXPECT_EQ(json["width"], 48);
  EXPECT_EQ(json["rows"].size(), 1u);
}

TEST(BenchHeadsetCli, RefusesAWindowConfigAndFlagsTheHeadsetDecides) {
  const std::string config = small_headset_config().string();
  const std::string tiny = "bench --scenes primitives --spp 1 --repeats 1 --methods gt ";
  expect_one_line_error(run(tiny + "--headset " + std::string(FOVLAB_SOURCE_DIR) + "/experiments/fipr_main.toml"),
                        "expected a headset's config");
  for (const std::string flag :
       {"--width 64", "--height 48", "--diagonal-in 24", "--size-mm 500x300", "--distance-mm 600"}) {
    const std::string name = flag.substr(0, flag.find(' '));
    expect_one_line_error(run(tiny + "--headset " + config + " " + flag), name + ": not with --headset");
  }
  expect_one_line_error(run(tiny + "--eye left"), "--eye left: only with --headset");
  expect_one_line_error(run(tiny + "--headset " + config + " --eye middle"), "--eye");
  expect_one_line_error(run(tiny + "--headset " + config + " --cells 1/2 --json x.json"),
                        "--cells 1/2: not with --headset");
}

}  // namespace
}  // namespace fovlab
