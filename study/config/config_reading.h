#pragma once
// Internals of the study config reader (study_config.h), one file a part of the config:
//   study_config.cpp          the order the tables are read in, [study], [analysis], [participant],
//                             [[block]], the canonical text behind content_hash, the field helpers
//   display_gaze_config.cpp   [display], [gaze], [validation] (what the participant sees, where they look)
//   headset_display_config.cpp  [display] kind = "openxr": a headset's keys and its per-eye checks
//   stimulus_config.cpp       [stimulus] (methods, variants, parameter rules), [levels], scenes
//   conditions_file.cpp       [conditions]: the variants and levels as a CSV file's rows
//   protocol_config.cpp       [protocol], [timing], [attention], [practice], [procedure.NAME]
// Each reader takes its table's fields and fails with a message naming the field (core/toml_fields.h).
#include <cstdint>
#include <optional>
#include <string>

#include "core/toml_fields.h"
#include "study/config/study_config.h"

namespace fovlab::config_detail {

// How a config is read: where its scene names are checked, and whether the keys of configs from
// before the typed model (log schema 2 and earlier) are taken (only for configs a log carries).
struct Reading {
  const SceneCatalog* scenes = nullptr;  // nullptr: scene names taken as written
  bool legacy_keys = false;
  int log_schema_version = 0;  // of the log that carries the config (0: none); its parameters' defaults
  const std::string* logged_conditions_csv = nullptr;  // a logged config: the header's conditions_csv
};

// ---- field helpers (study_config.cpp) ----

// Block and variant names follow the study name's rule (they name files and label results).
bool is_safe_name(const std::string& name);
// Fails on `key` unless low <= value <= high (the value as given: 0.9000001 is not "0.9").
void check_range(const TomlFields& fields, const std::string& key, double value, double low, double high);
// An optional number field (`fallback` when absent) in [low, high].
double bounded_number(const TomlFields& fields, const std::string& key, double fallback, double low, double high);
// An integer field (required when `fallback` is empty) in [low, high].
int bounded_integer(const TomlFields& fields, const std::string& key, std::optional<int64_t> fallback, int low,
                    int high);

// ---- [display], [gaze], [validation] (display_gaze_config.cpp) ----

void read_display(const TomlFields& fields, DisplayConfig& display);
void read_gaze(const TomlFields& fields, GazeConfig& gaze);
void read_validation(const TomlFields& fields, const DisplayConfig& display, ValidationConfig& validation);

// ---- [display] kind = "openxr" (headset_display_config.cpp) ----

// A window's [display] giving a headset's key: one line naming the key and the kind.
void refuse_headset_keys(const TomlFields& fields);
// The rest of [display] once its kind is "openxr" (a window's keys refused, naming the kind).
void read_headset_display(const TomlFields& fields, DisplayConfig& display);
// [validation]'s targets and their disks inside each eye's field of view.
void check_validation_targets_in_each_eye(const TomlFields& fields, const HeadsetDisplayConfig& headset,
                                          const ValidationConfig& validation);

// ---- [stimulus], [levels], scenes (stimulus_config.cpp) ----

void read_stimulus(const TomlFields& fields, const DisplayConfig& display, const Reading& reading,
                   StimulusConfig& stimulus);
void read_levels(const TomlFields& fields, const MethodConfig& test, const Reading& reading, bool from_conditions,
                 LevelsConfig& levels);
// Rules between parameters, for every stimulus the config makes (the error names the field that set one).
void check_parameter_rules(const TomlFields& stimulus_fields, const StimulusConfig& stimulus,
                           const TomlFields* levels_fields, const LevelsConfig& levels, bool conditions_file);
// The renderers' rule on the frame size, which is the display's (named by [display]'s fields).
void check_frame_size_rules(const TomlFields& display_fields, const DisplayConfig& display,
                            const StimulusConfig& stimulus, const LevelsConfig& levels);
// A block's or the practice's scene: a built-in name, or a file relative to the config.
std::string resolve_scene(const TomlFields& fields, const std::string& scene, const std::string& config_path,
                          const SceneCatalog* catalog, SceneKind kind);
// The methods that render a kind of scene: "pt and fpt", for messages.
std::string methods_of_kind(SceneKind kind, const char* conjunction);
// "a sphere-traced method", "a path-traced method", "a volume method": for messages.
std::string kind_of_method(SceneKind kind);

// ---- [conditions] (conditions_file.cpp) ----

void read_conditions(const TomlFields& fields, const Reading& reading, StudyConfig& config);

// ---- [protocol], [timing], [attention], [practice], [procedure.NAME] (protocol_config.cpp) ----

void read_protocol(const TomlFields& fields, const LevelsConfig& levels, const StimulusConfig& stimulus,
                   ProtocolConfig& protocol);
void read_timing(const TomlFields& fields, TimingConfig& timing);
void read_attention(const TomlFields& fields, const ProtocolConfig& protocol, AttentionConfig& attention);
void read_practice(const TomlFields& fields, StudyConfig& config, const Reading& reading, SceneKind scene_kind);
ProcedureConfig read_procedure(const TomlFields& fields, const std::string& name);
// A block's procedure against the study (its protocol, every variant's level grid).
void check_procedure(const TomlFields& fields, const StudyConfig& config, const ProcedureConfig& procedure);
// The QUEST+ tables a session would hold, at most kQuestPlusMaxTableEntries entries in all.
void check_quest_plus_tables(const TomlFields& fields, const StudyConfig& config);

}  // namespace fovlab::config_detail
