#pragma once
// The session log's events as types (docs/log-schema.md, schema 3): one struct per event kind, the
// key names in one place (log_keys), and each struct's JSON both ways. Each struct's JSON fields
// are listed once, in its table (log_event_fields.h), from which to_json, parse_*, the field type
// checks and the fast scan's reading all come. The writer (protocols/session) builds these
// structs and logs to_json(event); the full reader (session_record) parses every trial event into
// them; the fast scan (session_scan) reads the fields the tables mark for it into them. to_json
// writes exactly the keys and value types the log has always had (nlohmann::json sorts keys), so
// the bytes of a log do not change.
//
// Fields every event has: "event" (the struct's `kind`), "seq", "t", "chain", "mac". The structs
// hold `t` and `seq` (as read; unset when the writer fills them in: SessionRun::log adds "t",
// EventLogWriter "seq", "chain", "mac" and a seal's "last_chain"). to_json writes `t` and `seq`
// only when set.
//
// parse_X reads an event's fields. A missing field keeps its default (older schemas lack some,
// e.g. schema 2 stimulus events have no latency fields). A field of the wrong type:
// FieldCheck::strict throws InputError "KIND: KEY: expected ..., got ..." (the caller adds the
// file and line); FieldCheck::lenient leaves the default, as the full reader does for the fields
// the shared type checks (check_log_field_types) do not cover, so that it accepts every log the
// fast scan accepts.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "study/config/study_config.h"  // GazeSourceKind

