// Numerical stress: the camera from 1e-3 to 1e5 scene units off the geometry, and rays grazing a
// plane. Every pixel stays finite, no ray passes the step cap uncounted, and IPR shows the surfaces
// GT shows (within the SSIM bound of the IPR tests).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "metrics/image_metrics.h"
#include "core/colour.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

using test::VulkanTest;

struct StressCase {
  const char* scene_file;
  float log10_distance;  // the fixture's camera parameter (scene time)
};

class NumericalStress : public VulkanTest, public ::testing::WithParamInterface<StressCase> {};

// "stress_distance_at_1e-3": readable CTest names.
std::string case_name(const ::testing::TestParamInfo<StressCase>& info) {
  std::string name = std::string(info.param.scene_file);
  name = name.substr(0, name.find('.')) + "_at_1e" + std::to_string(int(info.param.log10_distance));
  for (char& c : name) {
    if (c == '-') c = 'm';
  }
  return name;
}

TEST_P(NumericalStress, FramesStayFiniteCappedRaysAreCountedAndIprMatchesGt) {
  const StressCase& stress = GetParam();
  SphereTracer tracer(context(),
                      load_scene(std::string(FOVLAB_SOURCE_DIR) + "/tests/fixtures/scenes/" + stress.scene_file));
  SphereTraceSettings settings;
  settings.width = 96;
  settings.height = 64;
  settings.time_s = stress.log10_distance;
  settings.max_steps = 256;
  settings.method = TraceMethod::ground_truth;
  const SphereTraceResult gt = tracer.render(settings);
  settings.method = TraceMethod::inverted_pyramid;
  const SphereTraceResult ipr = tracer.render(settings);

  for (const SphereTraceResult* result : {&gt, &ipr}) {
    ASSERT_TRUE(std::all_of(result->colour_linear.pixels.begin(), result->colour_linear.pixels.end(),
                            [](float v) { return std::isfinite(v) && v >= 0.0f; }));
  }
  // A GT pixel traces one ray (spp 1): no pixel may pass the cap, and every ray counted as capped
  // must be a pixel that used exactly the cap.
  const std::vector<float>& steps = gt.steps_per_pixel.pixels;
  EXPECT_LE(*std::max_element(steps.begin(), steps.end()), float(settings.max_steps));
  const auto pixels_at_cap = uint64_t(std::count(steps.begin(), steps.end(), float(settings.max_steps)));
  EXPECT_LE(gt.capped_rays, pixels_at_cap);

  const double ssim = metrics::ssim(encode_srgb(gt.colour_linear), encode_srgb(ipr.colour_linear)).mean_ssim;
  EXPECT_GE(ssim, 0.995) << stress.scene_file << " at 10^" << stress.log10_distance;
}

INSTANTIATE_TEST_SUITE_P(CameraDistance, NumericalStress,
                         ::testing::Values(StressCase{"stress_distance.glsl", -3.0f},
                                           StressCase{"stress_distance.glsl", -1.0f},
                                           StressCase{"stress_distance.glsl", 1.0f},
                                           StressCase{"stress_distance.glsl", 3.0f},
                                           StressCase{"stress_distance.glsl", 5.0f}),
                         case_name);
INSTANTIATE_TEST_SUITE_P(Grazing, NumericalStress,
                         ::testing::Values(StressCase{"stress_grazing.glsl", -3.0f},
                                           StressCase{"stress_grazing.glsl", -2.0f},
                                           StressCase{"stress_grazing.glsl", -1.0f}),
                         case_name);

}  // namespace
}  // namespace fovlab
