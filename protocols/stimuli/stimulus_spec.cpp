#include "protocols/stimuli/stimulus_spec.h"

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "core/input_error.h"
#include "core/number_text.h"
#include "renderer/foveation/display_geometry.h"
#include "renderer/prerender/frame_cache.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "renderer/zone_blend/zone_layout.h"

namespace fovlab {
namespace {

constexpr double kNoOuterPeripheryDeg = 180.0;  // eccentricities are below 180 degrees: no outer periphery

// The physical display of fipr and fpt (0: not given; the schedule fills them from [display]).
const std::vector<MethodParameter>& display_parameters() {
  static const std::vector<MethodParameter> parameters = {
      {kDisplayWidthParameter, 0, 1, 1e6, false, {}},
      {kDisplayHeightParameter, 0, 1, 1e6, false, {}},
      {kViewingDistanceParameter, 0, 1, 1e6, false, {}},
  };
  return parameters;
}

std::vector<MethodParameter> sphere_trace_parameters(bool pyramid, int min_pyramid_levels) {
  const SphereTraceSettings defaults;
  std::vector<MethodParameter> parameters = {
      {"samples_per_pixel", 1, 1, 16, true, {1, 4, 16}},
      {"max_steps", double(defaults.max_steps), 1, 4096, true, {}},
      // The renderer takes (0, 8] (renderer/sphere_tracing/sphere_tracer.cpp, validate).
      {"hit_threshold", double(defaults.hit_threshold), 1e-4, 8.0, false, {}},
  };
  if (pyramid) {
    parameters.push_back({"pyramid_levels", double(defaults.pyramid_levels), double(min_pyramid_levels), 5, true, {}});
    parameters.push_back({"min_filter_size", double(defaults.min_filter_size), 1, 5, true, {1, 3, 5}});
  }
  return parameters;
}

// FIPR (seed 000 section 3.2): IPR's parameters with at least 3 levels (low, mid and top), the
// foveation (renderer/sphere_tracing/sphere_tracer.h, FoveationSettings) and the display.
std::vector<MethodParameter> fipr_parameters() {
  std::vector<MethodParameter> parameters = sphere_trace_parameters(true, 3);
  const std::vector<MethodParameter> foveation = {
      {"fovea_deg", 7.5, 0, 180, false, {}},
      {"outer_periphery_deg", kNoOuterPeripheryDeg, 0, kNoOuterPeripheryDeg, false, {}},
      {"periphery_refresh", 1, 1, 4, true, {1, 2, 4}},
      {"periphery_steps", double(FoveationSettings{}.periphery_steps), 0, 4096, true, {}},
      {"blur", 0, 0, 1, true, {0, 1}},
      {"combine", double(static_cast<uint32_t>(MaskCombine::max)), 0, 3, true, {0, 1, 2, 3}},
      {"edge_threshold", 0.4, 1e-4, 1000, false, {}},
      {"mask_seed", 0, 0, double(std::numeric_limits<uint32_t>::max()), true, {}},
  };
  parameters.insert(parameters.end(), foveation.begin(), foveation.end());
  parameters.insert(parameters.end(), display_parameters().begin(), display_parameters().end());
  return parameters;
}

// Path tracing (renderer/path_tracing/path_tracer.h): the paper's reference is 128 samples and 32
// bounces.
std::vector<MethodParameter> path_trace_parameters() {
  const PathTraceSettings defaults;
  return {
      {"samples_per_pixel", double(defaults.samples_per_pixel), 1, 65536, true, {}},
      {"max_bounces", double(defaults.max_bounces), 0, 1024, true, {}},
      {"path_seed", double(defaults.seed), 0, double(std::numeric_limits<uint32_t>::max()), true, {}},
  };
}

// The emulated foveated path tracer (seed 001 section 3.2; renderer/zone_blend/zone_layout.h):
// zone angles are full apertures; -1 periphery bounces: the same as max_bounces.
std::vector<MethodParameter> fpt_parameters() {
  std::vector<MethodParameter> parameters = path_trace_parameters();
  const ZoneBounds defaults;
  const std::vector<MethodParameter> zones = {
      {"foveal_deg", defaults.foveal_deg, 0, 360, false, {}},
      {"middle_over_foveal_deg", kMiddleOverFovealDeg, 0, 360, false, {}},
      {"band_deg", defaults.band_deg, 0, 90, false, {}},
      {"periphery_bounces", -1, -1, 1024, true, {}},
  };
  parameters.insert(parameters.end(), zones.begin(), zones.end());
  parameters.insert(parameters.end(), display_parameters().begin(), display_parameters().end());
  return parameters;
}

double parameter_or(const StimulusSpec& spec, const char* name, double fallback) {
  const auto found = spec.parameters.find(name);
  return found == spec.parameters.end() ? fallback : found->second;
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
  if (method == "gt") return sphere_trace_parameters(false, 2);
  if (method == "ipr") return sphere_trace_parameters(true, 2);
  if (method == "fipr") return fipr_parameters();
  if (method == "pt") return path_trace_parameters();
  if (method == "fpt") return fpt_parameters();
  return std::nullopt;
}

std::string known_methods() { return "gt, ipr, fipr, pt, fpt"; }

bool method_depends_on_gaze(const std::string& method) { return method == "fipr" || method == "fpt"; }

bool is_path_traced_method(const std::string& method) { return method == "pt" || method == "fpt"; }

std::optional<ParameterConflict> parameter_conflict(const std::string& method,
                                                    const std::map<std::string, double>& parameters) {
  if (method != "fipr") return std::nullopt;
  const auto fovea = parameters.find("fovea_deg");
  const auto outer = parameters.find("outer_periphery_deg");
  if (fovea == parameters.end() || outer == parameters.end() || outer->second >= fovea->second) return std::nullopt;
  return ParameterConflict{{"fovea_deg", "outer_periphery_deg"},
                           "expected outer_periphery_deg (" + format_number(outer->second, 6) + ") >= fovea_deg (" +
                               format_number(fovea->second, 6) + "): the outer periphery starts beyond the fovea"};
}

SphereTraceSettings sphere_trace_settings(const StimulusSpec& spec, int frame) {
  SphereTraceSettings settings;
  if (spec.method == "gt") {
    settings.method = TraceMethod::ground_truth;
  } else if (spec.method == "ipr") {
    settings.method = TraceMethod::inverted_pyramid;
  } else if (spec.method == "fipr") {
    settings.method = TraceMethod::foveated_pyramid;
  } else {
    throw std::logic_error("sphere_trace_settings: not a sphere-tracing method: " + spec.method);
  }
  const auto get = [&](const char* name, double fallback) { return parameter_or(spec, name, fallback); };
  settings.width = spec.width_px;
  settings.height = spec.height_px;
  settings.time_s = static_cast<float>(spec.frame_time_s(frame));
  settings.samples_per_pixel = static_cast<int>(get("samples_per_pixel", settings.samples_per_pixel));
  settings.max_steps = static_cast<int>(get("max_steps", settings.max_steps));
  settings.hit_threshold = static_cast<float>(get("hit_threshold", settings.hit_threshold));
  settings.pyramid_levels = static_cast<int>(get("pyramid_levels", settings.pyramid_levels));
  settings.min_filter_size = static_cast<int>(get("min_filter_size", settings.min_filter_size));
  if (settings.method != TraceMethod::foveated_pyramid) return settings;

  FoveationSettings& foveation = settings.foveation;
  foveation.display = stimulus_display(spec);
  foveation.gaze_x_px = std::numeric_limits<double>::quiet_NaN();
  foveation.gaze_y_px = std::numeric_limits<double>::quiet_NaN();
  foveation.acuity.fovea_deg = get("fovea_deg", foveation.acuity.fovea_deg);
  const double outer_deg = get("outer_periphery_deg", kNoOuterPeripheryDeg);
  foveation.acuity.outer_periphery_deg =
      outer_deg >= kNoOuterPeripheryDeg ? std::numeric_limits<double>::infinity() : outer_deg;
  foveation.periphery_refresh = static_cast<int>(get("periphery_refresh", foveation.periphery_refresh));
  foveation.periphery_steps = static_cast<int>(get("periphery_steps", foveation.periphery_steps));
  foveation.blur = get("blur", 0.0) != 0.0;
  foveation.combine = static_cast<MaskCombine>(static_cast<uint32_t>(get("combine", 0.0)));
  foveation.edge_threshold = static_cast<float>(get("edge_threshold", foveation.edge_threshold));
  foveation.seed = static_cast<uint32_t>(get("mask_seed", 0.0));
  foveation.frame_index = 0;
  return settings;
}

DisplayGeometry stimulus_display(const StimulusSpec& spec) {
  const double width_mm = parameter_or(spec, kDisplayWidthParameter, 0.0);
  const double height_mm = parameter_or(spec, kDisplayHeightParameter, 0.0);
  const double distance_mm = parameter_or(spec, kViewingDistanceParameter, 0.0);
  if (!(width_mm > 0.0 && height_mm > 0.0 && distance_mm > 0.0))
    throw InputError("stimulus " + spec.canonical() + ": " + spec.method + " needs " + kDisplayWidthParameter + ", " +
                     kDisplayHeightParameter + " and " + kViewingDistanceParameter +
                     " (a study's schedule fills them from [display])");
  return display_from_size(spec.width_px, spec.height_px, width_mm, height_mm, distance_mm);
}

PathTracedFrames path_traced_frames(const StimulusSpec& spec) {
  if (!is_path_traced_method(spec.method))
    throw std::logic_error("path_traced_frames: not a path-traced method: " + spec.method);
  PathTraceSequence frames;
  frames.scene = spec.scene;
  frames.width_px = spec.width_px;
  frames.height_px = spec.height_px;
  frames.samples_per_pixel = static_cast<int>(parameter_or(spec, "samples_per_pixel", frames.samples_per_pixel));
  frames.max_bounces = static_cast<int>(parameter_or(spec, "max_bounces", frames.max_bounces));
  frames.seed = static_cast<uint32_t>(parameter_or(spec, "path_seed", frames.seed));
  frames.frames_per_second = spec.frames_per_second;
  frames.camera_start_s = spec.camera_start_s;
  frames.frame_count = spec.frame_count;
  PathTracedFrames result{{frames}};
  const int periphery_bounces = static_cast<int>(parameter_or(spec, "periphery_bounces", -1));
  if (spec.method == "fpt" && periphery_bounces >= 0 && periphery_bounces != frames.max_bounces) {
    PathTraceSequence periphery = frames;
    periphery.max_bounces = periphery_bounces;
    result.sequences.push_back(periphery);
  }
  return result;
}

ZoneBounds zone_bounds(const StimulusSpec& spec) {
  ZoneBounds bounds;
  bounds.foveal_deg = parameter_or(spec, "foveal_deg", bounds.foveal_deg);
  bounds.middle_deg = bounds.foveal_deg + parameter_or(spec, "middle_over_foveal_deg", kMiddleOverFovealDeg);
  bounds.band_deg = parameter_or(spec, "band_deg", bounds.band_deg);
  return bounds;
}

}  // namespace fovlab
