#include "study/config/study_config.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <cstdio>
#include <set>
#include <sstream>
#include <string_view>

#include "core/content_hash.h"
#include "core/csv.h"
#include "core/input_file.h"
#include "core/input_error.h"
#include "core/number_text.h"
#include "study/config/input_keys.h"
#include "core/toml_fields.h"
#include "core/toml_guard.h"
#include "study/stimulus/render_method.h"

namespace fovlab {

namespace {

// Block and variant names follow the study name's rule (they name files and label results).
bool is_safe_name(const std::string& name) { return is_valid_study_name(name); }

void check_range(const TomlFields& fields, const std::string& key, double value, double low, double high) {
  if (!(value >= low && value <= high))  // the value as given: 0.9000001 is not "0.9"
    fields.fail(key, "expected a value in [" + exact_number_text(low) + ", " + exact_number_text(high) + "], got " +
                         exact_number_text(value));
}

// A parameter's value as a message quotes it: a choice by its name, a number as it was given (the
// canonical text's 17 digits, 0.10000000000000001, are for logs, not people).
std::string value_in_message(const ParameterDescriptor& parameter, double value) {
  const bool named = parameter.type == ParameterType::choice && value >= 0 && value < double(parameter.choices.size()) &&
                     value == std::floor(value);
  return named ? parameter_value_text(parameter, value) : exact_number_text(value);
}

// An optional number field (`fallback` when absent) in [low, high].
double bounded_number(const TomlFields& fields, const std::string& key, double fallback, double low, double high) {
  const double value = fields.number(key, fallback);
  check_range(fields, key, value, low, high);
  return value;
}

// An integer field (required when `fallback` is empty) in [low, high]; the range is checked on the
// 64-bit value, before it is narrowed.
int bounded_integer(const TomlFields& fields, const std::string& key, std::optional<int64_t> fallback, int low, int high) {
  const int64_t value = fallback ? fields.integer(key, *fallback) : fields.integer(key);
  if (value < low || value > high)
    fields.fail(key, "expected a value in [" + std::to_string(low) + ", " + std::to_string(high) + "], got " +
                         std::to_string(value));
  return static_cast<int>(value);
}

// How a config is read: where its scene names are checked, and whether the keys of configs from
// before the typed model (log schema 2 and earlier) are taken (only for configs a log carries).
struct Reading {
  const SceneCatalog* scenes = nullptr;  // nullptr: scene names taken as written
  bool legacy_keys = false;
  int log_schema_version = 0;  // of the log that carries the config (0: none); its parameters' defaults
  const std::string* logged_conditions_csv = nullptr;  // a logged config: the header's conditions_csv
};

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
      fields.fail(name, "not a parameter of method \"" + std::string(descriptor.name) + "\" (expected one of: " +
                            parameter_keys(descriptor) + ")");
    double value = 0.0;
    if (parameter->type == ParameterType::choice && !(reading.legacy_keys && node.is_number())) {
      if (!node.is_string())
        fields.fail(name, "expected " + *check_parameter_value(*parameter, -1) + " (a name), got " +
                              (node.is_number() ? exact_number_text(fields.number(name)) : "another type"));
      const std::string choice = fields.string(name);
      const std::optional<double> index = parse_choice(*parameter, choice);
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
      config.parameters.emplace(std::string(parameter.key), default_in_log_schema(parameter, reading.log_schema_version));
  return config;
}

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
    const auto conflict =
        parameter_conflict(parameters_with(reference.method, {&reference.parameters}));
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
      all.push_back(parameters_with(stimulus.test.method, {&stimulus.test.parameters, variant ? &variant->parameters : &none, &level}));
  }
  return all;
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
      if (samples > method.max_samples_per_frame)
        display_fields.fail("width_px", "expected width_px x height_px x samples_per_pixel of at most " +
                                            std::to_string(method.max_samples_per_frame) + " samples a frame (" +
                                            std::string(method.name) + "), got " + std::to_string(display.width_px) +
                                            " x " + std::to_string(display.height_px) + " x " + format_number(spp, 6) +
                                            " = " + std::to_string(samples));
    }
  }
}

ProtocolKind read_kind(const TomlFields& fields) {
  const std::string kind = fields.string("kind");
  const std::optional<ProtocolKind> found = find_protocol(kind);
  if (!found) fields.fail("kind", "expected one of " + known_protocols() + ", got \"" + kind + "\"");
  return *found;
}

void read_display(const TomlFields& fields, DisplayConfig& display) {
  display.width_px = bounded_integer(fields, "width_px", std::nullopt, 8, 16384);
  display.height_px = bounded_integer(fields, "height_px", std::nullopt, 8, 16384);
  display.refresh_hz = fields.number("refresh_hz", 60.0);
  check_range(fields, "refresh_hz", display.refresh_hz, 1.0, 1000.0);
  const bool has_diagonal = fields.has("diagonal_in");
  const bool has_size = fields.has("width_mm") || fields.has("height_mm");
  if (has_diagonal == has_size)
    fields.fail("", "expected either diagonal_in or width_mm and height_mm (the visible area), not both or neither");
  if (has_diagonal) {
    const double diagonal_in = fields.number("diagonal_in");
    check_range(fields, "diagonal_in", diagonal_in, 0.1, 10000.0);
    // Square pixels: the visible area has the resolution's aspect ratio.
    const double diagonal_px = std::hypot(double(display.width_px), double(display.height_px));
    display.width_mm = diagonal_in * 25.4 * display.width_px / diagonal_px;
    display.height_mm = diagonal_in * 25.4 * display.height_px / diagonal_px;
  } else {
    display.width_mm = fields.number("width_mm");
    check_range(fields, "width_mm", display.width_mm, 1.0, 1e6);
    display.height_mm = fields.number("height_mm");
    check_range(fields, "height_mm", display.height_mm, 1.0, 1e6);
  }
  display.viewing_distance_mm = fields.number("viewing_distance_mm");
  check_range(fields, "viewing_distance_mm", display.viewing_distance_mm, 1.0, 1e6);
  display.fullscreen = fields.boolean("fullscreen", false);
  fields.finish();
}

