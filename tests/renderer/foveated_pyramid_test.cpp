// FIPR (Polychronakis et al. 2023 section 3.2) at small sizes: the GPU mask against the CPU reference, the fallbacks
// for missing or far gaze, the periphery refresh and reconstruction, the blur, the statistics and the
// bad settings.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <vector>

#include "core/input_error.h"
#include "foveation/display_geometry.h"
#include "foveation/foveation_mask.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "tests/renderer/frame_ssim.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

using test::VulkanTest;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A small frame on a small, close display, so the fovea, the periphery and the frame's edges all
// show at 96x64 pixels: the frame spans about 43 x 30 degrees.
SphereTraceSettings fipr_frame(int width = 96, int height = 64) {
  SphereTraceSettings settings;
  settings.method = TraceMethod::foveated_pyramid;
  settings.width = width;
  settings.height = height;
  settings.foveation.display = display_from_size(width, height, 240.0, 160.0, 300.0);
  settings.foveation.gaze_x_px = width * 0.5;
  settings.foveation.gaze_y_px = height * 0.5;
  settings.foveation.acuity.fovea_radius_deg = 5.0;
  return settings;
}

bool all_finite(const Image& image) {
  return std::all_of(image.pixels.begin(), image.pixels.end(), [](float v) { return std::isfinite(v); });
}

bool colour_differs(const Image& a, const Image& b, int x, int y) {
  for (int c = 0; c < 3; ++c)
    if (a.at(x, y, c) != b.at(x, y, c)) return true;
  return false;
}

// The FIPR setting, small: 320x180 on the bench's display (238 x 134 mm at 100 mm), fovea 7.5 degrees.
SphereTraceSettings bench_display_frame() {
  SphereTraceSettings settings = fipr_frame(320, 180);
  settings.foveation.display = display_from_size(320, 180, 238.0, 134.0, 100.0);
  settings.foveation.acuity.fovea_radius_deg = 7.5;
  return settings;
}

// GT's frame with these settings, and a frame's SSIM (sRGB) against it.
SphereTraceResult ground_truth(SphereTracer& tracer, SphereTraceSettings settings) {
  settings.method = TraceMethod::ground_truth;
  return tracer.render(settings);
}

double mask_sum(const SphereTraceResult& result) {
  return std::accumulate(result.mask.pixels.begin(), result.mask.pixels.end(), 0.0);
}

// The CPU reference of a pixel's probability without edges (MaskCombine::acuity).
double acuity_probability(const SphereTraceSettings& settings, int x, int y) {
  const FoveationSettings& f = settings.foveation;
  return f.acuity.trace_probability(eccentricity_deg(f.display, f.gaze_x_px, f.gaze_y_px, x + 0.5, y + 0.5));
}

// With edges left out the mask is a function of geometry, acuity and the hash alone: the GPU must
// agree with the CPU reference on every pixel whose threshold is not within float rounding of its
// probability.
TEST_F(VulkanTest, FoveationMaskMatchesTheCpuReference) {
  SphereTracer tracer(context(), load_scene("primitives"));
  for (const auto& [gaze_x, gaze_y] : {std::pair{48.0, 32.0}, {3.0, 60.0}, {-40.0, 10.0}}) {
    SphereTraceSettings settings = fipr_frame();
    settings.foveation.combine = MaskCombine::acuity;
    settings.foveation.near_misses = NearMisses::ignore;  // the mask pass alone (promotion only adds: below)
    settings.foveation.gaze_x_px = gaze_x;
    settings.foveation.gaze_y_px = gaze_y;
    settings.foveation.seed = 17;
    settings.foveation.frame_index = 3;
    const SphereTraceResult result = tracer.render(settings);
    int compared = 0, masked = 0;
    for (int y = 0; y < settings.height; ++y) {
      for (int x = 0; x < settings.width; ++x) {
        const double p = acuity_probability(settings, x, y);
        const double xi = mask_threshold(17, 3, uint32_t(x), uint32_t(y));
        if (std::fabs(p - xi) < 1e-5) continue;
        ++compared;
        const bool expected = xi < p;
        masked += expected;
        ASSERT_EQ(result.mask.at(x, y, 0), expected ? 1.0f : 0.0f) << "pixel " << x << "," << y << " gaze " << gaze_x;
      }
    }
    EXPECT_GT(compared, settings.width * settings.height - 10);
    EXPECT_GT(masked, 0);
    EXPECT_LT(masked, compared) << "the periphery is not traced in full";
    EXPECT_EQ(result.foveation.masked_pixels, uint64_t(mask_sum(result)));
  }
}

