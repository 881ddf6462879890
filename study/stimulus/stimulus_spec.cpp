#include "study/stimulus/stimulus_spec.h"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <vector>

#include "core/input_error.h"
#include "core/number_text.h"

namespace fovlab {
namespace {

// The method's parameters sorted by key (the canonical order), sorted once per method: specs are
// compared by their canonical text while a schedule is made.
const std::vector<const ParameterDescriptor*>& sorted_parameters(RenderMethod method) {
  static const std::vector<std::vector<const ParameterDescriptor*>> by_method = [] {
    std::vector<std::vector<const ParameterDescriptor*>> all;
    for (const MethodDescriptor& descriptor : all_methods()) {
      std::vector<const ParameterDescriptor*> sorted;
      for (const ParameterDescriptor& parameter : descriptor.parameters) sorted.push_back(&parameter);
      std::sort(sorted.begin(), sorted.end(), [](const auto* a, const auto* b) { return a->key < b->key; });
      all.push_back(std::move(sorted));
    }
    return all;
  }();
  return by_method.at(method_index(method));
}

bool left_out(const ParameterDescriptor& parameter, const MethodParameters& parameters) {
  const double omitted = parameter.default_since_log_schema > 0 ? parameter.earlier_default : parameter.default_value;
  return parameter.omitted_at_default && parameter.read(parameters) == omitted;
}

}  // namespace

std::string StimulusSpec::canonical() const {
  std::string text = "scene=" + scene + ";method=";
  text.reserve(256);
  text += method_name();
  for (const ParameterDescriptor* parameter : sorted_parameters(method())) {
    if (left_out(*parameter, parameters)) continue;
    text += ';';
    text += parameter->key;
    text += '=';
    text += parameter_value_text(*parameter, parameter->read(parameters));
  }
  text += ";size=" + std::to_string(width_px) + "x" + std::to_string(height_px);
  text += ";frames=" + std::to_string(frame_count) + "@" + format_number(frames_per_second, 17);
  text += ";camera_start_s=" + format_number(camera_start_s, 17);
  return text;
}

nlohmann::json to_json(const StimulusSpec& spec) {
  nlohmann::json parameters = nlohmann::json::object();
  for (const ParameterDescriptor* parameter : sorted_parameters(spec.method())) {
    if (left_out(*parameter, spec.parameters)) continue;
    const double value = parameter->read(spec.parameters);
    if (parameter->type == ParameterType::choice)
      parameters[std::string(parameter->key)] = parameter_value_text(*parameter, value);
    else parameters[std::string(parameter->key)] = value;
  }
  return {{"scene", spec.scene},
          {"method", spec.method_name()},
          {"parameters", parameters},
          {"width_px", spec.width_px},
          {"height_px", spec.height_px},
          {"frame_count", spec.frame_count},
          {"frames_per_second", spec.frames_per_second},
          {"camera_start_s", spec.camera_start_s}};
}

DisplaySize stimulus_display_size(const StimulusSpec& spec) {
  const StimulusDisplay* display = display_of(spec.parameters);
  if (!display) throw std::logic_error("stimulus_display_size: " + std::string(spec.method_name()) + " has no display");
  if (!(display->display_width_mm > 0.0 && display->display_height_mm > 0.0 && display->viewing_distance_mm > 0.0))
    throw InputError("stimulus " + spec.canonical() + ": " + std::string(spec.method_name()) +
                     " needs display_width_mm, display_height_mm and viewing_distance_mm (a study's schedule fills "
                     "them from [display])");
  return {display->display_width_mm, display->display_height_mm, display->viewing_distance_mm};
}

}  // namespace fovlab
