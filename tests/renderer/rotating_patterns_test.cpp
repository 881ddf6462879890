// Ye et al. 2022's Figure 12 patterns (stimuli/scenes/rotating-*.glsl): the rod, the textured rod and the
// texture turn about the view axis by 10 degrees per second of scene time, counter-clockwise on
// screen; a half turn gives the same frame back; the textures carry fine detail and fill the frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "core/colour.h"
#include "core/image.h"
#include "metrics/image_metrics.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

using test::VulkanTest;

constexpr float kDegreesPerSecond = 10.0f;  // docs/scenes.md: the angle is 10 x time_s

// Rod probes (128x72): the rod's luma is about 0.95, the plain plane's about 0.28.
constexpr float kRodLumaAbove = 0.6f;
constexpr float kPlaneLumaBelow = 0.4f;

// The luma of a ground-truth frame at one pattern angle, sRGB-encoded as a viewer sees it, 1 sample
// a pixel.
Image render_luma(SphereTracer& tracer, float angle_deg, int width, int height) {
  SphereTraceSettings settings;
  settings.method = TraceMethod::ground_truth;
  settings.width = width;
  settings.height = height;
  settings.samples_per_pixel = 1;
  settings.time_s = angle_deg / kDegreesPerSecond;
  settings.outputs = TraceOutputs::colour;
  const SphereTraceResult result = tracer.render(settings);
  EXPECT_EQ(result.capped_rays, 0u) << "angle " << angle_deg;
  return metrics::luma(encode_srgb(result.colour_linear));
}

double psnr_db(const Image& a, const Image& b) { return metrics::psnr(a, b).psnr_db; }

// Luma of the pixel holding the point `distance_px` from the frame's centre in the direction
// `direction_deg` (counter-clockwise from the right, screen y down).
float luma_towards(const Image& image, float direction_deg, float distance_px) {
  const float direction_rad = direction_deg * std::numbers::pi_v<float> / 180.0f;
  const int x = int(std::floor(0.5f * float(image.width) + distance_px * std::cos(direction_rad)));
  const int y = int(std::floor(0.5f * float(image.height) - distance_px * std::sin(direction_rad)));
  return image.at(x, y, 0);
}

// Mean squared step between neighbouring pixels along a band through the frame's centre: four
// rows (`vertical` false) over the middle 60 % of the width, or four columns over the middle 80 % of
// the height. Along a rod lying in that band this is the rod's own detail; the edges do not count.
double band_step_energy(const Image& image, bool vertical) {
  double sum = 0.0;
  int count = 0;
  const int across_centre = vertical ? image.width / 2 : image.height / 2;
  const int along_length = vertical ? image.height : image.width;
  const double margin = vertical ? 0.1 : 0.2;
  for (int across = across_centre - 2; across < across_centre + 2; ++across) {
    for (int along = int(margin * along_length); along < int((1.0 - margin) * along_length); ++along) {
      const float here = vertical ? image.at(across, along, 0) : image.at(along, across, 0);
      const float next = vertical ? image.at(across, along + 1, 0) : image.at(along + 1, across, 0);
      sum += double(next - here) * double(next - here);
      ++count;
    }
  }
  return sum / count;
}

// Mean squared discrete Laplacian over the frame's interior: its high-frequency energy.
double laplacian_energy(const Image& image) {
  double sum = 0.0;
  for (int y = 1; y + 1 < image.height; ++y) {
    for (int x = 1; x + 1 < image.width; ++x) {
      const double laplacian = 4.0 * image.at(x, y, 0) - image.at(x - 1, y, 0) - image.at(x + 1, y, 0) -
                               image.at(x, y - 1, 0) - image.at(x, y + 1, 0);
      sum += laplacian * laplacian;
    }
  }
  return sum / (double(image.width - 2) * double(image.height - 2));
}

// Standard deviation of the luma in a size x size block with top-left corner (x0, y0).
double block_deviation(const Image& image, int x0, int y0, int size) {
  double sum = 0.0, sum_squares = 0.0;
  for (int y = y0; y < y0 + size; ++y) {
    for (int x = x0; x < x0 + size; ++x) {
      sum += image.at(x, y, 0);
      sum_squares += double(image.at(x, y, 0)) * image.at(x, y, 0);
    }
  }
  const double count = double(size) * size;
  const double mean = sum / count;
  return std::sqrt(std::max(sum_squares / count - mean * mean, 0.0));
}