// The same on an off-axis display (a headset eye's asymmetric view: display_from_field_of_view), whose
// principal point is off the frame's centre.
TEST_F(VulkanTest, FoveationMaskOfAnOffAxisDisplayMatchesTheCpuReference) {
  SphereTracer tracer(context(), load_scene("primitives"));
  const double degree = std::numbers::pi / 180.0;
  for (const auto& [gaze_x, gaze_y] : {std::pair{48.0, 32.0}, {70.0, 12.0}, {-40.0, 10.0}}) {
    SphereTraceSettings settings = fipr_frame();
    settings.foveation.display =
        display_from_field_of_view(96, 64, {-30 * degree, 14 * degree, 12 * degree, -20 * degree});
    settings.foveation.combine = MaskCombine::acuity;
    settings.foveation.near_misses = NearMisses::ignore;
    settings.foveation.gaze_x_px = gaze_x;
    settings.foveation.gaze_y_px = gaze_y;
    settings.foveation.seed = 17;
    settings.foveation.frame_index = 3;
    const SphereTraceResult result = tracer.render(settings);
    int compared = 0, masked = 0;
    for (int y = 0; y < settings.height; ++y) {
      for (int x = 0; x < settings.width; ++x) {
        const double p = acuity_probability(settings, x, y);
        const double xi = mask_threshold(17, 3, uint32_t(x), uint32_t(y));
        if (std::fabs(p - xi) < 1e-5) continue;
        ++compared;
        masked += xi < p;
        ASSERT_EQ(result.mask.at(x, y, 0), xi < p ? 1.0f : 0.0f) << "pixel " << x << "," << y << " gaze " << gaze_x;
      }
    }
    EXPECT_GT(compared, settings.width * settings.height - 10);
    EXPECT_GT(masked, 0);
    EXPECT_LT(masked, compared);
  }
}

// Under `max` every pixel the acuity model alone would trace is traced, the whole fovea included,
// and edges add pixels; under the literal product a fovea pixel off the edges is not traced.
TEST_F(VulkanTest, MaskCombinationsOrderAsDocumented) {
  SphereTracer tracer(context(), load_scene("primitives"));
  SphereTraceSettings settings = fipr_frame();
  const auto render_with = [&](MaskCombine combine) {
    settings.foveation.combine = combine;
    return tracer.render(settings);
  };
  const SphereTraceResult acuity = render_with(MaskCombine::acuity);
  const SphereTraceResult max = render_with(MaskCombine::max);
  const SphereTraceResult fovea_or_product = render_with(MaskCombine::fovea_or_product);
  const SphereTraceResult product = render_with(MaskCombine::product);
  int fovea_pixels = 0, product_fovea_dropped = 0;
  for (int y = 0; y < settings.height; ++y) {
    for (int x = 0; x < settings.width; ++x) {
      EXPECT_GE(max.mask.at(x, y, 0), acuity.mask.at(x, y, 0));
      EXPECT_GE(max.mask.at(x, y, 0), fovea_or_product.mask.at(x, y, 0));
      EXPECT_GE(fovea_or_product.mask.at(x, y, 0), product.mask.at(x, y, 0));
      if (acuity_probability(settings, x, y) == 1.0) {
        ++fovea_pixels;
        EXPECT_EQ(max.mask.at(x, y, 0), 1.0f);
        EXPECT_EQ(fovea_or_product.mask.at(x, y, 0), 1.0f);
        product_fovea_dropped += product.mask.at(x, y, 0) == 0.0f;
      }
    }
  }
  EXPECT_GT(fovea_pixels, 100);
  EXPECT_GT(product_fovea_dropped, 0) << "the literal product drops fovea pixels off the edges (Fig. 6 does not)";
  EXPECT_GT(mask_sum(max), mask_sum(acuity)) << "edges add peripheral pixels";
}

