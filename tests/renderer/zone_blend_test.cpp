// The emulated foveated path tracer's zones and blend (issue 6, Polychronakis et al. 2021 section 3.2): the weights,
// the nearest-neighbour decimation, and the GPU's zone buffers and blend against the double CPU
// reference.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "bench/blend_cost.h"
#include "core/colour.h"
#include "core/input_error.h"
#include "core/prng.h"
#include "renderer/upsampling/upsample_filter.h"
#include "renderer/zone_blend/zone_blender.h"
#include "foveation/zone_layout.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

using test::VulkanTest;

Image noisy_frame(int width, int height, uint64_t seed, float largest = 3.0f) {
  Pcg32 random(seed);
  Image image(width, height, 3);
  for (float& value : image.pixels) value = static_cast<float>(random.uniform()) * largest;
  return image;
}

// A small display whose 64x48 pixels span about 66 x 52 degrees at 250 mm, so both zone boundaries
// of a 10-degree fovea (middle 62.5) fall on the frame.
DisplayGeometry small_display() { return display_from_size(64, 48, 320.0, 240.0, 250.0); }

double largest_difference(const Image& a, const Image& b) {
  double largest = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i)
    largest = std::max(largest, double(std::fabs(a.pixels[i] - b.pixels[i])));
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
  expect(4.5, 0.75, 0.25, 0);  // a quarter into the 4..6 band
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

// A crop of the top-left width x height pixels.
Image crop(const Image& image, int width, int height) {
  Image out(width, height, image.channels);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < image.channels; ++c) out.at(x, y, c) = image.at(x, y, c);
  return out;
}

// Issue 18: a 1366x768 panel or a 480x270 frame could not run fpt (sides had to be multiples of
// 4). The middle and outer zones are now ceil(side / 2) and ceil(side / 4), upsampled and cropped
// back: every kept pixel is the uncropped reference's, the right and bottom edges included, and a
// session's display frame of such a size blends as at any other.
TEST_F(VulkanTest, ZoneBuffersOfSidesThatAreNotMultiplesOfFour) {
  ZoneBlender blender(context());
  for (const auto& [width, height] :
       {std::pair{61, 35}, std::pair{66, 38}, std::pair{1, 1}, std::pair{3, 7}, std::pair{5, 2}}) {
    SCOPED_TRACE(std::to_string(width) + "x" + std::to_string(height));
    const Image frame = noisy_frame(width, height, 29);
    blender.set_frame(frame);
    EXPECT_EQ(blender.width(), width);
    EXPECT_EQ(largest_difference(blender.zone_buffer(Zone::foveal), frame), 0.0);
    const Image middle =
        crop(upsample_reference(decimate_nearest(frame, 2), 2, UpsampleFilter::lanczos3), width, height);
    const Image outer =
        crop(upsample_reference(decimate_nearest(frame, 4), 4, UpsampleFilter::lanczos3), width, height);
    EXPECT_LT(largest_difference(blender.zone_buffer(Zone::middle), middle), 1e-4 * 3.0);
    EXPECT_LT(largest_difference(blender.zone_buffer(Zone::outer), outer), 1e-4 * 3.0);
    const DisplayGeometry display = display_from_size(width, height, 5.0 * width, 5.0 * height, 250.0);
    const Image gpu = blender.blend(display, 0.3 * width, 0.6 * height, {10.0, 40.0, 2.0}).image;
    const Image reference = blend_zones_reference(display, 0.3 * width, 0.6 * height, {10.0, 40.0, 2.0}, frame,
                                                  blender.zone_buffer(Zone::middle), blender.zone_buffer(Zone::outer));
    EXPECT_LT(largest_difference(gpu, reference), 1e-4 * 3.0);
    EXPECT_EQ(blender.display_frame(display, 0.3 * width, 0.6 * height, {10.0, 40.0, 2.0}).size(),
              size_t(width) * size_t(height) * 4);
  }
}

// The GPU blend against the double reference for gazes at the centre, a corner, off the screen and far
// off it, with bands (weights continuous: 1e-4 of the values' range everywhere), with bands that
// overlap (pixels with all three zones), without a middle zone, and with hard edges (where pixels
// within 1e-3 degrees of a boundary may fall either side in float).
TEST_F(VulkanTest, BlendMatchesTheReference) {
  const Image frame = noisy_frame(64, 48, 11);
  const DisplayGeometry display = small_display();
  ZoneBlender blender(context());
  blender.set_frame(frame);
  const Image middle = blender.zone_buffer(Zone::middle);
  const Image outer = blender.zone_buffer(Zone::outer);
  const double gazes[][2] = {{32.0, 24.0}, {3.5, 44.0}, {-40.0, 10.0}, {-3.0e6, 2.0e6}};
  for (const auto& gaze : gazes)
    for (const ZoneBounds bounds : {ZoneBounds{10.0, 62.5, 2.0}, ZoneBounds{20.0, 40.0, 0.0},
                                    ZoneBounds{10.0, 5.0, 1.0}, ZoneBounds{20.0, 24.0, 6.0}}) {
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
                << "pixel " << x << "," << y << " gaze " << gaze[0] << "," << gaze[1] << " foveal "
                << bounds.foveal_deg;
        }
      EXPECT_GT(compared, frame.width * frame.height - 8);
    }
}

