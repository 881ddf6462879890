// fovlab resample: the offline preview of Ye et al. 2022's sampling models on a pre-rendered frame (what
// pt-rmfr, pt-hyperbolic, pt-linear and pt-kfr show for one gaze sample) through the command line,
// and bad input as one line and exit code 2 with nothing written.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "core/image_io.h"
#include "tests/app/cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using fovlab::cli_test::expect_one_line_error;
using fovlab::cli_test::run;

fs::path scratch() { return fovlab::cli_test::scratch("fovlab-resample-cli-test"); }

// A smooth linear-light frame of 50x29 pixels (no side a multiple of 4 or of sigma).
fs::path frame_file() {
  const fs::path path = scratch() / "frame.exr";
  fovlab::Image image(50, 29, 3);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      image.at(x, y, 0) = 0.5f + 0.4f * std::sin(0.2f * float(x));
      image.at(x, y, 1) = float(y) / 29.0f;
      image.at(x, y, 2) = 0.25f;
    }
  fovlab::write_image(path, image);
  return path;
}

// Every model writes an image of the frame's size, close to the frame where the gaze rests, with its
// mask and density pictures; the report says what was sampled and the error against the frame.
TEST(ResampleCli, EveryModelWritesTheResampledFrame) {
  const fs::path frame = frame_file();
  const fovlab::Image source = fovlab::read_image(frame);
  const struct {
    std::string model, flags;
  } cases[] = {{"rmfr", "--sigma 2 --fx 0.2 --resample lanczos"},
               {"hyperbolic", "--outer-pixel-size 4"},
               {"linear", "--min-probability 0.2"},
               {"kfr", "--sigma 2 --alpha 3"}};
  for (const auto& c : cases) {
    const fs::path out = scratch() / (c.model + ".exr");
    const fs::path mask = scratch() / (c.model + "_mask.png");
    const fs::path density = scratch() / (c.model + "_density.png");
    const auto result = run("resample --frame " + frame.string() + " --method " + c.model + " " + c.flags +
                            " --gaze 20,15 --size-mm 250x145 --distance-mm 400 --repeats 2 --out " + out.string() +
                            " --mask-out " + mask.string() + " --density-out " + density.string());
    ASSERT_EQ(result.exit_code, 0) << result.err;
    EXPECT_NE(result.out.find(c.model + ": "), std::string::npos) << result.out;
    EXPECT_NE(result.out.find("samples read"), std::string::npos) << result.out;
    EXPECT_NE(result.out.find("against the frame: SSIM"), std::string::npos) << result.out;
    const fovlab::Image written = fovlab::read_image(out);
    ASSERT_EQ(written.width, 50);
    ASSERT_EQ(written.height, 29);
    // Where the gaze rests the samples lie about a pixel apart (KFR's innermost ring, with alpha 3,
    // about 2.6 px out), and the frame's red changes by up to 0.08 a pixel.
    EXPECT_NEAR(written.at(20, 15, 0), source.at(20, 15, 0), c.model == "kfr" ? 0.15 : 0.04)
        << c.model << " at the gaze";
    EXPECT_TRUE(fs::exists(mask) && fs::exists(density)) << c.model;
  }
}

TEST(ResampleCli, BadInputIsOneLineAndWritesNothing) {
  const fs::path frame = frame_file();
  const fs::path out = scratch() / "never.png";
  const std::string head = "resample --frame " + frame.string() + " --out " + out.string();
  expect_one_line_error(run(head + " --method rmfr --sigma 9"), "--sigma");
  expect_one_line_error(run(head + " --method rmfr --alpha 3"), "--alpha");  // kfr's alone
  expect_one_line_error(run(head + " --method linear --outer-pixel-size 4"), "--outer-pixel-size");
  expect_one_line_error(run(head + " --method kfr --gaze 1,x"), "--gaze");
  expect_one_line_error(run(head + " --method rmfr --repeats 0"), "--repeats");
  expect_one_line_error(run(head + " --method hyperbolic --equalise --sigma 8"), "equalise");
  expect_one_line_error(
      run("resample --frame " + (scratch() / "missing.exr").string() + " --method rmfr --out " + out.string()),
      "missing.exr");
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