// No gaze (NaN) or a fovea covering everything: every pixel is traced at the top level, which is
// exactly the inverted pyramid's frame.
TEST_F(VulkanTest, MissingGazeOrWholeFoveaRendersTheInvertedPyramidFrame) {
  SphereTracer tracer(context(), load_scene("columns"));
  SphereTraceSettings settings = fipr_frame();
  settings.method = TraceMethod::inverted_pyramid;
  const SphereTraceResult ipr = tracer.render(settings);
  settings.method = TraceMethod::foveated_pyramid;
  for (int variant = 0; variant < 2; ++variant) {
    SphereTraceSettings fipr = settings;
    if (variant == 0) fipr.foveation.gaze_x_px = kNaN;
    if (variant == 1) fipr.foveation.acuity.fovea_radius_deg = 180.0;
    const SphereTraceResult result = tracer.render(fipr);
    EXPECT_EQ(mask_sum(result), double(settings.width * settings.height));
    EXPECT_EQ(result.colour_linear.pixels, ipr.colour_linear.pixels) << "variant " << variant;
    EXPECT_EQ(result.foveation.refreshed_pixels, 0u);
  }
}

// Gaze swept over the frame, its corners and far off it: every pixel of every scene stays finite,
// and the share traced at the top level falls as the gaze leaves the frame.
TEST_F(VulkanTest, GazeSweepKeepsEveryPixelFinite) {
  for (const char* scene : {"primitives", "columns", "temple"}) {
    SphereTracer tracer(context(), load_scene(scene));
    SphereTraceSettings settings = fipr_frame(64, 40);
    double centre_share = 0.0, far_share = 1.0;
    const double positions[] = {-1e12, -500.0, 0.0, 0.5, 0.25, 0.75, 1.0, 1.0 + 500.0 / 64, 1e12};
    for (double gx : positions) {
      for (double gy : positions) {
        settings.foveation.gaze_x_px = std::fabs(gx) > 2.0 ? gx : gx * settings.width;
        settings.foveation.gaze_y_px = std::fabs(gy) > 2.0 ? gy : gy * settings.height;
        const SphereTraceResult result = tracer.render(settings);
        ASSERT_TRUE(all_finite(result.colour_linear)) << scene << " gaze " << gx << "," << gy;
        const double share = mask_sum(result) / (settings.width * settings.height);
        if (gx == 0.5 && gy == 0.5) centre_share = share;
        if (gx == 1e12 && gy == 1e12) far_share = share;
      }
    }
    EXPECT_LT(far_share, centre_share) << scene;
  }
}

// Extreme displays: the eye almost touching the screen (every pixel but the gaze's is near 90
// degrees away), and a screen kilometres wide seen from 600 mm (the same). Only the gaze pixel's
// neighbourhood is foveal; the frame stays finite; eccentricity 0 at the gaze pixel itself.
TEST_F(VulkanTest, ExtremeDisplaysKeepTheFoveaAtTheGazeAndEveryPixelFinite) {
  SphereTracer tracer(context(), load_scene("primitives"));
  for (const DisplayGeometry& display :
       {display_from_size(96, 64, 240.0, 160.0, 1e-3), display_from_size(96, 64, 1e7, 6.667e6, 600.0),
        display_from_size(96, 64, 1e-3, 6.67e-4, 600.0)}) {
    SphereTraceSettings settings = fipr_frame();
    settings.foveation.display = display;
    settings.foveation.combine = MaskCombine::acuity;
    settings.foveation.near_misses = NearMisses::ignore;  // acuity alone decides (promotion only adds: below)
    settings.foveation.gaze_x_px = 10.5;                  // the centre of pixel (10, 20)
    settings.foveation.gaze_y_px = 20.5;
    const SphereTraceResult result = tracer.render(settings);
    ASSERT_TRUE(all_finite(result.colour_linear)) << display.viewing_distance_mm;
    EXPECT_EQ(result.mask.at(10, 20, 0), 1.0f) << "eccentricity 0 is foveal";
    const double share = mask_sum(result) / (settings.width * settings.height);
    if (display.width_mm < 1.0) {
      EXPECT_EQ(share, 1.0) << "a screen 1 micrometre wide at 600 mm is all fovea";
    } else {
      EXPECT_LT(share, 0.05) << "almost every pixel is near 90 degrees away";
    }
  }
}

