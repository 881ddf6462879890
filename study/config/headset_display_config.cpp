// [display] kind = "openxr": the headset's keys, each eye's geometry in angles, and the checks a
// headset config gets per eye (docs/config.md, docs/hmd.md).
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/input_error.h"
#include "core/number_text.h"
#include "core/toml_fields.h"
#include "study/config/config_reading.h"
#include "study/config/headset_display.h"
#include "study/config/study_config.h"

namespace fovlab {

namespace {

double tan_deg(double degrees) { return std::tan(degrees * std::numbers::pi / 180.0); }
double degrees(double radians) { return radians * 180.0 / std::numbers::pi; }

}  // namespace

const char* display_kind_name(DisplayKind kind) { return kind == DisplayKind::openxr ? "openxr" : "window"; }

const char* headset_view_model_name(HeadsetViewModel model) {
  return model == HeadsetViewModel::head_tracked ? "head-tracked" : "head-locked";
}

EyeViewGeometry eye_view_geometry(const EyeFieldOfView& fov, int width_px, int height_px) {
  EyeViewGeometry eye;
  eye.width_px = width_px;
  eye.height_px = height_px;
  eye.tan_left = std::tan(fov.angle_left_rad);
  eye.tan_right = std::tan(fov.angle_right_rad);
  eye.tan_up = std::tan(fov.angle_up_rad);
  eye.tan_down = std::tan(fov.angle_down_rad);
  const double plane_width = eye.tan_right - eye.tan_left, plane_height = eye.tan_up - eye.tan_down;
  eye.centre_x_px = -eye.tan_left / plane_width * width_px;
  eye.centre_y_px = eye.tan_up / plane_height * height_px;
  // d tan(a) / da = 1 at a = 0: a radian at the centre covers the image plane's unit length.
  const double radians_per_degree = std::numbers::pi / 180.0;
  eye.pixels_per_degree_x = width_px / plane_width * radians_per_degree;
  eye.pixels_per_degree_y = height_px / plane_height * radians_per_degree;
  eye.width_deg = degrees(fov.angle_right_rad - fov.angle_left_rad);
  eye.height_deg = degrees(fov.angle_up_rad - fov.angle_down_rad);
  return eye;
}

std::pair<double, double> eye_pixel_of_direction(const EyeViewGeometry& eye, double horizontal_deg,
                                                 double vertical_deg) {
  return {(tan_deg(horizontal_deg) - eye.tan_left) / (eye.tan_right - eye.tan_left) * eye.width_px,
          (eye.tan_up - tan_deg(vertical_deg)) / (eye.tan_up - eye.tan_down) * eye.height_px};
}

FlatDisplayOfEye flat_display_of_eye(const EyeFieldOfView& fov) {
  const double distance_mm = kFieldOfViewPlaneDistanceMm;
  return {distance_mm * (std::tan(fov.angle_right_rad) - std::tan(fov.angle_left_rad)),
          distance_mm * (std::tan(fov.angle_up_rad) - std::tan(fov.angle_down_rad)), distance_mm};
}

std::string field_of_view_text(const EyeFieldOfView& fov) {
  return "[" + format_number(degrees(fov.angle_left_rad), 6) + ", " + format_number(degrees(fov.angle_right_rad), 6) +
         ", " + format_number(degrees(fov.angle_up_rad), 6) + ", " + format_number(degrees(fov.angle_down_rad), 6) +
         "] deg";
}

}  // namespace fovlab

