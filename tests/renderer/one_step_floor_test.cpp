// The one-step floor of `fovlab bench` (SphereTraceSettings::one_step_floor): every sample starts
// where GT's own trace of it stopped and takes exactly one step (misses none) and its shading; its
// frame is GT's but for the refining step onto the surface; the timed pass is that one alone.
#include <gtest/gtest.h>

#include "core/colour.h"
#include "core/input_error.h"
#include "metrics/image_metrics.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

using test::VulkanTest;

TEST_F(VulkanTest, OneStepFloorTakesOneStepASampleAndShowsGroundTruthsFrame) {
  SphereTracer tracer(context(), load_scene("primitives"));
  SphereTraceSettings settings;
  settings.width = 160;
  settings.height = 90;
  settings.samples_per_pixel = 4;
  const SphereTraceResult gt = tracer.render(settings);
  settings.one_step_floor = true;
  const SphereTraceResult floor = tracer.render(settings);

  const uint64_t samples = 160u * 90u * 4u;
  EXPECT_LE(floor.total_steps, samples);
  EXPECT_GT(floor.total_steps, samples / 2) << "primitives' ground and shapes fill most of the frame";
  EXPECT_EQ(floor.capped_rays, 0u);
  EXPECT_EQ(floor.restarted_rays, 0u);
  ASSERT_EQ(floor.passes.size(), 1u);
  EXPECT_EQ(floor.passes[0].name, "one_step_floor");
  // GT but for the refining step onto the surface (0.997 at this size).
  EXPECT_GE(metrics::ssim(encode_srgb(gt.colour_linear), encode_srgb(floor.colour_linear)).mean_ssim, 0.99);

  // The buffer of sample depths follows the sample count: at 16 spp every sample still starts at
  // its own depth (a mix-up would start samples at other samples' depths, far from GT's frame).
  settings.samples_per_pixel = 16;
  const SphereTraceResult floor_16 = tracer.render(settings);
  settings.one_step_floor = false;
  const SphereTraceResult gt_16 = tracer.render(settings);
  EXPECT_EQ(floor_16.restarted_rays, 0u);
  EXPECT_GE(metrics::ssim(encode_srgb(gt_16.colour_linear), encode_srgb(floor_16.colour_linear)).mean_ssim, 0.99);
}

TEST(OneStepFloorValidation, IsMeasuredOnGroundTruthOnly) {
  SphereTraceSettings settings;
  settings.one_step_floor = true;
  settings.method = TraceMethod::inverted_pyramid;
  try {
    validate(settings);
    FAIL() << "expected a SettingError";
  } catch (const SettingError& error) {
    EXPECT_EQ(error.field, "one_step_floor");
  }
  settings.method = TraceMethod::ground_truth;
  EXPECT_NO_THROW(validate(settings));
}

}  // namespace
}  // namespace fovlab
