#pragma once
// A study as its TOML config describes it (docs/config.md, field by field). Parsing validates
// everything before a session can start: a StudyConfig that exists is a runnable study.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "study/config/headset_display.h"
#include "study/config/scene_catalog.h"
#include "study/protocol/protocol_rules.h"
#include "study/schedule/quest_plus.h"
#include "study/schedule/staircase.h"
#include "study/stimulus/render_method.h"

namespace fovlab {

// The protocol's name in configs and logs (study/protocol/protocol_rules.h).
// (The rules' names are string literals, so the view is NUL-terminated.)
inline const char* protocol_name(ProtocolKind kind) { return protocol_rules(kind).name.data(); }

// [display]. A window's fields as given; a headset's (kind openxr) in `headset`, with width_px and
// height_px each eye's image and the millimetres those of its left eye's flat_display_of_eye (the
// plan's stimuli are made for them until per-eye rendering).
struct DisplayConfig {
  DisplayKind kind = DisplayKind::window;
  int width_px = 0;
  int height_px = 0;
  double refresh_hz = 60.0;
  double width_mm = 0.0;  // physical size of the visible area (given, or from diagonal_in)
  double height_mm = 0.0;
  double viewing_distance_mm = 0.0;
  bool fullscreen = false;
  HeadsetDisplayConfig headset;  // kind openxr only
};

// A rendering method and its parameters (names and ranges in study/stimulus/stimulus_spec.h).
struct MethodConfig {
  RenderMethod method = RenderMethod::ground_truth;
  ParameterLayer parameters;  // as given (by key; a choice as its index); the schedule adds the defaults
};

// A named set of overrides of the test method's parameters (e.g. blur on / off); conditions are
// variants x levels.
struct VariantConfig {
  std::string name;
  ParameterLayer parameters;  // overrides of the test method's parameters
  // From a conditions file: this variant's levels, ascending (a design need not be variants x
  // levels). Empty: every [levels] value.
  std::vector<double> levels;
};

struct StimulusConfig {
  double duration_s = 2.0;
  double frames_per_second = 30.0;  // animation rate; each frame is held refresh_hz / fps refreshes
  double camera_start_s = 0.0;      // scene time of the first frame
  MethodConfig reference;
  MethodConfig test;
  std::vector<VariantConfig> variants;  // empty: one unnamed variant

