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
// z = viewing distance, x to the right and y downwards (like pixel rows), all in millimetres.
struct Ray {
  double x, y, z;
};

Ray ray_to(const DisplayGeometry& display, double x_px, double y_px) {
  return {(x_px - 0.5 * display.width_px) * display.pixel_pitch_x_mm(),
          (y_px - 0.5 * display.height_px) * display.pixel_pitch_y_mm(), display.viewing_distance_mm};
}

// The same direction with its largest component of magnitude 1, so that products of two rays
// neither overflow nor underflow for points far off the screen.
Ray normalised_scale(const Ray& r) {
  const double largest = std::max({std::fabs(r.x), std::fabs(r.y), std::fabs(r.z)});
  return {r.x / largest, r.y / largest, r.z / largest};
}

}  // namespace

double DisplayGeometry::pixels_per_degree_at_centre() const {
  // At the centre a small angle dθ (radians) covers D dθ millimetres of the display.
  return viewing_distance_mm / kDegreesPerRadian / pixel_pitch_x_mm();
}

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
