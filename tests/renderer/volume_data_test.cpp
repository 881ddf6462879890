// Bruder et al. 2019's volumes and volume scenes (renderer/volume/volume_grid.h, volume_scene.h): the generated
// fields against their formulas, the file readers (NRRD through libteem, .dat) on files written
// here, and one-line errors for bad files and scenes, with sizes refused before anything is read.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "core/input_error.h"
#include "renderer/volume/volume_grid.h"
#include "renderer/volume/volume_scene.h"
#include "tests/support/temp_dir.h"

namespace fovlab {
namespace {

const VolumeLimits kLimits{256, uint64_t(1) << 26};

std::string error_of(const std::function<void()>& run) {
  try {
    run();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

std::string dat_bytes(int x, int y, int z, const std::vector<uint16_t>& values) {
  std::string bytes;
  for (int side : {x, y, z}) {
    bytes += char(side & 0xFF);
    bytes += char((side >> 8) & 0xFF);
  }
  for (uint16_t value : values) {
    bytes += char(value & 0xFF);
    bytes += char(value >> 8);
  }
  return bytes;
}

TEST(VolumeData, GeneratedFieldsFollowTheirFormulas) {
  // Marschner-Lobb at the origin: rho_r(0) = cos(12 pi) = 1, so (1 - 0 + 0.25 x 2) / 2.5 = 0.6.
  EXPECT_NEAR(marschner_lobb(0, 0, 0), 0.6, 1e-12);
  // At z = 1 the sine term is 1: (0 + 0.25 (1 + rho_r)) / 2.5.
  const double r = 0.5, rho = std::cos(2 * M_PI * 6 * std::cos(M_PI * r / 2));
  EXPECT_NEAR(marschner_lobb(r, 0, 1), 0.25 * (1 + rho) / 2.5, 1e-12);
  // Shepp-Logan: the brain (1 - 0.8) at the centre, the skull shell (1) just inside the outer
  // ellipsoid, nothing outside.
  EXPECT_NEAR(shepp_logan(0, 0, 0), 0.2, 1e-12);
  EXPECT_NEAR(shepp_logan(0, 0.9, 0), 1.0, 1e-12);
  EXPECT_EQ(shepp_logan(0.95, 0.95, 0.95), 0.0);

  // A one-voxel grid holds the field at its centre, the origin, on 16 bits.
  const VolumeGrid one = generate_volume(GeneratedVolume::marschner_lobb, 1, 1, kLimits);
  ASSERT_EQ(one.values.size(), 1u);
  EXPECT_EQ(one.values[0], uint16_t(std::lround(0.6 * 65535)));
}

TEST(VolumeData, CombustionIsSeededAndDeterministic) {
  const VolumeGrid a = generate_volume(GeneratedVolume::combustion, 24, 7, kLimits);
  const VolumeGrid b = generate_volume(GeneratedVolume::combustion, 24, 7, kLimits);
  const VolumeGrid c = generate_volume(GeneratedVolume::combustion, 24, 8, kLimits);
  EXPECT_EQ(a.values, b.values);
  EXPECT_NE(a.values, c.values);
  uint16_t largest = 0;
  for (uint16_t value : a.values) largest = std::max(largest, value);
  EXPECT_GT(largest, 20000) << "the plume is there";
  EXPECT_EQ(a.values.front(), 0) << "a corner is outside the plume";
}

TEST(VolumeData, SizesAreCheckedBeforeAnythingIsAllocated) {
  EXPECT_NE(error_of([] {
              generate_volume(GeneratedVolume::shepp_logan, 0, 1, kLimits);
            }).find("expected 1 to 256 voxels a side"),
            std::string::npos);
  EXPECT_NE(error_of([] { generate_volume(GeneratedVolume::shepp_logan, 300, 1, kLimits); }).find("300x300x300"),
            std::string::npos);
  const VolumeLimits tight{256, 1000};
  EXPECT_NE(error_of([] {
              check_volume_size({10, 10, 10}, VolumeLimits{256, 1000}, "v");
            }).find("2000 bytes"),
            std::string::npos);
  (void)tight;
}

TEST(VolumeData, ReadsDatFilesAndRefusesBadOnes) {
  testing::TempDir dir;
  const std::vector<uint16_t> values{0, 4095, 100, 200, 300, 400, 500, 600};
  const std::string path = dir.write("v.dat", dat_bytes(2, 2, 2, values));
  const VolumeGrid grid = load_volume_file(path, std::nullopt, kLimits);
  EXPECT_EQ(grid.size_voxels, (std::array<int, 3>{2, 2, 2}));
  EXPECT_EQ(grid.at(1, 0, 0), 65535) << "12-bit data: 4095 is the top of the axis";
  EXPECT_EQ(grid.at(0, 1, 0), uint16_t(std::lround(100.0 / 4095 * 65535)));
  // A given range wins.
  EXPECT_EQ(load_volume_file(path, ValueRange{0, 8190}, kLimits).at(1, 0, 0), uint16_t(std::lround(0.5 * 65535)));

  const std::string truncated = dir.write("short.dat", dat_bytes(2, 2, 2, values).substr(0, 10));
  EXPECT_NE(
      error_of([&] { load_volume_file(truncated, std::nullopt, kLimits); }).find("expected 6 + 2 x 2x2x2 = 22 bytes"),
      std::string::npos);
  const std::string huge = dir.write("huge.dat", dat_bytes(4000, 4000, 4000, {}));
  const std::string message = error_of([&] { load_volume_file(huge, std::nullopt, kLimits); });
  EXPECT_NE(message.find("huge.dat: 4000x4000x4000 voxels"), std::string::npos) << message;
  EXPECT_NE(error_of([&] {
              load_volume_file(dir.write("v.raw", "x"), std::nullopt, kLimits);
            }).find("expected a volume file"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              load_volume_file(path, ValueRange{1, 1}, kLimits);
            }).find("expected finite low < high"),
            std::string::npos);
}

std::string nrrd_file(const std::string& header, const std::string& data) {
  return "NRRD0004\n" + header + "\n" + data;
}

TEST(VolumeData, ReadsNrrdThroughTeem) {
  testing::TempDir dir;
  // Floats with a NaN and infinities: the finite range maps to 0..1, NaN and -inf to 0, +inf to 1.
  std::vector<float> values{1.0f,
                            2.0f,
                            3.0f,
                            std::numeric_limits<float>::quiet_NaN(),
                            std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity()};
  std::string data(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float));
  const std::string path = dir.write("f.nrrd", nrrd_file("type: float\ndimension: 3\nsizes: 3 2 1\nspacings: 1 2 3\n"
                                                         "endian: little\nencoding: raw\n",
                                                         data));
  const VolumeGrid grid = load_volume_file(path, std::nullopt, kLimits);
  EXPECT_EQ(grid.size_voxels, (std::array<int, 3>{3, 2, 1}));
  EXPECT_EQ(grid.spacing, (std::array<double, 3>{1, 2, 3}));
  EXPECT_EQ(grid.values, (std::vector<uint16_t>{0, 32768, 65535, 0, 65535, 0}));

  const std::string flat =
      dir.write("flat.nrrd", nrrd_file("type: uchar\ndimension: 2\nsizes: 2 2\nencoding: raw\n", "abcd"));
  EXPECT_NE(
      error_of([&] { load_volume_file(flat, std::nullopt, kLimits); }).find("2 axes: expected a 3-D scalar volume"),
      std::string::npos);
  const std::string big =
      dir.write("big.nrrd", nrrd_file("type: uchar\ndimension: 3\nsizes: 1000 1000 1000\nencoding: raw\n", "a"));
  EXPECT_NE(error_of([&] { load_volume_file(big, std::nullopt, kLimits); }).find("1000x1000x1000 voxels"),
            std::string::npos);
  const std::string thin =
      dir.write("thin.nrrd", nrrd_file("type: uchar\ndimension: 3\nsizes: 2 1 1\nspacings: 1e-30 1 1\n"
                                       "encoding: raw\n",
                                       "ab"));
  EXPECT_NE(
      error_of([&] { load_volume_file(thin, std::nullopt, kLimits); }).find("expected the largest at most 1000 times"),
      std::string::npos)
      << "a voxel 1e30 times thinner than wide would make the step vanish";
  EXPECT_NE(error_of([&] {
              load_volume_file(path, ValueRange{-1e308, 1e308}, kLimits);
            }).find("expected a finite span"),
            std::string::npos);
  const std::string garbage = dir.write("bad.nrrd", "not a nrrd at all");
  const std::string message = error_of([&] { load_volume_file(garbage, std::nullopt, kLimits); });
  EXPECT_NE(message.find("bad.nrrd: "), std::string::npos);
  EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
}

// A header with its data in other files (teem's three forms: one file, a %d template, a LIST) reads
// the same voxels as the attached file, through the descriptors fovlab opened (teem opens no path).
// A data file larger than the header's sizes and encoding allow is refused before it is read.
TEST(VolumeData, ReadsNrrdDataFilesInEveryFormAndRefusesOversizedOnes) {
  testing::TempDir dir;
  std::string voxels(2 * 3 * 4, '\0');
  for (size_t i = 0; i < voxels.size(); ++i) voxels[i] = char(10 * i);
  const std::string fields = "type: uchar\ndimension: 3\nsizes: 2 3 4\nspacings: 1 1 2\nencoding: raw\n";
  const VolumeGrid attached = load_volume_file(dir.write("a.nrrd", nrrd_file(fields, voxels)), std::nullopt, kLimits);
  ASSERT_EQ(attached.values.size(), 24u);

  dir.write("all.raw", voxels);
  const std::string single = dir.write("single.nhdr", "NRRD0004\n" + fields + "data file: all.raw\n");
  EXPECT_EQ(load_volume_file(single, std::nullopt, kLimits).values, attached.values);
  EXPECT_EQ(load_volume_file(single, std::nullopt, kLimits).spacing, attached.spacing);

  for (int slice = 0; slice < 4; ++slice)
    dir.write("slice0" + std::to_string(slice + 1) + ".raw", voxels.substr(size_t(6 * slice), 6));
  const std::string pattern = dir.write("pattern.nhdr", "NRRD0004\ndata file: slice%02d.raw 1 4 1 2\n" + fields);
  EXPECT_EQ(load_volume_file(pattern, std::nullopt, kLimits).values, attached.values)
      << "the field before the sizes, too";
  const std::string list = dir.write("list.nhdr", "NRRD0004\n" + fields +
                                                      "data file: LIST 2\nslice01.raw\nslice02.raw\n"
                                                      "slice03.raw\nslice04.raw\n");
  EXPECT_EQ(load_volume_file(list, std::nullopt, kLimits).values, attached.values);

  const std::string printf_like =
      dir.write("printf.nhdr", "NRRD0004\n" + fields + "data file: slice%s%d.raw 1 4 1 2\n");
  EXPECT_NE(error_of([&] { load_volume_file(printf_like, std::nullopt, kLimits); }).find("expected one %d conversion"),
            std::string::npos)
      << "a template is formatted by fovlab, never handed to a printf as the file gives it";

  dir.write("big.raw", voxels + std::string(size_t(2) << 20, 'x'));
  const std::string big = dir.write("big.nhdr", "NRRD0004\n" + fields + "data file: big.raw\n");
  const std::string message = error_of([&] { load_volume_file(big, std::nullopt, kLimits); });
  EXPECT_NE(
      message.find("big.raw: 2097176 bytes of data: expected at most 1048600 for 24 values of unsigned char (raw)"),
      std::string::npos)
      << message;
}

const char* kScene = R"(
[volume]
generator = "shepp-logan"
size_voxels = 16

[camera]
distance = 3.0
orbit_deg_per_s = 45.0

[[transfer_point]]
value = 0.0
colour = [0.0, 0.0, 0.0]
opacity = 0.0

[[transfer_point]]
value = 0.5
colour = [1.0, 0.5, 0.0]
opacity = 0.5
)";

TEST(VolumeScenes, ReadsAFileAndItsTransferTable) {
  testing::TempDir dir;
  const VolumeScene scene = load_volume_scene(dir.write("s.toml", kScene));
  EXPECT_EQ(scene.name, "s");
  ASSERT_TRUE(scene.generator.has_value());
  EXPECT_EQ(*scene.generator, GeneratedVolume::shepp_logan);
  EXPECT_EQ(scene.size_voxels, 16);
  EXPECT_EQ(scene.camera.distance, 3.0);
  EXPECT_EQ(scene.camera.orbit_deg_per_s, 45.0);
  const auto table = transfer_table(scene.transfer_function, 5);  // entries at 0, 0.25, 0.5, 0.75, 1
  EXPECT_FLOAT_EQ(table[1][0], 0.5f);
  EXPECT_FLOAT_EQ(table[1][3], 0.25f);
  EXPECT_FLOAT_EQ(table[2][1], 0.5f);
  EXPECT_FLOAT_EQ(table[4][3], 0.5f) << "constant beyond the last point";
  EXPECT_EQ(load_scene_volume(scene, kLimits).values.size(), 16u * 16u * 16u);
}

TEST(VolumeScenes, BuiltInScenesLoad) {
  const std::vector<std::string> names = builtin_volume_names();
  EXPECT_EQ(names, (std::vector<std::string>{"combustion", "marschner-lobb", "shepp-logan"}));
  for (const std::string& name : names) EXPECT_GE(load_volume_scene(name).transfer_function.size(), 2u) << name;
  EXPECT_NE(
      error_of([] { load_volume_scene("nebula"); }).find("expected one of combustion, marschner-lobb, shepp-logan"),
      std::string::npos);
}

TEST(VolumeScenes, BadScenesGetOneLineNamingTheField) {
  testing::TempDir dir;
  const auto message = [&](const std::string& text) {
    return error_of([&] { load_volume_scene(dir.write("bad.toml", text)); });
  };
  const std::string points =
      "[[transfer_point]]\nvalue = 0.0\ncolour = [0, 0, 0]\nopacity = 0\n"
      "[[transfer_point]]\nvalue = 1.0\ncolour = [1, 1, 1]\nopacity = 1\n";
  EXPECT_NE(message("[volume]\ngenerator = \"nebula\"\n" + points).find("volume.generator: expected one of"),
            std::string::npos);
  EXPECT_NE(
      message("[volume]\ngenerator = \"combustion\"\nfile = \"x.nrrd\"\n" + points).find("expected exactly one of"),
      std::string::npos);
  EXPECT_NE(message("[volume]\ngenerator = \"combustion\"\nsize_voxels = 0\n" + points)
                .find("size_voxels: expected 1 to 2048"),
            std::string::npos);
  EXPECT_NE(
      message(
          "[volume]\ngenerator = \"combustion\"\n[[transfer_point]]\nvalue = 0.0\ncolour = [0, 0, 0]\nopacity = 0\n")
          .find("expected 2 to 4096 [[transfer_point]] tables"),
      std::string::npos);
  EXPECT_NE(
      message("[volume]\ngenerator = \"combustion\"\n[[transfer_point]]\nvalue = 0.5\ncolour = [0, 0, 0]\nopacity = 0\n"
              "[[transfer_point]]\nvalue = 0.2\ncolour = [0, 0, 0]\nopacity = 0\n")
          .find("values that increase"),
      std::string::npos);
  EXPECT_NE(
      message("[volume]\ngenerator = \"combustion\"\n[[transfer_point]]\nvalue = 0.0\ncolour = [0, 2, 0]\nopacity = 0\n"
              "[[transfer_point]]\nvalue = 1.0\ncolour = [0, 0, 0]\nopacity = 0\n")
          .find("colour: expected [red, green, blue]"),
      std::string::npos);
  EXPECT_NE(message("[volume]\ngenerator = \"combustion\"\ncolor = 1\n" + points).find("color"), std::string::npos)
      << "a misspelt key is refused";
  EXPECT_NE(message("[volume\n").find("(not valid TOML)"), std::string::npos);
  EXPECT_NE(message("[volume]\ngenerator = \"combustion\"\n[[transfer_point]]\nvalue = 0.0\ncolour = [0, 0, 0]\n"
                    "[[transfer_point]]\nvalue = 1.0\ncolour = [1, 1, 1]\nopacity = 1\n")
                .find("transfer_point[1].opacity"),
            std::string::npos)
      << "a forgotten opacity is refused, not read as 0";
  const std::string missing = message("[volume]\nfile = \"nowhere.nrrd\"\n" + points);
  EXPECT_EQ(missing, "") << "the file is read when the volume is loaded, not when the scene is";
}

}  // namespace
}  // namespace fovlab
