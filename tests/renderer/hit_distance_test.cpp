// SphereTracer::hit_distance (issue 42: a headset's gaze resting on the rendered depth) against a
// scene whose distances are known exactly (tests/fixtures/scenes/gaze_wall.glsl): a wall 1 in front
// of the camera and a ball of radius 0.2 before it; rays that leave the bounds meet the sky.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <optional>
#include <string>

#include "core/input_error.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

using SphereTracerHitDistance = test::VulkanTest;

constexpr double kHitAngleRad = 2e-3;
// The shader marches in float: a few ulps of t per step, over tens of steps.
constexpr double kFloatRelative = 1e-5;

SceneSource gaze_wall() { return load_scene(std::string(FOVLAB_SOURCE_DIR) + "/tests/fixtures/scenes/gaze_wall.glsl"); }

SurfaceRay ray_along(const std::array<double, 3>& direction, const std::array<double, 3>& origin = {0.0, 0.0, 0.0},
                     float time_s = 0.0f) {
  SurfaceRay ray;
  ray.time_s = time_s;
  ray.origin_in_head = origin;
  ray.direction_in_head = direction;
  ray.hit_angle_rad = kHitAngleRad;
  return ray;
}

double norm(const std::array<double, 3>& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

// The header's bound: never beyond the surface, short of it by at most hit_angle x t / cos(incidence).
void expect_within_hit_band(const std::optional<double>& traced, double analytic, double cos_incidence) {
  ASSERT_TRUE(traced.has_value()) << "expected a hit at " << analytic;
  const double rounding = kFloatRelative * analytic;
  EXPECT_LE(*traced, analytic + rounding);
  EXPECT_GE(*traced, analytic - kHitAngleRad * analytic / cos_incidence - rounding);
}

TEST_F(SphereTracerHitDistance, MeetsTheWallWithinTheHitBand) {
  SphereTracer tracer(context(), gaze_wall());
  expect_within_hit_band(tracer.hit_distance(ray_along({0.0, 0.0, -1.0})), 1.0, 1.0);
  // Oblique: the plane z = -1 is 1 / cos(incidence) along the unit ray, cos = |d.z| / |d|.
  const std::array<double, 3> oblique{0.6, -0.4, -1.0};
  expect_within_hit_band(tracer.hit_distance(ray_along(oblique)), norm(oblique), 1.0 / norm(oblique));
  // From an eye's place (the left eye, 31.5 mm left of the head's origin), length of the direction ignored.
  expect_within_hit_band(tracer.hit_distance(ray_along({0.0, 0.0, -7.0}, {-0.0315, 0.02, 0.0})), 1.0, 1.0);
}

TEST_F(SphereTracerHitDistance, MeetsTheBallInFrontOfTheWall) {
  SphereTracer tracer(context(), gaze_wall());
  // Towards the ball's centre: its surface is |centre| - radius away, met head-on.
  const std::array<double, 3> centre{-0.5, 0.0, -0.7};
  expect_within_hit_band(tracer.hit_distance(ray_along(centre)), norm(centre) - 0.2, 1.0);
}

TEST_F(SphereTracerHitDistance, TracesTheSceneAtTheTimeAsked) {
  SphereTracer tracer(context(), gaze_wall());
  // The camera (the head) moves 0.5 towards the wall between 1 s and 2 s.
  expect_within_hit_band(tracer.hit_distance(ray_along({0.0, 0.0, -1.0}, {0.0, 0.0, 0.0}, 2.0f)), 0.5, 1.0);
  expect_within_hit_band(tracer.hit_distance(ray_along({0.0, 0.0, -1.0}, {0.0, 0.0, 0.0}, 0.5f)), 1.0, 1.0);
}

TEST_F(SphereTracerHitDistance, ASkyRayMeetsNothing) {
  SphereTracer tracer(context(), gaze_wall());
  EXPECT_EQ(tracer.hit_distance(ray_along({0.0, 1.0, -0.2})), std::nullopt) << "leaves the bounds above the wall";
  EXPECT_EQ(tracer.hit_distance(ray_along({0.0, 0.0, 1.0})), std::nullopt) << "backwards, away from the wall";
  // and the tracer still meets the wall afterwards (its buffers reused)
  expect_within_hit_band(tracer.hit_distance(ray_along({0.0, 0.0, -1.0})), 1.0, 1.0);
}

TEST_F(SphereTracerHitDistance, RefusesARayThatIsNone) {
  SphereTracer tracer(context(), gaze_wall());
  EXPECT_THROW(tracer.hit_distance(ray_along({0.0, 0.0, 0.0})), SettingError);
  EXPECT_THROW(tracer.hit_distance(ray_along({NAN, 0.0, -1.0})), SettingError);
  EXPECT_THROW(tracer.hit_distance(ray_along({0.0, 0.0, -1.0}, {INFINITY, 0.0, 0.0})), SettingError);
  SurfaceRay no_band = ray_along({0.0, 0.0, -1.0});
  no_band.hit_angle_rad = 0.0;
  EXPECT_THROW(tracer.hit_distance(no_band), SettingError);
}

}  // namespace
}  // namespace fovlab