void read_stimulus(const TomlFields& fields, const DisplayConfig& display, const Reading& reading,
                   StimulusConfig& stimulus) {
  stimulus.duration_s = fields.number("duration_s");
  check_range(fields, "duration_s", stimulus.duration_s, 1e-3, 3600.0);
  stimulus.frames_per_second = fields.number("frames_per_second", display.refresh_hz);
  check_range(fields, "frames_per_second", stimulus.frames_per_second, 1e-3, display.refresh_hz);
  const double ratio = display.refresh_hz / stimulus.frames_per_second;
  if (std::abs(ratio - std::round(ratio)) > 1e-6)
    fields.fail("frames_per_second", "expected the display's refresh rate divided by a whole number (each frame "
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
      if (candidate.type != ParameterType::choice) numeric += (numeric.empty() ? "" : ", ") + std::string(candidate.key);
    fields.fail("parameter", "not a numeric parameter of the test method \"" + std::string(method.name) +
                                 "\" (expected one of: " + numeric + ")");
  }
  levels.parameter = parameter->key;
  if (from_conditions) {
    if (fields.has("values"))
      fields.fail("values", "the [conditions] file gives the levels (its \"" + levels.parameter + "\" column); expected no values");
    levels.higher_is_better = fields.boolean("higher_is_better", true);
    fields.finish();
    return;
  }
  levels.values = fields.numbers("values");
  for (size_t i = 0; i < levels.values.size(); ++i) {
    if (const std::optional<std::string> expected = check_parameter_value(*parameter, levels.values[i]))
      fields.fail("values", "expected " + *expected + ", got " + exact_number_text(levels.values[i]));
    if (i > 0 && !(levels.values[i] > levels.values[i - 1])) fields.fail("values", "expected strictly ascending values");
  }
  levels.higher_is_better = fields.boolean("higher_is_better", true);
  fields.finish();
}

void read_protocol(const TomlFields& fields, const LevelsConfig& levels, const StimulusConfig& stimulus,
                   ProtocolConfig& protocol) {
  protocol.kind = read_kind(fields);
  const bool ladder = protocol.kind == ProtocolKind::ramp || protocol.kind == ProtocolKind::slider;
  if (ladder && levels.values.size() < 2)
    fields.fail("kind", std::string(protocol_name(protocol.kind)) + " needs a [levels] table with at least two values");
  for (const VariantConfig& variant : stimulus.variants)
    if (ladder && variant_levels(levels, &variant).size() < 2)
      fields.fail("kind", std::string(protocol_name(protocol.kind)) + " needs at least two levels in every variant (\"" +
                              variant.name + "\" has fewer in the conditions file)");
  if (protocol.kind == ProtocolKind::two_afc) {
    const std::string question = fields.string("question");
    const std::optional<TwoAfcQuestion> found = find_two_afc_question(question);
    if (!found)
      fields.fail("question", "expected \"same\" (same/different) or \"better\" (first/second), got \"" + question + "\"");
    protocol.two_afc_question = *found;
  }
  protocol.repeats = bounded_integer(fields, "repeats", 1, 1, 1000);
  const ProtocolRules& rules = protocol.rules();
  const bool two_intervals = rules.two_intervals;
  // Default: counterbalanced whenever the repeats can be split in halves.
  protocol.counterbalance = fields.boolean("counterbalance", two_intervals && protocol.repeats % 2 == 0);
  if (protocol.counterbalance && !two_intervals)
    fields.fail("counterbalance", "only 2afc, pair and rating trials have an order to counterbalance");
  if (protocol.counterbalance && protocol.repeats % 2 != 0)
    fields.fail("repeats", "expected an even number with counterbalance = true (half with the reference first)");
  const std::string trial_order = fields.string("trial_order", "random");
  if (trial_order != "random" && trial_order != "fixed") fields.fail("trial_order", "expected \"random\" or \"fixed\"");
  protocol.randomise_trials = trial_order == "random";
  const std::string block_order = fields.string("block_order", "fixed");
  if (block_order == "fixed") protocol.block_order = ProtocolConfig::BlockOrder::fixed;
  else if (block_order == "random") protocol.block_order = ProtocolConfig::BlockOrder::random;
  else if (block_order == "latin_square") protocol.block_order = ProtocolConfig::BlockOrder::latin_square;
  else fields.fail("block_order", "expected \"fixed\", \"random\" or \"latin_square\"");
  protocol.question.text = fields.string("question_text", std::string(rules.default_question));

  const toml::table* keys_table = fields.optional_table("keys");
  std::map<std::string, std::string> answer_of_key;
  for (const ProtocolAnswer& rule : rules.answers) {
    const std::string answer(rule.name);
    std::vector<std::string> keys(rule.default_keys.begin(), rule.default_keys.end());
    if (keys_table) {
      const TomlFields keys_fields(*keys_table, fields.path(), fields.name_of("keys"));
      if (keys_fields.has(answer)) {
        keys = keys_fields.strings(answer);
        for (const std::string& key : keys)
          if (!is_input_name(key))
            keys_fields.fail(answer, "unknown key \"" + key + "\" (expected one of " + input_names_summary() + ")");
      }
    }
    for (const std::string& key : keys) {
      const auto [where, inserted] = answer_of_key.emplace(key, answer);
      if (!inserted) fields.fail("keys", "key \"" + key + "\" is bound to both \"" + where->second + "\" and \"" + answer + "\"");
    }
    protocol.question.answers.emplace_back(answer, std::move(keys));
  }
  if (keys_table) {
    const TomlFields keys_fields(*keys_table, fields.path(), fields.name_of("keys"));
    for (auto&& [key, node] : *keys_table)
      if (!rules.is_answer(key.str())) {
        std::string expected;
        for (const ProtocolAnswer& answer : rules.answers) expected += (expected.empty() ? "" : ", ") + std::string(answer.name);
        keys_fields.fail(std::string(key.str()), "not an answer of this protocol (expected " + expected + ")");
      }
  }
  if (protocol.kind == ProtocolKind::slider) {
    protocol.slider.start_level = fields.number("start_level", levels.values.empty() ? 0.0 : levels.values.front());
    if (std::find(levels.values.begin(), levels.values.end(), protocol.slider.start_level) == levels.values.end())
      fields.fail("start_level", "expected one of [levels] values");
    for (const VariantConfig& variant : stimulus.variants) {
      const std::vector<double>& own = variant_levels(levels, &variant);
      if (std::find(own.begin(), own.end(), protocol.slider.start_level) == own.end())
        fields.fail("start_level", "expected a level of every variant (\"" + variant.name + "\" has no " +
                                       format_number(protocol.slider.start_level, 6) + " in the conditions file)");
    }
  }
  fields.finish();
}

