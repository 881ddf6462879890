#include "protocols/gaze/headset_gaze.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace fovlab {
namespace {

using Vec3 = std::array<double, 3>;

Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

double length(const Vec3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

// v turned by the eye's orientation (the eye's axes into the head's), or by its inverse. The
// quaternion is normalised here, as the shaders take it (eye_view_shader_values).
Vec3 turned(const EyeView& eye, const Vec3& v, bool inverse) {
  const auto& o = eye.orientation_in_head;
  const double norm = std::sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2] + o[3] * o[3]);
  const double sign = inverse ? -1.0 : 1.0;  // the conjugate turns back
  const Vec3 q{sign * o[0] / norm, sign * o[1] / norm, sign * o[2] / norm};
  const double w = o[3] / norm;
  // v + 2 q x (q x v + w v)
  const Vec3 c = cross(q, v);
  const Vec3 t = cross(q, {c[0] + w * v[0], c[1] + w * v[1], c[2] + w * v[2]});
  return {v[0] + 2.0 * t[0], v[1] + 2.0 * t[1], v[2] + 2.0 * t[2]};
}

void require_size(int width_px, int height_px, const char* function) {
  if (width_px < 1 || height_px < 1)
    throw std::invalid_argument(std::string(function) + ": an image of " + std::to_string(width_px) + "x" +
                                std::to_string(height_px) + " pixels; expected at least 1x1");
}

void require_distance(double distance_m, const char* function) {
  if (!(std::isfinite(distance_m) && distance_m > 0.0))
    throw std::invalid_argument(std::string(function) + ": fixation_distance_m " + std::to_string(distance_m) +
                                ": expected a positive finite distance in metres");
}

// Both samples invalid for `reason`, at the template's position (sanitize_gaze substitutes it).
std::array<GazeSample, 2> both_invalid(const GazeSample& template_sample, const std::string& reason) {
  GazeSample invalid = template_sample;
  invalid.valid = false;
  invalid.invalid_reason = reason;
  return {invalid, invalid};
}

GazeSample at(const GazeSample& template_sample, const std::pair<double, double>& pixel) {
  GazeSample sample = template_sample;
  sample.x_px = pixel.first;
  sample.y_px = pixel.second;
  return sample;
}

}  // namespace

std::optional<std::pair<double, double>> eye_pixel_of_point(const EyeView& eye, int width_px, int height_px,
                                                            const Vec3& point_in_head_m) {
  require_size(width_px, height_px, "eye_pixel_of_point");
  const Vec3 offset{point_in_head_m[0] - eye.position_in_head[0], point_in_head_m[1] - eye.position_in_head[1],
                    point_in_head_m[2] - eye.position_in_head[2]};
  const Vec3 in_eye = turned(eye, offset, true);
  const double forward = -in_eye[2];  // the eye looks along its -z
  if (!(forward > 0.0) || !std::isfinite(forward)) return std::nullopt;
  const double tan_x = in_eye[0] / forward, tan_up = in_eye[1] / forward;
  const EyeFieldOfView& fov = eye.field_of_view;
  const double left = std::tan(fov.angle_left_rad), right = std::tan(fov.angle_right_rad);
  const double up = std::tan(fov.angle_up_rad), down = std::tan(fov.angle_down_rad);
  const double x_px = width_px * (tan_x - left) / (right - left);
  const double y_px = height_px * (up - tan_up) / (up - down);
  if (!std::isfinite(x_px) || !std::isfinite(y_px)) return std::nullopt;
  return std::pair{x_px, y_px};
}

std::optional<std::pair<double, double>> eye_pixel_of_direction(const EyeView& eye, int width_px, int height_px,
                                                                const Vec3& direction_in_head) {
  // The point one unit along the direction from the eye itself: the eye sees it along the direction.
  const Vec3 point{eye.position_in_head[0] + direction_in_head[0], eye.position_in_head[1] + direction_in_head[1],
                   eye.position_in_head[2] + direction_in_head[2]};
  return eye_pixel_of_point(eye, width_px, height_px, point);
}

Vec3 direction_of_eye_pixel(const EyeView& eye, int width_px, int height_px, double x_px, double y_px) {
  require_size(width_px, height_px, "direction_of_eye_pixel");
  const EyeFieldOfView& fov = eye.field_of_view;
  const double left = std::tan(fov.angle_left_rad), right = std::tan(fov.angle_right_rad);
  const double up = std::tan(fov.angle_up_rad), down = std::tan(fov.angle_down_rad);
  const double u = x_px / width_px, v = y_px / height_px;
  const Vec3 in_eye{left + (right - left) * u, up + (down - up) * v, -1.0};
  const Vec3 in_head = turned(eye, in_eye, false);
  const double norm = length(in_head);
  return {in_head[0] / norm, in_head[1] / norm, in_head[2] / norm};
}

std::array<GazeSample, 2> eye_gaze_from_ray(const HeadsetGazeGeometry& geometry, const Vec3& origin_m,
                                            const Vec3& direction, const GazeSample& template_sample) {
  require_distance(geometry.fixation_distance_m, "eye_gaze_from_ray");
  if (!template_sample.valid) return {template_sample, template_sample};
  const double norm = length(direction);
  if (!(std::isfinite(norm) && norm > 0.0) || !std::isfinite(length(origin_m)))
    return both_invalid(template_sample, "not_finite");
  const double reach = geometry.fixation_distance_m / norm;
  const Vec3 point{origin_m[0] + reach * direction[0], origin_m[1] + reach * direction[1],
                   origin_m[2] + reach * direction[2]};
  const auto left = eye_pixel_of_point(geometry.eyes[0], geometry.width_px, geometry.height_px, point);
  const auto right = eye_pixel_of_point(geometry.eyes[1], geometry.width_px, geometry.height_px, point);
  if (!left || !right) return both_invalid(template_sample, "off_screen");
  return {at(template_sample, *left), at(template_sample, *right)};
}

