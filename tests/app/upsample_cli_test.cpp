// fovlab upsample: a zone buffer written and upsampled through the command line, EXR precision kept,
// the OpenImageIO comparison printed, bad input as one line and exit code 2 with nothing written.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/image_io.h"
#include "renderer/upsampling/upsample_filter.h"
#include "tests/app/cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using fovlab::cli_test::expect_one_line_error;
using fovlab::cli_test::run;

fs::path scratch() { return fovlab::cli_test::scratch("fovlab-upsample-cli-test"); }

fs::path zone_buffer() {
  const fs::path path = scratch() / "zone.exr";
  fovlab::Image image(9, 5, 3);
  for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = float(i % 7) * 0.37f + 0.001f * float(i);
  fovlab::write_image(path, image);
  return path;
}

TEST(UpsampleCli, WritesTheReferenceImageAndComparesWithOpenImageIO) {
  const fs::path in = zone_buffer();
  const fs::path out = scratch() / "up.exr";
  const auto result = run("upsample " + in.string() + " --factor 4 --repeats 2 --against-oiio --out " + out.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("OpenImageIO"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("GPU - reference"), std::string::npos) << result.out;
  // The three agree: the same filter on the GPU, in double and in OpenImageIO.
  const auto difference_after = [&](const std::string& label) {
    const size_t at = result.out.find(label);
    return at == std::string::npos ? 1.0 : std::stod(result.out.substr(at + label.size()));
  };
  EXPECT_LT(difference_after("OpenImageIO - reference "), 1e-3) << result.out;
  EXPECT_LT(difference_after("GPU - OpenImageIO "), 1e-3) << result.out;
  const fovlab::Image written = fovlab::read_image(out);
  const fovlab::Image expected =
      fovlab::upsample_reference(fovlab::read_image(in), 4, fovlab::UpsampleFilter::lanczos3);
  ASSERT_EQ(written.width, 36);
  ASSERT_EQ(written.height, 20);
  for (size_t i = 0; i < expected.pixels.size(); ++i) ASSERT_NEAR(written.pixels[i], expected.pixels[i], 1e-5);
}

TEST(UpsampleCli, BadInputIsOneLineAndWritesNothing) {
  const fs::path in = zone_buffer();
  const fs::path out = scratch() / "never.exr";
  expect_one_line_error(run("upsample " + in.string() + " --factor 3 --out " + out.string()), "--factor 3");
  expect_one_line_error(
      run("upsample " + in.string() + " --factor 2 --filter bilinear --against-oiio --out " + out.string()),
      "--against-oiio");
  expect_one_line_error(run("upsample " + in.string() + " --factor 2 --repeats 0 --out " + out.string()), "--repeats");
  expect_one_line_error(run("upsample " + (scratch() / "missing.exr").string() + " --factor 2 --out " + out.string()),
                        "missing.exr");
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