  int frame_count() const;  // round(duration_s * frames_per_second), at least 1
  int refreshes_per_frame(double refresh_hz) const;
};

struct LevelsConfig {
  std::string parameter;         // key of the test parameter each level sets; empty: one condition
  std::vector<double> values;    // ascending
  bool higher_is_better = true;  // which end of the values looks more like the reference
};

// The levels a variant is tested at: its own (a conditions file's rows), else every [levels] value.
// `variant` null: the one unnamed variant of a config without variants.
const std::vector<double>& variant_levels(const LevelsConfig& levels, const VariantConfig* variant);
// The variants each block tests: the config's, in order, or one unnamed variant (null) when it has none.
std::vector<const VariantConfig*> tested_variants(const StimulusConfig& stimulus);

// [procedure.NAME]: an adaptive procedure a block may name (docs/config.md). Each variant of the
// block gets its tracks, their trials interleaved: a staircase per start level, or one QUEST+. The
// schedule plans each track to its max_trials, and a track that stops sooner (max_reversals, the
// QUEST+ entropy or interval rules) skips the rest.
struct ProcedureConfig {
  enum class Kind { staircase, quest_plus };
  std::string name;
  Kind kind = Kind::staircase;
  StaircaseRule staircase;     // start_index unused: each staircase starts at one of `starts`
  std::vector<double> starts;  // level values, one staircase each; default: each variant's easiest level
  // QUEST+: the grids as given (empty: the defaults for each variant's levels, quest_plus.h); rising
  // and guess come from [levels] and the protocol (quest_plus_rule).
  QuestPlusRule quest;
  int max_trials() const { return kind == Kind::staircase ? staircase.max_trials : quest.max_trials; }
};

// The levels an adaptive track of `variant` works on, easiest (least like the reference) first:
// grid index 0 is the easiest difference to see (study/schedule/staircase.h).
std::vector<double> adaptive_grid(const LevelsConfig& levels, const VariantConfig* variant);

struct ProtocolConfig;
// A QUEST+ procedure's rule on `grid`: its grids (or the defaults for the grid), p_see rising where
// higher levels look less like the reference, and the guess rate: the procedure's guess_rate, else
// 1/2 for 2afc "better" (forced choice) and 0.05 for answers that may report a difference where
// none is (2afc "same", pair).
QuestPlusRule quest_plus_rule(const ProcedureConfig& procedure, const ProtocolConfig& protocol,
                              const LevelsConfig& levels, const std::vector<double>& grid);

struct BlockConfig {
  std::string name;
  std::string scene;
  int procedure = -1;  // index into StudyConfig::procedures; -1: constant stimuli
};

struct TimingConfig {
  double black_interval_s =
      0.5;  // between the intervals of a trial (0.5 s Polychronakis et al. 2021, 0.75 s Ye et al. 2022)
  double inter_trial_s = 0.5;          // black screen after a response
  double rest_between_blocks_s = 0.0;  // minimum rest between blocks (600 s in Polychronakis et al. 2023)
  double response_timeout_s = 0.0;     // 0: wait for an answer as long as it takes
  double fixation_s = 0.0;             // a fixation cross before each trial's first stimulus; 0: none
};

struct QuestionConfig {
  std::string text;
  // answer -> keys (normalised key names of display/presenter.h), in answer order
  std::vector<std::pair<std::string, std::vector<std::string>>> answers;
};

struct AttentionConfig {
  double share = 0.0;     // share of all trials of a block that are attention checks, in [0, 0.9]
  double break_s = 30.0;  // forced break after a wrong answer
  int max_errors = 3;     // at this many wrong answers the session ends, participant excluded
  // Shown to an excluded participant (until a key), so the session does not just stop.
  std::string excluded_message = "The session has ended. Thank you for taking part.";
};

// [validation]: an eye-tracker check before the first trial of every run (and after breaks): targets
// shown one at a time, the gaze measured on each (protocols/gaze/tracker_validation.h), repeated
// until the mean accuracy and precision are within the limits; every attempt is logged.
struct ValidationConfig {
  bool enabled = false;            // the config has a [validation] table
  int targets = 9;                 // 5 (centre and the grid's corners) or 9 (a 3 x 3 grid)
  double target_offset_deg = 8.0;  // the outer targets' horizontal and vertical offset from the centre
  double target_radius_deg = 0.3;  // the drawn disk's radius
  double target_s = 1.5;           // each target shown this long
  double settle_s = 0.5;           // the first part of each target not measured (the saccade to it)
  double max_accuracy_deg = 1.0;   // passes when the targets' mean accuracy is at most this
  double max_precision_deg = 0.5;  // ... and their mean RMS sample-to-sample precision at most this
  int max_attempts = 3;            // failed this many times in a row: the session pauses (recalibrate, resume)
  bool after_breaks = true;        // also after every rest between blocks and attention-check break
};

// The validation targets' centres in display pixels (origin top left), in reading order: the 3 x 3
// grid at ±target_offset_deg from the centre along each axis (x = centre + D tan(offset) / pitch),
// or its centre and 4 corners.
std::vector<std::pair<double, double>> validation_targets_px(const DisplayConfig& display,
                                                             const ValidationConfig& validation);
// The target disk's radius in pixels (D tan(radius) / horizontal pitch, at least 2).
double validation_target_radius_px(const DisplayConfig& display, const ValidationConfig& validation);

// [gaze]: the kinds of gaze source a study may run with (docs/gaze.md). A tracker is an eye tracker
// (`--gaze pupil...`); a trace replays a recorded file; synthetic is a simulated gaze; the mouse
// moves the gaze with the pointer (a rehearsal).
enum class GazeSourceKind { tracker, trace, synthetic, mouse };
const char* gaze_source_kind_name(GazeSourceKind kind);  // "tracker", "trace", "synthetic", "mouse"
std::optional<GazeSourceKind> parse_gaze_source_kind(const std::string& name);
// The kind of a gaze source as a session log names it (the header's and session_resumed's `gaze`,
// GazeSource::describe(): "mouse", "trace:FILE", "synthetic:seed=N...", "pupil:HOST:PORT..."); none
// for any other text.
std::optional<GazeSourceKind> gaze_source_kind_of_spec(const std::string& spec);

struct GazeConfig {
  // `require`: one kind or an array of kinds; a session whose source is of another kind is refused.
  // Empty: the config requires none (a gaze-contingent study in a window then requires a tracker
  // unless --gaze names the source: docs/gaze.md).
  std::vector<GazeSourceKind> require;
  int require_line = 0;  // its line in the config (messages)
  bool allows(GazeSourceKind kind) const;
  std::string require_text() const;  // "tracker", "tracker or trace"
};

// [practice]: trials before the first block that teach the task. They run as the study's trials do
// (in a block of their own, named "practice") and are logged with "practice": true; no analysis
// counts them.
struct PracticeConfig {
  int trials = 0;              // 0: no practice
  std::vector<double> levels;  // 2afc, pair, rating: the levels practised (default: the one least like the reference)
  std::string scene;           // "": the scene of the participant's first block
};

struct SliderConfig {
  double start_level = 0.0;  // one of the level values
};

struct ProtocolConfig {
  ProtocolKind kind = ProtocolKind::two_afc;
  TwoAfcQuestion two_afc_question = TwoAfcQuestion::same;
  const ProtocolRules& rules() const { return protocol_rules(kind, two_afc_question); }
  int repeats = 1;               // presentations of each condition per block (per direction for ramp)
  bool counterbalance = true;    // reference first in half of the presentations
  bool randomise_trials = true;  // shuffle trials within a block
  // Block order per participant: as listed; shuffled (seeded by the participant); or counterbalanced
  // by a balanced Latin square (Williams design) whose row is chosen by the participant's number.
  enum class BlockOrder { fixed, random, latin_square };
  BlockOrder block_order = BlockOrder::fixed;
  QuestionConfig question;
  SliderConfig slider;
};

// [analysis]: how `fovlab analyze` reports the study (docs/analysis.md, "The headline").
struct AnalysisConfig {
  // headline = "paper": each group's headline is the paper's own rule (the walk, the per-participant
  // rule) rather than the estimate the design calls for ("estimate", the default).
  bool headline_is_paper_rule = false;
};

struct StudyConfig {
  std::string name;  // results/<name>/...
  uint64_t seed = 0;
  std::string instructions;
  DisplayConfig display;
  StimulusConfig stimulus;
  ProtocolConfig protocol;
  LevelsConfig levels;
  std::vector<BlockConfig> blocks;
  std::vector<ProcedureConfig> procedures;  // [procedure.NAME] tables, in name order
  TimingConfig timing;
  AttentionConfig attention;
  ValidationConfig validation;
  GazeConfig gaze;
  PracticeConfig practice;
  AnalysisConfig analysis;
  // [participant] fields: what each participant is asked before the session (age, handedness, ...):
  // given with fovlab run --field NAME=VALUE or asked on the terminal, kept in the log's header and
  // exported. Names: 1-32 of a-z, 0-9, '_', unique, at most 32 of them.
  std::vector<std::string> participant_fields;

