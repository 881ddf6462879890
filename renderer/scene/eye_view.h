#pragma once
// An eye's view of a scene, for per-eye (headset) rendering (issue 42): where the eye sits and where
// it looks relative to the head, and its asymmetric field of view. The view model is head-locked:
// the scene's camera path (scene_camera: eye, target, world up +y) is the head, the eye sits at
// position_in_head along the head's right, up and backward axes (OpenXR's VIEW space: x right, y up,
// z backwards) and looks along the head's axes turned by orientation_in_head. Its image plane is
// perpendicular to its forward axis; pixel (x, y) of a width x height image looks along tan-angles
// lerp(tan(left), tan(right), (x + 0.5) / width) and lerp(tan(up), tan(down), (y + 0.5) / height)
// (y down), so the eye's axis meets the image at the off-axis display's principal point
// (foveation/display_geometry.h display_from_field_of_view). The renderers take it as an option:
// without one they render the scene camera's own symmetric frustum, as on the desktop.
#include <array>

#include "core/pose.h"
#include "foveation/display_geometry.h"

namespace fovlab {

struct EyeView {
  std::array<double, 3> position_in_head{0.0, 0.0, 0.0};          // scene units
  std::array<double, 4> orientation_in_head{0.0, 0.0, 0.0, 1.0};  // unit quaternion x, y, z, w
  EyeFieldOfView field_of_view;                                   // radians, as XrFovf
  bool operator==(const EyeView&) const = default;
};

// The eye's image plane of width_px x height_px pixels (display_from_field_of_view): for the
// eccentricity of its pixels (FIPR's fovea, the sampling models, the zone blend). Throws InputError
// for a field of view that is not one (display_from_field_of_view).
DisplayGeometry eye_display(const EyeView& view, int width_px, int height_px);

// What the shaders take of a view: the tangents of the four angles (left, right, up, down), the
// orientation and the position, in float. Throws InputError for a bad field of view or an
// orientation that is not a unit quaternion (within 1e-3) or a position that is not finite, naming
// the field.
struct EyeViewShaderValues {
  std::array<float, 4> tan_angles{};   // tan(left), tan(right), tan(up), tan(down)
  std::array<float, 4> orientation{};  // x, y, z, w
  std::array<float, 3> position{};
};
EyeViewShaderValues eye_view_shader_values(const EyeView& view);

// The head-tracked view model (issue 42, docs/hmd.md): where the head is relative to where it was
// when the session started (its reference pose in the runtime's LOCAL space), in the head's axes at
// that start (x right, y up, z backwards; metres, a scene unit each). The scene's camera at the
// frame's time stands where the head started, so an eye's pose in the scene is
// camera(t) * head_delta * eye_in_head.
using HeadPose = Pose;

// The eye as the moved head carries it: its orientation head.orientation * eye's, its position the
// eye's offset turned by the head's orientation first, then moved by the head's position
// (head.position_m + rotate(head.orientation, eye.position_in_head)); the field of view is the eye's.
// So it stays an EyeView "in the head" of the scene's camera, and every renderer that takes an eye's
// view renders it unchanged. The identity pose gives the eye back bit for bit.
EyeView eye_view_in_moved_head(const EyeView& eye, const HeadPose& head);

}  // namespace fovlab
