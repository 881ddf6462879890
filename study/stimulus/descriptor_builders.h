#pragma once
// The builders the method descriptors share (render_method.cpp: every method but the sampling
// models; sampling_method_descriptors.cpp: the sampling models on each source). Private to
// study/stimulus: nothing outside these two files includes it.
#include <cstdint>
#include <limits>
#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "study/stimulus/render_method.h"

namespace fovlab::descriptor_builders {

// Reading and writing one member of one method's struct as a double (the edges' number).
template <class>
struct MemberOf;
template <class Struct, class Value>
struct MemberOf<Value Struct::*> {
  using object = Struct;
  using value = Value;
};

template <class Part, class Variant>
constexpr bool is_alternative_of = false;
template <class Part, class... Alternatives>
constexpr bool is_alternative_of<Part, std::variant<Alternatives...>> = (std::is_same_v<Part, Alternatives> || ...);

// The struct a member belongs to: a method's, or a sampling-model method's source or model.
template <class Part, class Parameters>
auto& part_of(Parameters& parameters) {
  if constexpr (is_alternative_of<Part, SampleSource>)
    return std::get<Part>(std::get<SampledParameters>(parameters).source);
  else if constexpr (is_alternative_of<Part, SamplingModelParameters>)
    return std::get<Part>(std::get<SampledParameters>(parameters).model);
  else return std::get<Part>(parameters);
}

template <auto Member>
double read_member(const MethodParameters& parameters) {
  using Traits = MemberOf<decltype(Member)>;
  const auto value = part_of<typename Traits::object>(parameters).*Member;
  if constexpr (std::is_enum_v<typename Traits::value>)
    return static_cast<double>(static_cast<std::underlying_type_t<typename Traits::value>>(value));
  else return static_cast<double>(value);
}

template <auto Member>
void write_member(MethodParameters& parameters, double value) {
  using Traits = MemberOf<decltype(Member)>;
  using Value = typename Traits::value;
  auto& member = part_of<typename Traits::object>(parameters).*Member;
  if constexpr (std::is_enum_v<Value>) member = static_cast<Value>(static_cast<std::underlying_type_t<Value>>(value));
  else if constexpr (std::is_same_v<Value, bool>) member = value != 0.0;
  else member = static_cast<Value>(value);
}

template <auto Member>
ParameterDescriptor parameter(std::string_view key, std::string_view unit, ParameterType type, double default_value,
                              double min_value, double max_value, std::string_view help) {
  ParameterDescriptor descriptor;
  descriptor.key = key;
  descriptor.unit = unit;
  descriptor.help = help;
  descriptor.type = type;
  descriptor.default_value = default_value;
  descriptor.min_value = min_value;
  descriptor.max_value = max_value;
  descriptor.read = &read_member<Member>;
  descriptor.write = &write_member<Member>;
  return descriptor;
}

inline ParameterDescriptor with_allowed(ParameterDescriptor descriptor, std::vector<double> allowed) {
  descriptor.allowed = std::move(allowed);
  return descriptor;
}

inline ParameterDescriptor omitted_at_default(ParameterDescriptor descriptor) {
  descriptor.omitted_at_default = true;
  return descriptor;
}

// Since log schema `since_log_schema`, configs that leave this parameter out mean its default; in
// logs of earlier schemas they meant `earlier_default`.
inline ParameterDescriptor with_changed_default(ParameterDescriptor descriptor, int since_log_schema, double earlier_default) {
  descriptor.default_since_log_schema = since_log_schema;
  descriptor.earlier_default = earlier_default;
  return descriptor;
}

inline ParameterDescriptor with_legacy_key(ParameterDescriptor descriptor, std::string_view legacy_key) {
  descriptor.legacy_key = legacy_key;
  return descriptor;
}

inline constexpr double kSeedMax = double(std::numeric_limits<uint32_t>::max());
// The sphere tracer's samples of one frame live in one buffer indexed by 32-bit words
// (renderer/sphere_tracing/sphere_tracer.h kMaxSphereTraceSamplesPerFrame; protocols/stimuli checks).
inline constexpr uint64_t kSphereTraceSamplesPerFrame = uint64_t{1} << 28;

// The parameters GT, IPR and FIPR share, then IPR's and FIPR's pyramid.
template <class Struct>
std::vector<ParameterDescriptor> sphere_trace_parameters() {
  return {
      with_allowed(parameter<&Struct::samples_per_pixel>("samples_per_pixel", "", ParameterType::integer, 1, 1, 16,
                                                         "samples a pixel (fixed sample patterns, docs/scenes.md)"),
                   {1, 4, 16}),
      parameter<&Struct::max_steps>("max_steps", "steps", ParameterType::integer, 256, 1, 4096,
                                    "step cap of one ray at one level"),
      parameter<&Struct::hit_threshold>("hit_threshold", "", ParameterType::real, 0.25, 1e-4, 8.0,
                                        "a ray hits when its distance is below t x pixel angle x level scale x this"),
  };
}

template <class Struct>
void add_display_parameters(std::vector<ParameterDescriptor>& parameters) {
  const auto display = [](std::string_view key, std::string_view help, double (*read)(const MethodParameters&),
                          void (*write)(MethodParameters&, double)) {
    ParameterDescriptor descriptor;
    descriptor.key = key;
    descriptor.unit = "mm";
    descriptor.help = help;
    descriptor.type = ParameterType::real;
    descriptor.default_value = 0.0;  // not given: the schedule fills it from [display]
    descriptor.min_value = 1.0;
    descriptor.max_value = 1e6;
    descriptor.read = read;
    descriptor.write = write;
    return descriptor;
  };
  parameters.push_back(display(
      "display_width_mm", "physical width of the stimulus image (default: from [display])",
      [](const MethodParameters& p) { return display_of(p)->display_width_mm; },
      [](MethodParameters& p, double value) { display_of(p)->display_width_mm = value; }));
  parameters.push_back(display(
      "display_height_mm", "physical height of the stimulus image (default: from [display])",
      [](const MethodParameters& p) { return display_of(p)->display_height_mm; },
      [](MethodParameters& p, double value) { display_of(p)->display_height_mm = value; }));
  parameters.push_back(display(
      "viewing_distance_mm", "eye to screen (default: from [display])",
      [](const MethodParameters& p) { return display_of(p)->viewing_distance_mm; },
      [](MethodParameters& p, double value) { display_of(p)->viewing_distance_mm = value; }));
}

template <class Struct>
std::vector<ParameterDescriptor> path_trace_parameters() {
  return {
      parameter<&Struct::samples_per_pixel>("samples_per_pixel", "", ParameterType::integer, 128, 1, 65536,
                                            "samples of each pre-rendered frame"),
      parameter<&Struct::max_bounces>("max_bounces", "", ParameterType::integer, 32, 0, 1024,
                                      "scattering events a path may have (docs/path-tracing.md)"),
      parameter<&Struct::path_seed>("path_seed", "", ParameterType::integer, 1, 0, kSeedMax, "the path tracer's seed"),
  };
}

// Every (source, model) pair of the sampling models, source-major (sampling_method_descriptors.cpp).
std::vector<MethodDescriptor> sampling_models();

}  // namespace fovlab::descriptor_builders