std::optional<Vec3> point_on_fixation_plane(const Vec3& origin_m, const Vec3& direction, double distance_m) {
  const double along = (-distance_m - origin_m[2]) / direction[2];
  if (!(along > 0.0) || !std::isfinite(along)) return std::nullopt;
  return Vec3{origin_m[0] + along * direction[0], origin_m[1] + along * direction[1],
              origin_m[2] + along * direction[2]};
}

std::array<GazeSample, 2> eye_gaze_from_left_eye_pixel(const HeadsetGazeGeometry& geometry, const GazeSample& left) {
  require_distance(geometry.fixation_distance_m, "eye_gaze_from_left_eye_pixel");
  if (!left.valid) return {left, left};
  if (!std::isfinite(left.x_px) || !std::isfinite(left.y_px)) return both_invalid(left, "not_finite");
  const EyeView& left_eye = geometry.eyes[0];
  const Vec3 direction = direction_of_eye_pixel(left_eye, geometry.width_px, geometry.height_px, left.x_px, left.y_px);
  const std::optional<Vec3> point =
      point_on_fixation_plane(left_eye.position_in_head, direction, geometry.fixation_distance_m);
  if (!point) return both_invalid(left, "off_screen");
  const auto right = eye_pixel_of_point(geometry.eyes[1], geometry.width_px, geometry.height_px, *point);
  if (!right) return both_invalid(left, "off_screen");
  return {left, at(left, *right)};
}

namespace {

// Where each eye sees the ray's resting point: hit_distance_m along its unit direction, or with no
// hit its direction at optical infinity. nullopt for a point or direction not in front of an eye.
std::optional<std::array<std::pair<double, double>, 2>> eye_pixels_at_depth(const HeadsetGazeGeometry& geometry,
                                                                            const Vec3& origin_m,
                                                                            const Vec3& unit_direction,
                                                                            std::optional<double> hit_distance_m) {
  std::array<std::pair<double, double>, 2> pixels;
  for (size_t i = 0; i < 2; ++i) {
    const EyeView& eye = geometry.eyes[i];
    std::optional<std::pair<double, double>> pixel;
    if (hit_distance_m) {
      const Vec3 point{origin_m[0] + *hit_distance_m * unit_direction[0],
                       origin_m[1] + *hit_distance_m * unit_direction[1],
                       origin_m[2] + *hit_distance_m * unit_direction[2]};
      pixel = eye_pixel_of_point(eye, geometry.width_px, geometry.height_px, point);
    } else {
      pixel = eye_pixel_of_direction(eye, geometry.width_px, geometry.height_px, unit_direction);
    }
    if (!pixel) return std::nullopt;
    pixels[i] = *pixel;
  }
  return pixels;
}

bool usable_distance(std::optional<double> hit_distance_m) {
  return !hit_distance_m || (std::isfinite(*hit_distance_m) && *hit_distance_m >= 0.0);
}

}  // namespace

std::array<GazeSample, 2> eye_gaze_from_ray_at_depth(const HeadsetGazeGeometry& geometry, const Vec3& origin_m,
                                                     const Vec3& direction, std::optional<double> hit_distance_m,
                                                     const GazeSample& template_sample) {
  require_size(geometry.width_px, geometry.height_px, "eye_gaze_from_ray_at_depth");
  if (!template_sample.valid) return {template_sample, template_sample};
  const double norm = length(direction);
  if (!(std::isfinite(norm) && norm > 0.0) || !std::isfinite(length(origin_m)) || !usable_distance(hit_distance_m))
    return both_invalid(template_sample, "not_finite");
  const Vec3 unit{direction[0] / norm, direction[1] / norm, direction[2] / norm};
  const auto pixels = eye_pixels_at_depth(geometry, origin_m, unit, hit_distance_m);
  if (!pixels) return both_invalid(template_sample, "off_screen");
  return {at(template_sample, (*pixels)[0]), at(template_sample, (*pixels)[1])};
}

std::optional<GazeRay> left_eye_ray_of_pixel(const HeadsetGazeGeometry& geometry, double x_px, double y_px) {
  if (!std::isfinite(x_px) || !std::isfinite(y_px)) return std::nullopt;
  const EyeView& left_eye = geometry.eyes[0];
  return GazeRay{left_eye.position_in_head,
                 direction_of_eye_pixel(left_eye, geometry.width_px, geometry.height_px, x_px, y_px)};
}

std::array<GazeSample, 2> eye_gaze_from_left_eye_pixel_at_depth(const HeadsetGazeGeometry& geometry,
                                                                const GazeSample& left,
                                                                std::optional<double> hit_distance_m) {
  require_size(geometry.width_px, geometry.height_px, "eye_gaze_from_left_eye_pixel_at_depth");
  if (!left.valid) return {left, left};
  const std::optional<GazeRay> ray = left_eye_ray_of_pixel(geometry, left.x_px, left.y_px);
  if (!ray || !usable_distance(hit_distance_m)) return both_invalid(left, "not_finite");
  const auto pixels = eye_pixels_at_depth(geometry, ray->origin_m, ray->direction, hit_distance_m);
  if (!pixels) return both_invalid(left, "off_screen");
  return {left, at(left, (*pixels)[1])};
}

}  // namespace fovlab
