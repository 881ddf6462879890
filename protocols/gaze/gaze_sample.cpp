#include "protocols/gaze/gaze_sample.h"

#include <cmath>

namespace fovlab {

namespace {

bool usable(const GazeSample& sample, int width_px, int height_px) {
  return sample.valid && std::isfinite(sample.x_px) && std::isfinite(sample.y_px) && sample.x_px >= 0.0 &&
         sample.y_px >= 0.0 && sample.x_px < width_px && sample.y_px < height_px;
}

}  // namespace

GazeSample sanitize_gaze(const GazeSample& raw, int width_px, int height_px, const GazeSample* last_valid) {
  std::string reason;
  if (!raw.valid) {
    reason = raw.invalid_reason.empty() ? "no_data" : raw.invalid_reason;
  } else if (!std::isfinite(raw.x_px) || !std::isfinite(raw.y_px)) {
    reason = "not_finite";
  } else if (raw.x_px < 0.0 || raw.y_px < 0.0 || raw.x_px >= width_px || raw.y_px >= height_px) {
    reason = "off_screen";
  } else {
    return raw;
  }

  GazeSample held;
  held.time_s = raw.time_s;
  held.valid = false;
  held.invalid_reason = std::move(reason);
  // The held position must itself be a usable one; otherwise fall back to the centre.
  if (last_valid != nullptr && usable(*last_valid, width_px, height_px)) {
    held.x_px = last_valid->x_px;
    held.y_px = last_valid->y_px;
  } else {
    held.x_px = 0.5 * width_px;
    held.y_px = 0.5 * height_px;
  }
  return held;
}

}  // namespace fovlab
