#pragma once
// The headset's eye tracker as a session's gaze source (`--gaze openxr`, a headset session's default
// where the runtime has XR_EXT_eye_gaze_interaction): the combined gaze ray located in the head at the
// session time asked (the runtime's XrTime of it), given with the sample (GazeSample::ray_in_head),
// and the left eye's pixel of where it rests. With a fixation distance (geometry.fixation_distance_m
// > 0: gaze_fixation = "fixation-distance") that is the point on the plane fixation_distance_m in
// front of the head, and the session gives the right eye the pixel of the same point
// (eye_gaze_from_left_eye_pixel, which meets that plane too). Without one (0: "rendered-depth") it
// is the ray's direction at optical infinity, all a source can say without the scene; the session
// rests the ray on the rendered scene and replaces both eyes' pixels (eye_gaze_from_ray_at_depth).
// No ray (the tracker lost the eyes, or the gaze action is not active) is an invalid "no_data"
// sample, a point not in front of the left eye or off its image "off_screen". docs/hmd.md,
// docs/gaze.md.
#include "display/openxr/openxr_presenter.h"
#include "protocols/gaze/gaze_source.h"
#include "protocols/gaze/headset_gaze.h"

namespace fovlab {

class OpenXrGazeSource final : public GazeSource {
 public:
  // time_base_s: the session time at which the presenter's clock reads 0 (a resumed log's last time).
  OpenXrGazeSource(OpenXrPresenter& headset, const HeadsetGazeGeometry& geometry, double time_base_s)
      : headset_(headset), geometry_(geometry), time_base_s_(time_base_s) {}
  GazeSample sample(double time_s) override;
  std::string describe() const override { return "openxr"; }

 private:
  OpenXrPresenter& headset_;
  HeadsetGazeGeometry geometry_;
  double time_base_s_;
};

}  // namespace fovlab
