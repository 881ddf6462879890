#include "foveation/zone_layout.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/input_error.h"
#include "core/number_text.h"

namespace fovlab {

namespace {

// 1 inside the boundary, 0 outside, a linear ramp across the band centred on it.
double inside_weight(double eccentricity_deg, double boundary_deg, double band_deg) {
  if (band_deg <= 0.0) return eccentricity_deg <= boundary_deg ? 1.0 : 0.0;
  return std::clamp((boundary_deg + 0.5 * band_deg - eccentricity_deg) / band_deg, 0.0, 1.0);
}

void check_angle(double value, const char* name) {
  if (!std::isfinite(value) || value < 0.0)
    throw InputError(std::string(name) + ": expected a finite angle >= 0 degrees, got " + exact_number_text(value));
}

}  // namespace

double default_middle_deg(double foveal_deg) { return foveal_deg + kMiddleOverFovealDeg; }

void check_zone_bounds(const ZoneBounds& bounds) {
  check_angle(bounds.foveal_deg, "foveal_deg");
  check_angle(bounds.middle_deg, "middle_deg");
  check_angle(bounds.band_deg, "band_deg");
}

ZoneWeights zone_weights(const ZoneBounds& bounds, double eccentricity_deg) {
  if (!std::isfinite(eccentricity_deg)) return {1.0, 0.0, 0.0};
  ZoneWeights weights;
  weights.foveal = inside_weight(eccentricity_deg, 0.5 * bounds.foveal_deg, bounds.band_deg);
  const double within_middle = bounds.middle_deg > bounds.foveal_deg
                                   ? inside_weight(eccentricity_deg, 0.5 * bounds.middle_deg, bounds.band_deg)
                                   : 0.0;
  weights.middle = (1.0 - weights.foveal) * within_middle;
  weights.outer = 1.0 - weights.foveal - weights.middle;
  return weights;
}

Image blend_zones_reference(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px,
                            const ZoneBounds& bounds, const Image& foveal, const Image& middle, const Image& outer) {
  const auto same_shape = [&](const Image& image) {
    return image.width == foveal.width && image.height == foveal.height && image.channels == foveal.channels;
  };
  if (!same_shape(middle) || !same_shape(outer) || foveal.width != display.width_px ||
      foveal.height != display.height_px)
    throw InputError("zone buffers: expected three images of the display's " + std::to_string(display.width_px) + "x" +
                     std::to_string(display.height_px) + " pixels with the same channels");
  Image blended(foveal.width, foveal.height, foveal.channels);
  for (int y = 0; y < foveal.height; ++y)
    for (int x = 0; x < foveal.width; ++x) {
      const ZoneWeights w = zone_weights(bounds, eccentricity_deg(display, gaze_x_px, gaze_y_px, x + 0.5, y + 0.5));
      for (int c = 0; c < foveal.channels; ++c)
        blended.at(x, y, c) = static_cast<float>(w.foveal * foveal.at(x, y, c) + w.middle * middle.at(x, y, c) +
                                                 w.outer * outer.at(x, y, c));
    }
  return blended;
}

Image zone_map(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px, const ZoneBounds& bounds) {
  Image map(display.width_px, display.height_px, 3);
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const ZoneWeights w = zone_weights(bounds, eccentricity_deg(display, gaze_x_px, gaze_y_px, x + 0.5, y + 0.5));
      map.at(x, y, 0) = static_cast<float>(w.foveal);
      map.at(x, y, 1) = static_cast<float>(w.middle);
      map.at(x, y, 2) = static_cast<float>(w.outer);
    }
  return map;
}

Image decimate_nearest(const Image& image, int factor) {
  if (factor < 1) throw std::invalid_argument("decimate_nearest: factor must be >= 1");
  Image out((image.width + factor - 1) / factor, (image.height + factor - 1) / factor, image.channels);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      const int source_x = std::min(x * factor + factor / 2, image.width - 1);
      const int source_y = std::min(y * factor + factor / 2, image.height - 1);
      for (int c = 0; c < image.channels; ++c) out.at(x, y, c) = image.at(source_x, source_y, c);
    }
  return out;
}

}  // namespace fovlab
