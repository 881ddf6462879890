// The emulated foveated path tracer's zones and blend (issue 6, seed 001 section 3.2): the weights,
// the nearest-neighbour decimation, and the GPU's zone buffers and blend against the double CPU
// reference.
#include <gtest/gtest.h>

#include <cmath>

#include "core/input_error.h"
#include "core/prng.h"
#include "renderer/upsampling/upsample_filter.h"
#include "renderer/zone_blend/zone_blender.h"
#include "renderer/zone_blend/zone_layout.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

using test::VulkanTest;

Image noisy_frame(int width, int height, uint64_t seed) {
  Pcg32 random(seed);
  Image image(width, height, 3);
  for (float& value : image.pixels) value = static_cast<float>(random.uniform()) * 3.0f;
  return image;
}

// A small display whose 64x48 pixels span about 66 x 52 degrees at 250 mm, so both zone boundaries
// of a 10-degree fovea (middle 62.5) fall on the frame.
DisplayGeometry small_display() { return display_from_size(64, 48, 320.0, 240.0, 250.0); }

double largest_difference(const Image& a, const Image& b) {
  double largest = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) largest = std::max(largest, double(std::fabs(a.pixels[i] - b.pixels[i])));
  return largest;
}

TEST(ZoneLayout, WeightsFollowTheZonesAndBands) {
  const ZoneBounds bounds{10.0, 62.5, 2.0};  // boundaries at 5 and 31.25 degrees of eccentricity
  const auto expect = [&](double eccentricity, double foveal, double middle, double outer) {
    const ZoneWeights w = zone_weights(bounds, eccentricity);
    EXPECT_NEAR(w.foveal, foveal, 1e-12) << eccentricity;
    EXPECT_NEAR(w.middle, middle, 1e-12) << eccentricity;
    EXPECT_NEAR(w.outer, outer, 1e-12) << eccentricity;
  };
  expect(0.0, 1, 0, 0);
  expect(3.99, 1, 0, 0);
  expect(4.5, 0.75, 0.25, 0);   // a quarter into the 4..6 band
  expect(5.0, 0.5, 0.5, 0);
  expect(6.0, 0, 1, 0);
  expect(20.0, 0, 1, 0);
  expect(31.25, 0, 0.5, 0.5);
  expect(32.5, 0, 0, 1);
  expect(89.0, 0, 0, 1);
  expect(std::nan(""), 1, 0, 0);  // no usable eccentricity: shown as the fovea
  // Hard edges: a pixel exactly on a boundary is inner; no middle zone when middle <= foveal.
  EXPECT_EQ(zone_weights({10.0, 62.5, 0.0}, 5.0).foveal, 1.0);
  EXPECT_EQ(zone_weights({10.0, 62.5, 0.0}, 5.0 + 1e-9).middle, 1.0);
  EXPECT_EQ(zone_weights({30.0, 20.0, 0.0}, 16.0).outer, 1.0);
  EXPECT_EQ(default_middle_deg(5.0), 57.5);
  EXPECT_EQ(default_middle_deg(30.0), 82.5);
  EXPECT_THROW(check_zone_bounds({-1.0, 60.0, 1.0}), InputError);
  EXPECT_THROW(check_zone_bounds({10.0, std::nan(""), 1.0}), InputError);
}

TEST(ZoneLayout, DecimationKeepsThePixelUnderEachCellCentre) {
  Image image(9, 6, 1);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 9; ++x) image.at(x, y, 0) = float(100 * y + x);
  const Image half = decimate_nearest(image, 2);
  ASSERT_EQ(half.width, 5);
  ASSERT_EQ(half.height, 3);
  EXPECT_EQ(half.at(0, 0, 0), 101.0f);  // pixel (1, 1)
  EXPECT_EQ(half.at(3, 2, 0), 507.0f);  // pixel (7, 5)
  EXPECT_EQ(half.at(4, 2, 0), 508.0f);  // clamped to the last column
  const Image quarter = decimate_nearest(image, 4);
  ASSERT_EQ(quarter.width, 3);
  ASSERT_EQ(quarter.height, 2);
  EXPECT_EQ(quarter.at(1, 1, 0), 506.0f);  // pixel (6, 5): row 6 is past the edge
}