// Every step of Ye et al. 2022's sweep, 0..180 degrees by 10: the rod lies along the step's angle
// (bright both ways from the centre) and not across it (the plain plane there).
TEST_F(VulkanTest, RotatingRodLiesAlongTenDegreesPerSecondCounterClockwise) {
  SphereTracer tracer(context(), load_scene("rotating-rod"));
  const float probe_px = 25.0f;  // inside the 72-pixel-high frame at every angle; the rod is ~113 px long
  for (int step = 0; step <= 18; ++step) {
    const float angle_deg = 10.0f * float(step);
    const Image frame = render_luma(tracer, angle_deg, 128, 72);
    for (float side_deg : {0.0f, 180.0f}) {
      EXPECT_GT(luma_towards(frame, angle_deg + side_deg, probe_px), kRodLumaAbove)
          << "on the rod at " << angle_deg << " degrees, side " << side_deg;
      EXPECT_LT(luma_towards(frame, angle_deg + side_deg + 90.0f, probe_px), kPlaneLumaBelow)
          << "across the rod at " << angle_deg << " degrees, side " << side_deg;
    }
    EXPECT_GT(luma_towards(frame, 0.0f, 0.0f), kRodLumaAbove) << "the rod's middle stays at the centre";
  }
}

TEST_F(VulkanTest, RotatingRodIsTheSameAfterAHalfTurnAndDiffersAfterAQuarter) {
  SphereTracer tracer(context(), load_scene("rotating-rod"));
  const Image at_0 = render_luma(tracer, 0.0f, 128, 72);
  const Image at_90 = render_luma(tracer, 90.0f, 128, 72);
  const Image at_180 = render_luma(tracer, 180.0f, 128, 72);
  // About 52 dB: the camera's tiny tilt and the one-sided normal differences, nothing more.
  EXPECT_GT(psnr_db(at_0, at_180), 40.0);
  EXPECT_LT(psnr_db(at_0, at_90), 20.0);  // about 15 dB
}

// 256x144: an axial checker cell is about 1.5 pixels, resolved; at 128x72 the footprint filter
// averages the texture away.
TEST_F(VulkanTest, TexturedRodCarriesDetailAlongItsLengthThatThePlainRodLacks) {
  SphereTracer plain(context(), load_scene("rotating-rod"));
  SphereTracer textured(context(), load_scene("rotating-textured-rod"));
  for (float angle_deg : {0.0f, 90.0f}) {
    const bool vertical = angle_deg == 90.0f;
    const double plain_energy = band_step_energy(render_luma(plain, angle_deg, 256, 144), vertical);
    const double textured_energy = band_step_energy(render_luma(textured, angle_deg, 256, 144), vertical);
    EXPECT_LT(plain_energy, 1e-3) << angle_deg << " degrees: the plain rod is uniform along its length";
    EXPECT_GT(textured_energy, 0.01) << angle_deg << " degrees";  // about 0.065
    EXPECT_GT(textured_energy, 20.0 * plain_energy) << angle_deg << " degrees";
  }
  // Over the whole frame, edges included, the texture still more than doubles the energy (about 4x).
  EXPECT_GT(laplacian_energy(render_luma(textured, 0.0f, 256, 144)),
            2.0 * laplacian_energy(render_luma(plain, 0.0f, 256, 144)));
}

TEST_F(VulkanTest, TexturedRodIsTheSameAfterAHalfTurn) {
  SphereTracer tracer(context(), load_scene("rotating-textured-rod"));
  EXPECT_GT(psnr_db(render_luma(tracer, 0.0f, 256, 144), render_luma(tracer, 180.0f, 256, 144)), 40.0);
}

// 256x144: a checker cell is about 2.2 pixels and the grating's period 1.8 (filtered, not gone).
TEST_F(VulkanTest, RotatingTextureFillsTheFrameAndChangesWithEveryTurnButAHalf) {
  SphereTracer tracer(context(), load_scene("rotating-texture"));
  const Image at_0 = render_luma(tracer, 0.0f, 256, 144);
  const Image at_45 = render_luma(tracer, 45.0f, 256, 144);
  const Image at_90 = render_luma(tracer, 90.0f, 256, 144);
  const Image at_180 = render_luma(tracer, 180.0f, 256, 144);
  EXPECT_GT(psnr_db(at_0, at_180), 40.0);  // about 80 dB: both parts are point-symmetric
  EXPECT_LT(psnr_db(at_0, at_45), 25.0);   // about 16 dB
  EXPECT_LT(psnr_db(at_0, at_90), 25.0);   // about 13 dB: the oblique grating breaks the quarter turn
  // Textured to the corners at every angle (about 0.1 in each 16x16 corner block): the plane
  // reaches past the frame's diagonal, and no ray sees the flat background.
  for (const Image* frame : {&at_0, &at_45, &at_90}) {
    const int right = frame->width - 16, bottom = frame->height - 16;
    for (const auto& [x0, y0] : {std::pair{0, 0}, std::pair{right, 0}, std::pair{0, bottom}, std::pair{right, bottom}})
      EXPECT_GT(block_deviation(*frame, x0, y0, 16), 0.05) << "corner block at " << x0 << "," << y0;
  }
}

}  // namespace
}  // namespace fovlab
