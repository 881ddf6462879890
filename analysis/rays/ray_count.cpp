#include "analysis/rays/ray_count.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/input_error.h"
#include "core/number_text.h"

namespace fovlab::analysis {

namespace {

void require_zone_angle(double angle_deg, const char* zone) {
  if (!std::isfinite(angle_deg) || angle_deg < 0.0) {
    throw InputError(std::string(zone) + " zone angle " + format_number(angle_deg, 6) +
                     ": expected a finite angle of at least 0 degrees");
  }
}

}  // namespace

EccentricityTable::EccentricityTable(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px) {
  if (display.width_px <= 0 || display.height_px <= 0) {
    throw InputError("display resolution " + std::to_string(display.width_px) + "x" +
                     std::to_string(display.height_px) + ": expected a positive width and height in pixels");
  }
  if (!std::isfinite(gaze_x_px) || !std::isfinite(gaze_y_px)) {
    throw InputError("gaze point (" + format_number(gaze_x_px, 6) + ", " + format_number(gaze_y_px, 6) +
                     "): expected finite pixel coordinates");
  }
  sorted_eccentricity_deg_.reserve(static_cast<size_t>(display.width_px) * static_cast<size_t>(display.height_px));
  for (int y = 0; y < display.height_px; ++y) {
    for (int x = 0; x < display.width_px; ++x) {
      sorted_eccentricity_deg_.push_back(eccentricity_deg(display, gaze_x_px, gaze_y_px, x + 0.5, y + 0.5));
    }
  }
  std::sort(sorted_eccentricity_deg_.begin(), sorted_eccentricity_deg_.end());
}

int64_t EccentricityTable::pixels_within(double eccentricity_deg) const {
  // upper_bound: a pixel exactly on the bound is inside.
  return std::upper_bound(sorted_eccentricity_deg_.begin(), sorted_eccentricity_deg_.end(), eccentricity_deg) -
         sorted_eccentricity_deg_.begin();
}

RayCell count_rays(const EccentricityTable& table, double foveal_deg, double middle_deg) {
  require_zone_angle(foveal_deg, "foveal");
  require_zone_angle(middle_deg, "middle");
  RayCell cell;
  cell.foveal_deg = foveal_deg;
  cell.middle_deg = middle_deg;
  // A zone of (full) aperture A holds the pixels whose centre lies within A / 2 of the gaze point.
  cell.foveal_pixels = table.pixels_within(foveal_deg / 2.0);
  cell.middle_pixels = std::max<int64_t>(0, table.pixels_within(middle_deg / 2.0) - cell.foveal_pixels);
  cell.outer_pixels = table.pixel_count() - cell.foveal_pixels - cell.middle_pixels;
  cell.rays = static_cast<double>(cell.foveal_pixels) + static_cast<double>(cell.middle_pixels) / 4.0 +
              static_cast<double>(cell.outer_pixels) / 16.0;
  cell.speedup = static_cast<double>(table.pixel_count()) / cell.rays;
  return cell;
}

std::vector<RayCell> count_ray_grid(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px,
                                    const std::vector<double>& foveal_deg, const std::vector<double>& middle_deg) {
  // Check the angles before the table costs anything.
  for (double angle : foveal_deg) require_zone_angle(angle, "foveal");
  for (double angle : middle_deg) require_zone_angle(angle, "middle");
  const EccentricityTable table(display, gaze_x_px, gaze_y_px);
  std::vector<RayCell> cells;
  cells.reserve(foveal_deg.size() * middle_deg.size());
  for (double foveal : foveal_deg) {
    for (double middle : middle_deg) cells.push_back(count_rays(table, foveal, middle));
  }
  return cells;
}

}  // namespace fovlab::analysis
