// A headset eye's view in the renderers (renderer/scene/eye_view.h): in the sphere tracer the
// asymmetric frustum against the symmetric frame it is a window of, the eye's offset against the
// disparity the geometry gives, the eye's orientation; the path tracer and the volume raycaster with
// an eye at the head against the camera's own frame; the view's checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/input_error.h"
#include "renderer/path_tracing/courtyard_scene.h"
#include "renderer/path_tracing/path_tracer.h"
#include "renderer/scene/eye_view.h"
#include "renderer/scene/scene_source.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "renderer/volume/volume_grid.h"
#include "renderer/volume/volume_raycaster.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

using test::VulkanTest;

// The largest difference of any channel, and how many pixels differ by more than `tolerance`.
struct Difference {
  float largest = 0.0f;
  int pixels_over = 0;
};

Difference difference(const Image& crop_of, int x0, int y0, const Image& frame, float tolerance) {
  Difference d;
  for (int y = 0; y < frame.height; ++y)
    for (int x = 0; x < frame.width; ++x) {
      float pixel = 0.0f;
      for (int c = 0; c < 3; ++c) pixel = std::max(pixel, std::fabs(crop_of.at(x0 + x, y0 + y, c) - frame.at(x, y, c)));
      d.largest = std::max(d.largest, pixel);
      d.pixels_over += pixel > tolerance ? 1 : 0;
    }
  return d;
}

// An eye whose frustum is the window (x0, y0, w, h) of a symmetric frame of W x H pixels with the
// vertical tan-half-angle T: the symmetric frame's pixel column X looks along T (X + 0.5 - W / 2) / (H / 2)
// (rows likewise, up positive), so the window's edges are at these tan-angles.
EyeView window_of(double tan_half_fov, int big_width, int big_height, int x0, int y0, int w, int h) {
  const double half_h = 0.5 * big_height;
  EyeView eye;
  eye.field_of_view = {std::atan(tan_half_fov * (x0 - 0.5 * big_width) / half_h),
                       std::atan(tan_half_fov * (x0 + w - 0.5 * big_width) / half_h),
                       std::atan(tan_half_fov * (half_h - y0) / half_h),
                       std::atan(tan_half_fov * (half_h - y0 - h) / half_h)};
  return eye;
}

// "primitives" (its scene_camera): 50 degrees vertical.
constexpr double kPrimitivesTanHalfFov = 0.46630765815499858;  // tan(25 degrees)

// GT of an asymmetric view equals the matching window of a symmetric GT frame at the same pixel
// density. Not bit for bit: the eye's ray is forward + tx right + ty up with tx, ty interpolated
// between float tangents (made in double from the angles, then rounded), the symmetric ray
// forward + T (ndc.x right - ndc.y up), so each direction differs by a few float ulps; a march that
// grazes a surface may then take one step more or less and land a hair elsewhere. The tolerance:
// 1e-3 of the linear range on any channel for all but 0.5 % of the pixels (a silhouette pixel whose
// ray passes within the hit threshold of an edge may flip on another device); on lavapipe every
// pixel is within 2.4e-5. A window one pixel off differs on about a third of its pixels.
TEST_F(VulkanTest, AsymmetricGroundTruthIsTheWindowOfTheSymmetricFrame) {
  SphereTracer tracer(context(), load_scene("primitives"));
  SphereTraceSettings symmetric;
  symmetric.width = 128;
  symmetric.height = 96;
  symmetric.outputs = TraceOutputs::colour;
  symmetric.time_s = 1.5f;
  const SphereTraceResult big = tracer.render(symmetric);
  for (const auto& [x0, y0] : {std::pair{40, 10}, std::pair{0, 24}, std::pair{64, 0}}) {
    SphereTraceSettings eye = symmetric;
    eye.width = 64;
    eye.height = 72;
    eye.eye = window_of(kPrimitivesTanHalfFov, 128, 96, x0, y0, 64, 72);
    const SphereTraceResult window = tracer.render(eye);
    const Difference d = difference(big.colour_linear, x0, y0, window.colour_linear, 1e-3f);
    EXPECT_LE(d.pixels_over, 64 * 72 / 200) << "window at " << x0 << "," << y0 << ", largest " << d.largest;
    // The window is not all one colour (so that a frustum shifted by a pixel would show).
    const auto [lo, hi] = std::minmax_element(window.colour_linear.pixels.begin(), window.colour_linear.pixels.end());
    EXPECT_GT(*hi - *lo, 0.2f);
    // A window one pixel off is far worse: the check can fail.
    if (x0 + 1 + 64 <= 128) {
      const Difference off = difference(big.colour_linear, x0 + 1, y0, window.colour_linear, 1e-3f);
      EXPECT_GT(off.pixels_over, 4 * std::max(d.pixels_over, 8)) << "window at " << x0 << "," << y0;
    }
  }
}