void read_timing(const TomlFields& fields, TimingConfig& timing) {
  timing.black_interval_s = bounded_number(fields, "black_interval_s", timing.black_interval_s, 0.0, 600.0);
  timing.inter_trial_s = bounded_number(fields, "inter_trial_s", timing.inter_trial_s, 0.0, 600.0);
  timing.rest_between_blocks_s = bounded_number(fields, "rest_between_blocks_s", timing.rest_between_blocks_s, 0.0, 7200.0);
  timing.response_timeout_s = bounded_number(fields, "response_timeout_s", timing.response_timeout_s, 0.0, 3600.0);
  timing.fixation_s = bounded_number(fields, "fixation_s", timing.fixation_s, 0.0, 60.0);
  fields.finish();
}

void read_attention(const TomlFields& fields, const ProtocolConfig& protocol, AttentionConfig& attention) {
  attention.share = fields.number("share");
  check_range(fields, "share", attention.share, 0.0, 0.9);
  if (attention.share > 0 && identical_answer(protocol).empty())
    fields.fail("share", "attention checks need an answer that means \"identical\" (2afc with question = \"same\", "
                         "pair or rating)");
  attention.break_s = bounded_number(fields, "break_s", attention.break_s, 0.0, 3600.0);
  attention.max_errors = bounded_integer(fields, "max_errors", attention.max_errors, 1, 1000);
  attention.excluded_message = fields.string("excluded_message", attention.excluded_message);
  fields.finish();
}

// [gaze] require = "tracker" or ["tracker", "trace"]: the kinds of source a session may use.
void read_gaze(const TomlFields& fields, GazeConfig& gaze) {
  const std::string expected = "expected a gaze source kind (tracker, trace, synthetic or mouse) or a non-empty array of them";
  if (!fields.has("require")) fields.fail("require", "missing: " + expected + " (or no [gaze] table)");
  const toml::node& node = *fields.raw().get("require");
  gaze.require_line = static_cast<int>(node.source().begin.line);
  std::vector<std::string> names;
  if (node.is_string()) names.push_back(fields.string("require"));
  else if (node.is_array()) names = fields.strings("require");
  else fields.fail("require", expected);
  for (const std::string& name : names) {
    const std::optional<GazeSourceKind> kind = parse_gaze_source_kind(name);
    if (!kind)
      fields.fail("require", expected + ", got \"" + name + "\"" +
                                 (name == "pupil" ? " (Pupil Core is the kind \"tracker\")" : ""));
    if (gaze.allows(*kind)) fields.fail("require", "\"" + name + "\" given twice; expected each kind once");
    gaze.require.push_back(*kind);
  }
  fields.finish();
}

void read_validation(const TomlFields& fields, const DisplayConfig& display, ValidationConfig& validation) {
  validation.enabled = true;
  validation.targets = bounded_integer(fields, "targets", validation.targets, 5, 9);
  if (validation.targets != 5 && validation.targets != 9) fields.fail("targets", "expected 5 or 9");
  validation.target_offset_deg = bounded_number(fields, "target_offset_deg", validation.target_offset_deg, 0.5, 40.0);
  validation.target_radius_deg = bounded_number(fields, "target_radius_deg", validation.target_radius_deg, 0.05, 2.0);
  validation.target_s = bounded_number(fields, "target_s", validation.target_s, 0.2, 10.0);
  validation.settle_s = bounded_number(fields, "settle_s", validation.settle_s, 0.0, validation.target_s - 0.1);
  validation.max_accuracy_deg = bounded_number(fields, "max_accuracy_deg", validation.max_accuracy_deg, 0.01, 10.0);
  validation.max_precision_deg = bounded_number(fields, "max_precision_deg", validation.max_precision_deg, 0.001, 10.0);
  validation.max_attempts = bounded_integer(fields, "max_attempts", validation.max_attempts, 1, 20);
  validation.after_breaks = fields.boolean("after_breaks", validation.after_breaks);
  // At least three refreshes measured a target (two successive samples give a precision).
  const int refreshes = static_cast<int>(std::floor(validation.target_s * display.refresh_hz + 1e-9));
  const int first = std::max(1, static_cast<int>(std::ceil(validation.settle_s * display.refresh_hz - 1e-9)));
  if (refreshes - first + 1 < 3)
    fields.fail("settle_s", "expected target_s - settle_s to hold at least 3 refreshes at " +
                                format_number(display.refresh_hz, 6) + " Hz (each target is measured on them)");
  // Every target, disk included, on the screen.
  const double radius_px = validation_target_radius_px(display, validation);
  for (const auto& [x_px, y_px] : validation_targets_px(display, validation)) {
    if (x_px - radius_px < 0 || x_px + radius_px > display.width_px || y_px - radius_px < 0 ||
        y_px + radius_px > display.height_px)
      fields.fail("target_offset_deg", "expected targets on the screen: at " + format_number(validation.target_offset_deg, 6) +
                                           " deg the outer ones fall off this display (" + std::to_string(display.width_px) +
                                           "x" + std::to_string(display.height_px) + " px at " +
                                           format_number(display.viewing_distance_mm, 6) + " mm)");
  }
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
  const std::vector<std::string>& names = kind == SceneKind::path_traced ? catalog->path_traced_names
                                          : kind == SceneKind::volume    ? catalog->volume_names
                                                                         : catalog->signed_distance_names;
  std::string known;
  for (const std::string& name : names) known += (known.empty() ? "" : ", ") + name;
  if (std::find(names.begin(), names.end(), scene) != names.end()) return scene;
  if (kind != SceneKind::signed_distance) {
    const std::string& extension = kind == SceneKind::path_traced ? catalog->path_traced_file_extension
                                                                  : catalog->volume_file_extension;
    std::string tail = scene.size() >= extension.size() ? scene.substr(scene.size() - extension.size()) : std::string();
    for (char& c : tail) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (tail != extension)
      fields.fail("scene", std::string("expected a ") + (kind == SceneKind::path_traced ? "path-traced" : "volume") +
                               " scene (" + known + " or a " + extension + " file) for " + methods_of_kind(kind, "and") +
                               ", got \"" + scene + "\"");
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
    case SceneKind::signed_distance: return "a sphere-traced method";
    case SceneKind::path_traced: return "a path-traced method";
    case SceneKind::volume: return "a volume method";
  }
  return "a method";
}

