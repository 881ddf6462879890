#include "renderer/scene/eye_view.h"

#include <cmath>
#include <string>

#include "core/input_error.h"
#include "core/number_text.h"

namespace fovlab {

DisplayGeometry eye_display(const EyeView& view, int width_px, int height_px) {
  return display_from_field_of_view(width_px, height_px, view.field_of_view);
}

EyeViewShaderValues eye_view_shader_values(const EyeView& view) {
  display_from_field_of_view(1, 1, view.field_of_view);  // checks the angles
  const auto& q = view.orientation_in_head;
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!std::isfinite(norm) || std::fabs(norm - 1.0) > 1e-3)
    throw InputError("eye view orientation_in_head: a quaternion of length " + format_number(norm, 6) +
                     "; expected a unit quaternion");
  for (double p : view.position_in_head)
    if (!std::isfinite(p)) throw InputError("eye view position_in_head: expected finite coordinates");
  const EyeFieldOfView& fov = view.field_of_view;
  EyeViewShaderValues values;
  values.tan_angles = {float(std::tan(fov.angle_left_rad)), float(std::tan(fov.angle_right_rad)),
                       float(std::tan(fov.angle_up_rad)), float(std::tan(fov.angle_down_rad))};
  for (int i = 0; i < 4; ++i) values.orientation[size_t(i)] = float(q[size_t(i)] / norm);
  for (int i = 0; i < 3; ++i) values.position[size_t(i)] = float(view.position_in_head[size_t(i)]);
  return values;
}

}  // namespace fovlab
