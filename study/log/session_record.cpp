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

namespace k = log_keys;

std::string text_of(const nlohmann::json& event, const char* key) {
  const auto found = event.find(key);
  return found != event.end() && found->is_string() ? found->get<std::string>() : std::string();
}

}  // namespace

namespace {
SessionRecord build_session_record(const EventLogFile& log, const LabKey* lab_key);
}

void check_session_header(const nlohmann::json& first_event, const std::string& path) {
  const auto fail = [&](const std::string& what) { throw InputError(path + ":1: " + what); };
  if (event_kind(first_event) != SessionHeaderEvent::kind) fail("expected a session_header event first");
  const auto schema = first_event.find(k::schema_version);
  if (schema == first_event.end() || !schema->is_number_integer())
    fail("session_header: schema_version missing (expected " + std::to_string(log_schema_version) + ")");
  if (schema->get<int64_t>() < oldest_log_schema_version || schema->get<int64_t>() > log_schema_version)
    fail("session_header: schema_version " + schema->dump() + " is not one this fovlab reads (expected " +
         std::to_string(oldest_log_schema_version) + " to " + std::to_string(log_schema_version) + ")");
  // Both name folders (results/<study>/<participant>) and analysis outputs: a header is as
  // untrusted as any file, so they obey the config's rules before any path is made from them.
  const std::string study = text_of(first_event, k::study);
  if (!is_valid_study_name(study))
    fail("session_header: study \"" + study.substr(0, 80) +
         "\" is not a study name (expected 1-64 letters, digits, '_', '-' or '.', not starting with '.' or '-')");
  try {
    check_participant_id(text_of(first_event, k::participant));
  } catch (const InputError& error) {
    fail(std::string("session_header: ") + error.what());
  }
}

bool is_trial_event(const std::string& kind, bool names_a_trial) {
  return kind == StimulusEvent::kind || kind == ResponseEvent::kind || kind == AttentionCheckEvent::kind ||
         kind == SliderSavedEvent::kind || (kind == BreakEvent::kind && names_a_trial) || kind == TrialEndEvent::kind;
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
    if (const std::string wrong = check_log_field_types(log.events[i]); !wrong.empty()) fail(i, wrong);
    const auto mac = log.events[i].find(k::mac);
    integrity.mac(text_of(log.events[i], k::chain),
                  mac != log.events[i].end() && mac->is_string() ? std::optional<std::string>(mac->get<std::string>())
                                                                 : std::nullopt,
                  log.line_numbers[i]);
  }

  TrialAssembly<RecordedTrial> trials;
  for (size_t i = 1; i < log.events.size(); ++i) {
    const nlohmann::json& event = log.events[i];
    const std::string kind = event_kind(event);
    if (kind.empty()) fail(i, "event: missing (expected a string naming the event)");
    if (kind == SealEvent::kind) {
      integrity.seal(event, log.line_numbers[i], text_of(log.events[i - 1], k::chain), trials.complete_count());
      continue;
    }
    integrity.event();
    if (const auto t = event.find(k::t); t != event.end() && t->is_number())
      record.last_time_s = std::max(record.last_time_s, t->get<double>());
    const auto trial_field = event.find(k::trial);
    const std::optional<int> trial_index = trial_field != event.end() && trial_field->is_number_integer()
                                               ? std::optional<int>(trial_field->get<int>())
                                               : std::nullopt;
    if (kind == TrialStartEvent::kind) {
      if (!trial_index) fail(i, "trial_start: trial missing (expected the trial index)");
      RecordedTrial trial;
      trial.index = *trial_index;
      trial.line = log.line_numbers[i];
      trial.start = parse_trial_start(event, FieldCheck::lenient);
      trials.start(std::move(trial));
      continue;
    }
    if (!is_trial_event(kind, trial_index.has_value())) {
      if (kind == ExcludedEvent::kind) record.excluded = true;
      if (kind == SessionEndEvent::kind) {
        record.ended = true;
        record.end_reason = parse_session_end(event, FieldCheck::lenient).reason;
        record.end_line = log.line_numbers[i];
      }
      if (kind == SessionResumedEvent::kind) {
        trials.resume();
        record.resumes.push_back(parse_session_resumed(event, FieldCheck::lenient));
      }
      if (kind == BlockStartEvent::kind) record.blocks.push_back(parse_block_start(event, FieldCheck::lenient));
      if (kind == TrackerValidationEvent::kind)
        record.validations.push_back(parse_tracker_validation(event, FieldCheck::lenient));
      continue;
    }
    RecordedTrial* open = trials.open_for(trial_index);
    if (!open) fail(i, kind + ": trial does not match the trial started last");
    if (kind == StimulusEvent::kind) open->stimuli.push_back(parse_stimulus(event, FieldCheck::lenient));
    if (kind == ResponseEvent::kind) open->responses.push_back(parse_response(event, FieldCheck::lenient));
    if (kind == AttentionCheckEvent::kind) open->attention_check = parse_attention_check(event, FieldCheck::lenient);
    if (kind == SliderSavedEvent::kind) open->slider_saved.push_back(parse_slider_saved(event, FieldCheck::lenient));
    if (kind == BreakEvent::kind) open->breaks.push_back(parse_break(event, FieldCheck::lenient));
    if (kind == TrialEndEvent::kind) {
      open->end = parse_trial_end(event, FieldCheck::lenient);
      if (!trials.end())
        fail(i,
             "trial_end: trial " + std::to_string(*trial_index) + " is complete twice in this log (forged or spliced)");
    }
  }
  record.incomplete_trial = trials.incomplete_index();
  record.integrity = integrity.finish(log.first_chain_error_line, log.torn_tail.has_value());
  record.trials = trials.take_complete();
  for (const RecordedTrial& trial : record.trials) {
    if (trial.attention_check && !trial.attention_check->correct.value_or(true)) ++record.attention_errors;
    if (trial.index == record.next_trial) ++record.next_trial;  // by index: the first without a record
  }
  return record;
}

}  // namespace

}  // namespace fovlab