// [conditions] file: the conditions as a CSV file's rows (PsychoPy's conditions files). The header
// names the columns: `variant` (the condition's variant), the [levels] parameter (its level), and
// parameters of the test method (overrides, as a variant's table holds them; an empty cell leaves
// the parameter as the test method has it). A variant's rows differ in level only. The result is
// the variants (with their own levels) and the levels (every level of any row, ascending).
void read_conditions(const TomlFields& fields, const Reading& reading, StudyConfig& config) {
  const std::string file = fields.string("file");
  if (file.empty())  // else the config's folder, or a file named "", would be read in its place
    fields.fail("file", "expected the path of a conditions file (.csv, relative to the config's folder), got \"\"");
  fields.finish();
  std::filesystem::path path(file);
  if (path.is_relative()) path = std::filesystem::path(config.source_path).parent_path() / path;
  // A logged config's file is the header's conditions_csv, named so in messages.
  const std::string name = reading.logged_conditions_csv ? config.source_path + ": conditions_csv" : path.lexically_normal().string();
  if (reading.logged_conditions_csv) {
    if (reading.logged_conditions_csv->empty())
      fields.fail("file", "the log's header holds no conditions_csv (expected the conditions file's text beside the config's)");
    if (reading.logged_conditions_csv->size() > kMaxConditionsBytes)
      throw InputError(name + ": " + std::to_string(reading.logged_conditions_csv->size()) +
                       " bytes: expected a conditions file of at most " + byte_size_text(kMaxConditionsBytes));
    config.conditions_csv = *reading.logged_conditions_csv;
  } else {
    config.conditions_csv = read_input_file(name, "a conditions file (.csv)", kMaxConditionsBytes);
  }
  config.conditions_path = file;
  const std::vector<CsvRow> rows = read_csv_rows(config.conditions_csv, name);
  const auto fail = [&](int line, const std::string& what) {
    throw InputError(name + ":" + std::to_string(line) + ": " + what);
  };
  if (rows.size() < 2) fail(rows.empty() ? 1 : rows.front().line, "expected a header row and at least one condition");
  if (rows.size() - 1 > kMaxConditionsRows) fail(rows[kMaxConditionsRows + 1].line, "expected at most " + std::to_string(kMaxConditionsRows) + " conditions");
  const MethodDescriptor& test = describe(config.stimulus.test.method);
  const std::string& level_key = config.levels.parameter;
  const std::vector<std::string>& header = rows.front().cells;
  const int header_line = rows.front().line;
  int variant_column = -1, level_column = -1;
  std::vector<const ParameterDescriptor*> parameters(header.size(), nullptr);
  std::set<std::string> seen;
  for (size_t column = 0; column < header.size(); ++column) {
    const std::string& key = header[column];
    if (key.empty()) fail(header_line, "column " + std::to_string(column + 1) + ": expected a column name, got an empty cell");
    if (!seen.insert(key).second) fail(header_line, "column " + quoted_input(key) + " appears twice");
    if (key == "variant") variant_column = int(column);
    else if (!level_key.empty() && key == level_key) level_column = int(column);
    else if (!(parameters[column] = find_parameter(test, key, reading.legacy_keys)))
      fail(header_line, "column " + quoted_input(key) + ": expected variant" + (level_key.empty() ? "" : ", " + level_key + " (the level)") +
                  " or a parameter of the test method \"" + std::string(test.name) + "\" (" + parameter_keys(test) + ")");
  }
  if (!level_key.empty() && level_column < 0)
    fail(header_line, "expected a column \"" + level_key + "\" ([levels] parameter) holding each condition's level");
  const bool overrides = std::any_of(parameters.begin(), parameters.end(), [](const ParameterDescriptor* p) { return p; });
  if (variant_column < 0 && (overrides || level_column < 0))
    fail(header_line, "expected a column \"variant\" naming each condition's variant (without one, only the level column)");

  const ParameterDescriptor* level_parameter = level_column >= 0 ? find_parameter(test, level_key) : nullptr;
  // Rows, grouped by variant in order of first appearance.
  std::map<std::string, size_t> variant_index;
  std::vector<int> first_line;
  for (size_t r = 1; r < rows.size(); ++r) {
    const CsvRow& row = rows[r];
    if (row.cells.size() != header.size())
      fail(row.line, "expected " + std::to_string(header.size()) + " cells as the header has, got " + std::to_string(row.cells.size()));
    const std::string variant_name = variant_column >= 0 ? row.cells[size_t(variant_column)] : std::string();
    if (variant_column >= 0 && !is_safe_name(variant_name))
      fail(row.line, "variant " + quoted_input(variant_name) + ": expected 1-64 letters, digits, '_', '-' or '.'");
    ParameterLayer layer;
    std::optional<double> level;
    for (size_t column = 0; column < header.size(); ++column) {
      const std::string& cell = row.cells[column];
      const ParameterDescriptor* parameter = int(column) == level_column ? level_parameter : parameters[column];
      if (!parameter) continue;
      const std::string where = "column " + quoted_input(header[column]) + ": ";
      if (cell.empty()) {
        if (int(column) == level_column) fail(row.line, where + "expected the condition's level, got an empty cell");
        continue;
      }
      double value = 0.0;
      if (parameter->type == ParameterType::choice) {
        const std::optional<double> index = parse_choice(*parameter, cell);
        if (!index) fail(row.line, where + "expected " + *check_parameter_value(*parameter, -1) + ", got " + quoted_input(cell));
        value = *index;
      } else {
        const std::optional<double> number = parse_finite_number(cell);
        if (!number) fail(row.line, where + "expected a number, got " + quoted_input(cell));
        value = *number;
      }
      if (const std::optional<std::string> expected = check_parameter_value(*parameter, value))
        fail(row.line, where + "expected " + *expected + ", got " + cell);  // as the file has it
      if (int(column) == level_column) level = value;
      else layer[std::string(parameter->key)] = value;
    }
    ParameterLayer level_layer;
    if (level) level_layer[level_key] = *level;
    if (const auto conflict = parameter_conflict(parameters_with(test.method, {&config.stimulus.test.parameters, &layer, &level_layer})))
      fail(row.line, conflict->expected);
    const auto [found, added] = variant_index.emplace(variant_name, config.stimulus.variants.size());
    if (added) {
      config.stimulus.variants.push_back(VariantConfig{variant_name, layer, {}});
      first_line.push_back(row.line);
    }
    VariantConfig& variant = config.stimulus.variants[found->second];
    if (variant.parameters != layer)
      fail(row.line, "variant \"" + variant_name + "\" sets other parameters than on line " +
                         std::to_string(first_line[found->second]) + " (a variant's rows differ in level only; name another variant)");
    if (!level) {
      if (!added) fail(row.line, "variant \"" + variant_name + "\" is a condition already (line " + std::to_string(first_line[found->second]) + ")");
      continue;
    }
    if (std::find(variant.levels.begin(), variant.levels.end(), *level) != variant.levels.end())
      fail(row.line, "the condition " + (variant_name.empty() ? "" : variant_name + " at ") + level_key + " = " +
                         format_number(*level, 6) + " appears twice");
    variant.levels.push_back(*level);
  }
  std::set<double> all_levels;
  for (VariantConfig& variant : config.stimulus.variants) {
    std::sort(variant.levels.begin(), variant.levels.end());
    all_levels.insert(variant.levels.begin(), variant.levels.end());
  }
  config.levels.values.assign(all_levels.begin(), all_levels.end());
  // Only the level column: a list of levels, not variants.
  if (variant_column < 0) config.stimulus.variants.clear();
}