// The same on an off-axis display (a headset eye's asymmetric view: display_from_field_of_view): the
// rays are taken from its principal point, off the frame's centre.
TEST_F(VulkanTest, BlendOfAnOffAxisDisplayMatchesTheReference) {
  const Image frame = noisy_frame(64, 48, 11);
  const double degree = std::numbers::pi / 180.0;
  const DisplayGeometry display =
      display_from_field_of_view(64, 48, {-40 * degree, 25 * degree, 20 * degree, -35 * degree});
  ZoneBlender blender(context());
  blender.set_frame(frame);
  const Image middle = blender.zone_buffer(Zone::middle);
  const Image outer = blender.zone_buffer(Zone::outer);
  for (const auto& [gaze_x, gaze_y] : {std::pair{32.0, 24.0}, {50.0, 10.0}, {-40.0, 10.0}}) {
    const ZoneBounds bounds{20.0, 50.0, 4.0};
    const Image gpu = blender.blend(display, gaze_x, gaze_y, bounds).image;
    const Image reference = blend_zones_reference(display, gaze_x, gaze_y, bounds, frame, middle, outer);
    for (int y = 0; y < frame.height; ++y)
      for (int x = 0; x < frame.width; ++x)
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(gpu.at(x, y, c), reference.at(x, y, c), 1e-4 * 3.0) << "pixel " << x << "," << y;
    // The principal point matters here: the square-on display of the same size blends otherwise.
    const DisplayGeometry square_on =
        display_from_size(64, 48, display.width_mm, display.height_mm, display.viewing_distance_mm);
    EXPECT_NE(blend_zones_reference(square_on, gaze_x, gaze_y, bounds, frame, middle, outer).pixels, reference.pixels);
  }
}

// What a session shows: the same blend, sRGB-encoded to 8 bits on the GPU (two passes: the pixels
// outside the bands copied from the zones' own encoding, the listed band pixels blended). Against the
// CPU's encoding of the linear blend, a byte may differ by one where float rounding lands on the
// other side of a half step (a handful of pixels), never by more; alpha is opaque. Bands of the
// usual kind, overlapping bands, none (an empty band list), every pixel in a band (the longest list)
// and gazes off the screen; no gaze (NaN) shows the frame itself.
TEST_F(VulkanTest, DisplayFrameIsTheBlendEncodedToEightBitSrgb) {
  const Image frame = noisy_frame(64, 48, 5, 1.2f);  // some values above 1, to be clipped
  const DisplayGeometry display = small_display();
  ZoneBlender blender(context());
  blender.set_frame(frame);
  const auto expect_encoded = [&](const std::vector<uint8_t>& bytes, const Image& linear, const std::string& what) {
    ASSERT_EQ(bytes.size(), linear.pixel_count() * 4) << what;
    size_t off_by_one = 0;
    for (size_t pixel = 0; pixel < linear.pixel_count(); ++pixel) {
      for (size_t c = 0; c < 3; ++c) {
        const long expected = std::lround(encode_srgb(linear.pixels[pixel * 3 + c]) * 255.0f);
        const long got = bytes[pixel * 4 + c];
        ASSERT_LE(std::labs(got - expected), 1) << what << " pixel " << pixel << " channel " << c;
        off_by_one += got != expected;
      }
      ASSERT_EQ(bytes[pixel * 4 + 3], 255) << what;
    }
    EXPECT_LE(off_by_one, linear.pixel_count() * 3 / 100) << what;
  };
  const double gazes[][2] = {{20.0, 30.0}, {-40.0, 10.0}, {-3.0e6, 2.0e6}};
  for (const auto& gaze : gazes)
    for (const ZoneBounds bounds : {ZoneBounds{10.0, 62.5, 2.0}, ZoneBounds{20.0, 24.0, 6.0},
                                    ZoneBounds{10.0, 62.5, 0.0}, ZoneBounds{10.0, 62.5, 400.0}}) {
      const Image linear = blender.blend(display, gaze[0], gaze[1], bounds).image;
      expect_encoded(blender.display_frame(display, gaze[0], gaze[1], bounds), linear,
                     "gaze " + std::to_string(gaze[0]) + "," + std::to_string(gaze[1]) + " band " +
                         std::to_string(bounds.band_deg));
    }
  expect_encoded(blender.display_frame(display, std::nan(""), 10.0, {}), frame, "no gaze");
  EXPECT_THROW(blender.display_frame(display_from_size(32, 24, 320.0, 240.0, 250.0), 1.0, 1.0, {}), InputError);
}

