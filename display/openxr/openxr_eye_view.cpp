#include "display/openxr/openxr_eye_view.h"

namespace fovlab {

EyeView eye_view_from_openxr(const XrView& view_in_head, double scene_units_per_metre) {
  const XrPosef& pose = view_in_head.pose;
  EyeView view;
  view.position_in_head = {pose.position.x * scene_units_per_metre, pose.position.y * scene_units_per_metre,
                           pose.position.z * scene_units_per_metre};
  view.orientation_in_head = {pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w};
  view.field_of_view = {view_in_head.fov.angleLeft, view_in_head.fov.angleRight, view_in_head.fov.angleUp,
                        view_in_head.fov.angleDown};
  return view;
}

}  // namespace fovlab