// Refresh 4 with a moving camera: frame 0 refreshes everything; later frames give a new colour to the
// unmasked pixels of one phase of the 2x2 pattern of 16x16-pixel tiles (and they change), and every
// other unmasked pixel keeps the colour it had, bit for bit.
void check_periphery_refresh(vk::Context& context, int periphery_steps) {
  SCOPED_TRACE("periphery_steps " + std::to_string(periphery_steps));
  SphereTracer tracer(context, load_scene("primitives"));
  SphereTraceSettings settings = fipr_frame();
  settings.foveation.periphery_steps = periphery_steps;
  settings.foveation.periphery_refresh = 4;
  SphereTraceSettings reference = settings;
  reference.foveation.periphery_refresh = 1;
  const SphereTraceResult all_refreshed = tracer.render(reference);
  const SphereTraceResult first = tracer.render(settings);
  EXPECT_EQ(first.colour_linear.pixels, all_refreshed.colour_linear.pixels) << "frame 0 refreshes every pixel";
  EXPECT_EQ(first.foveation.kept_pixels, 0u);

  SphereTraceResult previous = first;
  uint64_t kept_in_cycle = 0, refreshed_in_cycle = 0;
  for (uint32_t frame = 1; frame < 6; ++frame) {
    settings.foveation.frame_index = frame;
    settings.time_s = 0.25f * float(frame);  // the camera moves: refreshed pixels change
    const SphereTraceResult result = tracer.render(settings);
    uint64_t kept = 0, due_changed = 0;
    for (int y = 0; y < settings.height; ++y) {
      for (int x = 0; x < settings.width; ++x) {
        if (result.mask.at(x, y, 0) != 0.0f) continue;
        const uint32_t phase = uint32_t((x / 16) & 1) | (uint32_t((y / 16) & 1) << 1);  // 16x16-pixel tiles
        if (phase == frame % 4) {
          due_changed += colour_differs(result.colour_linear, previous.colour_linear, x, y);
          continue;
        }
        ++kept;
        for (int c = 0; c < 3; ++c) ASSERT_EQ(result.colour_linear.at(x, y, c), previous.colour_linear.at(x, y, c));
      }
    }
    EXPECT_EQ(kept, result.foveation.kept_pixels);
    EXPECT_GT(result.foveation.refreshed_pixels, 0u);
    EXPECT_GT(due_changed, result.foveation.refreshed_pixels / 4) << "refreshed pixels show the moved camera";
    EXPECT_EQ(result.foveation.masked_pixels + result.foveation.refreshed_pixels + result.foveation.kept_pixels,
              uint64_t(settings.width * settings.height));
    if (frame <= 4) {  // one whole cycle: every tile refreshed once
      kept_in_cycle += kept;
      refreshed_in_cycle += result.foveation.refreshed_pixels;
    }
    previous = result;
  }
  EXPECT_GT(kept_in_cycle, 2 * refreshed_in_cycle) << "about three quarters of the periphery is kept";
  settings.foveation.frame_index = 0;
  settings.time_s = 0.0f;
  EXPECT_EQ(tracer.render(settings).colour_linear.pixels, all_refreshed.colour_linear.pixels)
      << "frame 0 starts a new sequence";
  // Skipping a frame, or changing a setting, also starts one (no reuse of the wrong history).
  settings.foveation.frame_index = 1;
  const SphereTraceResult continued = tracer.render(settings);
  EXPECT_GT(continued.foveation.kept_pixels, 0u);
  settings.foveation.frame_index = 3;
  EXPECT_EQ(tracer.render(settings).foveation.kept_pixels, 0u) << "frame 3 after frame 1";
  settings.foveation.frame_index = 4;
  settings.foveation.seed += 1;
  EXPECT_EQ(tracer.render(settings).foveation.kept_pixels, 0u) << "another seed";
}

TEST_F(VulkanTest, PeripheryRefreshKeepsPixelsThatAreNotDue) {
  check_periphery_refresh(context(), 0);    // from the mid level
  check_periphery_refresh(context(), 256);  // traced from the mid depth, from the refresh list
}