void read_practice(const TomlFields& fields, StudyConfig& config, const Reading& reading, SceneKind scene_kind) {
  PracticeConfig& practice = config.practice;
  practice.trials = bounded_integer(fields, "trials", std::nullopt, 0, 1000);
  const bool comparison = config.protocol.kind != ProtocolKind::ramp && config.protocol.kind != ProtocolKind::slider;
  if (fields.has("levels")) {
    if (!comparison)
      fields.fail("levels", std::string("a ") + protocol_name(config.protocol.kind) +
                                " practice trial shows the whole ladder of levels; expected no practice.levels");
    practice.levels = fields.numbers("levels");
    for (double level : practice.levels)
      if (std::find(config.levels.values.begin(), config.levels.values.end(), level) == config.levels.values.end())
        fields.fail("levels", "expected levels of [levels] values, got " + format_number(level, 6));
  } else if (comparison && !config.levels.values.empty()) {
    // The level least like the reference: the easiest difference to see.
    practice.levels = {config.levels.higher_is_better ? config.levels.values.front() : config.levels.values.back()};
  }
  if (fields.has("scene"))
    practice.scene = resolve_scene(fields, fields.string("scene"), config.source_path, reading.scenes, scene_kind);
  fields.finish();
}

// [procedure.NAME]: read here; checked against each variant's levels when a block names it.
ProcedureConfig read_procedure(const TomlFields& fields, const std::string& name) {
  ProcedureConfig procedure;
  procedure.name = name;
  if (!is_safe_name(name)) fields.fail("", "expected a procedure name of letters, digits, '_', '-' or '.'");
  StaircaseRule& rule = procedure.staircase;
  const std::string kind = fields.string("kind");
  if (kind == "staircase") {
    rule.kind = StaircaseRule::Kind::transformed;
    rule.down = bounded_integer(fields, "down", 2, 1, 10);
    rule.step_sizes.clear();
    for (double step : fields.has("step_sizes") ? fields.numbers("step_sizes") : std::vector<double>{1.0}) {
      if (!(step >= 1 && step <= 1000 && step == std::floor(step)))
        fields.fail("step_sizes", "expected whole numbers of grid steps, 1 or more, got " + format_number(step, 6));
      rule.step_sizes.push_back(static_cast<int>(step));
    }
  } else if (kind == "weighted") {
    rule.kind = StaircaseRule::Kind::weighted;
    rule.harder_steps = bounded_integer(fields, "harder_steps", 1, 1, 1000);
    rule.easier_steps = bounded_integer(fields, "easier_steps", 3, 1, 1000);
  } else if (kind == "quest_plus") {
    procedure.kind = ProcedureConfig::Kind::quest_plus;
    QuestPlusRule& quest = procedure.quest;
    const std::string shape = fields.string("shape", "logistic");
    if (shape == "logistic") quest.shape = PsychometricShape::logistic;
    else if (shape == "weibull") quest.shape = PsychometricShape::weibull;
    else if (shape == "cumulative_normal") quest.shape = PsychometricShape::cumulative_normal;
    else fields.fail("shape", "expected \"logistic\", \"weibull\" or \"cumulative_normal\", got \"" + shape + "\"");
    for (const auto& [key, grid] : {std::pair{"thresholds", &quest.thresholds}, std::pair{"slopes", &quest.slopes},
                                    std::pair{"lapses", &quest.lapses}})
      if (fields.has(key)) *grid = fields.numbers(key);
    // Not given: -1, the protocol's (quest_plus_rule).
    quest.guess = fields.has("guess_rate") ? bounded_number(fields, "guess_rate", 0.0, 0.0, 0.99) : -1.0;
    quest.prior_mean = fields.number("prior_mean", 0.0);
    quest.prior_sd = bounded_number(fields, "prior_sd", 0.0, 0.0, 1e300);
    if (fields.has("prior_mean") != fields.has("prior_sd"))
      fields.fail(fields.has("prior_mean") ? "prior_mean" : "prior_sd",
                  std::string("expected ") + (fields.has("prior_mean") ? "prior_sd" : "prior_mean") +
                      " too (a normal prior over thresholds; without both the prior is uniform)");
    quest.max_trials = bounded_integer(fields, "max_trials", std::nullopt, 1, 10000);
    quest.stop_entropy_bits = bounded_number(fields, "stop_entropy_bits", 0.0, 0.0, 1000.0);
    quest.stop_interval_width = bounded_number(fields, "stop_interval_width", 0.0, 0.0, 1e300);
    return procedure;
  } else {
    fields.fail("kind", "expected \"staircase\" (Levitt's transformed up-down), \"weighted\" (Kaernbach's weighted "
                        "up-down) or \"quest_plus\" (Watson's QUEST+), got \"" + kind + "\"");
  }
  rule.max_trials = bounded_integer(fields, "max_trials", std::nullopt, 1, 10000);
  rule.max_reversals = bounded_integer(fields, "max_reversals", 0, 0, 10000);
  rule.reversals_averaged = bounded_integer(fields, "reversals_averaged", 6, 1, 10000);
  if (fields.has("starts")) procedure.starts = fields.numbers("starts");
  if (procedure.starts.size() > 16) fields.fail("starts", "expected at most 16 interleaved staircases");
  return procedure;
}

