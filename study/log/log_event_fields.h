#pragma once
// Each log event's fields, listed once: one table an event kind (docs/log-schema.md), a row a field
// (its JSON key, the struct member that holds it, when the writer writes it, and whether the fast
// scan reads it). From these rows come the writing (to_json), the full reader's parse_* (log_events.cpp),
// the field type checks both readers make on every line (check_log_field_types), and the fast
// scan's reading (session_scan.cpp). "event", "seq", "t", "chain" and "mac" are every event's
// envelope, read and written beside the tables (EventStamp, log_lines.h EventChain).
//
// A row's value type says how it is written and read: int (a 32-bit integer), int64_t, uint64_t,
// double, bool, std::string, nlohmann::json (written and read as it is), std::optional of those
// (null or absent: nullopt) and the arrays of the structs. nlohmann::json writes an object's keys
// sorted, so a table's row order is only for the reader; the bytes come from the value types,
// which are the members' own (an int is written 1, a double 1.0): a log's bytes, and its chain,
// are those the hand-written to_json of earlier builds wrote.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <type_traits>
#include <vector>

#include "study/log/log_events.h"

namespace fovlab::log_fields {

// When to_json writes a field.
enum class Write {
  always,          // an unset optional as null
  when_set,        // an optional: only when set
  when_true,       // a bool: only when true
  when_not_empty,  // a string or a vector: only when not empty; a JSON value: only when a non-empty object
  when_not_null,   // a JSON value: only when not null (schema 7 fields, absent from earlier headers)
};

// What the fast scan does with a field.
enum class Scan {
  no,     // only checks it as JSON (LogLines::check_value)
  typed,  // a typed field: every line, whatever its event, must give this key this field's type
          // (check_log_field_types in the full reader, the scan's decoder), and the scan keeps it
  kept,   // the scan keeps it, read as the full reader's lenient parse reads it (a value of
          // another type leaves the default); no type check
};

// How parse_* reads an optional field.
enum class Read {
  plain,       // absent or null: nullopt (an optional); a wrong type as FieldCheck says
  when_given,  // an optional set whenever its key is there (null too: then read as the value type,
               // a wrong type as FieldCheck says); absent: nullopt. Schema 3 stimulus fields.
};

template <typename Event, typename Member, Read read_rule = Read::plain>
struct Field {
  using EventType = Event;
  using MemberType = Member;
  static constexpr Read read = read_rule;
  const char* key;
  Member Event::*member;
  Write write = Write::always;
  Scan scan = Scan::no;
};

template <typename Event, typename Member>
constexpr Field<Event, Member> field(const char* key, Member Event::*member, Write write = Write::always) {
  return {key, member, write, Scan::no};
}
// A typed field (Scan::typed).
template <Read read = Read::plain, typename Event, typename Member>
constexpr Field<Event, Member, read> typed(const char* key, Member Event::*member, Write write = Write::always) {
  return {key, member, write, Scan::typed};
}
// A field the scan keeps without a type check (Scan::kept).
template <typename Event, typename Member>
constexpr Field<Event, Member> kept(const char* key, Member Event::*member, Write write = Write::always) {
  return {key, member, write, Scan::kept};
}

template <typename Event>
using Of = std::type_identity<Event>;

namespace k = log_keys;

// ---- the tables ----

constexpr auto fields(Of<SessionHeaderEvent>) {
  using E = SessionHeaderEvent;
  return std::tuple{
      field(k::schema_version, &E::schema_version),
      field(k::lab_key_id, &E::lab_key_id),  // null: not keyed
      field(k::fovlab_version, &E::fovlab_version),
      field(k::study, &E::study),
      field(k::participant, &E::participant),
      field(k::study_seed, &E::study_seed),
      field(k::session_seed, &E::session_seed),
      field(k::config_path, &E::config_path),
      field(k::config_hash, &E::config_hash),
      field(k::config_toml, &E::config_toml),
      field(k::protocol, &E::protocol),
      field(k::trial_count, &E::trial_count),
      field(k::scene_hashes, &E::scene_hashes),
      field(k::stimuli, &E::stimuli),
      field(k::device, &E::device),
      field(k::display, &E::display),
      field(k::presenter, &E::presenter),
      field(k::gaze, &E::gaze),
      field(k::observer, &E::observer),
      field(k::started_utc, &E::started_utc),
      // Only when there are some: a header without them keeps the bytes earlier builds wrote.
      field(k::participant_fields, &E::participant_fields, Write::when_not_empty),
      field(k::conditions_csv, &E::conditions_csv, Write::when_not_empty),
      // Schema 7; absent from a header of an earlier schema, which then writes back its own bytes.
      field(k::gaze_source, &E::gaze_source, Write::when_not_null),
      field(k::gaze_validation, &E::gaze_validation, Write::when_not_null),
      // Schema 9; only when the session shows images (img-rmfr, ...).
      field(k::image_hashes, &E::image_hashes, Write::when_not_empty),
      // Schema 11; only in a headset session.
      field(k::headset, &E::headset, Write::when_not_null),
  };
}

constexpr auto fields(Of<SessionResumedEvent>) {
  using E = SessionResumedEvent;
  return std::tuple{
      field(k::next_trial, &E::next_trial),
      field(k::discarded_trial, &E::discarded_trial),
      field(k::torn_line_set_aside, &E::torn_line_set_aside),
      field(k::gaze, &E::gaze),
      field(k::started_utc, &E::started_utc),
      field(k::gaze_source, &E::gaze_source, Write::when_not_null),  // schema 7
  };
}

constexpr auto fields(Of<InstructionsEvent>) { return std::tuple{field(k::shown_s, &InstructionsEvent::shown_s)}; }

constexpr auto fields(Of<BlockStartEvent>) {
  using E = BlockStartEvent;
  return std::tuple{
      typed(k::block, &E::block),
      typed(k::name, &E::name),
      typed(k::scene, &E::scene),
  };
}

constexpr auto fields(Of<BreakEvent>) {
  using E = BreakEvent;
  return std::tuple{
      field(k::reason, &E::reason),
      typed(k::trial, &E::trial, Write::when_set),  // attention-check breaks
      field(k::start_s, &E::start_s),
      field(k::duration_s, &E::duration_s),
  };
}

constexpr auto fields(Of<TrialStartEvent>) {
  using E = TrialStartEvent;
  return std::tuple{
      typed(k::trial, &E::trial),
      typed(k::block, &E::block),
      typed(k::condition, &E::condition),
      typed(k::variant, &E::variant),
      typed(k::level, &E::level, Write::when_set),
      typed(k::attention_check, &E::attention_check),
      typed(k::sequence, &E::sequence),
      field(k::reference, &E::reference),
      typed(k::reference_first, &E::reference_first, Write::when_set),
      typed(k::ramp_toward_reference, &E::ramp_toward_reference, Write::when_set),
      field(k::slider_start, &E::slider_start, Write::when_set),
      typed(k::practice, &E::practice, Write::when_true),
      typed(k::track, &E::track, Write::when_set),
  };
}

constexpr auto fields(Of<InvalidGaze>) {
  return std::tuple{
      field(k::invalid_index, &InvalidGaze::index),
      field(k::reason, &InvalidGaze::reason),
  };
}

constexpr auto fields(Of<StimulusEvent>) {
  using E = StimulusEvent;
  return std::tuple{
      typed(k::trial, &E::trial), typed(k::step, &E::step), field(k::stimulus, &E::stimulus),
      field(k::onset_s, &E::onset_s), kept(k::present_s, &E::present_s),  // the scan's frame intervals
      field(k::frame, &E::frame), field(k::hash, &E::hash), field(k::gaze, &E::gaze),
      kept(k::invalid_gaze, &E::invalid_gaze), typed(k::dropped_frames, &E::dropped_frames),
      // Schema 3 (absent in older logs).
      typed<Read::when_given>(k::gaze_acquired_s, &E::gaze_acquired_s, Write::when_set),
      typed<Read::when_given>(k::gaze_age_s, &E::gaze_age_s, Write::when_set),
      typed<Read::when_given>(k::present_clock, &E::present_clock, Write::when_set),
      // Schema 11; only in a headset session.
      field(k::right_eye_hash, &E::right_eye_hash, Write::when_set),
      field(k::right_eye_gaze, &E::right_eye_gaze, Write::when_set),
      // Schema 13; only in a headset session, and only when the right eye held its gaze.
      kept(k::right_eye_invalid_gaze, &E::right_eye_invalid_gaze, Write::when_not_empty),
      // Schema 12 (head-tracked views); only in a head-tracked headset session.
      field(k::head_pose, &E::head_pose, Write::when_set),
      // Schema 12; only in a headset session whose runtime converts CLOCK_MONOTONIC to its XrTime.
      typed<Read::when_given>(k::late_frames, &E::late_frames, Write::when_set),  // the report's late frames
  };
}

constexpr auto fields(Of<ResponseEvent>) {
  using E = ResponseEvent;
  return std::tuple{
      typed(k::trial, &E::trial),
      typed(k::step, &E::step),
      typed(k::answer, &E::answer),
      field(k::key, &E::key),
      field(k::rt_s, &E::rt_s, Write::when_set),
  };
}

constexpr auto fields(Of<SliderSavedEvent>) {
  using E = SliderSavedEvent;
  return std::tuple{
      typed(k::trial, &E::trial),
      field(k::ladder_index, &E::ladder_index),
      field(k::stimulus, &E::stimulus),
      typed(k::level, &E::level, Write::when_set),
  };
}

constexpr auto fields(Of<AttentionCheckEvent>) {
  using E = AttentionCheckEvent;
  return std::tuple{
      typed(k::trial, &E::trial),
      typed(k::correct, &E::correct, Write::when_set),
      field(k::errors, &E::errors),
  };
}

constexpr auto fields(Of<TrialEndEvent>) { return std::tuple{typed(k::trial, &TrialEndEvent::trial)}; }

constexpr auto fields(Of<ExcludedEvent>) {
  return std::tuple{
      field(k::errors, &ExcludedEvent::errors),
      field(k::max_errors, &ExcludedEvent::max_errors),
  };
}

constexpr auto fields(Of<ValidationTarget>) {
  using E = ValidationTarget;
  return std::tuple{
      field(k::x_px, &E::x_px),
      field(k::y_px, &E::y_px),
      field(k::samples, &E::samples),
      field(k::valid_samples, &E::valid_samples),
      field(k::accuracy_deg, &E::accuracy_deg),
      field(k::precision_deg, &E::precision_deg),
      field(k::gaze, &E::gaze),
  };
}

constexpr auto fields(Of<TrackerValidationEvent>) {
  using E = TrackerValidationEvent;
  return std::tuple{
      field(k::reason, &E::reason),
      field(k::attempt, &E::attempt),
      field(k::start_s, &E::start_s),
      field(k::targets, &E::targets),
      field(k::accuracy_deg, &E::accuracy_deg),
      field(k::precision_deg, &E::precision_deg),
      field(k::max_accuracy_deg, &E::max_accuracy_deg),
      field(k::max_precision_deg, &E::max_precision_deg),
      field(k::passed, &E::passed),
      field(k::stopped, &E::stopped, Write::when_true),
  };
}

constexpr auto fields(Of<SessionPausedEvent>) { return std::tuple{field(k::reason, &SessionPausedEvent::reason)}; }

constexpr auto fields(Of<SessionEndEvent>) {
  return std::tuple{
      field(k::reason, &SessionEndEvent::reason),
      field(k::completed_trials, &SessionEndEvent::completed_trials),
  };
}

constexpr auto fields(Of<SealEvent>) {
  return std::tuple{
      field(k::trials_complete, &SealEvent::trials_complete),
      field(k::last_chain, &SealEvent::last_chain, Write::when_not_empty),  // set by EventLogWriter
  };
}

// Calls `visit(row)` for every row of Event's table, in order.
template <typename Event, typename Visit>
void for_each_field(Visit&& visit) {
  std::apply([&](const auto&... row) { (visit(row), ...); }, fields(Of<Event>{}));
}

// ---- the line types: how a typed (or kept) field's value is checked on every line ----

enum class LineType {
  small_int,  // a 32-bit integer
  string,
  boolean,
  number_or_null,
  small_int_array,       // an array of 32-bit integers
  number_or_null_array,  // an array of numbers or nulls
  numbers_lenient,       // Scan::kept: an array of numbers, anything else left at the default
  invalid_gaze_lenient,  // Scan::kept: an array of {i, reason} objects, anything else left at the default
};

template <typename T>
struct LineTypeOf {};  // no line type: a field of this type is never scanned (no `value`)
template <typename T>
struct LineTypeOf<std::optional<T>> : LineTypeOf<T> {};
template <>
struct LineTypeOf<int> : std::integral_constant<LineType, LineType::small_int> {};
template <>
struct LineTypeOf<std::string> : std::integral_constant<LineType, LineType::string> {};
template <>
struct LineTypeOf<bool> : std::integral_constant<LineType, LineType::boolean> {};
template <>
struct LineTypeOf<std::optional<double>> : std::integral_constant<LineType, LineType::number_or_null> {};
template <>
struct LineTypeOf<std::vector<int>> : std::integral_constant<LineType, LineType::small_int_array> {};
template <>
struct LineTypeOf<std::optional<std::vector<std::optional<double>>>>
    : std::integral_constant<LineType, LineType::number_or_null_array> {};

// The line type of a row the scan reads (Scan::typed: by its member's type; Scan::kept: a
// std::vector<double> or the invalid gaze marks), or nullopt for a member type no scanned row may have.
template <typename Row>
constexpr std::optional<LineType> line_type(const Row& row) {
  using Member = typename Row::MemberType;
  if (row.scan == Scan::kept) {
    if constexpr (std::is_same_v<Member, std::vector<double>>) return LineType::numbers_lenient;
    if constexpr (std::is_same_v<Member, std::vector<InvalidGaze>>) return LineType::invalid_gaze_lenient;
    return std::nullopt;
  }
  if constexpr (requires { LineTypeOf<Member>::value; }) return LineTypeOf<Member>::value;
  return std::nullopt;
}

// A key the fast scan reads: a typed key (of every line) or a kept one.
struct ScannedKey {
  std::string_view key;
  LineType type;
  Scan scan;  // typed or kept
};

// Every key that a row of some table marks typed or kept, once, in order of first appearance
// (the tables in LogEvent's order). Built at first use; throws std::logic_error there when two
// rows of one key disagree (another line type, or typed in one event and not in another), so a
// key's rule is the same on every line.
const std::vector<ScannedKey>& scanned_keys();
// The index of `key` in scanned_keys(), or -1.
int scanned_key_index(std::string_view key);

}  // namespace fovlab::log_fields
