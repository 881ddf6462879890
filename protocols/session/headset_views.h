#pragma once
// A headset session's views (issue 42, docs/hmd.md): what each eye was shown from, as the session's
// header records it and its replay reads it back. The session takes each eye's view from the
// runtime at its start (xrLocateViews in the head's VIEW space: the eye's offset, orientation and
// asymmetric field of view), after checking that the fields of view are the config's, on which the
// plan was made; head-locked, those views hold for the whole session. The gaze of a source that gives
// pixels (trace, synthetic) is the left eye's pixel, and becomes the right eye's through the point
// where the left eye's ray through it rests: on the rendered scene (gaze_fixation "rendered-depth")
// or fixation_distance_m along it (protocols/gaze/headset_gaze.h).
#include <array>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "protocols/gaze/headset_gaze.h"
#include "renderer/scene/eye_view.h"
#include "study/config/headset_display.h"

namespace fovlab {

struct StudyConfig;

struct HeadsetViews {
  std::string runtime;  // the OpenXR runtime's name and version
  int eye_width_px = 0;
  int eye_height_px = 0;
  std::array<EyeView, 2> eyes;  // left, right; positions in metres (a scene unit is a metre)
  HeadsetViewModel view_model = HeadsetViewModel::head_locked;
  GazeFixation gaze_fixation = GazeFixation::fixation_distance;  // where the gaze ray rests
  double fixation_distance_mm = 0.0;  // fixation_distance: along the gaze ray, where both eyes' pixels meet
  // Head-tracked (schema 12): the head's pose in the runtime's LOCAL space when the session started,
  // which each refresh's logged head_pose is relative to (a record: replay needs only those).
  std::optional<HeadPose> head_reference;
  bool operator==(const HeadsetViews&) const = default;
};

// The header's `headset`: {"runtime", "eye_width_px", "eye_height_px", "view_model",
// "gaze_fixation": {"kind": "rendered-depth"} or {"kind": "fixation-distance", "distance_mm"}, "eyes": [{"position_m": [x, y, z],
// "orientation": [x, y, z, w], "fov_rad": [left, right, up, down]}, left then right]}; head-tracked
// also "head_reference": {"position_m": [x, y, z], "orientation": [x, y, z, w]}.
nlohmann::json headset_views_json(const HeadsetViews& views);
// Reads it back; InputError naming `where` (the log's header line) and the field for anything else.
HeadsetViews headset_views_from_json(const nlohmann::json& headset, const std::string& where);

// The geometry protocols/gaze/headset_gaze.h turns a gaze into each eye's pixel with (its
// fixation_distance_m 0 for rendered-depth, which needs none).
HeadsetGazeGeometry headset_gaze_geometry(const HeadsetViews& views);

// Refuses (InputError, one line naming the config's line and both angles) an eye whose field of view
// from the runtime differs from the config's by more than 0.01 degrees on any side: the plan's
// pixels per degree and foveal sizes were made from the config's.
void check_runtime_fields_of_view(const HeadsetViews& views, const StudyConfig& config);

}  // namespace fovlab