namespace fovlab::config_detail {

namespace {

// The keys of one kind of display, refused with the other.
constexpr std::array<const char*, 7> kWindowKeys{"width_px",  "height_px",           "diagonal_in", "width_mm",
                                                 "height_mm", "viewing_distance_mm", "fullscreen"};
constexpr std::array<const char*, 8> kHeadsetKeys{
    "eye_width_px", "eye_height_px", "left_eye_fov_deg", "right_eye_fov_deg",
    "ipd_mm",       "view_model",    "gaze_fixation",    "fixation_distance_mm"};

// 8..16384, as a window's size. Never "whatever the runtime recommends": the stimuli, their
// pre-rendered frames and the thresholds measured on them hold for one size only, so every
// participant of a study sees that size, whichever headset and runtime they sit at.
int read_eye_size(const TomlFields& fields, const std::string& key) {
  const int size = bounded_integer(fields, key, std::nullopt, 0, 16384);
  if (size < 8)
    fields.fail(key,
                "expected each eye's size in pixels, 8..16384, one size for every participant of the study "
                "(`fovlab devices` prints the runtime's recommended size), got " +
                    std::to_string(size));
  return size;
}

EyeFieldOfView read_field_of_view(const TomlFields& fields, const std::string& key) {
  const std::string expected =
      "expected [left, right, up, down]: four signed angles in degrees from the eye's forward direction, as OpenXR's "
      "XrFovf (left < 0 < right, down < 0 < up, each within (-90, 90))";
  const std::vector<double> angles = fields.numbers(key);
  if (angles.size() != 4) fields.fail(key, expected + ", got " + std::to_string(angles.size()) + " numbers");
  for (double angle : angles)
    if (!(angle > -90.0 && angle < 90.0)) fields.fail(key, expected + ", got " + exact_number_text(angle));
  const double left_deg = angles[0], right_deg = angles[1], up_deg = angles[2], down_deg = angles[3];
  if (!(left_deg < 0.0 && right_deg > 0.0))
    fields.fail(key, expected + ", got left " + exact_number_text(left_deg) + " and right " +
                         exact_number_text(right_deg));
  if (!(down_deg < 0.0 && up_deg > 0.0))
    fields.fail(key, expected + ", got up " + exact_number_text(up_deg) + " and down " + exact_number_text(down_deg));
  return field_of_view_from_deg(left_deg, right_deg, up_deg, down_deg);
}

}  // namespace

void refuse_headset_keys(const TomlFields& fields) {
  for (const char* key : kHeadsetKeys)
    if (fields.has(key))
      fields.fail(key,
                  "a key of [display] kind = \"openxr\" (a headset); this [display] is kind \"window\" (the "
                  "default)");
}

void read_headset_display(const TomlFields& fields, DisplayConfig& display) {
  for (const char* key : kWindowKeys)
    if (fields.has(key))
      fields.fail(key,
                  "not a key of [display] kind = \"openxr\": a headset's geometry is each eye's (eye_width_px, "
                  "eye_height_px, left_eye_fov_deg, right_eye_fov_deg)");
  HeadsetDisplayConfig& headset = display.headset;
  headset.eye_width_px = read_eye_size(fields, "eye_width_px");
  headset.eye_height_px = read_eye_size(fields, "eye_height_px");
  headset.eye_size_line = static_cast<int>(fields.raw().get("eye_width_px")->source().begin.line);
  display.refresh_hz = fields.number("refresh_hz");  // required: headsets run at 72 to 144 Hz
  check_range(fields, "refresh_hz", display.refresh_hz, 1.0, 1000.0);
  headset.left_eye_fov = read_field_of_view(fields, "left_eye_fov_deg");
  headset.right_eye_fov = read_field_of_view(fields, "right_eye_fov_deg");
  headset.ipd_mm = bounded_number(fields, "ipd_mm", headset.ipd_mm, 40.0, 90.0);
  const std::string view_model = fields.string("view_model", "head-locked");
  if (view_model == "head-tracked") {
    headset.view_model = HeadsetViewModel::head_tracked;
  } else if (view_model != "head-locked") {
    fields.fail("view_model", "expected \"head-locked\" (the default) or \"head-tracked\", got \"" + view_model + "\"");
  }
  // gaze_fixation: "rendered-depth" (the default) or "fixation-distance", which fixation_distance_mm
  // implies when gaze_fixation is left out.
  const bool has_distance = fields.has("fixation_distance_mm");
  const std::string fixation = fields.string("gaze_fixation", has_distance ? "fixation-distance" : "rendered-depth");
  if (fixation == "fixation-distance") {
    if (!has_distance)
      fields.fail("gaze_fixation",
                  "\"fixation-distance\" needs fixation_distance_mm (the distance along the gaze ray)");
    headset.gaze_fixation = GazeFixation::fixation_distance;
    headset.fixation_distance_mm = bounded_number(fields, "fixation_distance_mm", 0.0, 100.0, 1e6);
  } else if (fixation == "rendered-depth") {
    if (has_distance)
      fields.fail("fixation_distance_mm",
                  "not with gaze_fixation = \"rendered-depth\" (the gaze meets the scene at its rendered depth); "
                  "drop one");
  } else {
    fields.fail(
        "gaze_fixation",
        "expected \"rendered-depth\" (the default) or \"fixation-distance\" (with fixation_distance_mm), got \"" +
            fixation + "\"");
  }
  // The plan's stimuli: each eye's size, made for the left eye's image plane.
  display.width_px = headset.eye_width_px;
  display.height_px = headset.eye_height_px;
  const FlatDisplayOfEye flat = flat_display_of_eye(headset.left_eye_fov);
  display.width_mm = flat.width_mm;
  display.height_mm = flat.height_mm;
  display.viewing_distance_mm = flat.viewing_distance_mm;
  fields.finish();
}

void check_validation_targets_in_each_eye(const TomlFields& fields, const HeadsetDisplayConfig& headset,
                                          const ValidationConfig& validation) {
  // Each target at (+-offset, +-offset) deg from the eye's forward direction (at optical infinity,
  // so both eyes see it at the same angles), its disk inside every eye's field of view.
  const double reach_deg = validation.target_offset_deg + validation.target_radius_deg;
  for (const auto& [name, fov] : {std::pair{"left", headset.left_eye_fov}, std::pair{"right", headset.right_eye_fov}}) {
    if (reach_deg < -degrees(fov.angle_left_rad) && reach_deg < degrees(fov.angle_right_rad) &&
        reach_deg < degrees(fov.angle_up_rad) && reach_deg < -degrees(fov.angle_down_rad))
      continue;
    fields.fail("target_offset_deg", "expected targets in each eye's field of view: at " +
                                         format_number(validation.target_offset_deg, 6) +
                                         " deg the outer ones fall outside the " + name + " eye's " +
                                         field_of_view_text(fov) + " ([left, right, up, down])");
  }
}

}  // namespace fovlab::config_detail