// A rule's error "KEY: expected ..." as a config error of the procedure's table.
// ("levels: ..." is about [levels], not a key of the procedure's table.)
[[noreturn]] void fail_with_rule_error(const TomlFields& fields, const std::string& error, const std::string& suffix) {
  const size_t colon = error.find(": ");
  const std::string key = error.substr(0, colon);
  if (key == "levels") fields.fail("", "[levels] values: " + error.substr(colon + 2) + suffix);
  fields.fail(key, error.substr(colon + 2) + suffix);
}

// The QUEST+ tables a session would hold: one per (procedure, variant) that a block uses, at most
// kQuestPlusMaxTableEntries entries in all.
void check_quest_plus_tables(const TomlFields& fields, const StudyConfig& config) {
  std::set<int> used;
  for (const BlockConfig& block : config.blocks)
    if (block.procedure >= 0 && config.procedures[size_t(block.procedure)].kind == ProcedureConfig::Kind::quest_plus)
      used.insert(block.procedure);
  const std::vector<const VariantConfig*> variants = tested_variants(config.stimulus);
  size_t entries = 0;
  for (int index : used)
    for (const VariantConfig* variant : variants) {
      const std::vector<double> grid = adaptive_grid(config.levels, variant);
      const QuestPlusRule rule = quest_plus_rule(config.procedures[size_t(index)], config.protocol, config.levels, grid);
      entries += grid.size() * rule.thresholds.size() * rule.slopes.size() * rule.lapses.size();
    }
  if (entries > kQuestPlusMaxTableEntries)
    fields.table("procedure").table(config.procedures[size_t(*used.rbegin())].name)
        .fail("thresholds", "the QUEST+ tables of every variant and procedure would hold " + std::to_string(entries) +
                                " entries (levels x grid points); expected at most " +
                                std::to_string(kQuestPlusMaxTableEntries) + ": fewer levels, grid points or variants");
}

// A block's procedure against the study: a protocol whose answers are right or wrong, and a rule
// that works on every variant's level grid (a staircase from every start).
void check_procedure(const TomlFields& fields, const StudyConfig& config, const ProcedureConfig& procedure) {
  const ProtocolKind kind = config.protocol.kind;
  if (kind != ProtocolKind::two_afc && kind != ProtocolKind::pair)
    fields.fail("", std::string("an adaptive procedure needs answers that see the difference or not (2afc, pair); the "
                                "protocol is ") + protocol_name(kind));
  const std::vector<const VariantConfig*> variants = tested_variants(config.stimulus);
  for (const VariantConfig* variant : variants) {
    const std::vector<double> grid = adaptive_grid(config.levels, variant);
    const std::string of_variant = variant ? " (variant \"" + variant->name + "\")" : "";
    if (procedure.kind == ProcedureConfig::Kind::quest_plus) {
      const QuestPlusRule rule = quest_plus_rule(procedure, config.protocol, config.levels, grid);
      if (const std::optional<std::string> error = quest_plus_rule_error(rule, grid))
        fail_with_rule_error(fields, *error, of_variant);
      continue;
    }
    std::vector<int> start_indices;
    for (double start : procedure.starts) {
      const auto found = std::find(grid.begin(), grid.end(), start);
      if (found == grid.end())
        fields.fail("starts", "expected levels of the grid" + of_variant + ", got " + format_number(start, 6));
      start_indices.push_back(static_cast<int>(found - grid.begin()));
    }
    if (start_indices.empty()) start_indices.push_back(0);
    for (int start : start_indices) {
      StaircaseRule rule = procedure.staircase;
      rule.start_index = start;
      if (const std::optional<std::string> error = staircase_rule_error(rule, static_cast<int>(grid.size())))
        fail_with_rule_error(fields, *error, of_variant);
    }
  }
}

}  // namespace

bool is_valid_study_name(const std::string& name) {
  if (name.empty() || name.size() > 64 || name[0] == '.' || name[0] == '-') return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
           c == '.';
  });
}

std::vector<std::string> protocol_answers(ProtocolKind kind, TwoAfcQuestion question) {
  std::vector<std::string> names;
  for (const ProtocolAnswer& answer : protocol_rules(kind, question).answers) names.emplace_back(answer.name);
  return names;
}

std::string identical_answer(const ProtocolConfig& protocol) { return std::string(protocol.rules().identical); }

namespace {
double degrees_to_px(const DisplayConfig& display, double degrees, double pitch_mm) {
  return display.viewing_distance_mm * std::tan(degrees * std::numbers::pi / 180.0) / pitch_mm;
}
}  // namespace

std::vector<std::pair<double, double>> validation_targets_px(const DisplayConfig& display, const ValidationConfig& validation) {
  const double centre_x = 0.5 * display.width_px, centre_y = 0.5 * display.height_px;
  const double dx = degrees_to_px(display, validation.target_offset_deg, display.width_mm / display.width_px);
  const double dy = degrees_to_px(display, validation.target_offset_deg, display.height_mm / display.height_px);
  std::vector<std::pair<double, double>> targets;
  for (int row = -1; row <= 1; ++row)
    for (int column = -1; column <= 1; ++column)
      if (validation.targets == 9 || (row == 0) == (column == 0))  // 5: centre and corners
        targets.emplace_back(centre_x + column * dx, centre_y + row * dy);
  return targets;
}

double validation_target_radius_px(const DisplayConfig& display, const ValidationConfig& validation) {
  return std::max(2.0, degrees_to_px(display, validation.target_radius_deg, display.width_mm / display.width_px));
}

int StimulusConfig::frame_count() const {
  return std::max(1, static_cast<int>(std::lround(duration_s * frames_per_second)));
}

int StimulusConfig::refreshes_per_frame(double refresh_hz) const {
  return std::max(1, static_cast<int>(std::lround(refresh_hz / frames_per_second)));
}

namespace {

void write_quoted(std::string_view text, std::string& out) {
  out += '"';
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += escaped;
    } else {
      out += c;
    }
  }
  out += '"';
}

