#pragma once
// The head-tracked view model of a headset session (issue 42, docs/hmd.md): the head's pose at each
// refresh relative to where it was when the session started, as the session logs it and renders from
// it, and as its replay reads it back. The scene's camera path is where the head started; each
// refresh the head's motion since then carries both eyes (eye_view_in_moved_head).
#include <array>
#include <optional>
#include <string>

#include "renderer/scene/eye_view.h"

namespace fovlab {

// The step a logged head pose is rounded to, in metres and in quaternion components: finer than any
// headset tracks (a micrometre, a few microradians), and the same value in the log and the render.
constexpr double kHeadPoseStep = 1e-6;

// `pose` (both in the same space, e.g. the runtime's LOCAL) seen from `reference`: its position
// relative to the reference's, in the reference's axes, and its orientation relative to the
// reference's (conjugate(reference) * pose).
HeadPose head_pose_relative_to(const HeadPose& reference, const HeadPose& pose);

// Where an eye rendered for `head` (relative to `reference`, as head_pose_relative_to gives it) is in
// the space `reference` is given in (the runtime's LOCAL): the eye carried by the head's motion since
// the start (eye_view_in_moved_head), then by the reference. Its position and orientation are what
// the headset's compositor is told the eye's image was rendered from.
EyeView eye_view_in_reference_space(const EyeView& eye, const HeadPose& head, const HeadPose& reference);

// The pose a session renders from and logs for a refresh, as sanitize_gaze does for the gaze: each
// number rounded to kHeadPoseStep (never -0). A pose the runtime did not give (nullopt), or that is
// not one (a coordinate not finite, a quaternion not of unit length within 1e-3), holds the last pose
// used (`last_used`), or the start's (identity) before any.
HeadPose sanitize_head_pose(const std::optional<HeadPose>& raw, const HeadPose* last_used);

// A stimulus event's head_pose entry: [x_m, y_m, z_m, qx, qy, qz, qw].
std::array<double, 7> head_pose_entry(const HeadPose& pose);
// Reads one back; nullopt when it is not a pose (a coordinate not finite, the quaternion not of unit
// length within 1e-3). `error` gets the reason.
std::optional<HeadPose> head_pose_of_entry(const std::array<double, 7>& entry, std::string& error);

// A point and a direction given in the head now (the eye tracker's gaze ray) in the head's axes at
// the start, where the scene's camera stands: the point turned then moved, the direction turned.
std::array<double, 3> point_in_start_head(const HeadPose& head, const std::array<double, 3>& point);
std::array<double, 3> direction_in_start_head(const HeadPose& head, const std::array<double, 3>& direction);

}  // namespace fovlab
