#include "protocols/session/headset_views.h"

#include <cmath>
#include <numbers>

#include "core/number_text.h"
#include "core/input_error.h"
#include "study/config/study_config.h"

namespace fovlab {
namespace {

constexpr double kDegreesPerRadian = 180.0 / std::numbers::pi;

template <size_t N>
std::array<double, N> numbers_of(const nlohmann::json& json, const std::string& where, const std::string& field) {
  if (!json.is_array() || json.size() != N)
    throw InputError(where + ": headset." + field + ": expected an array of " + std::to_string(N) + " numbers");
  std::array<double, N> values{};
  for (size_t i = 0; i < N; ++i) {
    if (!json[i].is_number() || !std::isfinite(json[i].get<double>()))
      throw InputError(where + ": headset." + field + ": expected an array of " + std::to_string(N) + " numbers");
    values[i] = json[i].get<double>();
  }
  return values;
}

int positive_int_of(const nlohmann::json& headset, const char* key, const std::string& where) {
  const auto found = headset.find(key);
  if (found == headset.end() || !found->is_number_integer() || found->get<int64_t>() <= 0 ||
      found->get<int64_t>() > 1 << 16)
    throw InputError(where + ": headset." + key + ": expected a positive number of pixels");
  return found->get<int>();
}

}  // namespace

nlohmann::json headset_views_json(const HeadsetViews& views) {
  nlohmann::json eyes = nlohmann::json::array();
  for (const EyeView& eye : views.eyes) {
    const EyeFieldOfView& fov = eye.field_of_view;
    eyes.push_back({{"position_m", eye.position_in_head},
                    {"orientation", eye.orientation_in_head},
                    {"fov_rad", {fov.angle_left_rad, fov.angle_right_rad, fov.angle_up_rad, fov.angle_down_rad}}});
  }
  nlohmann::json json{{"runtime", views.runtime},
                      {"eye_width_px", views.eye_width_px},
                      {"eye_height_px", views.eye_height_px},
                      {"view_model", headset_view_model_name(views.view_model)},
                      {"gaze_fixation", views.gaze_fixation == GazeFixation::rendered_depth
                                            ? nlohmann::json{{"kind", "rendered-depth"}}
                                            : nlohmann::json{{"kind", "fixation-distance"},
                                                             {"distance_mm", views.fixation_distance_mm}}},
                      {"eyes", eyes}};
  if (views.head_reference)
    json["head_reference"] = {{"position_m", views.head_reference->position_m},
                              {"orientation", views.head_reference->orientation}};
  return json;
}

HeadsetViews headset_views_from_json(const nlohmann::json& headset, const std::string& where) {
  if (!headset.is_object()) throw InputError(where + ": headset: expected an object (a headset session's views)");
  HeadsetViews views;
  views.runtime = headset.value("runtime", "");
  views.eye_width_px = positive_int_of(headset, "eye_width_px", where);
  views.eye_height_px = positive_int_of(headset, "eye_height_px", where);
  const std::string model = headset.value("view_model", "");
  if (model == headset_view_model_name(HeadsetViewModel::head_tracked)) {
    views.view_model = HeadsetViewModel::head_tracked;
    const nlohmann::json reference = headset.value("head_reference", nlohmann::json());
    if (!reference.is_object())
      throw InputError(where +
                       ": headset.head_reference: expected {\"position_m\", \"orientation\"} (a head-tracked session's)");
    views.head_reference =
        HeadPose{numbers_of<3>(reference.value("position_m", nlohmann::json()), where, "head_reference.position_m"),
                 numbers_of<4>(reference.value("orientation", nlohmann::json()), where, "head_reference.orientation")};
  } else if (model != headset_view_model_name(HeadsetViewModel::head_locked)) {
    throw InputError(where + ": headset.view_model: expected \"head-locked\" or \"head-tracked\", got \"" + model +
                     "\"");
  }
  const nlohmann::json fixation = headset.value("gaze_fixation", nlohmann::json());
  const std::string fixation_kind = fixation.is_object() ? fixation.value("kind", "") : "";
  if (fixation_kind == "rendered-depth" && fixation.size() == 1) {
    views.gaze_fixation = GazeFixation::rendered_depth;
  } else if (fixation_kind == "fixation-distance" && fixation.value("distance_mm", nlohmann::json()).is_number() &&
             fixation["distance_mm"].get<double>() > 0.0 && std::isfinite(fixation["distance_mm"].get<double>())) {
    views.gaze_fixation = GazeFixation::fixation_distance;
    views.fixation_distance_mm = fixation["distance_mm"].get<double>();
  } else {
    throw InputError(where +
                     ": headset.gaze_fixation: expected {\"kind\": \"rendered-depth\"} or {\"kind\": "
                     "\"fixation-distance\", \"distance_mm\": > 0}");
  }
  const nlohmann::json eyes = headset.value("eyes", nlohmann::json());
  if (!eyes.is_array() || eyes.size() != 2) throw InputError(where + ": headset.eyes: expected the two eyes' views");
  for (size_t i = 0; i < 2; ++i) {
    const std::string eye = "eyes[" + std::to_string(i) + "]";
    if (!eyes[i].is_object()) throw InputError(where + ": headset." + eye + ": expected an object");
    EyeView& view = views.eyes[i];
    view.position_in_head = numbers_of<3>(eyes[i].value("position_m", nlohmann::json()), where, eye + ".position_m");
    view.orientation_in_head =
        numbers_of<4>(eyes[i].value("orientation", nlohmann::json()), where, eye + ".orientation");
    const std::array<double, 4> fov =
        numbers_of<4>(eyes[i].value("fov_rad", nlohmann::json()), where, eye + ".fov_rad");
    view.field_of_view = {fov[0], fov[1], fov[2], fov[3]};
    try {
      eye_view_shader_values(view);  // a unit orientation, an image plane the angles can make
      eye_display(view, views.eye_width_px, views.eye_height_px);
    } catch (const InputError& error) {
      throw InputError(where + ": headset." + eye + ": " + error.what());
    }
  }
  return views;
}

HeadsetGazeGeometry headset_gaze_geometry(const HeadsetViews& views) {
  HeadsetGazeGeometry geometry;
  geometry.eyes = views.eyes;
  geometry.width_px = views.eye_width_px;
  geometry.height_px = views.eye_height_px;
  geometry.fixation_distance_m = views.fixation_distance_mm / 1000.0;
  return geometry;
}

void check_runtime_fields_of_view(const HeadsetViews& views, const StudyConfig& config) {
  const HeadsetDisplayConfig& headset = config.display.headset;
  const std::array<std::pair<const char*, EyeFieldOfView>, 2> configured{
      std::pair{"left_eye_fov_deg", headset.left_eye_fov}, std::pair{"right_eye_fov_deg", headset.right_eye_fov}};
  for (size_t i = 0; i < 2; ++i) {
    const EyeFieldOfView& runtime = views.eyes[i].field_of_view;
    const EyeFieldOfView& config_fov = configured[i].second;
    const std::array<double, 4> difference_rad{
        runtime.angle_left_rad - config_fov.angle_left_rad, runtime.angle_right_rad - config_fov.angle_right_rad,
        runtime.angle_up_rad - config_fov.angle_up_rad, runtime.angle_down_rad - config_fov.angle_down_rad};
    for (const double rad : difference_rad) {
      if (std::abs(rad) * kDegreesPerRadian <= 0.01) continue;
      const auto deg = [](double angle_rad) { return format_number(angle_rad * kDegreesPerRadian, 4); };
      throw InputError(config.source_path + ": display." + configured[i].first + ": the headset's runtime (" +
                       views.runtime + ") gives this eye [" + deg(runtime.angle_left_rad) + ", " +
                       deg(runtime.angle_right_rad) + ", " + deg(runtime.angle_up_rad) + ", " +
                       deg(runtime.angle_down_rad) + "] deg, the config " + field_of_view_text(config_fov) +
                       ": the plan's pixels per degree would be wrong; put the runtime's angles in the config");
    }
  }
}

}  // namespace fovlab
