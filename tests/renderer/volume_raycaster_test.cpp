// Bruder et al. 2019's volume raycaster (renderer/volume/volume_raycaster.h) on small frames: finite pixels
// in the numerical stress cases the issue lists (one voxel, all zero, all one, a fully opaque or
// fully transparent transfer function, the camera inside the volume, very near and 1e5 sides away,
// gaze off the screen); empty-space skipping changes nothing it skips; the foveated frame of a
// uniform volume is uniform; the temporal smoothing follows its rules; tracing only the sites the
// reconstruction reads draws the frame that the one global reach draws.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "foveation/voronoi_reconstruction.h"
#include "renderer/volume/volume_raycaster.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

using test::VulkanTest;

constexpr int kSide = 32;

VolumeScene scene_with(std::vector<TransferPoint> points, double distance = 2.0) {
  VolumeScene scene;
  scene.name = "test";
  scene.transfer_function = std::move(points);
  scene.camera.distance = distance;
  return scene;
}

// Opacity rising with the value; a warm colour.
VolumeScene ramp_scene(double distance = 2.0) {
  return scene_with({{0.0, {0.0, 0.0, 0.0}, 0.0}, {0.3, {0.2, 0.1, 0.0}, 0.0}, {1.0, {1.0, 0.7, 0.3}, 0.6}}, distance);
}

VolumeGrid uniform_grid(int side, uint16_t value) {
  VolumeGrid grid;
  grid.size_voxels = {side, side, side};
  grid.values.assign(grid.voxel_count(), value);
  return grid;
}

VolumeRenderSettings frame_settings() {
  VolumeRenderSettings settings;
  settings.width_px = kSide;
  settings.height_px = kSide;
  return settings;
}

bool all_finite(const Image& image) {
  for (float value : image.pixels)
    if (!std::isfinite(value)) return false;
  return true;
}

double mean(const Image& image) {
  double sum = 0.0;
  for (float value : image.pixels) sum += value;
  return sum / double(image.pixels.size());
}

const VolumeLimits kLimits{256, uint64_t(1) << 28};

class VolumeRaycasterTest : public VulkanTest {};

TEST_F(VolumeRaycasterTest, StressCasesGiveFinitePixels) {
  const VolumeGrid phantom = generate_volume(GeneratedVolume::shepp_logan, 24, 1, kLimits);
  struct Case {
    const char* name;
    VolumeScene scene;
    VolumeGrid grid;
    bool drawn;  // something other than the black background shows
  };
  const std::vector<Case> cases = {
      {"one voxel", ramp_scene(), uniform_grid(1, 65535), true},
      {"all zero", ramp_scene(), uniform_grid(9, 0), false},
      {"all one", ramp_scene(), uniform_grid(9, 65535), true},
      {"opaque", scene_with({{0.0, {1, 1, 1}, 1.0}, {1.0, {1, 1, 1}, 1.0}}), phantom, true},
      {"transparent", scene_with({{0.0, {1, 1, 1}, 0.0}, {1.0, {1, 1, 1}, 0.0}}), phantom, false},
      {"inside", ramp_scene(0.05), phantom, true},
      {"near", ramp_scene(0.5 + 1e-3), phantom, true},
      {"far", ramp_scene(1e5), phantom, false},
  };
  for (const Case& c : cases) {
    VolumeRaycaster raycaster(context(), c.scene, c.grid);
    const VolumeFrameResult result = raycaster.render_full(frame_settings());
    EXPECT_TRUE(all_finite(result.colour_linear)) << c.name;
    if (c.drawn) {
      EXPECT_GT(mean(result.colour_linear), 0.01) << c.name;
    } else {
      EXPECT_EQ(mean(result.colour_linear), 0.0) << c.name << ": the black background everywhere";
    }
  }
}