// The canonical text of a parsed TOML value: tables by key in byte order, arrays in order, strings
// quoted as JSON quotes them, integers in decimal, floats with 17 significant digits, dates and
// times as TOML writes them. Comments, whitespace, key order, quoting style, number notation
// (0x10 / 16, 1.0 / 1.00) and inline versus [table] syntax leave no trace in it.
void write_canonical_toml(const toml::node& node, std::string& out) {
  if (const toml::table* table = node.as_table()) {
    std::vector<std::pair<std::string, const toml::node*>> entries;
    for (const auto& [key, value] : *table) entries.emplace_back(std::string(key.str()), &value);
    std::sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    out += '{';
    for (size_t i = 0; i < entries.size(); ++i) {
      if (i) out += ',';
      write_quoted(entries[i].first, out);
      out += ':';
      write_canonical_toml(*entries[i].second, out);
    }
    out += '}';
  } else if (const toml::array* array = node.as_array()) {
    out += '[';
    for (size_t i = 0; i < array->size(); ++i) {
      if (i) out += ',';
      write_canonical_toml(*array->get(i), out);
    }
    out += ']';
  } else if (const auto* text = node.as_string()) {
    write_quoted(text->get(), out);
  } else if (const auto* integer = node.as_integer()) {
    out += "i" + std::to_string(integer->get());
  } else if (const auto* number = node.as_floating_point()) {
    char digits[40];
    std::snprintf(digits, sizeof digits, "f%.17g", number->get());
    out += digits;
  } else if (const auto* flag = node.as_boolean()) {
    out += flag->get() ? "true" : "false";
  } else {  // a date, a time or a date-time
    std::ostringstream written;
    node.visit([&written](const auto& value) { written << value; });
    out += "t" + written.str();
  }
}

std::string canonical_config_content(const toml::table& root) {
  std::string out;
  write_canonical_toml(root, out);
  return out;
}

}  // namespace

namespace {

StudyConfig parse_config(const std::string& text, const std::string& path, const Reading& reading) {
  // The guards in front of toml++, here so that configs from files and from session logs' headers
  // (replay, analyze) pass the same ones.
  if (text.size() > kMaxStudyConfigBytes)
    throw InputError(path + ": " + std::to_string(text.size()) + " bytes: expected a study config of at most " +
                     byte_size_text(kMaxStudyConfigBytes));
  check_toml_nesting(text, path, kMaxStudyConfigNesting);
  toml::table root;
  try {
    root = toml::parse(shield_toml_hazards(text, path), path);
  } catch (const toml::parse_error& error) {
    throw InputError(path + ":" + std::to_string(error.source().begin.line) + ": " +
                     unshield_toml_hazards(std::string(error.description())) + " (not valid TOML)");
  }
  StudyConfig config;
  config.source_path = path;
  config.source_text = text;
  config.hash = ContentHash().add(text).hex();
  config.content_hash = ContentHash().add(canonical_config_content(root)).hex();

  const TomlFields fields(root, path, "");
  const TomlFields study = fields.table("study");
  config.name = study.string("name");
  if (!is_valid_study_name(config.name)) study.fail("name", "expected 1-64 letters, digits, '_', '-' or '.' (it names a folder)");
  const int64_t seed = study.integer("seed");
  if (seed < 0) study.fail("seed", "expected a non-negative integer");
  config.seed = static_cast<uint64_t>(seed);
  config.instructions = study.string("instructions", "Press any answer key to begin.");
  study.finish();

  read_display(fields.table("display"), config.display);
  read_stimulus(fields.table("stimulus"), config.display, reading, config.stimulus);
  const toml::table* conditions = fields.optional_table("conditions");
  std::optional<TomlFields> levels_fields;
  if (const toml::table* levels = fields.optional_table("levels")) {
    levels_fields.emplace(*levels, path, "levels");
    read_levels(*levels_fields, config.stimulus.test, reading, conditions != nullptr, config.levels);
  }
  check_parameter_rules(fields.table("stimulus"), config.stimulus, levels_fields ? &*levels_fields : nullptr,
                        config.levels, conditions != nullptr);
  if (conditions) {
    const TomlFields conditions_fields(*conditions, path, "conditions");
    if (!config.stimulus.variants.empty())
      conditions_fields.fail("file", "the conditions file gives the variants; expected no [[stimulus.variant]] tables");
    read_conditions(conditions_fields, reading, config);
    const std::string separator = std::string(1, '\0') + "conditions_csv " + std::to_string(config.conditions_csv.size()) + '\0';
    config.hash = ContentHash().add(text).add(separator).add(config.conditions_csv).hex();
    config.content_hash = ContentHash().add(canonical_config_content(root)).add(separator).add(config.conditions_csv).hex();
  }
  check_frame_size_rules(fields.table("display"), config.display, config.stimulus, config.levels);
  read_protocol(fields.table("protocol"), config.levels, config.stimulus, config.protocol);
  if (const toml::table* timing = fields.optional_table("timing"))
    read_timing(TomlFields(*timing, path, "timing"), config.timing);
  if (const toml::table* attention = fields.optional_table("attention"))
    read_attention(TomlFields(*attention, path, "attention"), config.protocol, config.attention);
  if (const toml::table* validation = fields.optional_table("validation"))
    read_validation(TomlFields(*validation, path, "validation"), config.display, config.validation);
  if (const toml::table* analysis = fields.optional_table("analysis")) {
    const TomlFields analysis_fields(*analysis, path, "analysis");
    const std::string headline = analysis_fields.string("headline", "estimate");
    if (headline != "estimate" && headline != "paper")
      analysis_fields.fail("headline", "expected \"estimate\" (the design's estimate, the default) or \"paper\" (the paper's own rule), got \"" +
                                           headline + "\"");
    config.analysis.headline_is_paper_rule = headline == "paper";
    analysis_fields.finish();
  }
  if (const toml::table* gaze = fields.optional_table("gaze")) read_gaze(TomlFields(*gaze, path, "gaze"), config.gaze);
  if (const toml::table* participant = fields.optional_table("participant")) {
    const TomlFields participant_fields(*participant, path, "participant");
    config.participant_fields = participant_fields.strings("fields");
    std::set<std::string> seen;
    for (const std::string& name : config.participant_fields) {
      const bool plain = !name.empty() && name.size() <= 32 &&
                         name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") == std::string::npos;
      if (!plain) participant_fields.fail("fields", "expected names of 1-32 lower-case letters, digits or '_', got \"" + name + "\"");
      if (!seen.insert(name).second) participant_fields.fail("fields", "duplicate field \"" + name + "\"");
    }
    if (config.participant_fields.size() > 32) participant_fields.fail("fields", "expected at most 32 fields");
    participant_fields.finish();
  }

  const SceneKind scene_kind = describe(config.stimulus.reference.method).scene_kind;
  const MethodDescriptor& test = describe(config.stimulus.test.method);
  if (test.scene_kind != scene_kind) {
    fields.table("stimulus").table("test").fail(
        "method", "expected " + kind_of_method(scene_kind) + " (" + methods_of_kind(scene_kind, "or") + ") like the reference's \"" +
                      std::string(describe(config.stimulus.reference.method).name) +
                      "\" (both render the same scene), got \"" + std::string(test.name) + "\"");
  }
  if (const toml::table* practice = fields.optional_table("practice")) {
    const TomlFields practice_fields(*practice, path, "practice");
    read_practice(practice_fields, config, reading, scene_kind);
  }
  if (const toml::table* procedures = fields.optional_table("procedure")) {
    const TomlFields procedure_fields(*procedures, path, "procedure");
    for (auto&& [key, value] : *procedures) {
      const std::string name(key.str());
      const TomlFields one = procedure_fields.table(name);
      config.procedures.push_back(read_procedure(one, name));
      one.finish();
    }
  }
  std::set<std::string> block_names;
  for (const TomlFields& block_fields : fields.tables("block")) {
    BlockConfig block;
    block.scene = resolve_scene(block_fields, block_fields.string("scene"), path, reading.scenes, scene_kind);
    if (block_fields.has("procedure")) {
      const std::string name = block_fields.string("procedure");
      const auto found = std::find_if(config.procedures.begin(), config.procedures.end(),
                                      [&](const ProcedureConfig& procedure) { return procedure.name == name; });
      if (found == config.procedures.end())
        block_fields.fail("procedure", "expected the name of a [procedure.NAME] table, got \"" + name + "\"");
      block.procedure = static_cast<int>(found - config.procedures.begin());
      check_procedure(fields.table("procedure").table(name), config, *found);
    }
    block.name = block_fields.string("name", std::filesystem::path(block.scene).stem().string());
    if (!is_safe_name(block.name)) block_fields.fail("name", "expected letters, digits, '_', '-' or '.'");
    if (!block_names.insert(block.name).second) block_fields.fail("name", "duplicate block \"" + block.name + "\"");
    if (config.practice.trials > 0 && block.name == "practice")
      block_fields.fail("name", "\"practice\" names the [practice] trials' block; expected another name");
    block_fields.finish();
    config.blocks.push_back(std::move(block));
  }
  check_quest_plus_tables(fields, config);
  fields.finish();
  return config;
}

}  // namespace

