#include "protocols/log/session_record.h"

#include <algorithm>
#include <map>

#include "core/input_error.h"

namespace fovlab {
namespace {

std::string text_of(const nlohmann::json& event, const char* key) {
  const auto found = event.find(key);
  return found != event.end() && found->is_string() ? found->get<std::string>() : std::string();
}

}  // namespace

namespace {
SessionRecord build_session_record(const EventLogFile& log);
}

SessionRecord read_session_record(const EventLogFile& log) {
  try {
    return build_session_record(log);
  } catch (const nlohmann::json::exception& error) {
    // A field of the wrong type (e.g. "correct": "yes"): the log was damaged or written by hand.
    throw InputError(log.path + ": an event has a field of the wrong type (" + error.what() + ")");
  }
}

namespace {

SessionRecord build_session_record(const EventLogFile& log) {
  const auto fail = [&](size_t event_index, const std::string& what) {
    const int line = event_index < log.line_numbers.size() ? log.line_numbers[event_index] : 1;
    throw InputError(log.path + ":" + std::to_string(line) + ": " + what);
  };
  if (log.events.empty()) fail(0, "the log has no complete event (expected a session_header first)");
  SessionRecord record;
  record.header = log.events.front();
  if (text_of(record.header, "event") != "session_header") fail(0, "expected a session_header event first");
  const auto schema = record.header.find("schema_version");
  if (schema == record.header.end() || !schema->is_number_integer())
    fail(0, "session_header: schema_version missing (expected " + std::to_string(log_schema_version) + ")");
  if (schema->get<int64_t>() != log_schema_version)
    fail(0, "session_header: schema_version " + schema->dump() + " is not one this fovlab reads (expected " +
                std::to_string(log_schema_version) + ")");

  std::map<int, RecordedTrial> complete;
  std::optional<RecordedTrial> open;
  for (size_t i = 1; i < log.events.size(); ++i) {
    const nlohmann::json& event = log.events[i];
    const std::string kind = text_of(event, "event");
    if (kind.empty()) fail(i, "event: missing (expected a string naming the event)");
    if (const auto t = event.find("t"); t != event.end() && t->is_number())
      record.last_time_s = std::max(record.last_time_s, t->get<double>());
    const auto trial_field = event.find("trial");
    const bool has_trial = trial_field != event.end() && trial_field->is_number_integer();
    if (kind == "trial_start") {
      if (!has_trial) fail(i, "trial_start: trial missing (expected the trial index)");
      open = RecordedTrial{};
      open->index = trial_field->get<int>();
      open->start = event;
      continue;
    }
    const bool in_trial = kind == "stimulus" || kind == "response" || kind == "attention_check" ||
                          kind == "slider_saved" || (kind == "break" && has_trial) || kind == "trial_end";
    if (!in_trial) {
      if (kind == "excluded") record.excluded = true;
      if (kind == "session_end") {
        record.ended = true;
        record.end_reason = text_of(event, "reason");
      }
      if (kind == "session_resumed") open.reset();  // a cut-off trial runs again after a resume
      continue;
    }
    if (!open || !has_trial || trial_field->get<int>() != open->index)
      fail(i, kind + ": trial does not match the trial started last");
    if (kind == "stimulus") open->stimuli.push_back(event);
    if (kind == "response") open->responses.push_back(event);
    if (kind == "attention_check") open->attention_check = event;
    if (kind == "slider_saved" || kind == "break") open->other.push_back(event);
    if (kind == "trial_end") {
      open->end = event;
      complete[open->index] = std::move(*open);
      open.reset();
    }
  }
  for (auto& [index, trial] : complete) {
    if (trial.attention_check && !trial.attention_check->value("correct", true)) ++record.attention_errors;
    record.trials.push_back(std::move(trial));
  }
  while (record.next_trial < static_cast<int>(complete.size() + 1) && complete.count(record.next_trial)) ++record.next_trial;
  if (open) record.incomplete_trial = open->index;
  return record;
}

}  // namespace

}  // namespace fovlab