// A symmetric view of the scene camera's own angles, the eye at the head: the eye path's image is
// the scene camera's (the same window argument, the whole frame).
TEST_F(VulkanTest, EyeAtTheHeadWithTheScenesAnglesIsTheDesktopFrame) {
  SphereTracer tracer(context(), load_scene("primitives"));
  SphereTraceSettings desktop;
  desktop.width = 64;
  desktop.height = 48;
  desktop.outputs = TraceOutputs::colour;
  SphereTraceSettings eye = desktop;
  eye.eye = window_of(kPrimitivesTanHalfFov, 64, 48, 0, 0, 64, 48);
  const Difference d = difference(tracer.render(desktop).colour_linear, 0, 0, tracer.render(eye).colour_linear, 1e-3f);
  EXPECT_LE(d.pixels_over, 64 * 48 / 200) << "largest " << d.largest;
}

// The rod's column in a frame of "rotating-rod" at 9 s (the rod runs down the frame; the dark ground
// plane fills the rest): the mean column weighted by the green channel above the plane's (about
// 0.06), so that the pixels the rod's edges cover in part count in part.
double rod_column(const Image& frame) {
  double sum = 0.0, weight = 0.0;
  for (int y = 0; y < frame.height; ++y)
    for (int x = 0; x < frame.width; ++x) {
      const double w = std::max(0.0, double(frame.at(x, y, 1)) - 0.1);
      sum += w * (x + 0.5);
      weight += w;
    }
  return weight > 0.0 ? sum / weight : -1.0;
}

// The eyes' offset along the head's right axis shifts a near object by the disparity the geometry
// gives: "rotating-rod" looks straight down from 4 units at a rod whose top is 3.75 units away and
// its axis 3.8; at 9 s the rod runs down the frame. Eyes at -+b/2 see it b / Z apart in tan-angle,
// b / Z / (tan span / width) pixels; the ground plane (4 units, uniform) does not show it.
TEST_F(VulkanTest, EyeOffsetShiftsANearObjectByItsDisparity) {
  SphereTracer tracer(context(), load_scene("rotating-rod"));
  const double tan_half = 0.25;  // the scene's vertical field of view: 2 atan(1 / 4)
  SphereTraceSettings settings;
  settings.width = 96;
  settings.height = 64;
  settings.samples_per_pixel = 4;
  settings.time_s = 9.0f;
  settings.outputs = TraceOutputs::colour;
  const double tan_half_x = tan_half * 96.0 / 64.0;
  const double baseline = 0.2;  // scene units between the eyes
  double columns[2] = {0.0, 0.0};
  for (int eye = 0; eye < 2; ++eye) {
    EyeView view;
    view.position_in_head = {(eye == 0 ? -0.5 : 0.5) * baseline, 0.0, 0.0};
    view.field_of_view = {-std::atan(tan_half_x), std::atan(tan_half_x), std::atan(tan_half), -std::atan(tan_half)};
    settings.eye = view;
    columns[eye] = rod_column(tracer.render(settings).colour_linear);
    ASSERT_GT(columns[eye], 0.0) << "eye " << eye << " sees the rod";
  }
  const double pixels_per_tan = 96.0 / (2.0 * tan_half_x);
  const double expected_px = baseline / 3.8 * pixels_per_tan;  // 6.74 pixels (measured 6.75)
  // The left eye sees the rod further right. Its visible surface lies 3.75 to 3.8 units away: 1.3 %.
  EXPECT_NEAR(columns[0] - columns[1], expected_px, 0.02 * expected_px + 0.1);
  // Without the offset the rod is between the two.
  settings.eye->position_in_head = {0.0, 0.0, 0.0};
  const double centre = rod_column(tracer.render(settings).colour_linear);
  EXPECT_NEAR(columns[0] - centre, 0.5 * expected_px, 0.02 * expected_px + 0.1);
}

// The eye's orientation turns its axes: rolled half a turn about its forward axis (a quaternion
// (0, 0, 1, 0) about z), a symmetric view shows the unrolled frame rotated by 180 degrees.
TEST_F(VulkanTest, EyeOrientationTurnsTheView) {
  SphereTracer tracer(context(), load_scene("primitives"));
  SphereTraceSettings settings;
  settings.width = 64;
  settings.height = 48;
  settings.outputs = TraceOutputs::colour;
  settings.eye = window_of(kPrimitivesTanHalfFov, 64, 48, 0, 0, 64, 48);
  const Image upright = tracer.render(settings).colour_linear;
  settings.eye->orientation_in_head = {0.0, 0.0, 1.0, 0.0};
  const Image rolled = tracer.render(settings).colour_linear;
  int over = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 3; ++c)
        if (std::fabs(upright.at(x, y, c) - rolled.at(63 - x, 47 - y, c)) > 1e-3f) {
          ++over;
          break;
        }
  EXPECT_LE(over, 64 * 48 / 200);
  EXPECT_NE(upright.pixels, rolled.pixels);
}

