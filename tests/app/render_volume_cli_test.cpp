// fovlab render --method volume|fvolume: Bruder et al. 2019's raycaster from the command line, full and
// foveated, the mask's cache under the working directory, and bad input as one line and exit code 2
// with nothing written.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdint>
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
  const auto foveated = run_in(dir,
                               "render --method fvolume --scene shepp-logan --width 48 --height 40 --sigma-deg 0.5 "
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
  for (const auto& entry : fs::directory_iterator(dir / "stimuli" / "cache" / "voronoi"))
    cached += entry.path().extension() == ".bin";
  EXPECT_EQ(cached, 1) << "the mask and its weights, kept for the next run";
}

TEST(RenderVolumeCli, BadInputIsOneLineAndWritesNothing) {
  const fs::path out = scratch() / "never.png";
  const std::string tail = " --width 32 --height 32 --out " + out.string();
  expect_one_line_error(run("render --method volume --scene nebula" + tail), "volume scene \"nebula\": unknown");
  expect_one_line_error(run("render --method volume --scene shepp-logan --spp 4" + tail), "--spp: the sphere tracer's");
  expect_one_line_error(run("render --method volume --scene shepp-logan --sigma-deg 2" + tail),
                        "--sigma-deg: only fvolume");
  expect_one_line_error(
      run("render --method volume --scene shepp-logan --mask-out " + (scratch() / "m.png").string() + tail),
      "--mask-out: only fvolume");
  expect_one_line_error(run("render --method fvolume --scene shepp-logan --sigma-deg -1" + tail), "--sigma-deg");
  expect_one_line_error(run("render --method volume --scene shepp-logan --step-voxels 0" + tail), "--step-voxels");
  const fs::path bad_scene = fovlab::cli_test::write_file(scratch() / "bad.toml", "[volume]\ngenerator = \"x\"\n");
  expect_one_line_error(run("render --method volume --scene " + bad_scene.string() + tail),
                        "bad.toml:2: volume.generator");
  EXPECT_FALSE(fs::exists(out));
}

// The mask cache is read through the input guard: a FIFO at its path hung `render` (and a session,
// holding the participant's lock), a 30 GiB file ended in bad_alloc (exit 1). Neither is read; the
// mask is made anew and replaces it, the same bytes as the first time. Under a timeout, so a
// regression fails instead of hanging.
TEST(RenderVolumeCli, AMaskCacheThatIsAFifoOrLargerThanAnyMaskIsMadeAnew) {
  const fs::path dir = fovlab::cli_test::fresh_folder(scratch(), "mask-cache");
  const std::string args =
      "render --method fvolume --scene shepp-logan --width 24 --height 20 --sigma-deg 0.5 --out fov.png";
  const auto first = run_in(dir, args, 300);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  fs::path cache;
  for (const auto& entry : fs::directory_iterator(dir / "stimuli" / "cache" / "voronoi"))
    if (entry.path().extension() == ".bin") cache = entry.path();
  ASSERT_FALSE(cache.empty());
  const std::string made = fovlab::cli_test::read_all(cache);

  fs::remove(cache);
  ASSERT_EQ(::mkfifo(cache.c_str(), 0600), 0);
  const auto after_fifo = run_in(dir, args, 300);
  EXPECT_EQ(after_fifo.exit_code, 0) << "124: it hung on the FIFO\n" << after_fifo.err;
  EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(cache))) << "made anew in the FIFO's place";
  EXPECT_TRUE(fovlab::cli_test::read_all(cache) == made);

  fs::remove(cache);
  { std::ofstream(cache, std::ios::binary) << made; }
  fs::resize_file(cache, uint64_t(30) << 30);  // sparse: no disk used
  const auto after_huge = run_in(dir, args, 300);
  EXPECT_EQ(after_huge.exit_code, 0) << after_huge.err;
  EXPECT_EQ(fs::file_size(cache), made.size()) << "made anew, not read";
  EXPECT_TRUE(fovlab::cli_test::read_all(cache) == made);
}

// A NRRD header's data file is opened through the input guard before teem sees it: /dev/zero and
// /dev/urandom were accepted (a volume of noise), "-" read the terminal, and a FIFO hung the command.
TEST(RenderVolumeCli, NrrdDataFilesThatAreNotRegularFilesAreRefused) {
  const fs::path dir = fovlab::cli_test::fresh_folder(scratch(), "nrrd-data-files");
  const std::string points =
      "[[transfer_point]]\nvalue = 0.0\ncolour = [0, 0, 0]\nopacity = 0\n"
      "[[transfer_point]]\nvalue = 1.0\ncolour = [1, 1, 1]\nopacity = 1\n";
  fovlab::cli_test::write_file(dir / "scene.toml", "[volume]\nfile = \"v.nhdr\"\n" + points);
  const auto header = [&](const std::string& data_file) {
    fovlab::cli_test::write_file(dir / "v.nhdr",
                                 "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n"
                                 "data file: " +
                                     data_file + "\n");
  };
  const std::string args = "render --method volume --scene scene.toml --width 16 --height 16 --out v.png";
  const std::string from = ": expected the data file of NRRD volume v.nhdr";  // as the scene names it

  std::string voxels(64, '\0');
  for (size_t i = 0; i < voxels.size(); ++i) voxels[i] = char(i * 4);
  fovlab::cli_test::write_file(dir / "v.raw", voxels);
  header("v.raw");
  const auto good = run_in(dir, args, 300);
  ASSERT_EQ(good.exit_code, 0) << good.err;
  const std::string rendered = fovlab::cli_test::read_all(dir / "v.png");

  header("/dev/zero");
  expect_one_line_error(run_in(dir, args, 300), "/dev/zero: not a regular file (a character device)" + from);
  header("/dev/urandom");
  expect_one_line_error(run_in(dir, args, 300), "/dev/urandom: not a regular file (a character device)" + from);
  header("-");
  expect_one_line_error(run_in(dir, args, 300), "v.nhdr: data file \"-\" (standard input): expected a data file");
  ASSERT_EQ(::mkfifo((dir / "fifo.raw").c_str(), 0600), 0);
  header("fifo.raw");
  expect_one_line_error(run_in(dir, args, 300), "fifo.raw: not a regular file (a FIFO or pipe)" + from);
  EXPECT_TRUE(fovlab::cli_test::read_all(dir / "v.png") == rendered) << "a refused volume wrote nothing";
}

}  // namespace