StudyConfig parse_study_config_text(const std::string& text, const std::string& path, const SceneCatalog& scenes) {
  return parse_config(text, path, Reading{&scenes, false});
}

StudyConfig parse_study_config_file(const std::string& path, const SceneCatalog& scenes) {
  return parse_study_config_text(read_input_file(path, "a study config (.toml)", kMaxStudyConfigBytes), path, scenes);
}

StudyConfig parse_logged_study_config(const std::string& text, const std::string& path, int log_schema_version,
                                      const SceneCatalog* scenes, const std::string& conditions_csv) {
  return parse_config(text, path, Reading{scenes, true, log_schema_version, &conditions_csv});
}

const char* gaze_source_kind_name(GazeSourceKind kind) {
  switch (kind) {
    case GazeSourceKind::tracker: return "tracker";
    case GazeSourceKind::trace: return "trace";
    case GazeSourceKind::synthetic: return "synthetic";
    case GazeSourceKind::mouse: return "mouse";
  }
  return "";
}

std::optional<GazeSourceKind> parse_gaze_source_kind(const std::string& name) {
  for (GazeSourceKind kind : {GazeSourceKind::tracker, GazeSourceKind::trace, GazeSourceKind::synthetic, GazeSourceKind::mouse})
    if (name == gaze_source_kind_name(kind)) return kind;
  return std::nullopt;
}

std::optional<GazeSourceKind> gaze_source_kind_of_spec(const std::string& spec) {
  const auto named = [&](const std::string& prefix) {
    return spec == prefix || spec.rfind(prefix + ":", 0) == 0 || spec.rfind(prefix + ",", 0) == 0;
  };
  if (spec == "mouse") return GazeSourceKind::mouse;
  if (spec.rfind("trace:", 0) == 0) return GazeSourceKind::trace;
  if (named("synthetic")) return GazeSourceKind::synthetic;
  if (named("pupil")) return GazeSourceKind::tracker;
  return std::nullopt;
}

bool GazeConfig::allows(GazeSourceKind kind) const {
  return std::find(require.begin(), require.end(), kind) != require.end();
}

std::string GazeConfig::require_text() const {
  std::string text;
  for (size_t i = 0; i < require.size(); ++i)
    text += (i == 0 ? "" : i + 1 == require.size() ? " or " : ", ") + std::string(gaze_source_kind_name(require[i]));
  return text;
}

bool is_gaze_contingent(const StudyConfig& config) {
  return describe(config.stimulus.reference.method).depends_on_gaze || describe(config.stimulus.test.method).depends_on_gaze;
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

std::vector<double> adaptive_grid(const LevelsConfig& levels, const VariantConfig* variant) {
  const std::vector<double>& grid = variant_levels(levels, variant);
  if (levels.higher_is_better) return grid;
  return {grid.rbegin(), grid.rend()};
}

QuestPlusRule quest_plus_rule(const ProcedureConfig& procedure, const ProtocolConfig& protocol, const LevelsConfig& levels,
                              const std::vector<double>& grid) {
  QuestPlusRule rule = procedure.quest;
  // Higher levels more like the reference: the difference is seen less as the level grows.
  rule.rising = !levels.higher_is_better;
  if (rule.guess < 0)
    rule.guess = protocol.kind == ProtocolKind::two_afc && protocol.two_afc_question == TwoAfcQuestion::better ? 0.5 : 0.05;
  if (grid.size() < 2) return rule;
  if (rule.thresholds.empty()) rule.thresholds = default_quest_thresholds(grid, rule.shape);
  if (rule.slopes.empty()) rule.slopes = default_quest_slopes(grid, rule.shape);
  if (rule.lapses.empty()) rule.lapses = default_quest_lapses();
  return rule;
}

}  // namespace fovlab
