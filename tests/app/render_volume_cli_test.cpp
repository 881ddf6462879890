// fovlab render --method volume|fvolume: seed 003's raycaster from the command line, full and
// foveated, the mask's cache under the working directory, and bad input as one line and exit code 2
// with nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/image_io.h"
#include "tests/app/cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using fovlab::cli_test::expect_one_line_error;
using fovlab::cli_test::run;
using fovlab::cli_test::run_in;

fs::path scratch() { return fovlab::cli_test::scratch("fovlab-render-volume-cli-test"); }

TEST(RenderVolumeCli, RendersFullAndFoveatedFrames) {
  const fs::path dir = fovlab::cli_test::fresh_folder(scratch(), "work");
  const auto full = run_in(dir, "render --method volume --scene shepp-logan --width 48 --height 40 --out full.png");
  ASSERT_EQ(full.exit_code, 0) << full.err;
  EXPECT_NE(full.out.find("shepp-logan volume 48x40"), std::string::npos) << full.out;
  const auto foveated = run_in(dir, "render --method fvolume --scene shepp-logan --width 48 --height 40 --sigma-deg 0.5 "
                                    "--gaze 25%,50% --frames 2 --out fov.png --mask-out sites.png --stats-json stats.json");
  ASSERT_EQ(foveated.exit_code, 0) << foveated.err;
  EXPECT_NE(foveated.out.find("of the pixels"), std::string::npos) << foveated.out;
  const fovlab::Image image = fovlab::read_image(dir / "fov.png"), sites = fovlab::read_image(dir / "sites.png");
  EXPECT_EQ(image.width, 48);
  EXPECT_EQ(sites.height, 40);
  nlohmann::json stats;
  std::ifstream(dir / "stats.json") >> stats;
  EXPECT_EQ(stats["method"], "fvolume");
  EXPECT_GT(stats["traced_share"].get<double>(), 0.0);
  EXPECT_LT(stats["traced_share"].get<double>(), 1.0);
  EXPECT_EQ(stats["gpu_ms_per_frame"].size(), 2u);
  int cached = 0;
  for (const auto& entry : fs::directory_iterator(dir / "stimuli" / "cache" / "voronoi")) cached += entry.path().extension() == ".bin";
  EXPECT_EQ(cached, 1) << "the mask and its weights, kept for the next run";
}

TEST(RenderVolumeCli, BadInputIsOneLineAndWritesNothing) {
  const fs::path out = scratch() / "never.png";
  const std::string tail = " --width 32 --height 32 --out " + out.string();
  expect_one_line_error(run("render --method volume --scene nebula" + tail), "volume scene \"nebula\": unknown");
  expect_one_line_error(run("render --method volume --scene shepp-logan --spp 4" + tail), "--spp: the sphere tracer's");
  expect_one_line_error(run("render --method volume --scene shepp-logan --sigma-deg 2" + tail), "--sigma-deg: only fvolume");
  expect_one_line_error(run("render --method volume --scene shepp-logan --mask-out " + (scratch() / "m.png").string() + tail),
                        "--mask-out: only fvolume");
  expect_one_line_error(run("render --method fvolume --scene shepp-logan --sigma-deg -1" + tail), "--sigma-deg");
  expect_one_line_error(run("render --method volume --scene shepp-logan --step-voxels 0" + tail), "--step-voxels");
  const fs::path bad_scene = fovlab::cli_test::write_file(scratch() / "bad.toml", "[volume]\ngenerator = \"x\"\n");
  expect_one_line_error(run("render --method volume --scene " + bad_scene.string() + tail), "bad.toml:2: volume.generator");
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
