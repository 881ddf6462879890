// fovlab blend: the offline preview of one frame and one gaze sample through the command line (the
// written image is the blend of the frame's zone buffers), the zone picture, the cost line, and
// bad input as one line and exit code 2 with nothing written.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/image_io.h"
#include "foveation/display_geometry.h"
#include "renderer/upsampling/upsample_filter.h"
#include "foveation/zone_layout.h"
#include "tests/app/cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using fovlab::cli_test::expect_one_line_error;
using fovlab::cli_test::run;

fs::path scratch() { return fovlab::cli_test::scratch("fovlab-blend-cli-test"); }

fs::path frame_file() {
  const fs::path path = scratch() / "frame.exr";
  fovlab::Image image(48, 32, 3);
  for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = float((i * 37) % 101) / 50.0f;
  fovlab::write_image(path, image);
  return path;
}

TEST(BlendCli, WritesTheBlendOfTheZoneBuffersAndTheZonePicture) {
  const fs::path frame = frame_file();
  const fs::path out = scratch() / "blend.exr";
  const fs::path zones = scratch() / "zones.png";
  const auto result = run("blend --frame " + frame.string() +
                          " --gaze 12,20 --foveal-deg 20 --middle-deg 50 --band-deg 2"
                          " --size-mm 240x160 --distance-mm 300 --repeats 2 --out " +
                          out.string() + " --zones-out " + zones.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("x the copy shader"), std::string::npos) << result.out;
  const fovlab::Image source = fovlab::read_image(frame);
  const fovlab::DisplayGeometry display = fovlab::display_from_size(48, 32, 240.0, 160.0, 300.0);
  const auto up = [&](int factor) {
    return fovlab::upsample_reference(fovlab::decimate_nearest(source, factor), factor,
                                      fovlab::UpsampleFilter::lanczos3);
  };
  const fovlab::Image expected =
      fovlab::blend_zones_reference(display, 12.0, 20.0, {20.0, 50.0, 2.0}, source, up(2), up(4));
  const fovlab::Image written = fovlab::read_image(out);
  ASSERT_EQ(written.width, 48);
  for (size_t i = 0; i < expected.pixels.size(); ++i) ASSERT_NEAR(written.pixels[i], expected.pixels[i], 5e-4) << i;
  const fovlab::Image picture = fovlab::read_image(zones);
  EXPECT_GT(picture.at(12, 20, 0), picture.at(12, 20, 2)) << "red over the gaze point";
  EXPECT_GT(picture.at(47, 0, 2), picture.at(47, 0, 0)) << "blue in the far corner";
}

TEST(BlendCli, BadInputIsOneLineAndWritesNothing) {
  const fs::path frame = frame_file();
  const fs::path out = scratch() / "never.png";
  const std::string head = "blend --frame " + frame.string() + " --out " + out.string();
  expect_one_line_error(run(head + " --gaze 100,5 --foveal-deg 10"), "--gaze");  // off the 48x32 frame
  expect_one_line_error(run(head + " --foveal-deg 10"), "--gaze");
  expect_one_line_error(run(head + " --gaze 5,5 --foveal-deg -3"), "foveal_deg");
  expect_one_line_error(run(head + " --gaze 5,5 --foveal-deg 10 --distance-mm 0"), "--distance-mm");
  expect_one_line_error(run("blend --frame " + (scratch() / "missing.exr").string() +
                            " --gaze 5,5 --foveal-deg 10 --out " + out.string()),
                        "missing.exr");
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
