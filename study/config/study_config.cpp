#include "study/config/study_config.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>
#include <string_view>

#include "core/content_hash.h"
#include "core/input_file.h"
#include "core/input_error.h"
#include "core/number_text.h"
#include "core/toml_fields.h"
#include "core/toml_guard.h"
#include "study/config/config_reading.h"
#include "study/stimulus/render_method.h"

namespace fovlab::config_detail {

// Block and variant names follow the study name's rule (they name files and label results).
bool is_safe_name(const std::string& name) { return is_valid_study_name(name); }

void check_range(const TomlFields& fields, const std::string& key, double value, double low, double high) {
  if (!(value >= low && value <= high))  // the value as given: 0.9000001 is not "0.9"
    fields.fail(key, "expected a value in [" + exact_number_text(low) + ", " + exact_number_text(high) + "], got " +
                         exact_number_text(value));
}

// An optional number field (`fallback` when absent) in [low, high].
double bounded_number(const TomlFields& fields, const std::string& key, double fallback, double low, double high) {
  const double value = fields.number(key, fallback);
  check_range(fields, key, value, low, high);
  return value;
}

// An integer field (required when `fallback` is empty) in [low, high]; the range is checked on the
// 64-bit value, before it is narrowed.
int bounded_integer(const TomlFields& fields, const std::string& key, std::optional<int64_t> fallback, int low,
                    int high) {
  const int64_t value = fallback ? fields.integer(key, *fallback) : fields.integer(key);
  if (value < low || value > high)
    fields.fail(key, "expected a value in [" + std::to_string(low) + ", " + std::to_string(high) + "], got " +
                         std::to_string(value));
  return static_cast<int>(value);
}

}  // namespace fovlab::config_detail

namespace fovlab {

using namespace config_detail;

bool is_valid_study_name(const std::string& name) {
  if (name.empty() || name.size() > 64 || name[0] == '.' || name[0] == '-') return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
           c == '.';
  });
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

// A head-tracked headset renders each refresh anew from the head's pose; pre-rendered path-traced
// frames and images were made ahead for one view and cannot follow it (issue 42, docs/hmd.md). The
// scene kind is the reference's (the test's is checked to match), so the reference names the method.
// Checked here, where every command reads its config, so validate, simulate, prerender and bench
// refuse what run would.
void check_head_tracked_scene_kind(const StudyConfig& config) {
  if (config.display.kind != DisplayKind::openxr || config.display.headset.view_model != HeadsetViewModel::head_tracked)
    return;
  const MethodDescriptor& reference = describe(config.stimulus.reference.method);
  const char* frames_made_ahead = reference.scene_kind == SceneKind::path_traced      ? "path-traced"
                                  : reference.scene_kind == SceneKind::image_sequence ? "image-sequence"
                                                                                      : nullptr;
  if (!frames_made_ahead) return;  // sphere-traced and volume stimuli render from any view
  throw InputError(config.source_path +
                   ": display.view_model: \"head-tracked\" renders every refresh anew from the "
                   "head's pose, and method " +
                   std::string(reference.name) + " (" + frames_made_ahead +
                   ") shows frames made ahead for one view; run it \"head-locked\"");
}

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
  if (!is_valid_study_name(config.name))
    study.fail("name", "expected 1-64 letters, digits, '_', '-' or '.' (it names a folder)");
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
    const std::string separator =
        std::string(1, '\0') + "conditions_csv " + std::to_string(config.conditions_csv.size()) + '\0';
    config.hash = ContentHash().add(text).add(separator).add(config.conditions_csv).hex();
    config.content_hash =
        ContentHash().add(canonical_config_content(root)).add(separator).add(config.conditions_csv).hex();
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
      analysis_fields.fail(
          "headline",
          "expected \"estimate\" (the design's estimate, the default) or \"paper\" (the paper's own rule), got \"" +
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
      if (!plain)
        participant_fields.fail("fields",
                                "expected names of 1-32 lower-case letters, digits or '_', got \"" + name + "\"");
      if (!seen.insert(name).second) participant_fields.fail("fields", "duplicate field \"" + name + "\"");
    }
    if (config.participant_fields.size() > 32) participant_fields.fail("fields", "expected at most 32 fields");
    participant_fields.finish();
  }

  const SceneKind scene_kind = describe(config.stimulus.reference.method).scene_kind;
  const MethodDescriptor& test = describe(config.stimulus.test.method);
  if (test.scene_kind != scene_kind) {
    fields.table("stimulus")
        .table("test")
        .fail("method", "expected " + kind_of_method(scene_kind) + " (" + methods_of_kind(scene_kind, "or") +
                            ") like the reference's \"" + std::string(describe(config.stimulus.reference.method).name) +
                            "\" (both render the same scene), got \"" + std::string(test.name) + "\"");
  }
  check_head_tracked_scene_kind(config);
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

}  // namespace fovlab
