#pragma once
// Eye-tracker validation: how far, in degrees of visual angle, the gaze a source reports lies from
// targets the participant was asked to look at. The session (session_run.h) shows the config's
// targets one at a time ([validation], study_config.h), reads the gaze source every refresh, and
// measures each target here; the definitions are Holmqvist et al.'s (docs/gaze.md):
//   accuracy  the angle between the target and the mean of the valid gaze positions (the centroid);
//   precision the root mean square of the angles between successive valid samples (RMS-S2S).
// Angles are exact (foveation/display_geometry.h eccentricity_deg), not pixels times a constant.
#include <vector>

#include "foveation/display_geometry.h"
#include "protocols/gaze/gaze_sample.h"
#include "study/config/study_config.h"
#include "study/log/log_events.h"

namespace fovlab {

DisplayGeometry display_geometry(const DisplayConfig& display);

// One target from the samples read while it was measured, in order, as the source gave them (not
// through sanitize_gaze: a gaze that lands off the screen near an outer target is still where the
// tracker says the eye looks, so it counts). Positions are rounded to kGazeStepPx, as logged. A
// sample read again (the same acquired_s as the one before: a tracker slower than the display) is
// one sample, so precision is per tracker sample. A sample is valid when its source says so and its
// position is finite; an invalid one counts in `samples` and breaks the succession for precision.
// Accuracy and precision are left null when fewer than half the samples, or fewer than two, are
// valid, or no two valid samples follow each other (no precision can be measured).
ValidationTarget measure_validation_target(const DisplayGeometry& display, double target_x_px, double target_y_px,
                                           const std::vector<GazeSample>& samples);

// The attempt's result from its targets: the means of their accuracy and precision (null when a
// target has none), and whether both are within the config's limits (never for a stopped attempt).
void summarise_validation(TrackerValidationEvent& attempt, const ValidationConfig& validation);

}  // namespace fovlab
