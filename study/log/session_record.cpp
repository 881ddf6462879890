#include "study/log/session_record.h"

#include <algorithm>
#include <cstdint>
#include <map>

#include "core/input_error.h"
#include "study/config/study_config.h"
#include "study/schedule/study_plan.h"
#include "study/log/trial_assembly.h"

namespace fovlab {
namespace {

std::string text_of(const nlohmann::json& event, const char* key) {
  const auto found = event.find(key);
  return found != event.end() && found->is_string() ? found->get<std::string>() : std::string();
}

// The types of the fields a trial summary reads, in every event, as the fast scan's decoder
// (session_scan.cpp) enforces them, so that both readers accept and refuse the same logs: a trial,
// block or step is a 32-bit integer, names and answers are strings, a level a number or null, the
// flags booleans, a sequence an array of 32-bit integers; of stimulus events (schema 3) the
// latency fields: gaze_acquired_s and gaze_age_s arrays of numbers or nulls, present_clock a string,
// dropped_frames a 32-bit integer. `fail` throws.
template <typename Fail>
void check_field_types(const nlohmann::json& event, const Fail& fail) {
  const auto small_int = [](const nlohmann::json& value) {
    return value.is_number_integer() && value.get<int64_t>() >= INT32_MIN && value.get<int64_t>() <= INT32_MAX;
  };
  for (const auto& [key, value] : event.items()) {
    bool ok = true;
    if (key == "trial" || key == "block" || key == "step") ok = small_int(value);
    else if (key == "event" || key == "condition" || key == "variant" || key == "answer" || key == "name" || key == "scene")
      ok = value.is_string();
    else if (key == "level") ok = value.is_number() || value.is_null();
    else if (key == "attention_check" || key == "reference_first" || key == "ramp_toward_reference" || key == "correct")
      ok = value.is_boolean();
    else if (key == "sequence") ok = value.is_array() && std::all_of(value.begin(), value.end(), small_int);
    else if (key == "dropped_frames") ok = small_int(value);
    else if (key == "present_clock") ok = value.is_string();
    else if (key == "gaze_acquired_s" || key == "gaze_age_s")
      ok = value.is_array() && std::all_of(value.begin(), value.end(), [](const nlohmann::json& element) {
             return element.is_number() || element.is_null();
           });
    if (!ok) fail("an event has a field of the wrong type (" + key + ": " + value.dump().substr(0, 40) + ")");
  }
}

}  // namespace

namespace {
SessionRecord build_session_record(const EventLogFile& log, const LabKey* lab_key);
}

void check_session_header(const nlohmann::json& first_event, const std::string& path) {
  const auto fail = [&](const std::string& what) { throw InputError(path + ":1: " + what); };
  if (text_of(first_event, "event") != "session_header") fail("expected a session_header event first");
  const auto schema = first_event.find("schema_version");
  if (schema == first_event.end() || !schema->is_number_integer())
    fail("session_header: schema_version missing (expected " + std::to_string(log_schema_version) + ")");
  if (schema->get<int64_t>() < oldest_log_schema_version || schema->get<int64_t>() > log_schema_version)
    fail("session_header: schema_version " + schema->dump() + " is not one this fovlab reads (expected " +
         std::to_string(oldest_log_schema_version) + " to " + std::to_string(log_schema_version) + ")");
  // Both name folders (results/<study>/<participant>) and analysis outputs: a header is as
  // untrusted as any file, so they obey the config's rules before any path is made from them.
  const std::string study = text_of(first_event, "study");
  if (!is_valid_study_name(study))
    fail("session_header: study \"" + study.substr(0, 80) + "\" is not a study name (expected 1-64 letters, digits, '_', '-' or '.', not starting with '.' or '-')");
  try {
    check_participant_id(text_of(first_event, "participant"));
  } catch (const InputError& error) {
    fail(std::string("session_header: ") + error.what());
  }
}

bool is_trial_event(const std::string& kind, bool names_a_trial) {
  return kind == "stimulus" || kind == "response" || kind == "attention_check" || kind == "slider_saved" ||
         (kind == "break" && names_a_trial) || kind == "trial_end";
}

SessionRecord read_session_record(const EventLogFile& log, const LabKey* lab_key) {
  try {
    return build_session_record(log, lab_key);
  } catch (const nlohmann::json::exception& error) {
    // A field of the wrong type (e.g. "correct": "yes"): the log was damaged or written by hand.
    throw InputError(log.path + ": an event has a field of the wrong type (" + error.what() + ")");
  }
}

namespace {

SessionRecord build_session_record(const EventLogFile& log, const LabKey* lab_key) {
  const auto fail = [&](size_t event_index, const std::string& what) {
    const int line = event_index < log.line_numbers.size() ? log.line_numbers[event_index] : 1;
    throw InputError(log.path + ":" + std::to_string(line) + ": " + what);
  };
  if (log.events.empty()) fail(0, "the log has no complete event (expected a session_header first)");
  SessionRecord record;
  record.header = log.events.front();
  check_session_header(record.header, log.path);
  IntegrityTracker integrity(lab_key);
  integrity.header(record.header, log.path);
  for (size_t i = 0; i < log.events.size(); ++i) {
    check_field_types(log.events[i], [&](const std::string& what) { fail(i, what); });
    const auto mac = log.events[i].find("mac");
    integrity.mac(text_of(log.events[i], "chain"),
                  mac != log.events[i].end() && mac->is_string() ? std::optional<std::string>(mac->get<std::string>()) : std::nullopt,
                  log.line_numbers[i]);
  }

  TrialAssembly<RecordedTrial> trials;
  for (size_t i = 1; i < log.events.size(); ++i) {
    const nlohmann::json& event = log.events[i];
    const std::string kind = text_of(event, "event");
    if (kind.empty()) fail(i, "event: missing (expected a string naming the event)");
    if (kind == "seal") {
      integrity.seal(event, log.line_numbers[i], text_of(log.events[i - 1], "chain"), trials.complete_count());
      continue;
    }
    integrity.event();
    if (const auto t = event.find("t"); t != event.end() && t->is_number())
      record.last_time_s = std::max(record.last_time_s, t->get<double>());
    const auto trial_field = event.find("trial");
    const std::optional<int> trial_index =
        trial_field != event.end() && trial_field->is_number_integer() ? std::optional<int>(trial_field->get<int>()) : std::nullopt;
    if (kind == "trial_start") {
      if (!trial_index) fail(i, "trial_start: trial missing (expected the trial index)");
      RecordedTrial trial;
      trial.index = *trial_index;
      trial.start = event;
      trials.start(std::move(trial));
      continue;
    }
    if (!is_trial_event(kind, trial_index.has_value())) {
      if (kind == "excluded") record.excluded = true;
      if (kind == "session_end") {
        record.ended = true;
        record.end_reason = text_of(event, "reason");
      }
      if (kind == "session_resumed") trials.resume();
      continue;
    }
    RecordedTrial* open = trials.open_for(trial_index);
    if (!open) fail(i, kind + ": trial does not match the trial started last");
    if (kind == "stimulus") open->stimuli.push_back(event);
    if (kind == "response") open->responses.push_back(event);
    if (kind == "attention_check") open->attention_check = event;
    if (kind == "slider_saved" || kind == "break") open->other.push_back(event);
    if (kind == "trial_end") {
      open->end = event;
      if (!trials.end()) fail(i, "trial_end: trial " + std::to_string(*trial_index) + " is complete twice in this log (forged or spliced)");
    }
  }
  record.incomplete_trial = trials.incomplete_index();
  record.integrity = integrity.finish(log.first_chain_error_line, log.torn_tail.has_value());
  record.trials = trials.take_complete();
  for (const RecordedTrial& trial : record.trials) {
    if (trial.attention_check && !trial.attention_check->value("correct", true)) ++record.attention_errors;
    if (trial.index == record.next_trial) ++record.next_trial;  // by index: the first without a record
  }
  return record;
}

}  // namespace

}  // namespace fovlab
