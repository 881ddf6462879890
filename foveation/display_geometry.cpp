#include "foveation/display_geometry.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/input_error.h"
#include "core/number_text.h"

namespace fovlab {

namespace {

constexpr double kMmPerInch = 25.4;
constexpr double kDegreesPerRadian = 180.0 / std::numbers::pi;

void require_positive_pixels(int width_px, int height_px) {
  if (width_px <= 0 || height_px <= 0) {
    throw InputError("display resolution " + std::to_string(width_px) + "x" + std::to_string(height_px) +
                     ": expected a positive width and height in pixels");
  }
}

void require_positive(double value, const char* what) {
  if (!std::isfinite(value) || value <= 0.0) {
    throw InputError(std::string(what) + " " + format_number(value, 6) + ": expected a positive finite number");
  }
}

// A point of the display's plane as seen from the eye: the eye is the origin, the display lies on
// z = viewing distance with the principal point on the z axis, x to the right and y downwards (like
// pixel rows), all in millimetres.
struct Ray {
  double x, y, z;
};

Ray ray_to(const DisplayGeometry& display, double x_px, double y_px) {
  return {(x_px - display.principal_point_x_px()) * display.pixel_pitch_x_mm(),
          (y_px - display.principal_point_y_px()) * display.pixel_pitch_y_mm(), display.viewing_distance_mm};
}

void require_angle_pair(double low_rad, double high_rad, const char* low_name, const char* high_name) {
  const double limit = 0.5 * std::numbers::pi;
  if (!std::isfinite(low_rad) || !std::isfinite(high_rad) ||
      !(-limit < low_rad && low_rad < high_rad && high_rad < limit)) {
    throw InputError(std::string("eye field of view: ") + low_name + " " +
                     format_number(low_rad * kDegreesPerRadian, 6) + " deg, " + high_name + " " +
                     format_number(high_rad * kDegreesPerRadian, 6) + " deg: expected -90 < " + low_name + " < " +
                     high_name + " < 90 degrees");
  }
}

// The same direction with its largest component of magnitude 1, so that products of two rays
// neither overflow nor underflow for points far off the screen.
Ray normalised_scale(const Ray& r) {
  const double largest = std::max({std::fabs(r.x), std::fabs(r.y), std::fabs(r.z)});
  return {r.x / largest, r.y / largest, r.z / largest};
}

}  // namespace

double DisplayGeometry::pixels_per_degree_at_principal_point() const {
  // At the principal point a small angle dθ (radians) covers D dθ millimetres of the display.
  return viewing_distance_mm / kDegreesPerRadian / pixel_pitch_x_mm();
}

double DisplayGeometry::pixels_per_degree_at_centre() const { return pixels_per_degree_at_principal_point(); }

DisplayGeometry display_from_diagonal(int width_px, int height_px, double diagonal_in, double viewing_distance_mm) {
  require_positive_pixels(width_px, height_px);
  require_positive(diagonal_in, "display diagonal (inches)");
  require_positive(viewing_distance_mm, "viewing distance (mm)");
  const double diagonal_px = std::hypot(static_cast<double>(width_px), static_cast<double>(height_px));
  const double pitch_mm = diagonal_in * kMmPerInch / diagonal_px;  // square pixels
  return display_from_size(width_px, height_px, pitch_mm * width_px, pitch_mm * height_px, viewing_distance_mm);
}

DisplayGeometry display_from_size(int width_px, int height_px, double width_mm, double height_mm,
                                  double viewing_distance_mm) {
  require_positive_pixels(width_px, height_px);
  require_positive(width_mm, "display width (mm)");
  require_positive(height_mm, "display height (mm)");
  require_positive(viewing_distance_mm, "viewing distance (mm)");
  return DisplayGeometry{width_px, height_px, width_mm, height_mm, viewing_distance_mm};
}

DisplayGeometry display_from_field_of_view(int width_px, int height_px, const EyeFieldOfView& field_of_view) {
  require_positive_pixels(width_px, height_px);
  require_angle_pair(field_of_view.angle_left_rad, field_of_view.angle_right_rad, "angle_left", "angle_right");
  require_angle_pair(field_of_view.angle_down_rad, field_of_view.angle_up_rad, "angle_down", "angle_up");
  const double tan_left = std::tan(field_of_view.angle_left_rad), tan_right = std::tan(field_of_view.angle_right_rad);
  const double tan_up = std::tan(field_of_view.angle_up_rad), tan_down = std::tan(field_of_view.angle_down_rad);
  const double distance_mm = kFieldOfViewPlaneDistanceMm;
  DisplayGeometry display{width_px, height_px, distance_mm * (tan_right - tan_left), distance_mm * (tan_up - tan_down),
                          distance_mm};
  // Where the tan-angles are 0: x / width = -tan_left / (tan_right - tan_left), y / height = tan_up / (tan_up - tan_down).
  display.principal_offset_x_px = width_px * (-tan_left / (tan_right - tan_left) - 0.5);
  display.principal_offset_y_px = height_px * (tan_up / (tan_up - tan_down) - 0.5);
  return display;
}

double eccentricity_deg(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px, double x_px, double y_px) {
  // angle = atan2(|a x b|, a . b): accurate for every angle, unlike acos of the normalised dot
  // product, which loses about half the digits near 0 (and can leave [-1, 1] by rounding).
  const Ray a = normalised_scale(ray_to(display, gaze_x_px, gaze_y_px));
  const Ray b = normalised_scale(ray_to(display, x_px, y_px));
  const double cross_x = a.y * b.z - a.z * b.y;
  const double cross_y = a.z * b.x - a.x * b.z;
  const double cross_z = a.x * b.y - a.y * b.x;
  const double dot = a.x * b.x + a.y * b.y + a.z * b.z;
  return std::atan2(std::sqrt(cross_x * cross_x + cross_y * cross_y + cross_z * cross_z), dot) * kDegreesPerRadian;
}

}  // namespace fovlab
