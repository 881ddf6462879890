#pragma once
// One gaze sample in screen pixels (origin top-left, x right, y down) at a session time.
#include <string>

namespace fovlab {

struct GazeSample {
  double time_s = 0.0;  // session clock (virtual in headless sessions)
  double x_px = 0.0;
  double y_px = 0.0;
  bool valid = true;
  std::string invalid_reason;  // "blink", "off_screen", "not_finite", "no_data", "low_confidence"; empty when valid
};

// What a session shows when a sample is invalid: the last valid position (held), or the screen
// centre before any valid sample. The returned sample keeps valid = false and the reason, so the log
// says the position was substituted.
GazeSample sanitize_gaze(const GazeSample& raw, int width_px, int height_px, const GazeSample* last_valid);

}  // namespace fovlab
