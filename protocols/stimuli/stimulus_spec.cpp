#include "protocols/stimuli/stimulus_spec.h"

#include <nlohmann/json.hpp>
#include <stdexcept>

#include "core/number_text.h"
#include "renderer/sphere_tracing/sphere_tracer.h"

namespace fovlab {
namespace {

std::vector<MethodParameter> sphere_trace_parameters(bool pyramid) {
  const SphereTraceSettings defaults;
  std::vector<MethodParameter> parameters = {
      {"samples_per_pixel", 1, 1, 16, true, {1, 4, 16}},
      {"max_steps", double(defaults.max_steps), 1, 4096, true, {}},
      {"hit_threshold", double(defaults.hit_threshold), 1e-4, 10.0, false, {}},
  };
  if (pyramid) {
    parameters.push_back({"pyramid_levels", double(defaults.pyramid_levels), 2, 5, true, {}});
    parameters.push_back({"min_filter_size", double(defaults.min_filter_size), 1, 5, true, {1, 3, 5}});
  }
  return parameters;
}

}  // namespace

std::string StimulusSpec::canonical() const {
  std::string text = "scene=" + scene + ";method=" + method;
  for (const auto& [name, value] : parameters) text += ";" + name + "=" + format_number(value, 17);
  text += ";size=" + std::to_string(width_px) + "x" + std::to_string(height_px);
  text += ";frames=" + std::to_string(frame_count) + "@" + format_number(frames_per_second, 17);
  text += ";camera_start_s=" + format_number(camera_start_s, 17);
  return text;
}

nlohmann::json to_json(const StimulusSpec& spec) {
  return {{"scene", spec.scene},
          {"method", spec.method},
          {"parameters", spec.parameters},
          {"width_px", spec.width_px},
          {"height_px", spec.height_px},
          {"frame_count", spec.frame_count},
          {"frames_per_second", spec.frames_per_second},
          {"camera_start_s", spec.camera_start_s}};
}

std::optional<std::vector<MethodParameter>> method_parameters(const std::string& method) {
  if (method == "gt") return sphere_trace_parameters(false);
  if (method == "ipr") return sphere_trace_parameters(true);
  return std::nullopt;
}

std::string known_methods() { return "gt, ipr"; }

bool method_depends_on_gaze(const std::string&) { return false; }  // gt and ipr do not

SphereTraceSettings sphere_trace_settings(const StimulusSpec& spec, int frame) {
  SphereTraceSettings settings;
  if (spec.method == "gt") {
    settings.method = TraceMethod::ground_truth;
  } else if (spec.method == "ipr") {
    settings.method = TraceMethod::inverted_pyramid;
  } else {
    throw std::logic_error("sphere_trace_settings: not a sphere-tracing method: " + spec.method);
  }
  const auto get = [&](const char* name, double fallback) {
    const auto found = spec.parameters.find(name);
    return found == spec.parameters.end() ? fallback : found->second;
  };
  settings.width = spec.width_px;
  settings.height = spec.height_px;
  settings.time_s = static_cast<float>(spec.frame_time_s(frame));
  settings.samples_per_pixel = static_cast<int>(get("samples_per_pixel", settings.samples_per_pixel));
  settings.max_steps = static_cast<int>(get("max_steps", settings.max_steps));
  settings.hit_threshold = static_cast<float>(get("hit_threshold", settings.hit_threshold));
  settings.pyramid_levels = static_cast<int>(get("pyramid_levels", settings.pyramid_levels));
  settings.min_filter_size = static_cast<int>(get("min_filter_size", settings.min_filter_size));
  return settings;
}

}  // namespace fovlab