namespace fovlab {

namespace log_keys {
// On every event.
inline constexpr const char* event = "event";
inline constexpr const char* seq = "seq";
inline constexpr const char* t = "t";
inline constexpr const char* chain = "chain";
inline constexpr const char* mac = "mac";
// session_header
inline constexpr const char* schema_version = "schema_version";
inline constexpr const char* lab_key_id = "lab_key_id";
inline constexpr const char* fovlab_version = "fovlab_version";
inline constexpr const char* study = "study";
inline constexpr const char* participant = "participant";
inline constexpr const char* study_seed = "study_seed";
inline constexpr const char* session_seed = "session_seed";
inline constexpr const char* config_path = "config_path";
inline constexpr const char* config_hash = "config_hash";
inline constexpr const char* config_toml = "config_toml";
inline constexpr const char* protocol = "protocol";
inline constexpr const char* trial_count = "trial_count";
inline constexpr const char* scene_hashes = "scene_hashes";
inline constexpr const char* image_hashes = "image_hashes";
inline constexpr const char* headset = "headset";
inline constexpr const char* stimuli = "stimuli";
inline constexpr const char* device = "device";
inline constexpr const char* display = "display";
inline constexpr const char* presenter = "presenter";
inline constexpr const char* gaze = "gaze";  // also a stimulus event's per-refresh positions
inline constexpr const char* observer = "observer";
inline constexpr const char* started_utc = "started_utc";
inline constexpr const char* participant_fields = "participant_fields";
inline constexpr const char* conditions_csv = "conditions_csv";
inline constexpr const char* gaze_source = "gaze_source";          // schema 7: also session_resumed's
inline constexpr const char* gaze_validation = "gaze_validation";  // schema 7
// session_resumed
inline constexpr const char* next_trial = "next_trial";
inline constexpr const char* discarded_trial = "discarded_trial";
inline constexpr const char* torn_line_set_aside = "torn_line_set_aside";
// instructions, block_start, break
inline constexpr const char* shown_s = "shown_s";
inline constexpr const char* block = "block";
inline constexpr const char* name = "name";
inline constexpr const char* scene = "scene";
inline constexpr const char* reason = "reason";  // also session_paused, session_end
inline constexpr const char* start_s = "start_s";
inline constexpr const char* duration_s = "duration_s";
// trial events
inline constexpr const char* trial = "trial";
inline constexpr const char* condition = "condition";
inline constexpr const char* variant = "variant";
inline constexpr const char* level = "level";
inline constexpr const char* attention_check = "attention_check";
inline constexpr const char* sequence = "sequence";
inline constexpr const char* reference = "reference";
inline constexpr const char* reference_first = "reference_first";
inline constexpr const char* ramp_toward_reference = "ramp_toward_reference";
inline constexpr const char* slider_start = "slider_start";
inline constexpr const char* step = "step";
inline constexpr const char* stimulus = "stimulus";
inline constexpr const char* onset_s = "onset_s";
inline constexpr const char* present_s = "present_s";
inline constexpr const char* frame = "frame";
inline constexpr const char* hash = "hash";
inline constexpr const char* invalid_gaze = "invalid_gaze";
inline constexpr const char* invalid_index = "i";  // an invalid_gaze entry's refresh
inline constexpr const char* dropped_frames = "dropped_frames";
inline constexpr const char* gaze_acquired_s = "gaze_acquired_s";
inline constexpr const char* gaze_age_s = "gaze_age_s";
inline constexpr const char* present_clock = "present_clock";
inline constexpr const char* right_eye_hash = "right_eye_hash";
inline constexpr const char* right_eye_gaze = "right_eye_gaze";
inline constexpr const char* right_eye_invalid_gaze = "right_eye_invalid_gaze";  // schema 13
inline constexpr const char* head_pose = "head_pose";  // schema 12, head-tracked headset sessions
// Schema 12, late frames in a headset (stimulus events; the header's headset block).
inline constexpr const char* late_frames = "late_frames";
inline constexpr const char* late_frames_measured = "late_frames_measured";
inline constexpr const char* answer = "answer";
inline constexpr const char* key = "key";
inline constexpr const char* rt_s = "rt_s";
inline constexpr const char* ladder_index = "ladder_index";
inline constexpr const char* correct = "correct";
inline constexpr const char* errors = "errors";
inline constexpr const char* max_errors = "max_errors";
inline constexpr const char* completed_trials = "completed_trials";
inline constexpr const char* trials_complete = "trials_complete";
inline constexpr const char* last_chain = "last_chain";
// trial_start of a practice trial (written only when true)
inline constexpr const char* practice = "practice";
// trial_start of an adaptive trial: its track (staircase or QUEST+) in the schedule (written only for those)
inline constexpr const char* track = "track";
// tracker_validation
inline constexpr const char* attempt = "attempt";
inline constexpr const char* targets = "targets";
inline constexpr const char* x_px = "x_px";
inline constexpr const char* y_px = "y_px";
inline constexpr const char* samples = "samples";
inline constexpr const char* valid_samples = "valid_samples";
inline constexpr const char* accuracy_deg = "accuracy_deg";
inline constexpr const char* precision_deg = "precision_deg";
inline constexpr const char* max_accuracy_deg = "max_accuracy_deg";
inline constexpr const char* max_precision_deg = "max_precision_deg";
inline constexpr const char* passed = "passed";
inline constexpr const char* stopped = "stopped";
}  // namespace log_keys

enum class FieldCheck { strict, lenient };

// The fields the writer does not set itself.
struct EventStamp {
  std::optional<double> t;
  std::optional<int64_t> seq;
  bool operator==(const EventStamp&) const = default;
};

struct SessionHeaderEvent {
  static constexpr const char* kind = "session_header";
  EventStamp stamp;
  int schema_version = 0;
  std::optional<std::string> lab_key_id;  // null: not keyed
  std::string fovlab_version, study, participant;
  uint64_t study_seed = 0, session_seed = 0;
  std::string config_path, config_hash, config_toml, protocol;
  int64_t trial_count = 0;
  nlohmann::json scene_hashes = nlohmann::json::object();  // scene -> hash
  nlohmann::json stimuli = nlohmann::json::array();        // every stimulus by id (StimulusSpec's JSON and more)
  nlohmann::json device = nlohmann::json::object();        // name, type, api_version, driver
  nlohmann::json display = nlohmann::json::object();
  std::string presenter, gaze;
  nlohmann::json observer = "human";  // "human" or the simulated observer's model
  std::string started_utc;
  nlohmann::json participant_fields = nlohmann::json::object();  // the config's [participant] fields: name -> text
  std::string conditions_csv;  // the config's [conditions] file, its bytes ("": none; then not written)
  // Schema 7 (null in earlier logs, and then not written): the gaze source the session started with
  // ({kind, spec, requested, require}) and the eye-tracker validation it runs with ({enabled, and
  // the [validation] settings}); docs/log-schema.md.
  nlohmann::json gaze_source;
  nlohmann::json gaze_validation;
  // Schema 9, only in a session of image stimuli (img-rmfr, ...; empty, and then not written, in
  // every other): each image folder's images, folder -> {image file name -> SHA-256 of its bytes}.
  nlohmann::json image_hashes = nlohmann::json::object();
  // Schema 11, only in a headset session (null, and then not written, in every other): the OpenXR
  // runtime, each eye's image size and view as the renderer took it, the view model and how the gaze
  // became each eye's pixel (protocols/session/headset_views.h, docs/log-schema.md).
  nlohmann::json headset;
  bool operator==(const SessionHeaderEvent&) const = default;
};

// Who answered a session, from its header's `observer`: "human", or "simulated" when it holds a
// simulated observer's model (an object). InputError for anything else, a missing field too: a
// session whose answerer is unknown is never counted as a person's.
std::string observer_kind(const nlohmann::json& header);

struct SessionResumedEvent;
// The kinds of gaze source a session's runs used, each once, in order of first use: the header's
// gaze_source.kind (schema 7) or, in an earlier log, the kind its `gaze` names
// (study_config.h gaze_source_kind_of_spec: the spec the session ran with, which every schema
// logs), then each resumed run's. Empty when no run's source can be told.
std::vector<GazeSourceKind> session_gaze_kinds(const nlohmann::json& header,
                                               const std::vector<SessionResumedEvent>& resumes);
// "tracker", "tracker+mouse" (several runs, several kinds); "" for none.
std::string gaze_kinds_text(const std::vector<GazeSourceKind>& kinds);

struct SessionResumedEvent {
  static constexpr const char* kind = "session_resumed";
  EventStamp stamp;
  int next_trial = 0;
  std::optional<int> discarded_trial;
  std::optional<std::string> torn_line_set_aside;
  std::string gaze, started_utc;
  nlohmann::json gaze_source;  // schema 7: as the header's, for this run (null earlier; then not written)
  bool operator==(const SessionResumedEvent&) const = default;
};

struct InstructionsEvent {
  static constexpr const char* kind = "instructions";
  EventStamp stamp;
  double shown_s = 0.0;
  bool operator==(const InstructionsEvent&) const = default;
};

struct BlockStartEvent {
  static constexpr const char* kind = "block_start";
  EventStamp stamp;
  int block = 0;
  std::string name, scene;
  bool operator==(const BlockStartEvent&) const = default;
};

struct BreakEvent {
  static constexpr const char* kind = "break";
  static constexpr const char* rest = "rest";
  static constexpr const char* attention_check = "attention_check";
  EventStamp stamp;
  std::string reason;        // rest, attention_check
  std::optional<int> trial;  // attention-check breaks
  double start_s = 0.0, duration_s = 0.0;
  bool operator==(const BreakEvent&) const = default;
};

struct TrialStartEvent {
  static constexpr const char* kind = "trial_start";
  EventStamp stamp;
  int trial = 0, block = 0;
  std::string condition, variant;
  std::optional<double> level;
  bool attention_check = false;
  std::vector<int> sequence;
  int reference = 0;
  std::optional<bool> reference_first;        // 2afc, pair, rating
  std::optional<bool> ramp_toward_reference;  // ramp
  std::optional<int> slider_start;            // slider
  bool practice = false;     // a practice trial: shown and logged, never analysed (written only when true)
  std::optional<int> track;  // an adaptive trial: its track (StudyPlan::tracks)
  bool operator==(const TrialStartEvent&) const = default;
};

struct InvalidGaze {
  int index = 0;  // the refresh ("i")
  std::string reason;
  bool operator==(const InvalidGaze&) const = default;
};

struct StimulusEvent {
  static constexpr const char* kind = "stimulus";
  EventStamp stamp;
  int trial = 0, step = 0, stimulus = -1;
  double onset_s = 0.0;
  // One entry a refresh presented.
  std::vector<double> present_s;
  std::vector<int> frame;
  std::vector<std::string> hash;
  std::vector<std::array<double, 2>> gaze;
  std::vector<InvalidGaze> invalid_gaze;
  int dropped_frames = 0;
  // Schema 3 (absent in older logs): null entries where the tracker had no sample.
  std::optional<std::vector<std::optional<double>>> gaze_acquired_s, gaze_age_s;
  std::optional<std::string> present_clock;
  // Schema 11, only in a headset session: `hash` and `gaze` are the left eye's, these the right
  // eye's, one entry a refresh as theirs.
  std::optional<std::vector<std::string>> right_eye_hash;
  std::optional<std::vector<std::array<double, 2>>> right_eye_gaze;
  // Schema 13, only in a headset session: the right eye's refreshes shown with a held gaze (as
  // invalid_gaze is the left eye's): its pixel was unusable, off its image or made from a left one
  // that was. Written only when there are any; a schema 11-12 log did not record them.
  std::vector<InvalidGaze> right_eye_invalid_gaze;
  // Schema 12 (head-tracked views), only in a head-tracked headset session: the head's pose at each
  // refresh relative to the session's start, as rendered: [x_m, y_m, z_m, qx, qy, qz, qw], one entry
  // a refresh as `hash` (docs/log-schema.md).
  std::optional<std::vector<std::array<double, 7>>> head_pose;
  // Schema 12, only in a headset session whose runtime has XR_KHR_convert_timespec_time (absent
  // otherwise, and in older logs: not measured, not 0): how many of this presentation's refreshes
  // were late, their xrEndFrame after the display time the runtime predicted for them (present_s).
  std::optional<int> late_frames;
  bool operator==(const StimulusEvent&) const = default;
};

struct ResponseEvent {
  static constexpr const char* kind = "response";
  EventStamp stamp;
  int trial = 0, step = 0;
  std::string answer, key;     // answer "" after a timeout
  std::optional<double> rt_s;  // the writer always writes it; nullopt: a log without it (unknown, not 0)
  bool operator==(const ResponseEvent&) const = default;
};

struct SliderSavedEvent {
  static constexpr const char* kind = "slider_saved";
  EventStamp stamp;
  int trial = 0, ladder_index = 0, stimulus = 0;
  std::optional<double> level;  // the writer writes 0 for a stimulus without a level
  bool operator==(const SliderSavedEvent&) const = default;
};

struct AttentionCheckEvent {
  static constexpr const char* kind = "attention_check";
  EventStamp stamp;
  int trial = 0;
  std::optional<bool> correct;  // the writer always writes it; nullopt: a log without it (unknown)
  int errors = 0;
  bool operator==(const AttentionCheckEvent&) const = default;
};

struct TrialEndEvent {
  static constexpr const char* kind = "trial_end";
  EventStamp stamp;
  int trial = 0;
  bool operator==(const TrialEndEvent&) const = default;
};

struct ExcludedEvent {
  static constexpr const char* kind = "excluded";
  EventStamp stamp;
  int errors = 0, max_errors = 0;
  bool operator==(const ExcludedEvent&) const = default;
};

// One target of an eye-tracker validation (protocols/gaze/tracker_validation.h).
struct ValidationTarget {
  double x_px = 0.0, y_px = 0.0;  // the target's centre
  int samples = 0;                // distinct gaze samples while it was measured (after settle_s)
  int valid_samples = 0;          // of those, valid ones
  // Those samples' positions as measured (rounded to 0.01 px), null for an invalid one: the figures
  // below can be computed again from the log.
  std::vector<std::optional<std::array<double, 2>>> gaze;
  std::optional<double> accuracy_deg;   // mean gaze to target; null: fewer than half the samples valid
  std::optional<double> precision_deg;  // RMS sample-to-sample; null as above
  bool operator==(const ValidationTarget&) const = default;
};

// One attempt at validating the eye tracker: before the first trial of a run, after breaks.
struct TrackerValidationEvent {
  static constexpr const char* kind = "tracker_validation";
  static constexpr const char* start = "start";        // before the first trial of a new session
  static constexpr const char* resumed = "resumed";    // before the first trial of a resumed one
  static constexpr const char* rest = "rest";          // after a rest between blocks
  static constexpr const char* after_break = "break";  // after an attention-check break
  EventStamp stamp;
  std::string reason;
  int attempt = 1;  // 1, 2, ... until one passes or max_attempts
  double start_s = 0.0;
  std::vector<ValidationTarget> targets;  // in the order shown
  std::optional<double> accuracy_deg;     // the targets' means; null when a target had too little gaze
  std::optional<double> precision_deg;
  double max_accuracy_deg = 0.0, max_precision_deg = 0.0;  // the config's limits
  bool passed = false;
  bool stopped = false;  // the session stopped during the attempt (its targets so far; written only when true)
  bool operator==(const TrackerValidationEvent&) const = default;
};

struct SessionPausedEvent {
  static constexpr const char* kind = "session_paused";
  EventStamp stamp;
  std::string reason;
  bool operator==(const SessionPausedEvent&) const = default;
};

struct SessionEndEvent {
  static constexpr const char* kind = "session_end";
  static constexpr const char* completed = "completed";
  static constexpr const char* excluded = "excluded";
  EventStamp stamp;
  std::string reason;  // completed, excluded
  int completed_trials = 0;
  bool operator==(const SessionEndEvent&) const = default;
};

struct SealEvent {
  static constexpr const char* kind = "seal";
  EventStamp stamp;
  int trials_complete = 0;
  std::string last_chain;  // set by EventLogWriter; written only when not empty
  bool operator==(const SealEvent&) const = default;
};

nlohmann::json to_json(const SessionHeaderEvent& event);
nlohmann::json to_json(const SessionResumedEvent& event);
nlohmann::json to_json(const InstructionsEvent& event);
nlohmann::json to_json(const BlockStartEvent& event);
nlohmann::json to_json(const BreakEvent& event);
nlohmann::json to_json(const TrialStartEvent& event);
nlohmann::json to_json(const StimulusEvent& event);
nlohmann::json to_json(const ResponseEvent& event);
nlohmann::json to_json(const SliderSavedEvent& event);
nlohmann::json to_json(const AttentionCheckEvent& event);
nlohmann::json to_json(const TrialEndEvent& event);
nlohmann::json to_json(const ExcludedEvent& event);
nlohmann::json to_json(const TrackerValidationEvent& event);
nlohmann::json to_json(const SessionPausedEvent& event);
nlohmann::json to_json(const SessionEndEvent& event);
nlohmann::json to_json(const SealEvent& event);

SessionHeaderEvent parse_session_header(const nlohmann::json& json, FieldCheck check = FieldCheck::strict);
SessionResumedEvent parse_session_resumed(const nlohmann::json& json, FieldCheck check = FieldCheck::strict);
InstructionsEvent parse_instructions(const nlohmann::json& json, FieldCheck check = FieldCheck::strict);
BlockStartEvent parse_block_start(const nlohmann::json& json, FieldCheck check = FieldCheck::strict);
BreakEvent parse_break(const nlohmann::json& json, FieldCheck check = FieldCheck::strict);
TrialStartEvent parse_trial_start(const nlohmann::json& json, FieldCheck check = FieldCheck::strict);
StimulusEvent parse_stimulus(const nlohmann::json& json, FieldCheck check = FieldCheck::strict);
ResponseEvent parse_response(const nlohmann::json& json, FieldCheck check = FieldCheck::strict);
SliderSavedEvent parse_slider_saved(const nlohmann::json& json, FieldCheck check = FieldCheck::strict);
AttentionCheckEvent parse_attention_check(const nlohmann::json& json, FieldCheck check = FieldCheck::strict);
TrialEndEvent parse_trial_end(const nlohmann::json& json, FieldCheck check = FieldCheck::strict);
ExcludedEvent parse_excluded(const nlohmann::json& json, FieldCheck check = FieldCheck::strict);
TrackerValidationEvent parse_tracker_validation(const nlohmann::json& json, FieldCheck check = FieldCheck::strict);
SessionPausedEvent parse_session_paused(const nlohmann::json& json, FieldCheck check = FieldCheck::strict);
SessionEndEvent parse_session_end(const nlohmann::json& json, FieldCheck check = FieldCheck::strict);
SealEvent parse_seal(const nlohmann::json& json, FieldCheck check = FieldCheck::strict);

// Any event of a log.
using LogEvent =
    std::variant<SessionHeaderEvent, SessionResumedEvent, InstructionsEvent, BlockStartEvent, BreakEvent,
                 TrialStartEvent, StimulusEvent, ResponseEvent, SliderSavedEvent, AttentionCheckEvent, TrialEndEvent,
                 ExcludedEvent, TrackerValidationEvent, SessionPausedEvent, SessionEndEvent, SealEvent>;
nlohmann::json to_json(const LogEvent& event);
// By its "event"; an unknown or missing kind is an InputError.
LogEvent parse_log_event(const nlohmann::json& json, FieldCheck check = FieldCheck::strict);

// The "event" of a logged event, or "" when it has none or it is not a string.
std::string event_kind(const nlohmann::json& event);

// The type checks both readers make on every event (the fast scan's decoder enforces the same),
// from the fields the tables mark typed (log_event_fields.h scanned_keys) and "event":
// a trial, block, step or track is a 32-bit integer; event, condition, variant, answer, name and scene are
// strings; a level a number or null; attention_check, reference_first, ramp_toward_reference and
// correct and practice booleans; a sequence an array of 32-bit integers; dropped_frames a 32-bit integer,
// present_clock a string, gaze_acquired_s and gaze_age_s arrays of numbers or nulls. Returns the
// first violation as "an event has a field of the wrong type (KEY: VALUE)", or "" when none.
std::string check_log_field_types(const nlohmann::json& event);

}  // namespace fovlab
