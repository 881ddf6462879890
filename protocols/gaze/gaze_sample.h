#pragma once
// One gaze sample in screen pixels (origin top-left, x right, y down) at a session time.
#include <array>
#include <optional>
#include <string>

namespace fovlab {

// A headset eye tracker's combined gaze ray in the head's frame (OpenXR's VIEW space: x right, y up,
// z backwards; metres), from which its sample's position came.
struct GazeRay {
  std::array<double, 3> origin_m{0.0, 0.0, 0.0};
  std::array<double, 3> direction{0.0, 0.0, -1.0};  // any length
};

struct GazeSample {
  double time_s = 0.0;  // session clock (virtual in headless sessions)
  // When the sample itself was taken, on the session clock: the cursor read (mouse), the trace's
  // time (trace), the query time less the configured age (synthetic), the tracker's timestamp mapped
  // to the session clock (pupil). nullopt when there was no sample at all (a live tracker with
  // nothing recent: "no_data"). The session logs it and its age at present time.
  std::optional<double> acquired_s;
  double x_px = 0.0;
  double y_px = 0.0;
  bool valid = true;
  std::string invalid_reason;  // "blink", "off_screen", "not_finite", "no_data", "low_confidence"; empty when valid
  // The ray the position came from, where the source measures one (the headset's eye tracker), so
  // that a headset session can rest the gaze where the ray meets the rendered scene (issue 42,
  // protocols/gaze/headset_gaze.h); nullopt for the sources that give pixels. Never logged.
  std::optional<GazeRay> ray_in_head;
};

// Sessions use and log gaze positions rounded to this step (the log's JSON numbers stay short and
// a replay reads back exactly what was used).
constexpr double kGazeStepPx = 0.01;

// A position rounded to kGazeStepPx (a non-finite one is returned as it is; never -0).
double round_gaze_px(double position_px);

// The position a session uses for a raw sample, rounded to kGazeStepPx. Validity is decided on the
// rounded position: one that rounds to the screen's width or height (x = 31.996 on a 32-pixel-wide
// display is 32.00) is off_screen. When a sample is invalid: the last valid position (held), or the
// screen centre before any valid sample. The returned sample keeps valid = false and the reason, so
// the log says the position was substituted. acquired_s stays that of the sample read (the held
// position may be older).
GazeSample sanitize_gaze(const GazeSample& raw, int width_px, int height_px, const GazeSample* last_valid);

}  // namespace fovlab