// The pt method's frames come from the shader that makes fpt's: the frame without foveation is the
// same bytes as fpt's frame with no gaze, and as fpt's frame inside the fovea for any gaze. Grey
// frames (one channel) are refused, not shown red.
TEST_F(VulkanTest, EncodingForDisplayMatchesTheFovealZoneToTheByte) {
  const Image frame = noisy_frame(64, 48, 6, 1.2f);
  const DisplayGeometry display = small_display();
  ZoneBlender blender(context());
  blender.set_frame(frame);
  const std::vector<uint8_t> encoded = blender.encode_for_display(frame);
  EXPECT_EQ(encoded, blender.display_frame(display, std::nan(""), 0.0, {}));
  const ZoneBounds bounds{20.0, 40.0, 2.0};
  const std::vector<uint8_t> foveated = blender.display_frame(display, 30.0, 20.0, bounds);
  int inside = 0;
  for (int y = 0; y < frame.height; ++y)
    for (int x = 0; x < frame.width; ++x) {
      if (zone_weights(bounds, eccentricity_deg(display, 30.0, 20.0, x + 0.5, y + 0.5)).foveal < 1.0) continue;
      ++inside;
      const size_t at = (size_t(y) * size_t(frame.width) + size_t(x)) * 4;
      for (size_t c = 0; c < 4; ++c) ASSERT_EQ(foveated[at + c], encoded[at + c]) << x << "," << y;
    }
  EXPECT_GT(inside, 50);
  // Any size, not only multiples of 4; the zones are left as they were.
  EXPECT_EQ(blender.encode_for_display(noisy_frame(7, 5, 2)).size(), 7u * 5u * 4u);
  EXPECT_EQ(blender.display_frame(display, 30.0, 20.0, bounds), foveated);
  EXPECT_THROW(blender.encode_for_display(Image(8, 8, 1)), InputError);
  blender.set_frame(Image(64, 48, 1));
  EXPECT_THROW(blender.display_frame(display, 30.0, 20.0, bounds), InputError);
}

TEST_F(VulkanTest, ZoneFramesMustFitOneStorageBuffer) {
  EXPECT_NO_THROW(check_zone_frame_size(context(), 1920, 1080));  // 99.5 MB: within every device's range
  try {
    check_zone_frame_size(context(), 16384, 16384);  // 12.9 GB: beyond any
    ADD_FAILURE() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("16384x16384"), std::string::npos) << error.what();
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
  EXPECT_NEAR(blended.at(32, 24, 0), 1.0f, 1e-6);  // the gaze point
  EXPECT_NEAR(blended.at(0, 0, 1), 0.25f, 1e-5);   // a corner, about 34 degrees out: outer zone
  EXPECT_NEAR(blended.at(32, 8, 2), 0.25f, 1e-5);  // about 17 degrees out: middle zone
  const auto costs = bench::measure_blend_cost(blender, display, 32.0, 24.0, {10.0, 40.0, 0.5}, 2);
  ASSERT_EQ(costs.size(), 2u);
  if (context().timestamp_period_ns > 0.0)
    for (const bench::BlendCost& cost : costs) {
      EXPECT_GT(cost.display_blend_ms, 0.0);
      EXPECT_GT(cost.linear_blend_ms, 0.0);
      EXPECT_GT(cost.copy_shader_ms, 0.0);
      EXPECT_GT(cost.copy_buffer_ms, 0.0);
    }
  // The band pixels the display blend's second pass blends: those the reference gives weights
  // strictly between 0 and 1 (give or take a pixel on a band's edge, in float), none without bands,
  // all of them in a band wider than the screen.
  int reference_band_pixels = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      const ZoneWeights w = zone_weights({10.0, 40.0, 0.5}, eccentricity_deg(display, 32.0, 24.0, x + 0.5, y + 0.5));
      reference_band_pixels += std::max({w.foveal, w.middle, w.outer}) < 1.0;
    }
  EXPECT_GT(reference_band_pixels, 40);
  EXPECT_NEAR(double(costs.front().band_pixels), double(reference_band_pixels), 4.0);
  EXPECT_EQ(bench::measure_blend_cost(blender, display, 32.0, 24.0, {10.0, 40.0, 0.0}, 1).front().band_pixels, 0u);
  EXPECT_EQ(bench::measure_blend_cost(blender, display, 32.0, 24.0, {10.0, 40.0, 400.0}, 1).front().band_pixels,
            64u * 48u);
  // Timing leaves the zones as they were.
  EXPECT_NEAR(blender.blend(display, 32.0, 24.0, {10.0, 40.0, 0.5}).image.at(32, 24, 0), 1.0f, 1e-6);
}

TEST_F(VulkanTest, ZoneBlenderRefusesFramesItCannotZone) {
  ZoneBlender blender(context());
  EXPECT_THROW(blender.set_frame(Image(0, 48, 3)), InputError);
  EXPECT_THROW(blender.set_frame(noisy_frame(20000, 1, 1)), InputError);  // over 16384 a side
  Image periphery = noisy_frame(32, 48, 2);
  EXPECT_THROW(blender.set_frame(noisy_frame(64, 48, 1), &periphery), InputError);
  blender.set_frame(noisy_frame(64, 48, 1));
  EXPECT_THROW(blender.blend(display_from_size(32, 24, 320.0, 240.0, 250.0), 1.0, 1.0, {}), InputError);
  EXPECT_THROW(blender.blend(small_display(), std::nan(""), 1.0, {}), InputError);
}

}  // namespace
}  // namespace fovlab