// The periphery's reconstruction from the mid level: textured over a frame pixel's footprint (bilinear,
// the default since log schema 5, and catmull-rom), the mid colours fill the pixels the mask leaves
// out closer to GT than those textured over the mid pixel's own footprint (every log before), on
// the checkered floor of `primitives` (a texture box-filtered over the footprint it is given); the
// pixels the mask traces are the same in all three. 320x180 at 4 spp on the bench's display
// (measured: SSIM 0.948 mid-footprint-bilinear, 0.969 catmull-rom).
TEST_F(VulkanTest, PeripheryTexturedAtThePixelsFootprintIsCloserToGroundTruth) {
  SphereTracer tracer(context(), load_scene("primitives"));
  SphereTraceSettings settings = bench_display_frame();
  settings.samples_per_pixel = 4;
  const SphereTraceResult gt = ground_truth(tracer, settings);
  const auto ssim = [&](const SphereTraceResult& test) { return test::srgb_ssim(gt, test); };
  settings.foveation.reconstruction = PeripheryReconstruction::mid_footprint_bilinear;
  const SphereTraceResult first_built = tracer.render(settings);
  std::vector<float> bilinear_colours;
  for (const PeripheryReconstruction reconstruction :
       {PeripheryReconstruction::bilinear, PeripheryReconstruction::catmull_rom}) {
    SCOPED_TRACE(periphery_reconstruction_name(reconstruction));
    settings.foveation.reconstruction = reconstruction;
    const SphereTraceResult result = tracer.render(settings);
    if (reconstruction == PeripheryReconstruction::bilinear) bilinear_colours = result.colour_linear.pixels;
    else EXPECT_NE(result.colour_linear.pixels, bilinear_colours) << "Catmull-Rom is another interpolation";
    ASSERT_EQ(result.mask.pixels, first_built.mask.pixels);
    uint64_t unmasked_changed = 0, masked = 0;
    for (int y = 0; y < settings.height; ++y) {
      for (int x = 0; x < settings.width; ++x) {
        if (result.mask.at(x, y, 0) != 0.0f) {
          ++masked;
          for (int c = 0; c < 3; ++c)
            ASSERT_EQ(result.colour_linear.at(x, y, c), first_built.colour_linear.at(x, y, c));
        } else {
          unmasked_changed += colour_differs(result.colour_linear, first_built.colour_linear, x, y);
        }
      }
    }
    EXPECT_GT(masked, 0u);
    EXPECT_GT(unmasked_changed, uint64_t(settings.width * settings.height) / 4)
        << "the floor is a quarter of the frame";
    EXPECT_GT(ssim(result), ssim(first_built) + 0.01);
    ASSERT_TRUE(all_finite(result.colour_linear));
    for (float value : result.colour_linear.pixels)
      ASSERT_GE(value, 0.0f) << "Catmull-Rom's negative lobes are clamped";
  }
}

