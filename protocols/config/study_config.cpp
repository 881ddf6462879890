#include "protocols/config/study_config.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include "core/content_hash.h"
#include "core/input_file.h"
#include "core/input_error.h"
#include "core/number_text.h"
#include "protocols/config/input_keys.h"
#include "protocols/config/toml_fields.h"
#include "protocols/config/toml_guard.h"
#include "protocols/stimuli/stimulus_spec.h"
#include "renderer/prerender/path_scene_source.h"
#include "renderer/scene/scene_source.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "renderer/zone_blend/zone_layout.h"

namespace fovlab {

namespace {

// Block and variant names follow the study name's rule (they name files and label results).
bool is_safe_name(const std::string& name) { return is_valid_study_name(name); }

void check_range(const TomlFields& fields, const std::string& key, double value, double low, double high) {
  if (!(value >= low && value <= high)) {
    std::ostringstream text;
    text << "expected a value in [" << low << ", " << high << "], got " << value;
    fields.fail(key, text.str());
  }
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

// Checks one parameter value of a method; `fields`/`key` name where it came from.
void check_parameter(const TomlFields& fields, const std::string& key, const MethodParameter& parameter,
                     double value) {
  if (!parameter.choices.empty()) {
    if (std::find(parameter.choices.begin(), parameter.choices.end(), value) == parameter.choices.end()) {
      std::ostringstream text;
      text << "expected one of";
      for (double choice : parameter.choices) text << " " << choice;
      text << ", got " << value;
      fields.fail(key, text.str());
    }
    return;
  }
  check_range(fields, key, value, parameter.min_value, parameter.max_value);
  if (parameter.integral && value != std::floor(value)) fields.fail(key, "expected a whole number");
}

const MethodParameter* find_parameter(const std::vector<MethodParameter>& parameters, const std::string& name) {
  for (const MethodParameter& parameter : parameters)
    if (parameter.name == name) return &parameter;
  return nullptr;
}

std::string parameter_names(const std::vector<MethodParameter>& parameters) {
  std::string names;
  for (const MethodParameter& parameter : parameters) names += (names.empty() ? "" : ", ") + parameter.name;
  return names;
}

// Reads every key of the table but `skip` as a parameter of the method.
std::map<std::string, double> read_parameters(const TomlFields& fields, const std::string& method,
                                              const std::set<std::string>& skip) {
  const auto parameters = method_parameters(method);
  std::map<std::string, double> values;
  for (auto&& [key, node] : fields.raw()) {
    const std::string name(key.str());
    if (skip.count(name)) continue;
    const MethodParameter* parameter = find_parameter(*parameters, name);
    if (!parameter)
      fields.fail(name, "not a parameter of method \"" + method + "\" (expected one of: " +
                            parameter_names(*parameters) + ")");
    const double value = fields.number(name);
    check_parameter(fields, name, *parameter, value);
    values[name] = value;
  }
  return values;
}

MethodConfig read_method(const TomlFields& fields) {
  MethodConfig config;
  config.method = fields.string("method");
  if (!method_parameters(config.method)) fields.fail("method", "expected one of " + known_methods() + ", got \"" + config.method + "\"");
  config.parameters = read_parameters(fields, config.method, {"method"});
  return config;
}

// The method's defaults with `overrides` on top (later maps win).
std::map<std::string, double> full_parameters(const std::string& method,
                                              std::initializer_list<const std::map<std::string, double>*> overrides) {
  std::map<std::string, double> values;
  const auto parameters = method_parameters(method);
  for (const MethodParameter& parameter : *parameters) values[parameter.name] = parameter.default_value;
  for (const std::map<std::string, double>* layer : overrides)
    for (const auto& [name, value] : *layer) values[name] = value;
  return values;
}

// Rules between parameters (parameter_conflict: FIPR's outer periphery at or beyond its fovea) must
// hold for every stimulus the config makes: the reference, and the test under every variant and
// level. The error names the field that set one of the parameters involved, the last layer first:
// the level values, the variant, the method's table (the table itself when only defaults clash).
void check_parameter_rules(const TomlFields& stimulus_fields, const StimulusConfig& stimulus,
                           const TomlFields* levels_fields, const LevelsConfig& levels) {
  const auto fail_in = [](const TomlFields& fields, const std::map<std::string, double>& given,
                          const ParameterConflict& conflict) {
    for (const std::string& name : conflict.parameters)
      if (given.count(name)) fields.fail(name, conflict.expected);
  };
  {
    const MethodConfig& reference = stimulus.reference;
    const auto conflict =
        parameter_conflict(reference.method, full_parameters(reference.method, {&reference.parameters}));
    if (conflict) {
      const TomlFields fields = stimulus_fields.table("reference");
      fail_in(fields, reference.parameters, *conflict);
      fields.fail("", conflict->expected);
    }
  }
  const MethodConfig& test = stimulus.test;
  const TomlFields test_fields = stimulus_fields.table("test");
  const std::vector<TomlFields> variant_fields =
      stimulus.variants.empty() ? std::vector<TomlFields>{} : stimulus_fields.tables("variant");
  std::vector<const VariantConfig*> variants;
  for (const VariantConfig& variant : stimulus.variants) variants.push_back(&variant);
  if (variants.empty()) variants.push_back(nullptr);
  std::vector<std::optional<double>> level_values(levels.values.begin(), levels.values.end());
  if (level_values.empty()) level_values.emplace_back(std::nullopt);
  const std::map<std::string, double> none;
  for (size_t v = 0; v < variants.size(); ++v) {
    const std::map<std::string, double>& variant = variants[v] ? variants[v]->parameters : none;
    for (const std::optional<double>& level : level_values) {
      std::map<std::string, double> level_parameter;
      if (level) level_parameter[levels.parameter] = *level;
      const auto conflict =
          parameter_conflict(test.method, full_parameters(test.method, {&test.parameters, &variant, &level_parameter}));
      if (!conflict) continue;
      const std::vector<std::string>& involved = conflict->parameters;
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
std::vector<std::pair<std::string, std::map<std::string, double>>> stimulus_parameters(const StimulusConfig& stimulus,
                                                                                        const LevelsConfig& levels) {
  std::vector<std::pair<std::string, std::map<std::string, double>>> all;
  const MethodConfig& reference = stimulus.reference;
  all.emplace_back(reference.method, full_parameters(reference.method, {&reference.parameters}));
  const std::map<std::string, double> none;
  std::vector<const std::map<std::string, double>*> variants;
  for (const VariantConfig& variant : stimulus.variants) variants.push_back(&variant.parameters);
  if (variants.empty()) variants.push_back(&none);
  std::vector<std::map<std::string, double>> level_parameters;
  for (double value : levels.values) level_parameters.push_back({{levels.parameter, value}});
  if (level_parameters.empty()) level_parameters.emplace_back();
  const MethodConfig& test = stimulus.test;
  for (const auto* variant : variants)
    for (const auto& level : level_parameters)
      all.emplace_back(test.method, full_parameters(test.method, {&test.parameters, variant, &level}));
  return all;
}

// The renderers' rules on the frame size, which is the display's: checked here, so that they name
// the config's fields (and fovlab validate finds them). What depends on the device (one storage
// buffer) is checked when a session prepares its stimuli (StimulusLibrary::prepare).
void check_frame_size_rules(const TomlFields& display_fields, const DisplayConfig& display,
                            const StimulusConfig& stimulus, const LevelsConfig& levels) {
  for (const auto& [method, parameters] : stimulus_parameters(stimulus, levels)) {
    if (method == "fpt") {
      for (const auto& [key, side_px] : {std::pair<const char*, int>{"width_px", display.width_px}, {"height_px", display.height_px}})
        if (side_px % kZoneSideMultiplePx != 0)
          display_fields.fail(key, "expected a multiple of " + std::to_string(kZoneSideMultiplePx) +
                                       " for fpt stimuli (the outer zone is 1/" + std::to_string(kZoneSideMultiplePx) +
                                       " of the frame per axis), got " + std::to_string(side_px));
    }
    const auto samples_per_pixel = parameters.find("samples_per_pixel");
    if (!is_path_traced_method(method) && samples_per_pixel != parameters.end()) {
      const uint64_t samples = uint64_t(display.width_px) * uint64_t(display.height_px) *
                               static_cast<uint64_t>(samples_per_pixel->second);
      if (samples > kMaxSphereTraceSamplesPerFrame)
        display_fields.fail("width_px", "expected width_px x height_px x samples_per_pixel of at most " +
                                            std::to_string(kMaxSphereTraceSamplesPerFrame) + " samples a frame (" +
                                            method + "), got " + std::to_string(display.width_px) + " x " +
                                            std::to_string(display.height_px) + " x " +
                                            format_number(samples_per_pixel->second, 6) + " = " + std::to_string(samples));
    }
  }
}

ProtocolKind read_kind(const TomlFields& fields) {
  const std::string kind = fields.string("kind");
  for (ProtocolKind candidate : {ProtocolKind::two_afc, ProtocolKind::pair, ProtocolKind::ramp, ProtocolKind::slider,
                                 ProtocolKind::rating})
    if (kind == protocol_name(candidate)) return candidate;
  fields.fail("kind", "expected one of 2afc, pair, ramp, slider, rating, got \"" + kind + "\"");
}

std::vector<std::string> default_keys(const std::string& answer) {
  static const std::map<std::string, std::vector<std::string>> defaults = {
      {"first", {"1", "left", "pad_left"}},   {"second", {"2", "right", "pad_right"}},
      {"same", {"s", "space", "pad_a"}},      {"different", {"d", "pad_b"}},
      {"increased", {"up", "pad_up"}},        {"decreased", {"down", "pad_down"}},
      {"1", {"1", "pad_b"}},                  {"2", {"2", "pad_y"}},
      {"3", {"3", "pad_a"}},                  {"up", {"up", "right", "pad_up"}},
      {"down", {"down", "left", "pad_down"}}, {"reference", {"r", "pad_x"}},
      {"save", {"enter", "space", "pad_a"}}};
  return defaults.at(answer);
}

std::string default_question(ProtocolKind kind, TwoAfcQuestion question) {
  switch (kind) {
    case ProtocolKind::two_afc:
      return question == TwoAfcQuestion::same ? "Was the quality the same in both sequences?"
                                              : "Which sequence had the better quality?";
    case ProtocolKind::pair: return "Which rendering was better, or were they the same?";
    case ProtocolKind::ramp: return "Did the quality increase, decrease or stay the same?";
    case ProtocolKind::slider:
      return "Change the level until the quality matches the reference; save when it does.";
    case ProtocolKind::rating:
      return "Score the difference: 3 identical, 2 minimal difference, 1 significant difference.";
  }
  return "";
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

void read_stimulus(const TomlFields& fields, const DisplayConfig& display, StimulusConfig& stimulus) {
  stimulus.duration_s = fields.number("duration_s");
  check_range(fields, "duration_s", stimulus.duration_s, 1e-3, 3600.0);
  stimulus.frames_per_second = fields.number("frames_per_second", display.refresh_hz);
  check_range(fields, "frames_per_second", stimulus.frames_per_second, 1e-3, display.refresh_hz);
  const double ratio = display.refresh_hz / stimulus.frames_per_second;
  if (std::abs(ratio - std::round(ratio)) > 1e-6)
    fields.fail("frames_per_second", "expected the display's refresh rate divided by a whole number (each frame "
                                     "is held for the same number of refreshes)");
  stimulus.camera_start_s = fields.number("camera_start_s", 0.0);
  stimulus.reference = read_method(fields.table("reference"));
  stimulus.test = read_method(fields.table("test"));
  if (fields.has("variant")) {
    std::set<std::string> names;
    for (const TomlFields& variant_fields : fields.tables("variant")) {
      VariantConfig variant;
      variant.name = variant_fields.string("name");
      if (!is_safe_name(variant.name)) variant_fields.fail("name", "expected letters, digits, '_', '-' or '.'");
      if (!names.insert(variant.name).second) variant_fields.fail("name", "duplicate variant \"" + variant.name + "\"");
      variant.parameters = read_parameters(variant_fields, stimulus.test.method, {"name"});
      stimulus.variants.push_back(std::move(variant));
    }
  }
  fields.finish();
}

void read_levels(const TomlFields& fields, const MethodConfig& test, LevelsConfig& levels) {
  levels.parameter = fields.string("parameter");
  const auto parameters = method_parameters(test.method);
  const MethodParameter* parameter = find_parameter(*parameters, levels.parameter);
  if (!parameter)
    fields.fail("parameter", "not a parameter of the test method \"" + test.method + "\" (expected one of: " +
                                 parameter_names(*parameters) + ")");
  levels.values = fields.numbers("values");
  for (size_t i = 0; i < levels.values.size(); ++i) {
    check_parameter(fields, "values", *parameter, levels.values[i]);
    if (i > 0 && !(levels.values[i] > levels.values[i - 1])) fields.fail("values", "expected strictly ascending values");
  }
  levels.higher_is_better = fields.boolean("higher_is_better", true);
  fields.finish();
}

void read_protocol(const TomlFields& fields, const LevelsConfig& levels, ProtocolConfig& protocol) {
  protocol.kind = read_kind(fields);
  if ((protocol.kind == ProtocolKind::ramp || protocol.kind == ProtocolKind::slider) && levels.values.size() < 2)
    fields.fail("kind", std::string(protocol_name(protocol.kind)) + " needs a [levels] table with at least two values");
  if (protocol.kind == ProtocolKind::two_afc) {
    const std::string question = fields.string("question");
    if (question == "same") protocol.two_afc_question = TwoAfcQuestion::same;
    else if (question == "better") protocol.two_afc_question = TwoAfcQuestion::better;
    else fields.fail("question", "expected \"same\" (same/different) or \"better\" (first/second), got \"" + question + "\"");
  }
  protocol.repeats = bounded_integer(fields, "repeats", 1, 1, 1000);
  const bool two_intervals = protocol.kind == ProtocolKind::two_afc || protocol.kind == ProtocolKind::pair ||
                             protocol.kind == ProtocolKind::rating;
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
  if (block_order != "random" && block_order != "fixed") fields.fail("block_order", "expected \"random\" or \"fixed\"");
  protocol.randomise_blocks = block_order == "random";
  protocol.question.text = fields.string("question_text", default_question(protocol.kind, protocol.two_afc_question));

  const std::vector<std::string> answers = protocol_answers(protocol.kind, protocol.two_afc_question);
  const toml::table* keys_table = fields.optional_table("keys");
  std::map<std::string, std::string> answer_of_key;
  for (const std::string& answer : answers) {
    std::vector<std::string> keys = default_keys(answer);
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
      if (std::find(answers.begin(), answers.end(), std::string(key.str())) == answers.end()) {
        std::string expected;
        for (const std::string& answer : answers) expected += (expected.empty() ? "" : ", ") + answer;
        keys_fields.fail(std::string(key.str()), "not an answer of this protocol (expected " + expected + ")");
      }
  }
  if (protocol.kind == ProtocolKind::slider) {
    protocol.slider.start_level = fields.number("start_level", levels.values.empty() ? 0.0 : levels.values.front());
    if (std::find(levels.values.begin(), levels.values.end(), protocol.slider.start_level) == levels.values.end())
      fields.fail("start_level", "expected one of [levels] values");
  }
  fields.finish();
}

void read_timing(const TomlFields& fields, TimingConfig& timing) {
  timing.black_interval_s = fields.number("black_interval_s", timing.black_interval_s);
  check_range(fields, "black_interval_s", timing.black_interval_s, 0.0, 600.0);
  timing.inter_trial_s = fields.number("inter_trial_s", timing.inter_trial_s);
  check_range(fields, "inter_trial_s", timing.inter_trial_s, 0.0, 600.0);
  timing.rest_between_blocks_s = fields.number("rest_between_blocks_s", timing.rest_between_blocks_s);
  check_range(fields, "rest_between_blocks_s", timing.rest_between_blocks_s, 0.0, 7200.0);
  timing.response_timeout_s = fields.number("response_timeout_s", timing.response_timeout_s);
  check_range(fields, "response_timeout_s", timing.response_timeout_s, 0.0, 3600.0);
  fields.finish();
}

void read_attention(const TomlFields& fields, const ProtocolConfig& protocol, AttentionConfig& attention) {
  attention.share = fields.number("share");
  check_range(fields, "share", attention.share, 0.0, 0.9);
  if (attention.share > 0 && identical_answer(protocol).empty())
    fields.fail("share", "attention checks need an answer that means \"identical\" (2afc with question = \"same\", "
                         "pair or rating)");
  attention.break_s = fields.number("break_s", attention.break_s);
  check_range(fields, "break_s", attention.break_s, 0.0, 3600.0);
  attention.max_errors = bounded_integer(fields, "max_errors", attention.max_errors, 1, 1000);
  fields.finish();
}

// Sphere-traced methods take SDF scenes (built-in names or .glsl files), path-traced ones
// path-traced scenes (courtyard or .obj files); files are relative to the config.
std::string resolve_scene(const TomlFields& fields, const std::string& scene, const std::string& config_path,
                          bool check_file, bool path_traced) {
  const std::vector<std::string> names = path_traced ? std::vector<std::string>{known_path_scenes()} : builtin_scene_names();
  if (path_traced && !is_path_scene_name(scene))
    fields.fail("scene", "expected a path-traced scene (" + known_path_scenes() + " or a .obj file) for pt and fpt, got \"" +
                             scene + "\"");
  if (std::find(names.begin(), names.end(), scene) != names.end()) return scene;
  std::filesystem::path path(scene);
  if (path.is_relative()) path = std::filesystem::path(config_path).parent_path() / path;
  std::error_code error;  // e.g. a name too long for the file system: not found, not a crash
  if (check_file && !std::filesystem::is_regular_file(path, error)) {
    std::string known;
    for (const std::string& name : names) known += (known.empty() ? "" : ", ") + name;
    fields.fail("scene", "no built-in scene or file \"" + scene + "\" (built-in: " + known + ")");
  }
  return path.lexically_normal().string();
}

}  // namespace

const char* protocol_name(ProtocolKind kind) {
  switch (kind) {
    case ProtocolKind::two_afc: return "2afc";
    case ProtocolKind::pair: return "pair";
    case ProtocolKind::ramp: return "ramp";
    case ProtocolKind::slider: return "slider";
    case ProtocolKind::rating: return "rating";
  }
  return "?";
}

bool is_valid_study_name(const std::string& name) {
  if (name.empty() || name.size() > 64 || name[0] == '.' || name[0] == '-') return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
           c == '.';
  });
}

std::vector<std::string> protocol_answers(ProtocolKind kind, TwoAfcQuestion question) {
  switch (kind) {
    case ProtocolKind::two_afc:
      return question == TwoAfcQuestion::same ? std::vector<std::string>{"same", "different"}
                                              : std::vector<std::string>{"first", "second"};
    case ProtocolKind::pair: return {"first", "second", "same"};
    case ProtocolKind::ramp: return {"increased", "decreased", "same"};
    case ProtocolKind::slider: return {"up", "down", "reference", "save"};
    case ProtocolKind::rating: return {"1", "2", "3"};
  }
  return {};
}

std::string identical_answer(const ProtocolConfig& protocol) {
  if (protocol.kind == ProtocolKind::rating) return "3";
  if (protocol.kind == ProtocolKind::pair) return "same";
  if (protocol.kind == ProtocolKind::two_afc && protocol.two_afc_question == TwoAfcQuestion::same) return "same";
  return "";
}

int StimulusConfig::frame_count() const {
  return std::max(1, static_cast<int>(std::lround(duration_s * frames_per_second)));
}

int StimulusConfig::refreshes_per_frame(double refresh_hz) const {
  return std::max(1, static_cast<int>(std::lround(refresh_hz / frames_per_second)));
}

StudyConfig parse_study_config_text(const std::string& text, const std::string& path, bool check_scene_files) {
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
  read_stimulus(fields.table("stimulus"), config.display, config.stimulus);
  std::optional<TomlFields> levels_fields;
  if (const toml::table* levels = fields.optional_table("levels")) {
    levels_fields.emplace(*levels, path, "levels");
    read_levels(*levels_fields, config.stimulus.test, config.levels);
  }
  check_parameter_rules(fields.table("stimulus"), config.stimulus, levels_fields ? &*levels_fields : nullptr,
                        config.levels);
  check_frame_size_rules(fields.table("display"), config.display, config.stimulus, config.levels);
  read_protocol(fields.table("protocol"), config.levels, config.protocol);
  if (const toml::table* timing = fields.optional_table("timing"))
    read_timing(TomlFields(*timing, path, "timing"), config.timing);
  if (const toml::table* attention = fields.optional_table("attention"))
    read_attention(TomlFields(*attention, path, "attention"), config.protocol, config.attention);

  const bool path_traced = is_path_traced_method(config.stimulus.reference.method);
  if (is_path_traced_method(config.stimulus.test.method) != path_traced)
    fields.table("stimulus").table("test").fail(
        "method", "expected " + std::string(path_traced ? "a path-traced method (pt, fpt)" : "a sphere-traced method (gt, ipr, fipr)") +
                      " like the reference's \"" + config.stimulus.reference.method +
                      "\" (both render the same scene), got \"" + config.stimulus.test.method + "\"");
  std::set<std::string> block_names;
  for (const TomlFields& block_fields : fields.tables("block")) {
    BlockConfig block;
    block.scene = resolve_scene(block_fields, block_fields.string("scene"), path, check_scene_files, path_traced);
    block.name = block_fields.string("name", std::filesystem::path(block.scene).stem().string());
    if (!is_safe_name(block.name)) block_fields.fail("name", "expected letters, digits, '_', '-' or '.'");
    if (!block_names.insert(block.name).second) block_fields.fail("name", "duplicate block \"" + block.name + "\"");
    block_fields.finish();
    config.blocks.push_back(std::move(block));
  }
  fields.finish();
  return config;
}

StudyConfig parse_study_config_file(const std::string& path) {
  return parse_study_config_text(read_input_file(path, "a study config (.toml)", kMaxStudyConfigBytes), path);
}

}  // namespace fovlab
