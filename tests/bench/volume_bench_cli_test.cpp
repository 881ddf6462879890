// fovlab bench-volume's display (bench/volume_bench.h, app/bench_volume_command.cpp): a frame smaller
// than the display is centred on it at the display's pixel pitch, so the fovea's size in pixels is
// the display's; Bruder et al. 2019's screen as a preset; the sites on the screen and the rays traced
// in the JSON; bad display flags are one line and exit code 2. Speed is reported, never asserted.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include <nlohmann/json.hpp>

#include "bench/volume_bench.h"
#include "core/input_error.h"
#include "foveation/voronoi_mask.h"
#include "tests/app/cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using fovlab::cli_test::expect_one_line_error;
using fovlab::cli_test::run;
using fovlab::cli_test::run_in;

fs::path scratch() { return fovlab::cli_test::scratch("fovlab-bench-volume-cli-test"); }

// A 24-inch 16:9 screen of 1920x1080 pixels at 600 mm: 531.3 mm wide, a pitch of 0.2767 mm, 37.84
// pixels a degree at its centre, so s = 2.5 degrees is 94.6 pixels, whatever part of it a frame covers.
double bruder_pitch_mm() { return 24.0 * 25.4 * 16.0 / std::sqrt(16.0 * 16.0 + 9.0 * 9.0) / 1920.0; }
double bruder_sigma_px() { return 2.5 * 600.0 * std::numbers::pi / 180.0 / bruder_pitch_mm(); }

TEST(VolumeBenchDisplay, FrameTakesTheDisplaysPitch) {
  const fovlab::DisplayGeometry screen = fovlab::display_from_diagonal(1920, 1080, 24.0, 600.0);
  for (int side : {256, 512, 1024}) {
    const fovlab::DisplayGeometry frame = fovlab::bench::frame_on_display(screen, side, side);
    EXPECT_EQ(frame.width_px, side);
    EXPECT_NEAR(frame.pixel_pitch_x_mm(), screen.pixel_pitch_x_mm(), 1e-12);
    EXPECT_NEAR(frame.width_mm, side * bruder_pitch_mm(), 1e-9);
    EXPECT_NEAR(frame.height_mm, side * bruder_pitch_mm(), 1e-9);
    EXPECT_NEAR(fovlab::density_sigma_px(frame, 2.5), bruder_sigma_px(), 1e-9) << side;
    EXPECT_NEAR(fovlab::density_sigma_px(frame, 2.5), 94.6, 0.05) << side;
  }
  // The frame as its own display (no display pixels given): a 27-inch square of 512 pixels at 500 mm
  // spans 485 mm, and the fovea shrinks to 23 pixels (the earlier, unlike-for-like default).
  const fovlab::DisplayGeometry own = fovlab::display_from_diagonal(512, 512, 27.0, 500.0);
  EXPECT_NEAR(fovlab::density_sigma_px(own, 2.5), 23.0, 0.1);
  EXPECT_THROW(fovlab::bench::frame_on_display(screen, 1024, 1081), fovlab::InputError);
}

TEST(BenchVolumeCli, BadDisplayFlagsAreOneLine) {
  const std::string tiny = "bench-volume --scenes shepp-logan --cameras 1 --gazes 1 --frames 1 ";
  expect_one_line_error(run(tiny + "--width 32 --height 32 --display-px 0x1080"), "--display-px: expected WxH");
  expect_one_line_error(run(tiny + "--width 32 --height 32 --display-px 1920"), "--display-px: expected WxH");
  expect_one_line_error(run(tiny + "--width 32 --height 32 --display-px 19.5x1080"), "--display-px: expected WxH");
  expect_one_line_error(run(tiny + "--width 32 --height 32 --display-px 1920x1080x2"), "--display-px: expected WxH");
  expect_one_line_error(run(tiny + "--width 1024 --height 1024 --display-px 1920x1000 --diagonal-in 24"),
                        "--width, --height: a frame of 1024x1024 pixels does not fit on the display's 1920x1000");
  expect_one_line_error(run(tiny + "--width 32 --height 32 --bruder-2019-display --diagonal-in 27"),
                        "--diagonal-in: --bruder-2019-display sets the display");
  expect_one_line_error(run(tiny + "--width 32 --height 32 --bruder-2019-display --display-px 800x600"),
                        "--display-px: --bruder-2019-display sets the display");
  expect_one_line_error(run(tiny + "--width 32 --height 32 --bruder-2019-display --distance-mm -3"),
                        "--distance-mm: expected a positive number");
}

TEST(BenchVolumeCli, PaperDisplayReportsFoveaSitesAndRays) {
  const fs::path dir = fovlab::cli_test::fresh_folder(scratch(), "work");
  const auto result = run_in(dir,
                             "bench-volume --scenes marschner-lobb --width 40 --height 32 --cameras 1 --gazes 2 "
                             "--frames 1 --bruder-2019-display --json bench.json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("--bruder-2019-display"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("of a 1920x1080 px"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("| fovea s px |"), std::string::npos) << result.out;
  nlohmann::json json;
  std::ifstream(dir / "bench.json") >> json;
  EXPECT_EQ(json["display"]["width_px"], 1920);
  EXPECT_EQ(json["display"]["viewing_distance_mm"], 600.0);
  EXPECT_NEAR(json["fovea_sigma_px"].get<double>(), bruder_sigma_px(), 1e-6);
  EXPECT_EQ(json["trace_read_sites_only"], true);
  const nlohmann::json& volume = json["volumes"][0];
  EXPECT_NEAR(volume["fovea_sigma_px"].get<double>(), bruder_sigma_px(), 1e-6);
  for (const char* earlier : {"speed_up", "traced_share", "sites", "full_ms", "foveated_ms", "ssim"})
    EXPECT_TRUE(volume.contains(earlier)) << earlier << ": the earlier fields stay";
  const double on_screen = volume["sites_on_screen"].get<double>(), rays = volume["traced_rays"].get<double>();
  EXPECT_GT(on_screen, 0.0);
  EXPECT_GE(rays, on_screen) << "every site on the screen is traced";
  EXPECT_NEAR(volume["traced_share"].get<double>(), rays / (40.0 * 32.0), 1e-9);
  EXPECT_LT(rays, double(volume["sites"].get<int>()));
}

}  // namespace
