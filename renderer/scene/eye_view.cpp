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

namespace {

// Hamilton product a * b of quaternions stored x, y, z, w.
std::array<double, 4> quaternion_product(const std::array<double, 4>& a, const std::array<double, 4>& b) {
  return {a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1], a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
          a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3], a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]};
}

}  // namespace

EyeView eye_view_in_moved_head(const EyeView& eye, const HeadPose& head) {
  // The identity is handed back as it is: a still head's frames are the head-locked ones, bit for bit
  // (a product with the identity could turn -0 into 0 and change the shader's floats).
  if (head == HeadPose{}) return eye;
  const std::array<double, 4>& q = head.orientation;
  const std::array<double, 4> conjugate{-q[0], -q[1], -q[2], q[3]};
  const std::array<double, 3>& p = eye.position_in_head;
  const std::array<double, 4> turned = quaternion_product(quaternion_product(q, {p[0], p[1], p[2], 0.0}), conjugate);
  EyeView moved = eye;
  moved.position_in_head = {head.position_m[0] + turned[0], head.position_m[1] + turned[1],
                            head.position_m[2] + turned[2]};
  moved.orientation_in_head = quaternion_product(q, eye.orientation_in_head);
  return moved;
}

}  // namespace fovlab
