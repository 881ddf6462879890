#include "protocols/gaze/gaze_sample.h"

#include <cmath>

namespace fovlab {

namespace {

bool inside(double x_px, double y_px, int width_px, int height_px) {
  return x_px >= 0.0 && y_px >= 0.0 && x_px < width_px && y_px < height_px;
}

// A held position must itself be on screen once rounded.
bool usable(const GazeSample& sample, int width_px, int height_px) {
  return sample.valid && std::isfinite(sample.x_px) && std::isfinite(sample.y_px) &&
         inside(round_gaze_px(sample.x_px), round_gaze_px(sample.y_px), width_px, height_px);
}

}  // namespace

double round_gaze_px(double position_px) {
  const double steps = position_px / kGazeStepPx;
  if (!std::isfinite(steps)) return position_px;  // not a number, or too far off any screen to round
  return std::round(steps) * kGazeStepPx + 0.0;   // + 0.0: -0.0 becomes 0.0
}

GazeSample sanitize_gaze(const GazeSample& measured, int width_px, int height_px, const GazeSample* last_valid) {
  GazeSample raw = measured;
  raw.x_px = round_gaze_px(measured.x_px);
  raw.y_px = round_gaze_px(measured.y_px);
  std::string reason;
  if (!raw.valid) {
    reason = raw.invalid_reason.empty() ? "no_data" : raw.invalid_reason;
  } else if (!std::isfinite(raw.x_px) || !std::isfinite(raw.y_px)) {
    reason = "not_finite";
  } else if (!inside(raw.x_px, raw.y_px, width_px, height_px)) {
    reason = "off_screen";
  } else {
    return raw;
  }

  GazeSample held;
  held.time_s = raw.time_s;
  held.acquired_s = raw.acquired_s;
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
  held.x_px = round_gaze_px(held.x_px);
  held.y_px = round_gaze_px(held.y_px);
  return held;
}

}  // namespace fovlab