TEST_F(VolumeRaycasterTest, VisibleBricksAreConservative) {
  // A volume that is 0 but for one voxel: only the bricks whose samples can read it are visible.
  VolumeGrid grid = uniform_grid(24, 0);
  grid.values[size_t((12 * 24 + 12) * 24 + 8)] = 65535;  // x 8 (the first of brick 1), y 12, z 12
  const auto table = transfer_table(ramp_scene().transfer_function, kTransferTableEntries);
  const std::vector<uint32_t> visible = visible_bricks(grid, table);
  ASSERT_EQ(visible.size(), 27u);
  std::vector<uint32_t> expected(27, 0);
  expected[(1 * 3 + 1) * 3 + 0] = 1;  // brick x 0 reads one voxel past its face: voxel 8
  expected[(1 * 3 + 1) * 3 + 1] = 1;
  EXPECT_EQ(visible, expected);
}

TEST_F(VolumeRaycasterTest, EmptySpaceSkippingDrawsTheSameFrame) {
  // The same volume twice: once with the ramp's transparent low end (empty bricks skipped), once
  // with an opacity of 1e-30 there (no brick skipped, nothing visibly added).
  const VolumeGrid phantom = generate_volume(GeneratedVolume::shepp_logan, 40, 1, kLimits);
  const VolumeScene scene = ramp_scene();
  VolumeRaycaster skipping(context(), scene, phantom);
  VolumeScene floor_scene = scene;
  floor_scene.transfer_function.front().opacity = 1e-30;
  floor_scene.transfer_function[1].opacity = 1e-30;
  VolumeRaycaster no_skipping(context(), floor_scene, phantom);
  const Image a = skipping.render_full(frame_settings()).colour_linear;
  const Image b = no_skipping.render_full(frame_settings()).colour_linear;
  double largest = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) largest = std::max(largest, double(std::abs(a.pixels[i] - b.pixels[i])));
  EXPECT_LT(largest, 1e-4) << "skipped bricks held nothing visible, and the steps stay on the same grid";
}

VoronoiReconstruction small_mask() {
  VoronoiMaskSettings settings;
  settings.screen_width_px = kSide;
  settings.screen_height_px = kSide;
  settings.density_sigma_px = 4.0;
  settings.initial_sites = 600;
  return make_voronoi_reconstruction(settings);
}

TEST_F(VolumeRaycasterTest, FoveatedFrameOfAUniformVolumeIsUniformAndTracesFewRays) {
  // A camera inside an opaque uniform volume: every ray gives the same colour (flat field: no
  // gradient, so no shading difference), so every rebuilt pixel is that colour.
  const VolumeScene scene = scene_with({{0.0, {0.5, 0.25, 1.0}, 1.0}, {1.0, {0.5, 0.25, 1.0}, 1.0}}, 0.01);
  VolumeRaycaster raycaster(context(), scene, uniform_grid(8, 30000));
  const VoronoiReconstruction mask = small_mask();
  raycaster.set_reconstruction(mask);
  const Image full = raycaster.render_full(frame_settings()).colour_linear;
  for (double gaze : {16.0, 0.0, -50.0, std::numeric_limits<double>::quiet_NaN()}) {
    const VolumeFrameResult result = raycaster.render_foveated(frame_settings(), gaze, gaze, false);
    ASSERT_TRUE(all_finite(result.colour_linear));
    // The sites' colours travel as half floats: equal within their rounding.
    for (size_t i = 0; i < full.pixels.size(); ++i)
      ASSERT_NEAR(result.colour_linear.pixels[i], full.pixels[i], 1e-3) << gaze;
    EXPECT_GT(result.rays, 0u);
    EXPECT_LT(result.rays, uint64_t(kSide * kSide));
  }
  EXPECT_EQ(raycaster.mask_offset(kSide, kSide, -50.0, 1e9), (std::pair<int, int>{kSide, 0}))
      << "the gaze clamped to the screen";
}

