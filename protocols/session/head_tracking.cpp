#include "protocols/session/head_tracking.h"

#include <cmath>

namespace fovlab {
namespace {

using Quaternion = std::array<double, 4>;  // x, y, z, w

Quaternion product(const Quaternion& a, const Quaternion& b) {
  return {a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1], a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
          a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3], a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]};
}

Quaternion conjugate(const Quaternion& q) { return {-q[0], -q[1], -q[2], q[3]}; }

std::array<double, 3> rotated(const Quaternion& q, const std::array<double, 3>& v) {
  const Quaternion r = product(product(q, {v[0], v[1], v[2], 0.0}), conjugate(q));
  return {r[0], r[1], r[2]};
}

double rounded(double value) { return std::round(value / kHeadPoseStep) * kHeadPoseStep + 0.0; }  // + 0.0: no -0

bool is_pose(const HeadPose& pose) {
  for (const double p : pose.position_m)
    if (!std::isfinite(p)) return false;
  const Quaternion& q = pose.orientation;
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  return std::isfinite(norm) && std::fabs(norm - 1.0) <= 1e-3;
}

}  // namespace

HeadPose head_pose_relative_to(const HeadPose& reference, const HeadPose& pose) {
  const Quaternion inverse = conjugate(reference.orientation);
  const std::array<double, 3> offset{pose.position_m[0] - reference.position_m[0],
                                     pose.position_m[1] - reference.position_m[1],
                                     pose.position_m[2] - reference.position_m[2]};
  return {rotated(inverse, offset), product(inverse, pose.orientation)};
}

HeadPose sanitize_head_pose(const std::optional<HeadPose>& raw, const HeadPose* last_used) {
  if (!raw || !is_pose(*raw)) return last_used ? *last_used : HeadPose{};
  HeadPose pose;
  for (size_t i = 0; i < 3; ++i) pose.position_m[i] = rounded(raw->position_m[i]);
  for (size_t i = 0; i < 4; ++i) pose.orientation[i] = rounded(raw->orientation[i]);
  return pose;
}

std::array<double, 7> head_pose_entry(const HeadPose& pose) {
  return {pose.position_m[0],  pose.position_m[1],  pose.position_m[2], pose.orientation[0],
          pose.orientation[1], pose.orientation[2], pose.orientation[3]};
}

std::optional<HeadPose> head_pose_of_entry(const std::array<double, 7>& entry, std::string& error) {
  const HeadPose pose{{entry[0], entry[1], entry[2]}, {entry[3], entry[4], entry[5], entry[6]}};
  if (is_pose(pose)) return pose;
  error = "expected [x_m, y_m, z_m, qx, qy, qz, qw] with finite numbers and a unit quaternion";
  return std::nullopt;
}

std::array<double, 3> point_in_start_head(const HeadPose& head, const std::array<double, 3>& point) {
  const std::array<double, 3> turned = rotated(head.orientation, point);
  return {head.position_m[0] + turned[0], head.position_m[1] + turned[1], head.position_m[2] + turned[2]};
}

std::array<double, 3> direction_in_start_head(const HeadPose& head, const std::array<double, 3>& direction) {
  return rotated(head.orientation, direction);
}

EyeView eye_view_in_reference_space(const EyeView& eye, const HeadPose& head, const HeadPose& reference) {
  return eye_view_in_moved_head(eye_view_in_moved_head(eye, head), reference);
}

}  // namespace fovlab
