#include "protocols/gaze/openxr_gaze_source.h"

namespace fovlab {

GazeSample OpenXrGazeSource::sample(double time_s) {
  GazeSample sample;
  sample.time_s = time_s;
  const auto invalid = [&](const char* reason) {
    sample.valid = false;
    sample.invalid_reason = reason;
    return sample;
  };
  const std::optional<OpenXrGazeRay> ray = headset_.input().locate_gaze(headset_.runtime_time(time_s - time_base_s_));
  if (!ray) return invalid("no_data");
  sample.acquired_s = ray->sample_time != 0 ? time_base_s_ + headset_.session_time_s(ray->sample_time) : time_s;
  sample.ray_in_head = GazeRay{ray->origin_m, ray->direction};
  std::optional<std::pair<double, double>> left;
  if (geometry_.fixation_distance_m > 0.0) {
    const auto point = point_on_fixation_plane(ray->origin_m, ray->direction, geometry_.fixation_distance_m);
    if (!point) return invalid("off_screen");
    left = eye_pixel_of_point(geometry_.eyes[0], geometry_.width_px, geometry_.height_px, *point);
  } else {
    left = eye_pixel_of_direction(geometry_.eyes[0], geometry_.width_px, geometry_.height_px, ray->direction);
  }
  if (!left) return invalid("off_screen");
  sample.x_px = left->first;
  sample.y_px = left->second;
  return sample;
}

}  // namespace fovlab