TEST_F(VolumeRaycasterTest, TracingTheReadSitesOnlyDrawsTheSameFrameWithFewerRays) {
  // The same frames as the one global reach gives, bit for bit: every site a screen pixel reads is
  // traced. The site colours left from another view (another scene time and gaze) would show where
  // a read site was skipped, so the foveated raycaster renders that view first.
  const VolumeGrid phantom = generate_volume(GeneratedVolume::shepp_logan, 24, 1, kLimits);
  VolumeScene scene = ramp_scene();
  scene.camera.orbit_deg_per_s = 40.0;
  const VoronoiReconstruction mask = small_mask();
  VolumeRaycaster read_only(context(), scene, phantom), global(context(), scene, phantom);
  read_only.set_reconstruction(mask);
  global.set_reconstruction(mask);
  VolumeRenderSettings other_view = frame_settings();
  other_view.time_s = 2.0;
  other_view.trace_read_sites_only = false;
  read_only.render_foveated(other_view, 31.0, 0.0, false);
  VolumeRenderSettings per_site = frame_settings(), reach = frame_settings();
  reach.trace_read_sites_only = false;
  uint64_t fewer = 0;
  for (const auto& [gx, gy] : std::vector<std::pair<double, double>>{{16, 16}, {0, 0}, {32, 5}, {-50, 40}, {7, 25}}) {
    const VolumeFrameResult a = read_only.render_foveated(per_site, gx, gy, false);
    const VolumeFrameResult b = global.render_foveated(reach, gx, gy, false);
    ASSERT_EQ(a.colour_linear.pixels, b.colour_linear.pixels) << gx << "," << gy;
    EXPECT_LE(a.rays, b.rays) << gx << "," << gy;
    EXPECT_GE(a.rays, a.sites_on_screen) << gx << "," << gy;
    EXPECT_EQ(a.sites_on_screen, b.sites_on_screen);
    EXPECT_GT(a.sites_on_screen, 0u);
    fewer += a.rays < b.rays ? 1 : 0;
  }
  EXPECT_GT(fewer, 0u) << "the global reach traces sites no screen pixel reads";
}

TEST(VolumeSiteReaders, BoxHoldsTheReadingPixelsAndTheSitesOwn) {
  // A 4x2 mask with three sites: site 0 read by pixels (0, 0) and (1, 1), site 1 by (3, 0) only
  // after a weight that rounded to 0 ends the list, site 2 by none (its own pixel only).
  VoronoiMask mask;
  mask.width_px = 4;
  mask.height_px = 2;
  mask.sites = {{0.5f, 0.5f}, {2.25f, 1.75f}, {3.5f, 0.5f}};
  std::vector<uint32_t> packed(size_t(4 * 2 * kVoronoiNeighbours), 0u);
  const auto put = [&](int x, int y, int k, uint32_t site, uint32_t weight) {
    packed[(size_t(y) * 4 + size_t(x)) * kVoronoiNeighbours + size_t(k)] = site | (weight << 20);
  };
  put(0, 0, 0, 0, 4095);
  put(1, 1, 0, 0, 3000);
  put(1, 1, 1, 1, 0);  // unused: ends the list, so site 2 after it is not read
  put(1, 1, 2, 2, 1000);
  put(3, 0, 0, 1, 4095);
  const std::vector<std::array<float, 4>> boxes = site_reader_boxes(packed, mask);
  ASSERT_EQ(boxes.size(), 3u);
  EXPECT_EQ(boxes[0], (std::array<float, 4>{0, 0, 2, 2}));
  EXPECT_EQ(boxes[1], (std::array<float, 4>{2, 0, 4, 2})) << "its own pixel (2, 1) and its reader (3, 0)";
  EXPECT_EQ(boxes[2], (std::array<float, 4>{3, 0, 4, 1})) << "its own pixel only";
  EXPECT_THROW(site_reader_boxes(std::vector<uint32_t>(8, 0u), mask), std::invalid_argument);
}