// Near misses (`wires`: sub-pixel wires in front of a wall, which the paper's low and mid rays pass
// between). With promote the mid level's unmasked children of a pixel whose ray passed a surface are
// traced at the top level, and masked pixels start in front of such a surface; nothing else changes:
// the mask only grows, and every pixel outside it is the frame ignore (the paper's FIPR) renders, bit
// for bit. On `wires` the frame keeps what ignore loses; on `columns` it is no further from GT.
// 320x180 at 1 spp on the bench's display (measured SSIM: wires 0.798 ignore, 0.858 promote, 7367
// pixels promoted; columns 0.9075 and 0.9081).
TEST_F(VulkanTest, NearMissesPromotedKeepTheWiresTheMidLevelPasses) {
  for (const std::string scene : {"wires", "columns"}) {
    SCOPED_TRACE(scene);
    SphereTracer tracer(context(), load_scene(scene));
    SphereTraceSettings settings = bench_display_frame();
    const SphereTraceResult gt = ground_truth(tracer, settings);
    const auto ssim = [&](const SphereTraceResult& test) { return test::srgb_ssim(gt, test); };
    settings.foveation.near_misses = NearMisses::ignore;
    const SphereTraceResult ignored = tracer.render(settings);
    settings.foveation.near_misses = NearMisses::promote;
    const SphereTraceResult promoted = tracer.render(settings);
    uint64_t added = 0;
    for (int y = 0; y < settings.height; ++y) {
      for (int x = 0; x < settings.width; ++x) {
        if (ignored.mask.at(x, y, 0) != 0.0f) {
          ASSERT_EQ(promoted.mask.at(x, y, 0), 1.0f) << "the mask only grows, at " << x << "," << y;
        } else if (promoted.mask.at(x, y, 0) != 0.0f) {
          ++added;
        } else {
          for (int c = 0; c < 3; ++c)
            ASSERT_EQ(promoted.colour_linear.at(x, y, c), ignored.colour_linear.at(x, y, c)) << x << "," << y;
        }
      }
    }
    EXPECT_EQ(promoted.foveation.masked_pixels, ignored.foveation.masked_pixels + added);
    EXPECT_EQ(promoted.levels[2].traced_pixels, uint64_t(mask_sum(promoted)));
    EXPECT_EQ(promoted.foveation.masked_pixels + promoted.foveation.refreshed_pixels,
              uint64_t(settings.width * settings.height));
    ASSERT_TRUE(all_finite(promoted.colour_linear));
    if (scene == "wires") {
      EXPECT_GT(added, uint64_t(settings.width * settings.height) / 50);
      EXPECT_GT(ssim(promoted), ssim(ignored) + 0.05);
    } else {
      EXPECT_GE(ssim(promoted), ssim(ignored));
    }
  }
}

// The blur changes only pixels filled from the mid level, and only next to top-level pixels.
TEST_F(VulkanTest, MaskedBlurTouchesOnlyTransitionPixels) {
  SphereTracer tracer(context(), load_scene("temple"));
  SphereTraceSettings settings = fipr_frame();
  const SphereTraceResult sharp = tracer.render(settings);
  settings.foveation.blur = true;
  const SphereTraceResult blurred = tracer.render(settings);
  ASSERT_EQ(sharp.mask.pixels, blurred.mask.pixels);
  int changed = 0;
  for (int y = 0; y < settings.height; ++y) {
    for (int x = 0; x < settings.width; ++x) {
      if (!colour_differs(sharp.colour_linear, blurred.colour_linear, x, y)) continue;
      ++changed;
      ASSERT_EQ(sharp.mask.at(x, y, 0), 0.0f) << "a top-level pixel was blurred at " << x << "," << y;
      bool near_top = false;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (nx >= 0 && ny >= 0 && nx < settings.width && ny < settings.height)
            near_top = near_top || sharp.mask.at(nx, ny, 0) != 0.0f;
        }
      ASSERT_TRUE(near_top) << x << "," << y;
    }
  }
  EXPECT_GT(changed, 0);
}

// With one sample per pixel and a full step budget the periphery's rays are IPR's top-level rays,
// so every pixel equals IPR's; with the mid level's colour instead (periphery_steps 0) the frame
// differs from IPR only outside the mask.
TEST_F(VulkanTest, PeripheryTracedInFullEqualsTheInvertedPyramid) {
  SphereTracer tracer(context(), load_scene("temple"));
  SphereTraceSettings settings = fipr_frame();
  settings.method = TraceMethod::inverted_pyramid;
  const SphereTraceResult ipr = tracer.render(settings);
  settings.method = TraceMethod::foveated_pyramid;
  // The mask pass's pixels are IPR's; those promoted for a near miss start from their own depth and
  // change nothing else (NearMissesPromotedKeepTheWiresTheMidLevelPasses).
  settings.foveation.near_misses = NearMisses::ignore;
  settings.foveation.periphery_steps = settings.max_steps;
  EXPECT_EQ(tracer.render(settings).colour_linear.pixels, ipr.colour_linear.pixels);
  settings.foveation.periphery_steps = 0;
  const SphereTraceResult from_mid = tracer.render(settings);
  int differing = 0;
  for (int y = 0; y < settings.height; ++y) {
    for (int x = 0; x < settings.width; ++x) {
      const bool differs = colour_differs(from_mid.colour_linear, ipr.colour_linear, x, y);
      if (from_mid.mask.at(x, y, 0) != 0.0f) {
        ASSERT_FALSE(differs) << "a top-level pixel at " << x << "," << y;
      }
      differing += differs;
    }
  }
  EXPECT_GT(differing, 0);
}

