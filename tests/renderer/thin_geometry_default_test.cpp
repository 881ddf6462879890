// Thin geometry safe by default (issue 41, log schema 10): IPR's and FIPR's default stimuli (the
// cone without the min filter, FIPR's edges from the centre ray; study/stimulus/render_method.cpp)
// show the wires, rods, rings and plate GT's frame of the `wires` scene shows, where the paper's
// pyramid (ray, 3x3: their defaults before schema 10) loses some; and each is at least as close to
// GT as its method's default before schema 10.
//
// "A thin feature GT shows" is a pixel of GT's frame darker than the median of its 5x5
// neighbourhood by more than a third of that median: a wire, the fence, a rod, a ring or the plate
// against the pale wall. A frame keeps it when a pixel within one pixel of it is darker than its
// own frame's 5x5 median there by more than a sixth: shown, perhaps a pixel off or at half the
// contrast (FIPR's periphery is interpolated from the mid level), but not gone. At 1 spp a wire a
// twentieth of a pixel wide shows where a sample happens to pass within the hit band, and which
// samples do depends on where each march's steps land (GT's own frame is not stable at that level,
// docs/benchmarks.md), so a frame may miss one in 500 of GT's; the paper's pyramid misses 1.5-2 %
// (measured: IPR 44 and FIPR 32 of 2135; the defaults 1 and 0). 160x90, 1 spp, FIPR gazing at the
// centre on the bench's display (238x134 mm at 100 mm, docs/benchmarks.md), so most of the frame is
// periphery.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "protocols/stimuli/stimulus_settings.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "study/stimulus/render_method.h"
#include "study/stimulus/stimulus_spec.h"
#include "tests/renderer/frame_ssim.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

using test::srgb_ssim;
using test::VulkanTest;

constexpr int kWidth = 160;
constexpr int kHeight = 90;

// The settings of a default stimulus of `method` on `wires` (FIPR: the bench's display, gaze at the centre).
SphereTraceSettings default_settings(RenderMethod method) {
  StimulusSpec spec;
  spec.scene = "wires";
  spec.width_px = kWidth;
  spec.height_px = kHeight;
  spec.parameters = default_parameters(method);
  if (auto* fipr = std::get_if<FoveatedPyramidParameters>(&spec.parameters)) fipr->display = {238.0, 134.0, 100.0};
  SphereTraceSettings settings = sphere_trace_settings(spec, 0);
  settings.foveation.gaze_x_px = kWidth * 0.5;
  settings.foveation.gaze_y_px = kHeight * 0.5;
  return settings;
}

std::vector<float> luminance(const Image& colour) {
  std::vector<float> y(size_t(colour.width) * size_t(colour.height));
  for (int row = 0; row < colour.height; ++row)
    for (int x = 0; x < colour.width; ++x)
      y[size_t(row) * size_t(colour.width) + size_t(x)] =
          0.2126f * colour.at(x, row, 0) + 0.7152f * colour.at(x, row, 1) + 0.0722f * colour.at(x, row, 2);
  return y;
}

// Per pixel, (median of its 5x5 neighbourhood (clamped at the borders) - luminance) / that median:
// how much darker than its surroundings it is.
std::vector<float> darker_than_neighbourhood(const Image& colour) {
  const std::vector<float> y = luminance(colour);
  std::vector<float> darker(y.size());
  std::array<float, 25> window{};
  for (int row = 0; row < colour.height; ++row)
    for (int x = 0; x < colour.width; ++x) {
      size_t n = 0;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const int sx = std::clamp(x + dx, 0, colour.width - 1), sy = std::clamp(row + dy, 0, colour.height - 1);
          window[n++] = y[size_t(sy) * size_t(colour.width) + size_t(sx)];
        }
      std::nth_element(window.begin(), window.begin() + 12, window.end());
      const size_t i = size_t(row) * size_t(colour.width) + size_t(x);
      darker[i] = (window[12] - y[i]) / std::max(window[12], 1e-4f);
    }
  return darker;
}

struct ThinFeatures {
  int shown_by_gt = 0;
  int missing = 0;  // of those, none within a pixel in the test frame
};