TEST(VolumeReconstructionPacking, IndexAndWeightShareAWord) {
  VoronoiReconstruction r;
  r.neighbour_sites = {7, 1048575, 3, 0, 0, 0, 0, 0};
  r.neighbour_weights = {40000, 25530, 5, 0, 0, 0, 0, 0};  // the third rounds to 0 on 12 bits
  const std::vector<uint32_t> packed = pack_neighbours(r);
  ASSERT_EQ(packed.size(), 8u);
  EXPECT_EQ(packed[0] & 0xFFFFFu, 7u);
  EXPECT_EQ(packed[0] >> 20, (40000u * 4095u + 32767u) / 65535u);
  EXPECT_EQ(packed[1] & 0xFFFFFu, 1048575u);
  EXPECT_EQ(packed[2], 0u) << "a weight that rounds to 0 is an unused entry";
  EXPECT_NEAR(double((packed[0] >> 20) + (packed[1] >> 20)), 4095.0, 2.0) << "each weight within half a step";
}

TEST_F(VolumeRaycasterTest, TemporalSmoothingKeepsFramesWhileTheViewStaysAndTheGazeMoves) {
  const VolumeGrid phantom = generate_volume(GeneratedVolume::shepp_logan, 24, 1, kLimits);
  VolumeScene scene = ramp_scene();
  scene.camera.orbit_deg_per_s = 30.0;
  VolumeRaycaster raycaster(context(), scene, phantom);
  raycaster.set_reconstruction(small_mask());
  const VolumeRenderSettings settings = frame_settings();
  const Image at_a = raycaster.render_foveated(settings, 8, 8, false).colour_linear;
  const Image at_b = raycaster.render_foveated(settings, 24, 20, false).colour_linear;
  raycaster.reset_history();
  const Image first = raycaster.render_foveated(settings, 8, 8, true).colour_linear;  // stored
  EXPECT_EQ(first.pixels, at_a.pixels) << "nothing stored before: the frame itself";
  const Image same_gaze = raycaster.render_foveated(settings, 8, 8, true).colour_linear;  // not stored again
  for (size_t i = 0; i < at_a.pixels.size(); ++i) ASSERT_NEAR(same_gaze.pixels[i], at_a.pixels[i], 1e-6);
  const Image moved = raycaster.render_foveated(settings, 24, 20, true).colour_linear;  // mean with the stored one
  for (size_t i = 0; i < at_a.pixels.size(); ++i)
    ASSERT_NEAR(moved.pixels[i], 0.5f * (at_a.pixels[i] + at_b.pixels[i]), 1e-5);
  // Another view (the camera orbits with time): the history is cleared.
  VolumeRenderSettings later = settings;
  later.time_s = 1.0;
  const Image plain_later = raycaster.render_foveated(later, 24, 20, false).colour_linear;
  const Image smoothed_later = raycaster.render_foveated(later, 24, 20, true).colour_linear;
  EXPECT_EQ(smoothed_later.pixels, plain_later.pixels);
}

TEST_F(VolumeRaycasterTest, CorrectedOpacityMakesTheFoveatedPeripheryDenser) {
  // With the longer peripheral step, uncorrected opacity lets more background through.
  const VolumeGrid phantom = generate_volume(GeneratedVolume::combustion, 24, 1, kLimits);
  const VolumeScene scene = ramp_scene();
  VolumeRaycaster raycaster(context(), scene, phantom);
  raycaster.set_reconstruction(small_mask());
  VolumeRenderSettings corrected = frame_settings(), uncorrected = frame_settings();
  uncorrected.correct_opacity = false;
  const double with = mean(raycaster.render_foveated(corrected, 0, 0, false).colour_linear);
  const double without = mean(raycaster.render_foveated(uncorrected, 0, 0, false).colour_linear);
  EXPECT_GT(with, without);
}

}  // namespace
}  // namespace fovlab