// Level statistics: the top level traces the masked pixels, the mid level at most all of its
// pixels, the low level all; with the periphery from the mid level (the default), fewer steps than
// the inverted pyramid.
TEST_F(VulkanTest, FoveatedStatisticsAddUp) {
  SphereTracer tracer(context(), load_scene("primitives"));
  SphereTraceSettings settings = fipr_frame(160, 90);
  const SphereTraceResult fipr = tracer.render(settings);
  ASSERT_EQ(fipr.levels.size(), 3u);
  EXPECT_EQ(fipr.levels[2].traced_pixels, uint64_t(mask_sum(fipr)));
  EXPECT_EQ(fipr.foveation.masked_pixels, uint64_t(mask_sum(fipr)));
  EXPECT_LE(fipr.levels[1].traced_pixels, uint64_t(fipr.levels[1].width * fipr.levels[1].height));
  EXPECT_EQ(fipr.levels[0].traced_share(), 1.0);
  EXPECT_EQ(fipr.foveation.masked_pixels + fipr.foveation.refreshed_pixels, uint64_t(160 * 90));
  std::vector<std::string> pass_names;
  for (const vk::PassTime& pass : fipr.passes) pass_names.push_back(pass.name);
  EXPECT_NE(std::find(pass_names.begin(), pass_names.end(), "sobel_edges"), pass_names.end());
  EXPECT_NE(std::find(pass_names.begin(), pass_names.end(), "foveation_mask"), pass_names.end());
  SphereTraceSettings traced = settings;
  traced.foveation.periphery_steps = 256;
  const SphereTraceResult traced_periphery = tracer.render(traced);
  EXPECT_EQ(traced_periphery.levels[2].traced_pixels, uint64_t(160 * 90)) << "frame 0: the periphery is traced too";
  EXPECT_EQ(traced_periphery.levels[1].shaded_pixels, 0u) << "and the mid level shades nothing";
  settings.method = TraceMethod::inverted_pyramid;
  EXPECT_LT(fipr.total_steps, tracer.render(settings).total_steps);
}

// Other layouts: an odd frame size, four pyramid levels, a 5x5 min filter and 4 samples per pixel.
// The masked pixels are IPR's pixels exactly (their start depths are the same), whether the
// periphery comes from the mid level or is traced, and every pixel is finite.
TEST_F(VulkanTest, OddSizesDeeperPyramidsAndWiderFiltersKeepMaskedPixelsExact) {
  SphereTracer tracer(context(), load_scene("columns"));
  for (const auto& [levels, filter] : {std::pair{4, 5}, {3, 1}, {5, 3}}) {
    SphereTraceSettings settings = fipr_frame(97, 61);
    settings.pyramid_levels = levels;
    settings.min_filter_size = filter;
    settings.samples_per_pixel = 4;
    settings.method = TraceMethod::inverted_pyramid;
    const SphereTraceResult ipr = tracer.render(settings);
    settings.method = TraceMethod::foveated_pyramid;
    settings.foveation.near_misses = NearMisses::ignore;  // the mask pass's pixels (as above)
    for (int periphery_steps : {0, 256}) {
      settings.foveation.periphery_steps = periphery_steps;
      const SphereTraceResult fipr = tracer.render(settings);
      ASSERT_TRUE(all_finite(fipr.colour_linear));
      ASSERT_EQ(fipr.levels.size(), size_t(levels));
      int masked = 0;
      for (int y = 0; y < settings.height; ++y) {
        for (int x = 0; x < settings.width; ++x) {
          if (fipr.mask.at(x, y, 0) == 0.0f) continue;
          ++masked;
          for (int c = 0; c < 3; ++c) {
            ASSERT_EQ(fipr.colour_linear.at(x, y, c), ipr.colour_linear.at(x, y, c))
                << "levels " << levels << " filter " << filter << " pixel " << x << "," << y;
          }
        }
      }
      EXPECT_GT(masked, 100);
    }
  }
}

