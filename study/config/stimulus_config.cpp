#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "core/number_text.h"
#include "core/toml_fields.h"
#include "study/config/config_reading.h"
#include "study/config/study_config.h"
#include "study/stimulus/render_method.h"

namespace fovlab::config_detail {
namespace {

// A parameter's value as a message quotes it: a choice by its name, a number as it was given (the
// canonical text's 17 digits, 0.10000000000000001, are for logs, not people).
std::string value_in_message(const ParameterDescriptor& parameter, double value) {
  const bool named = parameter.type == ParameterType::choice && value >= 0 &&
                     value < double(parameter.choices.size()) && value == std::floor(value);
  return named ? parameter_value_text(parameter, value) : exact_number_text(value);
}

// Reads every key of the table but `skip` as a parameter of the method: by its key (or a legacy
// key), its value checked against the descriptor. A choice is its name (legacy configs: its index).
std::map<std::string, double> read_parameters(const TomlFields& fields, RenderMethod method,
                                              const std::set<std::string>& skip, const Reading& reading) {
  const MethodDescriptor& descriptor = describe(method);
  std::map<std::string, double> values;
  for (auto&& [key, node] : fields.raw()) {
    const std::string name(key.str());
    if (skip.count(name)) continue;
    const ParameterDescriptor* parameter = find_parameter(descriptor, name, reading.legacy_keys);
    if (!parameter)
      fields.fail(name, "not a parameter of method \"" + std::string(descriptor.name) +
                            "\" (expected one of: " + parameter_keys(descriptor) + ")");
    double value = 0.0;
    if (parameter->type == ParameterType::choice && !(reading.legacy_keys && node.is_number())) {
      if (!node.is_string())
        fields.fail(name, "expected " + *check_parameter_value(*parameter, -1) + " (a name), got " +
                              (node.is_number() ? exact_number_text(fields.number(name)) : "another type"));
      const std::string choice = fields.string(name);
      const std::optional<double> index = parse_choice(*parameter, choice, reading.log_schema_version);
      if (!index) fields.fail(name, "expected " + *check_parameter_value(*parameter, -1) + ", got \"" + choice + "\"");
      value = *index;
    } else {
      value = fields.number(name);
    }
    if (const std::optional<std::string> expected = check_parameter_value(*parameter, value))
      fields.fail(name, "expected " + *expected + ", got " + value_in_message(*parameter, value));
    values[std::string(parameter->key)] = value;
  }
  return values;
}

MethodConfig read_method(const TomlFields& fields, const Reading& reading) {
  MethodConfig config;
  const std::string name = fields.string("method");
  const std::optional<RenderMethod> method = find_method(name);
  if (!method) fields.fail("method", "expected one of " + known_methods() + ", got \"" + name + "\"");
  config.method = *method;
  config.parameters = read_parameters(fields, config.method, {"method"}, reading);
  // A default that changed since the log was written is the one it was written with.
  for (const ParameterDescriptor& parameter : describe(config.method).parameters)
    if (default_changed_since(parameter, reading.log_schema_version))
      config.parameters.emplace(std::string(parameter.key),
                                default_in_log_schema(parameter, reading.log_schema_version));
  return config;
}

// The method and full parameters of every stimulus the config makes: the reference, and the test
// under every variant and level.
std::vector<MethodParameters> stimulus_parameters(const StimulusConfig& stimulus, const LevelsConfig& levels) {
  std::vector<MethodParameters> all;
  all.push_back(parameters_with(stimulus.reference.method, {&stimulus.reference.parameters}));
  const ParameterLayer none;
  const std::vector<const VariantConfig*> variants = tested_variants(stimulus);
  for (const VariantConfig* variant : variants) {
    std::vector<ParameterLayer> level_parameters;
    for (double value : variant_levels(levels, variant)) level_parameters.push_back({{levels.parameter, value}});
    if (level_parameters.empty()) level_parameters.emplace_back();
    for (const ParameterLayer& level : level_parameters)
      all.push_back(parameters_with(stimulus.test.method,
                                    {&stimulus.test.parameters, variant ? &variant->parameters : &none, &level}));
  }
  return all;
}

}  // namespace

// Rules between parameters (parameter_conflict: FIPR's outer periphery at or beyond its fovea) must
// hold for every stimulus the config makes: the reference, and the test under every variant and
// level (with a conditions file, read_conditions checks the test on each row). The error names the field that set one of the parameters involved, the last layer first:
// the level values, the variant, the method's table (the table itself when only defaults clash).
void check_parameter_rules(const TomlFields& stimulus_fields, const StimulusConfig& stimulus,
                           const TomlFields* levels_fields, const LevelsConfig& levels, bool conditions_file) {
  const auto fail_in = [](const TomlFields& fields, const std::map<std::string, double>& given,
                          const ParameterConflict& conflict) {
    for (std::string_view key : conflict.keys)
      if (given.count(std::string(key))) fields.fail(std::string(key), conflict.expected);
  };
  {
    const MethodConfig& reference = stimulus.reference;
    const auto conflict = parameter_conflict(parameters_with(reference.method, {&reference.parameters}));
    if (conflict) {
      const TomlFields fields = stimulus_fields.table("reference");
      fail_in(fields, reference.parameters, *conflict);
      fields.fail("", conflict->expected);
    }
  }
  if (conditions_file) return;  // each row of the conditions file is checked as it is read
  const MethodConfig& test = stimulus.test;
  const TomlFields test_fields = stimulus_fields.table("test");
  const std::vector<TomlFields> variant_fields =
      stimulus.variants.empty() ? std::vector<TomlFields>{} : stimulus_fields.tables("variant");
  const std::vector<const VariantConfig*> variants = tested_variants(stimulus);
  std::vector<std::optional<double>> level_values(levels.values.begin(), levels.values.end());
  if (level_values.empty()) level_values.emplace_back(std::nullopt);
  const std::map<std::string, double> none;
  for (size_t v = 0; v < variants.size(); ++v) {
    const std::map<std::string, double>& variant = variants[v] ? variants[v]->parameters : none;
    for (const std::optional<double>& level : level_values) {
      std::map<std::string, double> level_parameter;
      if (level) level_parameter[levels.parameter] = *level;
      const auto conflict =
          parameter_conflict(parameters_with(test.method, {&test.parameters, &variant, &level_parameter}));
      if (!conflict) continue;
      const std::vector<std::string_view>& involved = conflict->keys;
      if (level && levels_fields && std::find(involved.begin(), involved.end(), levels.parameter) != involved.end())
        levels_fields->fail("values", "value " + format_number(*level, 6) + ": " + conflict->expected);
      if (variants[v]) fail_in(variant_fields[v], variant, *conflict);
      fail_in(test_fields, test.parameters, *conflict);
      test_fields.fail("", conflict->expected);
    }
  }
}

// The renderers' rule on the frame size (the method descriptors' max_samples_per_frame), which is
// the display's: checked here, so that they name the config's
// fields (and fovlab validate finds them). What depends on the device (one storage buffer) is
// checked when a session prepares its stimuli (StimulusLibrary::prepare).
void check_frame_size_rules(const TomlFields& display_fields, const DisplayConfig& display,
                            const StimulusConfig& stimulus, const LevelsConfig& levels) {
  for (const MethodParameters& parameters : stimulus_parameters(stimulus, levels)) {
    const MethodDescriptor& method = describe(method_of(parameters));
    const ParameterDescriptor* samples_per_pixel = find_parameter(method, "samples_per_pixel");
    if (method.max_samples_per_frame > 0 && samples_per_pixel) {
      const double spp = samples_per_pixel->read(parameters);
      const uint64_t samples = uint64_t(display.width_px) * uint64_t(display.height_px) * static_cast<uint64_t>(spp);
      const bool headset = display.kind == DisplayKind::openxr;  // the size is each eye's
      const std::string width = headset ? "eye_width_px" : "width_px", height = headset ? "eye_height_px" : "height_px";
      if (samples > method.max_samples_per_frame)
        display_fields.fail(width, "expected " + width + " x " + height + " x samples_per_pixel of at most " +
                                       std::to_string(method.max_samples_per_frame) + " samples a frame (" +
                                       std::string(method.name) + "), got " + std::to_string(display.width_px) + " x " +
                                       std::to_string(display.height_px) + " x " + format_number(spp, 6) + " = " +
                                       std::to_string(samples));
    }
  }
}

void read_stimulus(const TomlFields& fields, const DisplayConfig& display, const Reading& reading,
                   StimulusConfig& stimulus) {
  stimulus.duration_s = fields.number("duration_s");
  check_range(fields, "duration_s", stimulus.duration_s, 1e-3, 3600.0);
  stimulus.frames_per_second = fields.number("frames_per_second", display.refresh_hz);
  check_range(fields, "frames_per_second", stimulus.frames_per_second, 1e-3, display.refresh_hz);
  const double ratio = display.refresh_hz / stimulus.frames_per_second;
  if (std::abs(ratio - std::round(ratio)) > 1e-6)
    fields.fail("frames_per_second",
                "expected the display's refresh rate divided by a whole number (each frame "
                "is held for the same number of refreshes)");
  stimulus.camera_start_s = fields.number("camera_start_s", 0.0);
  stimulus.reference = read_method(fields.table("reference"), reading);
  stimulus.test = read_method(fields.table("test"), reading);
  if (fields.has("variant")) {
    std::set<std::string> names;
    for (const TomlFields& variant_fields : fields.tables("variant")) {
      VariantConfig variant;
      variant.name = variant_fields.string("name");
      if (!is_safe_name(variant.name)) variant_fields.fail("name", "expected letters, digits, '_', '-' or '.'");
      if (!names.insert(variant.name).second) variant_fields.fail("name", "duplicate variant \"" + variant.name + "\"");
      variant.parameters = read_parameters(variant_fields, stimulus.test.method, {"name"}, reading);
      stimulus.variants.push_back(std::move(variant));
    }
  }
  fields.finish();
}

void read_levels(const TomlFields& fields, const MethodConfig& test, const Reading& reading, bool from_conditions,
                 LevelsConfig& levels) {
  const MethodDescriptor& method = describe(test.method);
  const std::string name = fields.string("parameter");
  const ParameterDescriptor* parameter = find_parameter(method, name, reading.legacy_keys);
  if (!parameter || parameter->type == ParameterType::choice) {
    std::string numeric;
    for (const ParameterDescriptor& candidate : method.parameters)
      if (candidate.type != ParameterType::choice)
        numeric += (numeric.empty() ? "" : ", ") + std::string(candidate.key);
    fields.fail("parameter", "not a numeric parameter of the test method \"" + std::string(method.name) +
                                 "\" (expected one of: " + numeric + ")");
  }
  levels.parameter = parameter->key;
  if (from_conditions) {
    if (fields.has("values"))
      fields.fail("values", "the [conditions] file gives the levels (its \"" + levels.parameter +
                                "\" column); expected no values");
    levels.higher_is_better = fields.boolean("higher_is_better", true);
    fields.finish();
    return;
  }
  levels.values = fields.numbers("values");
  for (size_t i = 0; i < levels.values.size(); ++i) {
    if (const std::optional<std::string> expected = check_parameter_value(*parameter, levels.values[i]))
      fields.fail("values", "expected " + *expected + ", got " + exact_number_text(levels.values[i]));
    if (i > 0 && !(levels.values[i] > levels.values[i - 1]))
      fields.fail("values", "expected strictly ascending values");
  }
  levels.higher_is_better = fields.boolean("higher_is_better", true);
  fields.finish();
}

// The methods that render a kind of scene: "pt and fpt", for messages.
std::string methods_of_kind(SceneKind kind, const char* conjunction) {
  std::vector<std::string> names;
  for (const MethodDescriptor& method : all_methods())
    if (method.scene_kind == kind) names.emplace_back(method.name);
  std::string text;
  for (size_t i = 0; i < names.size(); ++i)
    text += (i == 0 ? "" : i + 1 == names.size() ? std::string(" ") + conjunction + " " : ", ") + names[i];
  return text;
}

// Sphere-traced methods take SDF scenes (built-in names or files), path-traced and volume methods
// their own kind (built-in names or files with the catalog's extension for that kind); files are
// relative to the config. Without a catalog the scene is taken as written.
std::string resolve_scene(const TomlFields& fields, const std::string& scene, const std::string& config_path,
                          const SceneCatalog* catalog, SceneKind kind) {
  if (!catalog) return scene;
  if (kind == SceneKind::image_sequence) {  // a folder of images, relative to the config
    std::filesystem::path folder(scene);
    if (folder.is_relative()) folder = std::filesystem::path(config_path).parent_path() / folder;
    std::error_code error;
    if (catalog->check_files && !std::filesystem::is_directory(folder, error))
      fields.fail("scene", "expected a folder of .png or .exr images (relative to the config) for " +
                               methods_of_kind(kind, "and") + ", got \"" + scene + "\": no such folder");
    folder = folder.lexically_normal();
    if (folder.filename().empty() && folder.has_parent_path()) folder = folder.parent_path();  // "images/"
    return folder.string();
  }
  const std::vector<std::string>& names = kind == SceneKind::path_traced ? catalog->path_traced_names
                                          : kind == SceneKind::volume    ? catalog->volume_names
                                                                         : catalog->signed_distance_names;
  std::string known;
  for (const std::string& name : names) known += (known.empty() ? "" : ", ") + name;
  if (std::find(names.begin(), names.end(), scene) != names.end()) return scene;
  if (kind != SceneKind::signed_distance) {
    const std::string& extension =
        kind == SceneKind::path_traced ? catalog->path_traced_file_extension : catalog->volume_file_extension;
    std::string tail = scene.size() >= extension.size() ? scene.substr(scene.size() - extension.size()) : std::string();
    for (char& c : tail) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (tail != extension)
      fields.fail("scene", std::string("expected a ") + (kind == SceneKind::path_traced ? "path-traced" : "volume") +
                               " scene (" + known + " or a " + extension + " file) for " +
                               methods_of_kind(kind, "and") + ", got \"" + scene + "\"");
  }
  std::filesystem::path path(scene);
  if (path.is_relative()) path = std::filesystem::path(config_path).parent_path() / path;
  std::error_code error;  // e.g. a name too long for the file system: not found, not a crash
  if (catalog->check_files && !std::filesystem::is_regular_file(path, error))
    fields.fail("scene", "no built-in scene or file \"" + scene + "\" (built-in: " + known + ")");
  return path.lexically_normal().string();
}

// "a sphere-traced method", "a path-traced method", "a volume method": for messages.
std::string kind_of_method(SceneKind kind) {
  switch (kind) {
    case SceneKind::signed_distance:
      return "a sphere-traced method";
    case SceneKind::path_traced:
      return "a path-traced method";
    case SceneKind::volume:
      return "a volume method";
    case SceneKind::image_sequence:
      return "an image method";
  }
  return "a method";
}

}  // namespace fovlab::config_detail

namespace fovlab {

int StimulusConfig::frame_count() const {
  return std::max(1, static_cast<int>(std::lround(duration_s * frames_per_second)));
}

int StimulusConfig::refreshes_per_frame(double refresh_hz) const {
  return std::max(1, static_cast<int>(std::lround(refresh_hz / frames_per_second)));
}

const std::vector<double>& variant_levels(const LevelsConfig& levels, const VariantConfig* variant) {
  return variant && !variant->levels.empty() ? variant->levels : levels.values;
}

std::vector<const VariantConfig*> tested_variants(const StimulusConfig& stimulus) {
  std::vector<const VariantConfig*> variants;
  for (const VariantConfig& variant : stimulus.variants) variants.push_back(&variant);
  if (variants.empty()) variants.push_back(nullptr);
  return variants;
}

}  // namespace fovlab
