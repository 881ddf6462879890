// The off-axis display geometry of a headset eye (foveation/display_geometry.h): an image plane made
// from an eye's four field-of-view angles, its principal point where the eye's perpendicular meets
// it, and the exact eccentricity on it, checked in closed form. The square-on display's own checks are
// in tests/analysis/rays/ray_count_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "core/input_error.h"
#include "foveation/display_geometry.h"

namespace fovlab {
namespace {

constexpr double kDegrees = 180.0 / std::numbers::pi;
double radians(double degrees) { return degrees / kDegrees; }

// The left eye of the test runtime's headset (tests/xr_runtime): 54 degrees to the temple, 49 to
// the nose, 54 up and 56 down.
EyeFieldOfView left_eye() { return {radians(-54.0), radians(49.0), radians(54.0), radians(-56.0)}; }

// The angle at the eye between the rays through two pixel points, from the eye's tan-angles alone
// (the image-plane mapping of the brief: pixel x at lerp(tan left, tan right, x / w), y down).
double angle_between_deg(const EyeFieldOfView& fov, int width, int height, double ax, double ay, double bx, double by) {
  const auto ray = [&](double x, double y) {
    const double tx =
        std::tan(fov.angle_left_rad) + (std::tan(fov.angle_right_rad) - std::tan(fov.angle_left_rad)) * x / width;
    const double ty =
        std::tan(fov.angle_up_rad) + (std::tan(fov.angle_down_rad) - std::tan(fov.angle_up_rad)) * y / height;
    return std::vector<double>{tx, ty, 1.0};
  };
  const std::vector<double> a = ray(ax, ay), b = ray(bx, by);
  const double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  return std::acos(dot / std::sqrt((a[0] * a[0] + a[1] * a[1] + 1.0) * (b[0] * b[0] + b[1] * b[1] + 1.0))) * kDegrees;
}

TEST(OffAxisDisplay, PrincipalPointIsWhereTheTanAnglesAreZero) {
  const EyeFieldOfView fov = left_eye();
  const DisplayGeometry d = display_from_field_of_view(144, 160, fov);
  const double tl = std::tan(fov.angle_left_rad), tr = std::tan(fov.angle_right_rad);
  const double tu = std::tan(fov.angle_up_rad), td = std::tan(fov.angle_down_rad);
  EXPECT_NEAR(d.principal_point_x_px(), 144 * -tl / (tr - tl), 1e-9);
  EXPECT_NEAR(d.principal_point_y_px(), 160 * tu / (tu - td), 1e-9);
  // Wider to the temple (left): the axis meets the image right of its centre; more below than above:
  // above the centre (y down).
  EXPECT_GT(d.principal_offset_x_px, 1.0);
  EXPECT_LT(d.principal_offset_y_px, -0.5);
  // The image's edges lie at the four angles from the principal point.
  const double px = d.principal_point_x_px(), py = d.principal_point_y_px();
  EXPECT_NEAR(eccentricity_deg(d, px, py, 0.0, py), 54.0, 1e-9);
  EXPECT_NEAR(eccentricity_deg(d, px, py, 144.0, py), 49.0, 1e-9);
  EXPECT_NEAR(eccentricity_deg(d, px, py, px, 0.0), 54.0, 1e-9);
  EXPECT_NEAR(eccentricity_deg(d, px, py, px, 160.0), 56.0, 1e-9);
}

TEST(OffAxisDisplay, GazeAtThePrincipalPointIsAtanOfDistanceOverPlaneDistance) {
  const DisplayGeometry d = display_from_field_of_view(144, 160, left_eye());
  const double px = d.principal_point_x_px(), py = d.principal_point_y_px();
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{
           {0.5, 0.5}, {143.5, 159.5}, {px + 1.0, py}, {10.0, 150.0}, {-500.0, 80.0}}) {
    const double d_mm = std::hypot((x - px) * d.pixel_pitch_x_mm(), (y - py) * d.pixel_pitch_y_mm());
    EXPECT_NEAR(eccentricity_deg(d, px, py, x, y), std::atan(d_mm / d.viewing_distance_mm) * kDegrees, 1e-10)
        << x << "," << y;
  }
  // The image's centre is off the axis: 20 pixels from it are not atan(d / D) away.
  const double twenty_px_deg = std::atan(20.0 * d.pixel_pitch_x_mm() / d.viewing_distance_mm) * kDegrees;
  EXPECT_GT(std::fabs(eccentricity_deg(d, 72.0, 80.0, 92.0, 80.0) - twenty_px_deg), 1e-3);
}

TEST(OffAxisDisplay, EccentricityIsTheAngleBetweenTheEyesRays) {
  const EyeFieldOfView fov = left_eye();
  const DisplayGeometry d = display_from_field_of_view(64, 72, fov);
  const std::vector<std::pair<double, double>> points = {
      {0.5, 0.5}, {32.0, 36.0}, {63.5, 10.5}, {5.0, 70.0}, {40.25, 3.75}};
  for (const auto& [gx, gy] : points)
    for (const auto& [x, y] : points) {
      if (gx == x && gy == y) continue;
      EXPECT_NEAR(eccentricity_deg(d, gx, gy, x, y), angle_between_deg(fov, 64, 72, gx, gy, x, y), 1e-8)
          << gx << "," << gy << " " << x << "," << y;
    }
}

TEST(OffAxisDisplay, PixelsPerDegreeAtThePrincipalPoint) {
  const DisplayGeometry d = display_from_field_of_view(1440, 1600, left_eye());
  const double ppd = d.pixels_per_degree_at_principal_point();
  // That many pixels right of the principal point lie atan(pi / 180) radians out.
  const double px = d.principal_point_x_px(), py = d.principal_point_y_px();
  EXPECT_NEAR(eccentricity_deg(d, px, py, px + ppd, py), std::atan(1.0 / kDegrees) * kDegrees, 1e-10);
  // 1440 pixels over tan(54) + tan(49) of the plane's distance: 9.95 pixels a degree there.
  EXPECT_NEAR(ppd, 1440.0 / (std::tan(radians(54.0)) + std::tan(radians(49.0))) / kDegrees, 1e-9);
  EXPECT_NEAR(ppd, 9.9467, 1e-4);
}

TEST(OffAxisDisplay, SymmetricFieldOfViewIsTheSquareOnDisplay) {
  const double half = radians(30.0);
  const DisplayGeometry d = display_from_field_of_view(80, 80, {-half, half, half, -half});
  EXPECT_EQ(d.principal_offset_x_px, 0.0);
  EXPECT_EQ(d.principal_offset_y_px, 0.0);
  const DisplayGeometry square_on = display_from_size(80, 80, d.width_mm, d.height_mm, d.viewing_distance_mm);
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{{0.5, 0.5}, {79.5, 12.5}, {33.0, 61.0}})
    EXPECT_EQ(eccentricity_deg(d, 20.0, 30.0, x, y), eccentricity_deg(square_on, 20.0, 30.0, x, y));
}

TEST(OffAxisDisplay, BadAnglesNameTheField) {
  const auto message = [](const EyeFieldOfView& fov) {
    try {
      display_from_field_of_view(64, 72, fov);
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message({radians(10.0), radians(-10.0), radians(20.0), radians(-20.0)}),
            "eye field of view: angle_left 10 deg, angle_right -10 deg: expected -90 < angle_left < angle_right < 90 "
            "degrees");
  EXPECT_NE(message({radians(-10.0), radians(10.0), radians(-20.0), radians(20.0)}).find("angle_down"),
            std::string::npos);
  EXPECT_NE(message({radians(-90.0), radians(10.0), radians(20.0), radians(-20.0)}).find("angle_left"),
            std::string::npos);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message({-0.5, 0.5, nan, -0.5}).find("angle_up"), std::string::npos);
  EXPECT_THROW(display_from_field_of_view(0, 72, left_eye()), InputError);
}

}  // namespace
}  // namespace fovlab