  // [conditions] file: a CSV file of conditions (docs/config.md) instead of variants x levels; its
  // bytes are logged in the header beside the config's.
  std::string conditions_path;
  std::string conditions_csv;

  std::string source_path;  // where it was read from (messages)
  std::string source_text;  // the file's bytes (logged in the header, so a replay needs nothing else)
  std::string hash;         // content hash of source_text, then conditions_csv when there is one (hex)
  // The config's version: a content hash of what it says, comments and formatting aside (the
  // canonical text of its parsed TOML, canonical_config_content), then conditions_csv's bytes when
  // there is one. Two configs of one version run the same study; `fovlab run` keeps versions in
  // separate study folders and `fovlab analyze` pools only one version.
  std::string content_hash;
};

// A conditions file: at most this many bytes and rows.
constexpr uint64_t kMaxConditionsBytes = uint64_t(1) << 20;  // 1 MiB
constexpr size_t kMaxConditionsRows = 10000;

// Limits on the text of a config, far above any real one's (a few KiB, nested 4 levels deep), so
// that no input can exhaust memory or toml++'s stack: the bytes of the file (or of the text, when
// it comes from a session log's header) and the depth of nesting (toml_guard.h check_toml_nesting).
constexpr uint64_t kMaxStudyConfigBytes = uint64_t(16) << 20;  // 16 MiB
constexpr int kMaxStudyConfigNesting = 32;

// Parses and validates; throws InputError "path:LINE: key: what was expected" (for a missing key,
// LINE is the line of the table that should hold it). The file must be a regular file of at most
// kMaxStudyConfigBytes ("path: not a regular file (a directory): expected a study config (.toml)").
// A UTF-8 byte-order mark at the start is accepted (and ignored), as by every reader of fovlab.
// Scene names are checked against `scenes` (the renderer's: renderer_scene_catalog(),
// protocols/stimuli/stimulus_settings.h).
StudyConfig parse_study_config_file(const std::string& path, const SceneCatalog& scenes);
StudyConfig parse_study_config_text(const std::string& text, const std::string& path_for_messages,
                                    const SceneCatalog& scenes);
// A config that a session log carries (replay, analyze): also takes the parameter keys and numeric
// choices of configs written before the typed model (log schema 2 and earlier; docs/config.md).
// Without a catalog (readers of logs on another machine) scene names are taken as written.
// `conditions_csv`: the header's conditions_csv (a config with a [conditions] file is read from the
// log alone, never from the file on this machine). `log_schema_version`: the header's; a parameter
// the config leaves out takes the default of that schema (render_method.h default_in_log_schema), so
// the log's stimuli are those it recorded.
StudyConfig parse_logged_study_config(const std::string& text, const std::string& path_for_messages,
                                      int log_schema_version, const SceneCatalog* scenes,
                                      const std::string& conditions_csv = {});

// A gaze-contingent study: its stimuli follow the gaze (the reference's or the test's method
// depends_on_gaze: fipr, fpt, the sampling models), so where the gaze comes from decides what the
// participant sees.
bool is_gaze_contingent(const StudyConfig& config);

// A study name (study.name, and the study a session log's header names): 1-64 letters, digits,
// '_', '-' or '.', not starting with '.' or '-', so it is one folder name (results/<study>), never
// a path. Block and variant names follow the same rule.
bool is_valid_study_name(const std::string& name);

// The answers a protocol collects, in order (e.g. {"same", "different"}); the config's keys must
// map exactly these.
std::vector<std::string> protocol_answers(ProtocolKind kind, TwoAfcQuestion question);

// The answer that means "identical" (the correct answer to an attention check): "same" for 2afc
// with question "same" and pair, "3" for rating; "" for protocols that have none.
std::string identical_answer(const ProtocolConfig& protocol);

}  // namespace fovlab
