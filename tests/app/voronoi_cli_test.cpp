// fovlab voronoi: Bruder et al. 2019's sampling mask drawn for a screen (Figure 1), and bad input as one line
// and exit code 2 with nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "core/image_io.h"
#include "tests/app/cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using fovlab::cli_test::expect_one_line_error;
using fovlab::cli_test::run;

fs::path scratch() { return fovlab::cli_test::scratch("fovlab-voronoi-cli-test"); }

TEST(VoronoiCli, DrawsTheSitesAndCellsOfAMaskTwiceTheScreen) {
  const fs::path sites = scratch() / "sites.png", cells = scratch() / "cells.png";
  const auto result = run("voronoi --width 64 --height 36 --sigma-px 6 --out-sites " + sites.string() +
                          " --out-cells " + cells.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("mask 128x72 for a 64x36 screen"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("converged"), std::string::npos) << result.out;
  const fovlab::Image site_image = fovlab::read_image(sites), cell_image = fovlab::read_image(cells);
  EXPECT_EQ(site_image.width, 128);
  EXPECT_EQ(site_image.height, 72);
  EXPECT_EQ(cell_image.width, 128);
  // Denser at the centre than in a corner: count the black dots.
  const auto dots = [&](int x0, int y0) {
    int count = 0;
    for (int y = y0; y < y0 + 12; ++y)
      for (int x = x0; x < x0 + 12; ++x) count += site_image.at(x, y, 0) < 0.5f;
    return count;
  };
  EXPECT_GT(dots(58, 30), 3 * dots(0, 0) + 3);
  // With the display instead of pixels: 2.5 degrees on the default 27-inch display at 500 mm.
  const auto from_degrees = run("voronoi --width 64 --height 36");
  ASSERT_EQ(from_degrees.exit_code, 0) << from_degrees.err;
  EXPECT_NE(from_degrees.out.find("deg)"), std::string::npos) << from_degrees.out;
}

TEST(VoronoiCli, BadInputIsOneLineAndWritesNothing) {
  const fs::path out = scratch() / "never.png";
  const std::string tail = " --out-sites " + out.string();
  expect_one_line_error(run("voronoi --width 0 --height 36" + tail), "--width");
  expect_one_line_error(run("voronoi --width 64 --height 36 --sigma-deg 0" + tail), "--sigma-deg");
  expect_one_line_error(run("voronoi --width 64 --height 36 --gaze 3,4" + tail), "--gaze");
  expect_one_line_error(run("voronoi --width 64 --height 36 --out-sites /nonexistent-folder/x.png"), "--out-sites");
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
