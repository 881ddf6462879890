// A headset's gaze in each eye's image (protocols/gaze/headset_gaze.h): image positions and
// directions are each other's inverse for asymmetric and turned eyes, a point straight ahead shows
// each eye's disparity, points behind an eye have no pixel, mirrored eyes see mirrored pixels, and
// the two ways a gaze becomes both eyes' samples.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "protocols/gaze/headset_gaze.h"

namespace fovlab {
namespace {

constexpr double kIpdM = 0.063;
constexpr int kWidthPx = 48, kHeightPx = 40;

// A headset's left eye: asymmetric (more to the nose side inwards is less), and its mirror image.
EyeView left_eye() {
  EyeView eye;
  eye.position_in_head = {-0.5 * kIpdM, 0.0, 0.0};
  eye.field_of_view = field_of_view_from_deg(-52.0, 43.0, 48.0, -55.0);
  return eye;
}

EyeView mirrored(const EyeView& eye) {
  EyeView mirror = eye;
  mirror.position_in_head[0] = -eye.position_in_head[0];
  mirror.field_of_view.angle_left_rad = -eye.field_of_view.angle_right_rad;
  mirror.field_of_view.angle_right_rad = -eye.field_of_view.angle_left_rad;
  return mirror;
}

// A unit quaternion of `angle_deg` about the (unit) axis.
std::array<double, 4> about(const std::array<double, 3>& axis, double angle_deg) {
  const double half = 0.5 * angle_deg * std::numbers::pi / 180.0;
  return {axis[0] * std::sin(half), axis[1] * std::sin(half), axis[2] * std::sin(half), std::cos(half)};
}

HeadsetGazeGeometry geometry(double fixation_distance_m) {
  return {{left_eye(), mirrored(left_eye())}, kWidthPx, kHeightPx, fixation_distance_m};
}

TEST(HeadsetGaze, PixelToDirectionToPointToPixelRoundTrips) {
  EyeView turned = left_eye();
  turned.position_in_head = {-0.031, 0.012, -0.008};
  turned.orientation_in_head = about({0.6, 0.0, 0.8}, 7.0);
  EyeView narrow = mirrored(left_eye());
  narrow.field_of_view = field_of_view_from_deg(-10.0, 35.0, 5.0, -30.0);  // the axis near a corner
  int checked = 0;
  for (const EyeView& eye : {left_eye(), mirrored(left_eye()), turned, narrow})
    for (const auto& [x, y] : {std::pair{0.5, 0.5}, {24.0, 20.0}, {47.5, 39.5}, {3.25, 31.75}, {-6.0, 44.0}})
      for (double reach_m : {0.05, 0.7, 40.0}) {
        const std::array<double, 3> d = direction_of_eye_pixel(eye, kWidthPx, kHeightPx, x, y);
        EXPECT_NEAR(std::hypot(d[0], d[1], d[2]), 1.0, 1e-12);
        const std::array<double, 3> point{eye.position_in_head[0] + reach_m * d[0],
                                          eye.position_in_head[1] + reach_m * d[1],
                                          eye.position_in_head[2] + reach_m * d[2]};
        const auto pixel = eye_pixel_of_point(eye, kWidthPx, kHeightPx, point);
        ASSERT_TRUE(pixel) << x << "," << y;
        EXPECT_NEAR(pixel->first, x, 1e-9);
        EXPECT_NEAR(pixel->second, y, 1e-9);
        ++checked;
      }
  EXPECT_EQ(checked, 4 * 5 * 3);
}

// The pixel convention is the renderer's: pixel (x, y)'s centre, (x + 0.5, y + 0.5), looks along
// lerp(tan(left), tan(right), (x + 0.5) / width) across and lerp(tan(up), tan(down), ...) up, and
// the eye looks along its -z. Checked against those formulas directly, not through the inverse.
TEST(HeadsetGaze, PixelCentresLookAlongTheRenderersTanAngles) {
  const EyeView eye = left_eye();
  const EyeFieldOfView& fov = eye.field_of_view;
  const int x = 7, y = 30;
  const double tan_x = std::tan(fov.angle_left_rad) +
                       (std::tan(fov.angle_right_rad) - std::tan(fov.angle_left_rad)) * (x + 0.5) / kWidthPx;
  const double tan_up = std::tan(fov.angle_up_rad) +
                        (std::tan(fov.angle_down_rad) - std::tan(fov.angle_up_rad)) * (y + 0.5) / kHeightPx;
  const std::array<double, 3> d = direction_of_eye_pixel(eye, kWidthPx, kHeightPx, x + 0.5, y + 0.5);
  ASSERT_LT(d[2], 0.0);
  EXPECT_NEAR(d[0] / -d[2], tan_x, 1e-12);
  EXPECT_NEAR(d[1] / -d[2], tan_up, 1e-12);
  // The image's corners are its field of view's edges.
  const auto corner = eye_pixel_of_point(
      eye, kWidthPx, kHeightPx,
      {eye.position_in_head[0] + std::tan(fov.angle_left_rad), std::tan(fov.angle_up_rad), -1.0});
  ASSERT_TRUE(corner);
  EXPECT_NEAR(corner->first, 0.0, 1e-12);
  EXPECT_NEAR(corner->second, 0.0, 1e-12);
}

// A point straight ahead of the head at distance d lies atan(ipd / 2 / d) to the right eye's left
// and as far to the left eye's right, measured from each eye's forward axis.
TEST(HeadsetGaze, APointStraightAheadShowsEachEyesDisparity) {
  const HeadsetGazeGeometry headset = geometry(1.0);
  for (double d : {0.3, 1.0, 5.0}) {
    const double expected_rad = std::atan(0.5 * kIpdM / d);
    for (int e = 0; e < 2; ++e) {
      const EyeView& eye = headset.eyes[size_t(e)];
      const auto pixel = eye_pixel_of_point(eye, kWidthPx, kHeightPx, {0.0, 0.0, -d});
      ASSERT_TRUE(pixel);
      const EyeFieldOfView& fov = eye.field_of_view;
      const double tan_left = std::tan(fov.angle_left_rad), tan_right = std::tan(fov.angle_right_rad);
      const double angle_rad = std::atan(tan_left + (tan_right - tan_left) * pixel->first / kWidthPx);
      EXPECT_NEAR(angle_rad, e == 0 ? expected_rad : -expected_rad, 1e-12) << "eye " << e << " at " << d << " m";
      // On the eye's horizon: the row of its forward axis.
      const double tan_up = std::tan(fov.angle_up_rad), tan_down = std::tan(fov.angle_down_rad);
      EXPECT_NEAR(pixel->second, kHeightPx * tan_up / (tan_up - tan_down), 1e-9);
    }
  }
  // A nearer point is further apart in the two images.
  const auto near_right = eye_pixel_of_point(headset.eyes[1], kWidthPx, kHeightPx, {0.0, 0.0, -0.3});
  const auto far_right = eye_pixel_of_point(headset.eyes[1], kWidthPx, kHeightPx, {0.0, 0.0, -5.0});
  EXPECT_LT(near_right->first, far_right->first - 1.0);
}

TEST(HeadsetGaze, PointsNotInFrontOfTheEyeHaveNoPixel) {
  const EyeView eye = left_eye();
  EXPECT_FALSE(eye_pixel_of_point(eye, kWidthPx, kHeightPx, {0.0, 0.0, 1.0}));  // behind
  EXPECT_FALSE(eye_pixel_of_point(eye, kWidthPx, kHeightPx, {0.3, 0.1, 0.0}));  // in the eye's plane
  EXPECT_FALSE(eye_pixel_of_point(eye, kWidthPx, kHeightPx, {0.0, NAN, -1.0}));
  EXPECT_TRUE(eye_pixel_of_point(eye, kWidthPx, kHeightPx, {0.3, 0.1, -1e-3}));  // far off the image, in front
  // Turned half a turn about y, the eye looks backwards: the point behind the head is in front of it.
  EyeView backwards = eye;
  backwards.orientation_in_head = about({0.0, 1.0, 0.0}, 180.0);
  EXPECT_TRUE(eye_pixel_of_point(backwards, kWidthPx, kHeightPx, {0.0, 0.0, 1.0}));
  EXPECT_FALSE(eye_pixel_of_point(backwards, kWidthPx, kHeightPx, {0.0, 0.0, -1.0}));
  EXPECT_THROW(eye_pixel_of_point(eye, 0, kHeightPx, {0.0, 0.0, -1.0}), std::invalid_argument);
}

// Mirror-image eyes see a point and its mirror image (x -> -x) at mirrored pixels (x -> width - x).
TEST(HeadsetGaze, MirroredEyesSeeMirroredPixels) {
  const HeadsetGazeGeometry headset = geometry(1.0);
  for (const std::array<double, 3>& point :
       {std::array<double, 3>{0.0, 0.0, -0.8}, {0.21, -0.13, -0.6}, {-0.4, 0.3, -2.5}}) {
    const auto left = eye_pixel_of_point(headset.eyes[0], kWidthPx, kHeightPx, point);
    const auto right = eye_pixel_of_point(headset.eyes[1], kWidthPx, kHeightPx, {-point[0], point[1], point[2]});
    ASSERT_TRUE(left && right);
    EXPECT_NEAR(right->first, kWidthPx - left->first, 1e-9);
    EXPECT_NEAR(right->second, left->second, 1e-9);
  }
}

TEST(HeadsetGaze, ARayBecomesEachEyesViewOfItsFixationPoint) {
  HeadsetGazeGeometry headset = geometry(0.5);
  GazeSample template_sample;
  template_sample.time_s = 2.5;
  template_sample.acquired_s = 2.49;
  // A ray from between the eyes, a little right and down, of any length.
  const std::array<double, 3> direction{0.2, -0.1, -1.0};
  const auto samples = eye_gaze_from_ray(headset, {0.0, 0.0, 0.0}, {3 * direction[0], 3 * direction[1], -3.0},
                                         template_sample);
  const double n = std::hypot(direction[0], direction[1], direction[2]);
  const std::array<double, 3> point{0.5 * direction[0] / n, 0.5 * direction[1] / n, 0.5 * direction[2] / n};
  for (int e = 0; e < 2; ++e) {
    const GazeSample& sample = samples[size_t(e)];
    const auto expected = eye_pixel_of_point(headset.eyes[size_t(e)], kWidthPx, kHeightPx, point);
    ASSERT_TRUE(expected);
    EXPECT_TRUE(sample.valid);
    EXPECT_EQ(sample.time_s, 2.5);
    EXPECT_EQ(sample.acquired_s, 2.49);
    EXPECT_NEAR(sample.x_px, expected->first, 1e-9);
    EXPECT_NEAR(sample.y_px, expected->second, 1e-9);
  }
  // The near point's disparity: the two eyes' positions further apart than a far point's along the ray.
  headset.fixation_distance_m = 1000.0;
  const auto far = eye_gaze_from_ray(headset, {0.0, 0.0, 0.0}, direction, template_sample);
  EXPECT_GT(samples[0].x_px - samples[1].x_px, far[0].x_px - far[1].x_px + 2.0);
  headset.fixation_distance_m = 0.5;
  // Behind the head, or no direction: both invalid.
  const auto behind = eye_gaze_from_ray(headset, {0.0, 0.0, 0.0}, {0.0, 0.0, 1.0}, template_sample);
  EXPECT_FALSE(behind[0].valid || behind[1].valid);
  EXPECT_EQ(behind[1].invalid_reason, "off_screen");
  const auto none = eye_gaze_from_ray(headset, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, template_sample);
  EXPECT_FALSE(none[0].valid || none[1].valid);
  EXPECT_EQ(none[0].invalid_reason, "not_finite");
  // A ray from behind the head that ends short of the eyes' plane.
  const auto short_of = eye_gaze_from_ray(headset, {0.0, 0.0, 0.6}, {0.0, 0.0, -1.0}, template_sample);
  EXPECT_FALSE(short_of[0].valid || short_of[1].valid);
  // An invalid template stays invalid, with its reason.
  GazeSample blink = template_sample;
  blink.valid = false;
  blink.invalid_reason = "blink";
  const auto blinked = eye_gaze_from_ray(headset, {0.0, 0.0, 0.0}, direction, blink);
  EXPECT_EQ(blinked[0].invalid_reason, "blink");
  EXPECT_EQ(blinked[1].invalid_reason, "blink");
  EXPECT_FALSE(blinked[0].valid || blinked[1].valid);
  headset.fixation_distance_m = 0.0;
  EXPECT_THROW(eye_gaze_from_ray(headset, {0.0, 0.0, 0.0}, direction, template_sample), std::invalid_argument);
}

TEST(HeadsetGaze, TheLeftEyesPixelGivesTheRightEyesThroughTheFixationPlane) {
  const HeadsetGazeGeometry headset = geometry(0.75);
  GazeSample left;
  left.time_s = 1.0;
  left.x_px = 31.25;
  left.y_px = 12.5;
  const auto samples = eye_gaze_from_left_eye_pixel(headset, left);
  EXPECT_TRUE(samples[0].valid && samples[1].valid);
  EXPECT_EQ(samples[0].x_px, 31.25);  // the left eye's as given
  EXPECT_EQ(samples[0].y_px, 12.5);
  EXPECT_EQ(samples[1].time_s, 1.0);
  // The right eye's pixel looks at the point of the left eye's ray on the plane z = -0.75.
  const std::array<double, 3> from_left = direction_of_eye_pixel(headset.eyes[0], kWidthPx, kHeightPx, 31.25, 12.5);
  const std::array<double, 3> from_right =
      direction_of_eye_pixel(headset.eyes[1], kWidthPx, kHeightPx, samples[1].x_px, samples[1].y_px);
  const double along_left = 0.75 / -from_left[2], along_right = 0.75 / -from_right[2];
  EXPECT_NEAR(-0.5 * kIpdM + along_left * from_left[0], 0.5 * kIpdM + along_right * from_right[0], 1e-12);
  EXPECT_NEAR(along_left * from_left[1], along_right * from_right[1], 1e-12);
  // Straight ahead of the head, the same as the ray from the head's origin.
  const auto ahead = eye_pixel_of_point(headset.eyes[0], kWidthPx, kHeightPx, {0.0, 0.0, -0.75});
  GazeSample centre = left;
  centre.x_px = ahead->first;
  centre.y_px = ahead->second;
  const auto from_pixel = eye_gaze_from_left_eye_pixel(headset, centre);
  const auto from_ray = eye_gaze_from_ray(headset, {0.0, 0.0, 0.0}, {0.0, 0.0, -1.0}, centre);
  EXPECT_NEAR(from_pixel[1].x_px, from_ray[1].x_px, 1e-9);
  EXPECT_NEAR(from_pixel[1].y_px, from_ray[1].y_px, 1e-9);
  // An invalid left sample gives two invalid samples.
  GazeSample lost = left;
  lost.valid = false;
  lost.invalid_reason = "no_data";
  const auto both = eye_gaze_from_left_eye_pixel(headset, lost);
  EXPECT_FALSE(both[0].valid || both[1].valid);
  EXPECT_EQ(both[1].invalid_reason, "no_data");
}

// Rendered depth (gaze_fixation "rendered-depth"): the ray rests hit_distance_m along its unit
// direction, each eye's pixel that point's; no hit rests it at optical infinity, where both eyes see
// the ray's direction; no fixation distance is needed.
TEST(HeadsetGaze, ARayRestingOnTheRenderedDepthGivesEachEyeThePixelOfTheHitPoint) {
  const HeadsetGazeGeometry headset = geometry(0.0);  // rendered-depth: no fixation distance
  GazeSample template_sample;
  template_sample.time_s = 3.0;
  const std::array<double, 3> origin{0.01, -0.02, 0.0}, direction{0.6, -0.3, -2.0};
  const double n = std::hypot(direction[0], direction[1], direction[2]);
  const double hit_m = 0.8;
  const auto samples = eye_gaze_from_ray_at_depth(headset, origin, direction, hit_m, template_sample);
  const std::array<double, 3> point{origin[0] + hit_m * direction[0] / n, origin[1] + hit_m * direction[1] / n,
                                    origin[2] + hit_m * direction[2] / n};
  for (size_t e = 0; e < 2; ++e) {
    const auto expected = eye_pixel_of_point(headset.eyes[e], kWidthPx, kHeightPx, point);
    ASSERT_TRUE(expected);
    EXPECT_TRUE(samples[e].valid);
    EXPECT_EQ(samples[e].time_s, 3.0);
    EXPECT_NEAR(samples[e].x_px, expected->first, 1e-9);
    EXPECT_NEAR(samples[e].y_px, expected->second, 1e-9);
  }
  // The same as the fixation plane through that point, from the head's origin straight ahead.
  HeadsetGazeGeometry at_plane = geometry(0.8);
  const auto ahead = eye_gaze_from_ray_at_depth(headset, {0.0, 0.0, 0.0}, {0.0, 0.0, -1.0}, 0.8, template_sample);
  const auto plane = eye_gaze_from_ray(at_plane, {0.0, 0.0, 0.0}, {0.0, 0.0, -1.0}, template_sample);
  for (size_t e = 0; e < 2; ++e) EXPECT_NEAR(ahead[e].x_px, plane[e].x_px, 1e-9);
  // The sky: the direction in each eye, the eyes' disparity gone (mirrored eyes: mirrored pixels).
  const auto sky = eye_gaze_from_ray_at_depth(headset, origin, {0.0, 0.0, -1.0}, std::nullopt, template_sample);
  ASSERT_TRUE(sky[0].valid && sky[1].valid);
  EXPECT_NEAR(sky[0].x_px, kWidthPx - sky[1].x_px, 1e-9);
  EXPECT_NEAR(sky[0].y_px, sky[1].y_px, 1e-9);
  const auto left_of_direction = eye_pixel_of_direction(headset.eyes[0], kWidthPx, kHeightPx, {0.0, 0.0, -1.0});
  ASSERT_TRUE(left_of_direction);
  EXPECT_NEAR(sky[0].x_px, left_of_direction->first, 1e-12);
  EXPECT_GT(samples[0].x_px - samples[1].x_px,
            eye_gaze_from_ray_at_depth(headset, origin, direction, std::nullopt, template_sample)[0].x_px -
                eye_gaze_from_ray_at_depth(headset, origin, direction, std::nullopt, template_sample)[1].x_px + 1.0)
      << "a near hit has more disparity than the sky";
  // Invalid: a distance that is not one, a ray behind the eyes at infinity, a hit at an eye's place.
  EXPECT_EQ(eye_gaze_from_ray_at_depth(headset, origin, direction, NAN, template_sample)[1].invalid_reason,
            "not_finite");
  EXPECT_EQ(eye_gaze_from_ray_at_depth(headset, origin, direction, -0.1, template_sample)[0].invalid_reason,
            "not_finite");
  EXPECT_EQ(eye_gaze_from_ray_at_depth(headset, origin, {0.0, 0.0, 1.0}, std::nullopt, template_sample)[0].invalid_reason,
            "off_screen");
  GazeSample blink = template_sample;
  blink.valid = false;
  blink.invalid_reason = "blink";
  EXPECT_EQ(eye_gaze_from_ray_at_depth(headset, origin, direction, hit_m, blink)[1].invalid_reason, "blink");
}

TEST(HeadsetGaze, TheLeftEyesPixelGivesTheRightEyesThroughTheRenderedDepth) {
  const HeadsetGazeGeometry headset = geometry(0.0);
  GazeSample left;
  left.time_s = 1.0;
  left.x_px = 31.25;
  left.y_px = 12.5;
  const std::optional<GazeRay> ray = left_eye_ray_of_pixel(headset, left.x_px, left.y_px);
  ASSERT_TRUE(ray);
  EXPECT_EQ(ray->origin_m, headset.eyes[0].position_in_head);
  const auto samples = eye_gaze_from_left_eye_pixel_at_depth(headset, left, 1.25);
  EXPECT_TRUE(samples[0].valid && samples[1].valid);
  EXPECT_EQ(samples[0].x_px, 31.25);  // the left eye's as given
  EXPECT_EQ(samples[0].y_px, 12.5);
  // The right eye's pixel looks at the point 1.25 along the left eye's ray.
  const std::array<double, 3> point{ray->origin_m[0] + 1.25 * ray->direction[0],
                                    ray->origin_m[1] + 1.25 * ray->direction[1],
                                    ray->origin_m[2] + 1.25 * ray->direction[2]};
  const auto expected = eye_pixel_of_point(headset.eyes[1], kWidthPx, kHeightPx, point);
  ASSERT_TRUE(expected);
  EXPECT_NEAR(samples[1].x_px, expected->first, 1e-9);
  EXPECT_NEAR(samples[1].y_px, expected->second, 1e-9);
  // The left eye sees that point at its own pixel again.
  const auto back = eye_pixel_of_point(headset.eyes[0], kWidthPx, kHeightPx, point);
  EXPECT_NEAR(back->first, 31.25, 1e-9);
  // No hit: the right eye sees the left eye's direction.
  const auto sky = eye_gaze_from_left_eye_pixel_at_depth(headset, left, std::nullopt);
  const auto direction_pixel = eye_pixel_of_direction(headset.eyes[1], kWidthPx, kHeightPx, ray->direction);
  EXPECT_NEAR(sky[1].x_px, direction_pixel->first, 1e-9);
  EXPECT_NEAR(sky[1].y_px, direction_pixel->second, 1e-9);
  GazeSample lost = left;
  lost.valid = false;
  lost.invalid_reason = "no_data";
  EXPECT_EQ(eye_gaze_from_left_eye_pixel_at_depth(headset, lost, 1.0)[1].invalid_reason, "no_data");
  GazeSample nowhere = left;
  nowhere.x_px = INFINITY;
  EXPECT_EQ(eye_gaze_from_left_eye_pixel_at_depth(headset, nowhere, 1.0)[1].invalid_reason, "not_finite");
  EXPECT_FALSE(left_eye_ray_of_pixel(headset, NAN, 1.0));
}

}  // namespace
}  // namespace fovlab