ThinFeatures thin_features_kept(const SphereTraceResult& gt, const SphereTraceResult& test) {
  const std::vector<float> gt_contrast = darker_than_neighbourhood(gt.colour_linear);
  const std::vector<float> test_contrast = darker_than_neighbourhood(test.colour_linear);
  const int width = gt.colour_linear.width, height = gt.colour_linear.height;
  ThinFeatures features;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      if (gt_contrast[size_t(y) * size_t(width) + size_t(x)] <= 1.0f / 3.0f) continue;
      ++features.shown_by_gt;
      bool kept = false;
      for (int dy = -1; dy <= 1 && !kept; ++dy)
        for (int dx = -1; dx <= 1 && !kept; ++dx) {
          const int sx = x + dx, sy = y + dy;
          kept = sx >= 0 && sy >= 0 && sx < width && sy < height &&
                 test_contrast[size_t(sy) * size_t(width) + size_t(sx)] > 1.0f / 6.0f;
        }
      features.missing += kept ? 0 : 1;
    }
  return features;
}

TEST_F(VulkanTest, DefaultPyramidsKeepEveryWireGroundTruthShows) {
  SphereTracer tracer(context(), load_scene("wires"));
  SphereTraceSettings gt_settings = default_settings(RenderMethod::ground_truth);
  const SphereTraceResult gt = tracer.render(gt_settings);
  const SphereTraceSettings ipr_settings = default_settings(RenderMethod::inverted_pyramid);
  const SphereTraceSettings fipr_settings = default_settings(RenderMethod::foveated_pyramid);
  ASSERT_EQ(ipr_settings.coarse_test, CoarseTest::cone);
  ASSERT_EQ(fipr_settings.coarse_test, CoarseTest::cone);
  const SphereTraceResult ipr = tracer.render(ipr_settings);
  const SphereTraceResult fipr = tracer.render(fipr_settings);

  // IPR's default before log schema 10: the paper's pyramid, as a schema 9 log reads it.
  SphereTraceSettings before = ipr_settings;
  const ParameterDescriptor& coarse_test = *find_parameter(describe(RenderMethod::inverted_pyramid), "coarse_test");
  const ParameterDescriptor& min_filter = *find_parameter(describe(RenderMethod::inverted_pyramid), "min_filter_size");
  before.coarse_test = static_cast<CoarseTest>(int(default_in_log_schema(coarse_test, 9)));
  before.min_filter_size = int(default_in_log_schema(min_filter, 9));
  ASSERT_EQ(before.coarse_test, CoarseTest::centre_ray);
  ASSERT_EQ(before.min_filter_size, 3);
  const SphereTraceResult ipr_before = tracer.render(before);
  SphereTraceSettings fipr_before_settings = fipr_settings;
  fipr_before_settings.coarse_test = before.coarse_test;
  fipr_before_settings.min_filter_size = before.min_filter_size;
  const SphereTraceResult fipr_before = tracer.render(fipr_before_settings);

  const ThinFeatures in_ipr = thin_features_kept(gt, ipr);
  const ThinFeatures in_fipr = thin_features_kept(gt, fipr);
  const ThinFeatures in_ipr_before = thin_features_kept(gt, ipr_before);
  const ThinFeatures in_fipr_before = thin_features_kept(gt, fipr_before);
  RecordProperty("gt_thin_feature_pixels", in_ipr.shown_by_gt);
  RecordProperty("missing_ipr_fipr_ipr_before_fipr_before",
                 std::to_string(in_ipr.missing) + " " + std::to_string(in_fipr.missing) + " " +
                     std::to_string(in_ipr_before.missing) + " " + std::to_string(in_fipr_before.missing));
  ASSERT_GT(in_ipr.shown_by_gt, kWidth * kHeight / 20) << "the scene shows its wires";
  const int allowed = in_ipr.shown_by_gt / 500;  // GT's own aliasing at 1 spp (above)
  EXPECT_LE(in_ipr.missing, allowed) << "of " << in_ipr.shown_by_gt;
  EXPECT_LE(in_fipr.missing, allowed) << "of " << in_fipr.shown_by_gt;
  // What the defaults fix: the paper's pyramid loses wires, in IPR's frame and FIPR's.
  EXPECT_GT(in_ipr_before.missing, 5 * allowed) << "of " << in_ipr_before.shown_by_gt;
  EXPECT_GT(in_fipr_before.missing, 5 * allowed) << "of " << in_fipr_before.shown_by_gt;

  EXPECT_GE(srgb_ssim(gt, ipr), srgb_ssim(gt, ipr_before));
  EXPECT_GE(srgb_ssim(gt, fipr), srgb_ssim(gt, fipr_before));
}

}  // namespace
}  // namespace fovlab