// An eye whose four angles are the symmetric frustum of a camera's vertical field of view on a
// width x height frame, at the given position in the head.
EyeView symmetric_eye(double vertical_fov_deg, int width, int height, double x_in_head = 0.0) {
  const double tan_half = std::tan(vertical_fov_deg * std::numbers::pi / 360.0);
  const double tan_half_x = tan_half * width / height;
  EyeView eye;
  eye.position_in_head = {x_in_head, 0.0, 0.0};
  eye.field_of_view = {-std::atan(tan_half_x), std::atan(tan_half_x), std::atan(tan_half), -std::atan(tan_half)};
  return eye;
}

// The path tracer (Polychronakis et al. 2021's reference frames): an eye at the head with the
// camera's own angles traces the camera's frame (the same pixels and random numbers; the ray's
// direction only rounded differently, so a path may scatter differently where a ray grazes an edge:
// the mean differs by under 1 %), and an eye 0.3 units to the right another one.
TEST_F(VulkanTest, PathTracedEyeAtTheHeadIsTheCamerasFrame) {
  const PathScene scene = courtyard_scene();
  PathTracer tracer(context(), scene);
  PathTraceSettings settings;
  settings.width_px = 48;
  settings.height_px = 32;
  settings.samples_per_pixel = 4;
  settings.max_bounces = 2;
  const Image camera = tracer.render(settings).image;
  settings.eye = symmetric_eye(scene.camera.vertical_fov_deg, 48, 32);
  const Image eye = tracer.render(settings).image;
  double sum_camera = 0.0, sum_difference = 0.0;
  int close = 0;
  for (size_t i = 0; i < camera.pixels.size(); ++i) {
    sum_camera += camera.pixels[i];
    sum_difference += std::fabs(camera.pixels[i] - eye.pixels[i]);
    close += std::fabs(camera.pixels[i] - eye.pixels[i]) <= 1e-3f * std::max(1.0f, camera.pixels[i]) ? 1 : 0;
  }
  EXPECT_LT(sum_difference, 0.01 * sum_camera);
  EXPECT_GT(close, int(camera.pixels.size()) * 9 / 10);
  settings.eye->position_in_head[0] = 0.3;
  EXPECT_NE(tracer.render(settings).image.pixels, eye.pixels);
}

// The volume raycaster (Bruder et al. 2019): the same for its full frame, and the eye's offset moves
// the view.
TEST_F(VulkanTest, VolumeEyeAtTheHeadIsTheCamerasFrame) {
  VolumeScene scene;
  scene.name = "test";
  scene.transfer_function = {{0.0, {0.0, 0.0, 0.0}, 0.0}, {0.3, {0.2, 0.1, 0.0}, 0.0}, {1.0, {1.0, 0.7, 0.3}, 0.6}};
  VolumeGrid grid;
  grid.size_voxels = {16, 16, 16};
  grid.values.resize(grid.voxel_count());
  for (size_t i = 0; i < grid.values.size(); ++i)  // a ramp along x with a bright column
    grid.values[i] = uint16_t((i % 16) * 4000 + ((i / 16) % 16 == 8 ? 3000 : 0));
  VolumeRaycaster raycaster(context(), scene, grid);
  VolumeRenderSettings settings;
  settings.width_px = 40;
  settings.height_px = 32;
  const Image camera = raycaster.render_full(settings).colour_linear;
  settings.eye = symmetric_eye(scene.camera.vertical_fov_deg, 40, 32);
  const Image eye = raycaster.render_full(settings).colour_linear;
  int over = 0;
  for (size_t i = 0; i < camera.pixels.size(); ++i) over += std::fabs(camera.pixels[i] - eye.pixels[i]) > 1e-3f;
  EXPECT_LE(over, int(camera.pixels.size()) / 100);
  const auto [lo, hi] = std::minmax_element(eye.pixels.begin(), eye.pixels.end());
  EXPECT_GT(*hi - *lo, 0.1f) << "the frame shows the volume";
  settings.eye->position_in_head[0] = 0.2;
  EXPECT_NE(raycaster.render_full(settings).colour_linear.pixels, eye.pixels);
}

TEST(EyeViewValues, BadViewsNameTheirField) {
  EyeView view;
  view.field_of_view = {-0.5, 0.5, 0.4, -0.4};
  EXPECT_NO_THROW(eye_view_shader_values(view));
  view.orientation_in_head = {0.0, 0.0, 0.0, 2.0};
  try {
    eye_view_shader_values(view);
    FAIL() << "a quaternion of length 2";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "eye view orientation_in_head: a quaternion of length 2; expected a unit quaternion");
  }
  view.orientation_in_head = {0.0, 0.0, 0.0, 1.0};
  view.position_in_head[1] = std::nan("");
  EXPECT_THROW(eye_view_shader_values(view), InputError);
  view.position_in_head[1] = 0.0;
  view.field_of_view.angle_up_rad = -0.5;
  EXPECT_THROW(eye_view_shader_values(view), InputError);
  SphereTraceSettings settings;
  settings.eye = view;
  EXPECT_THROW(validate(settings), InputError);
}

}  // namespace
}  // namespace fovlab