TEST(FoveationSettingsValidation, BadSettingsNameTheirField) {
  const auto message_for = [](auto change) {
    SphereTraceSettings settings = fipr_frame();
    change(settings);
    try {
      validate(settings);
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  // The renderer names the field of its settings (the CLI words it as its flag, a study as its key).
  EXPECT_EQ(message_for([](SphereTraceSettings& s) { s.pyramid_levels = 2; }),
            "pyramid_levels 2: FIPR needs at least 3 pyramid levels (low, mid and top)");
  EXPECT_EQ(
      message_for([](SphereTraceSettings& s) { s.foveation.periphery_refresh = 3; }).rfind("periphery_refresh 3:", 0),
      0u);
  EXPECT_EQ(message_for([](SphereTraceSettings& s) {
              s.foveation.acuity.fovea_radius_deg = -1;
            }).rfind("fovea_radius_deg:", 0),
            0u);
  EXPECT_EQ(message_for([](SphereTraceSettings& s) {
              s.foveation.acuity.fovea_radius_deg = kNaN;
            }).rfind("fovea_radius_deg:", 0),
            0u);
  EXPECT_EQ(message_for([](SphereTraceSettings& s) {
              s.foveation.acuity.outer_periphery_radius_deg = 1.0;
            }).rfind("outer_periphery_radius_deg:", 0),
            0u);
  EXPECT_EQ(message_for([](SphereTraceSettings& s) { s.foveation.edge_threshold = 0.0f; }).rfind("edge_threshold:", 0),
            0u);
  EXPECT_EQ(
      message_for([](SphereTraceSettings& s) { s.foveation.periphery_steps = -1; }).rfind("periphery_steps -1:", 0),
      0u);
  try {
    SphereTraceSettings bad = fipr_frame();
    bad.max_steps = 0;
    validate(bad);
    FAIL() << "max_steps 0 accepted";
  } catch (const SettingError& error) {
    EXPECT_EQ(error.field, "max_steps");
    EXPECT_EQ(error.detail, " 0: expected 1 to 100000");
  }
  EXPECT_NE(message_for([](SphereTraceSettings& s) { s.width = 50; }).find("display"), std::string::npos);
  EXPECT_EQ(message_for([](SphereTraceSettings& s) { s.foveation.gaze_x_px = kNaN; }), "accepted");
}

TEST(FoveationMask, CombinationsAndThresholds) {
  EXPECT_EQ(mask_probability(MaskCombine::max, 0.05, false, true), 1.0);
  EXPECT_EQ(mask_probability(MaskCombine::max, 0.05, false, false), 0.05);
  EXPECT_EQ(mask_probability(MaskCombine::product, 1.0, true, false), 0.0);
  EXPECT_EQ(mask_probability(MaskCombine::fovea_or_product, 1.0, true, false), 1.0);
  EXPECT_EQ(mask_probability(MaskCombine::fovea_or_product, 0.05, false, true), 0.05);
  EXPECT_EQ(mask_probability(MaskCombine::acuity, 0.05, false, true), 0.05);
  for (MaskCombine combine :
       {MaskCombine::max, MaskCombine::fovea_or_product, MaskCombine::product, MaskCombine::acuity})
    EXPECT_EQ(parse_mask_combine(mask_combine_name(combine)), combine);
  EXPECT_FALSE(parse_mask_combine("sum").has_value());
  // Thresholds are uniform on [0, 1): the mean and the share below 0.1 of 200,000 pixels.
  double sum = 0.0;
  int below = 0;
  for (uint32_t y = 0; y < 400; ++y)
    for (uint32_t x = 0; x < 500; ++x) {
      const double xi = mask_threshold(5, 2, x, y);
      ASSERT_GE(xi, 0.0);
      ASSERT_LT(xi, 1.0);
      sum += xi;
      below += xi < 0.1;
    }
  EXPECT_NEAR(sum / 200000.0, 0.5, 0.003);
  EXPECT_NEAR(below / 200000.0, 0.1, 0.002);
  EXPECT_NE(mask_hash(5, 2, 10, 10), mask_hash(5, 3, 10, 10)) << "the frame changes the thresholds";
  EXPECT_NE(mask_hash(5, 2, 10, 10), mask_hash(6, 2, 10, 10)) << "so does the seed";
}

}  // namespace
}  // namespace fovlab
