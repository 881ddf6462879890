// The conservative pyramid (CoarseTest::cone) and the full-resolution depth level (issue 20): IPR
// keeps the thin geometry GT shows (the `wires` scene), where the paper's centre ray loses some,
// and both switches keep every scene within the SSIM bound of GT.
#include <gtest/gtest.h>

#include <cmath>

#include "renderer/sphere_tracing/sphere_tracer.h"
#include "tests/renderer/frame_ssim.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

using test::srgb_ssim;
using test::VulkanTest;

SphereTraceSettings frame_320x180(TraceMethod method, int spp) {
  SphereTraceSettings settings;
  settings.method = method;
  settings.width = 320;
  settings.height = 180;
  settings.samples_per_pixel = spp;
  return settings;
}

// The scene of sub-pixel wires, rods, rings and an edge-on plate in front of a wall: the centre
// ray of a coarse pixel passes between them and its finer rays start behind them; the cone does not.
// 320x180 at 4 spp (measured: the centre ray 0.915, the cone 0.998; at 1 spp 0.967 and 0.9966).
TEST_F(VulkanTest, ConeKeepsTheThinGeometryTheCentreRayLoses) {
  SphereTracer tracer(context(), load_scene("wires"));
  SphereTraceSettings settings = frame_320x180(TraceMethod::ground_truth, 4);
  const SphereTraceResult gt = tracer.render(settings);
  settings.method = TraceMethod::inverted_pyramid;
  const SphereTraceResult centre_ray = tracer.render(settings);
  settings.coarse_test = CoarseTest::cone;
  const SphereTraceResult cone = tracer.render(settings);

  EXPECT_LT(srgb_ssim(gt, centre_ray), 0.96) << "the scene no longer shows what the issue measured";
  EXPECT_GE(srgb_ssim(gt, cone), 0.997);
  EXPECT_GT(centre_ray.restarted_rays, 0u) << "centre rays overshoot thin geometry";
  EXPECT_EQ(cone.restarted_rays, 0u) << "a conservative start never lies inside geometry";
  EXPECT_EQ(gt.capped_rays, 0u);
  EXPECT_EQ(cone.capped_rays, 0u);
  EXPECT_LT(cone.total_steps, gt.total_steps);
}

// Every scene at 320x180 and 4 spp (as sphere_tracing_test's bound for the paper's pyramid) within
// SSIM 0.995 of GT with the cone: alone, without the min filter it makes redundant, and with the
// full-resolution depth level; the paper's pyramid with that level on the built-in scenes too.
class EveryScene : public VulkanTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(EveryScene, ConeAndFullResolutionDepthStayWithinTheBoundOfGroundTruth) {
  const std::string scene = GetParam();
  SphereTracer tracer(context(), load_scene(scene));
  SphereTraceSettings settings = frame_320x180(TraceMethod::ground_truth, 4);
  const SphereTraceResult gt = tracer.render(settings);
  struct Mode {
    CoarseTest test;
    int min_filter_size;
    bool full_depth;
  };
  for (const Mode mode : {Mode{CoarseTest::cone, 3, false}, Mode{CoarseTest::cone, 1, false},
                          Mode{CoarseTest::cone, 3, true}, Mode{CoarseTest::centre_ray, 3, true}}) {
    if (mode.test == CoarseTest::centre_ray && scene == "wires") continue;  // loses wires, as without the level
    settings.method = TraceMethod::inverted_pyramid;
    settings.coarse_test = mode.test;
    settings.min_filter_size = mode.min_filter_size;
    settings.full_resolution_depth = mode.full_depth;
    const SphereTraceResult ipr = tracer.render(settings);
    const std::string name = scene + ", " + coarse_test_name(mode.test) + ", min filter " +
                             std::to_string(mode.min_filter_size) + (mode.full_depth ? ", full depth" : "");
    EXPECT_GE(srgb_ssim(gt, ipr), 0.995) << name;
    if (mode.test == CoarseTest::cone) {
      EXPECT_EQ(ipr.restarted_rays, 0u) << name;
    }
    EXPECT_LT(ipr.total_steps, gt.total_steps) << name;
    EXPECT_EQ(ipr.levels.size(), mode.full_depth ? 4u : 3u) << name;
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, EveryScene, ::testing::Values("primitives", "columns", "temple", "wires"));

// At 16 spp every sample started from the half-size level costs several steps; from the
// full-resolution depth level fewer (measured at 160x90: 7.3 a sample against 5.4).
TEST_F(VulkanTest, FullResolutionDepthCutsTheStepsOfEverySample) {
  SphereTracer tracer(context(), load_scene("primitives"));
  SphereTraceSettings settings = frame_320x180(TraceMethod::inverted_pyramid, 16);
  settings.width = 160;
  settings.height = 90;
  const SphereTraceResult half_size_start = tracer.render(settings);
  settings.full_resolution_depth = true;
  const SphereTraceResult full_depth = tracer.render(settings);
  ASSERT_EQ(full_depth.levels.size(), 4u);
  EXPECT_EQ(full_depth.levels[2].scale, 1);
  EXPECT_EQ(full_depth.levels[2].shaded_pixels, 0u);
  const double samples = 160.0 * 90.0 * 16.0;
  const double steps_per_sample_before = double(half_size_start.levels.back().steps) / samples;
  const double steps_per_sample_after = double(full_depth.levels.back().steps) / samples;
  EXPECT_LT(steps_per_sample_after, 0.8 * steps_per_sample_before)
      << steps_per_sample_before << " -> " << steps_per_sample_after;
  EXPECT_LT(full_depth.total_steps, half_size_start.total_steps);
}

// FIPR's depth levels take the cone too: without gaze (every pixel traced) it is IPR's frame; with
// gaze its mid level shades the periphery from where the cone stopped.
TEST_F(VulkanTest, FoveatedPyramidWithTheConeKeepsTheWires) {
  SphereTracer tracer(context(), load_scene("wires"));
  SphereTraceSettings settings = frame_320x180(TraceMethod::ground_truth, 1);
  const SphereTraceResult gt = tracer.render(settings);
  settings.method = TraceMethod::foveated_pyramid;
  settings.coarse_test = CoarseTest::cone;
  settings.foveation.display = DisplayGeometry{320, 180, 531.0, 298.7, 600.0};
  settings.foveation.gaze_x_px = std::nan("");
  settings.foveation.gaze_y_px = std::nan("");
  const SphereTraceResult everywhere = tracer.render(settings);
  EXPECT_GE(srgb_ssim(gt, everywhere), 0.995);
  EXPECT_EQ(everywhere.restarted_rays, 0u);

  settings.foveation.gaze_x_px = 160.0;
  settings.foveation.gaze_y_px = 90.0;
  const SphereTraceResult foveated_cone = tracer.render(settings);
  settings.coarse_test = CoarseTest::centre_ray;
  const SphereTraceResult foveated_ray = tracer.render(settings);
  EXPECT_GT(srgb_ssim(gt, foveated_cone), srgb_ssim(gt, foveated_ray));
}

}  // namespace
}  // namespace fovlab