TEST_F(VulkanTest, ZoneBuffersAreTheDecimatedFrameUpsampled) {
  const Image frame = noisy_frame(64, 48, 7);
  ZoneBlender blender(context());
  blender.set_frame(frame);
  EXPECT_EQ(largest_difference(blender.zone_buffer(Zone::foveal), frame), 0.0);
  const Image middle = upsample_reference(decimate_nearest(frame, 2), 2, UpsampleFilter::lanczos3);
  const Image outer = upsample_reference(decimate_nearest(frame, 4), 4, UpsampleFilter::lanczos3);
  EXPECT_LT(largest_difference(blender.zone_buffer(Zone::middle), middle), 1e-4 * 3.0);
  EXPECT_LT(largest_difference(blender.zone_buffer(Zone::outer), outer), 1e-4 * 3.0);
}

// The GPU blend against the double reference for gazes at the centre, a corner and off the screen,
// with bands (weights continuous: 1e-4 of the values' range everywhere) and with hard edges (where pixels
// within 1e-3 degrees of a boundary may fall either side in float).
TEST_F(VulkanTest, BlendMatchesTheReference) {
  const Image frame = noisy_frame(64, 48, 11);
  const DisplayGeometry display = small_display();
  ZoneBlender blender(context());
  blender.set_frame(frame);
  const Image middle = blender.zone_buffer(Zone::middle);
  const Image outer = blender.zone_buffer(Zone::outer);
  const double gazes[][2] = {{32.0, 24.0}, {3.5, 44.0}, {-40.0, 10.0}};
  for (const auto& gaze : gazes)
    for (const ZoneBounds bounds : {ZoneBounds{10.0, 62.5, 2.0}, ZoneBounds{20.0, 40.0, 0.0}, ZoneBounds{10.0, 5.0, 1.0}}) {
      const Image gpu = blender.blend(display, gaze[0], gaze[1], bounds).image;
      const Image reference = blend_zones_reference(display, gaze[0], gaze[1], bounds, frame, middle, outer);
      int compared = 0;
      for (int y = 0; y < frame.height; ++y)
        for (int x = 0; x < frame.width; ++x) {
          const double eccentricity = eccentricity_deg(display, gaze[0], gaze[1], x + 0.5, y + 0.5);
          const bool on_edge = bounds.band_deg == 0.0 && (std::fabs(eccentricity - 0.5 * bounds.foveal_deg) < 1e-3 ||
                                                          std::fabs(eccentricity - 0.5 * bounds.middle_deg) < 1e-3);
          if (on_edge) continue;
          ++compared;
          for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(gpu.at(x, y, c), reference.at(x, y, c), 1e-4 * 3.0)  // 1e-4 of the values' range
                << "pixel " << x << "," << y << " gaze " << gaze[0] << "," << gaze[1] << " foveal " << bounds.foveal_deg;
        }
      EXPECT_GT(compared, frame.width * frame.height - 8);
    }
}

// The zones are really there: with three distinct constant-ish buffers (a periphery frame of other
// values), the fovea shows the frame, far pixels the periphery's upsampled buffers.
TEST_F(VulkanTest, PeripheryFrameFeedsTheMiddleAndOuterZones) {
  Image frame(64, 48, 3), periphery(64, 48, 3);
  std::fill(frame.pixels.begin(), frame.pixels.end(), 1.0f);
  std::fill(periphery.pixels.begin(), periphery.pixels.end(), 0.25f);
  ZoneBlender blender(context());
  blender.set_frame(frame, &periphery);
  const DisplayGeometry display = small_display();
  const Image blended = blender.blend(display, 32.0, 24.0, {10.0, 40.0, 0.5}).image;
  EXPECT_NEAR(blended.at(32, 24, 0), 1.0f, 1e-6);   // the gaze point
  EXPECT_NEAR(blended.at(0, 0, 1), 0.25f, 1e-5);    // a corner, about 34 degrees out: outer zone
  EXPECT_NEAR(blended.at(32, 8, 2), 0.25f, 1e-5);   // about 17 degrees out: middle zone
  EXPECT_EQ(blender.measure_cost(display, 32.0, 24.0, {10.0, 40.0, 0.5}, 2).size(), 2u);
}

TEST_F(VulkanTest, ZoneBlenderRefusesFramesItCannotZone) {
  ZoneBlender blender(context());
  EXPECT_THROW(blender.set_frame(noisy_frame(30, 48, 1)), InputError);  // 30 is not a multiple of 4
  Image periphery = noisy_frame(32, 48, 2);
  EXPECT_THROW(blender.set_frame(noisy_frame(64, 48, 1), &periphery), InputError);
  blender.set_frame(noisy_frame(64, 48, 1));
  EXPECT_THROW(blender.blend(display_from_size(32, 24, 320.0, 240.0, 250.0), 1.0, 1.0, {}), InputError);
  EXPECT_THROW(blender.blend(small_display(), std::nan(""), 1.0, {}), InputError);
}

}  // namespace
}  // namespace fovlab
