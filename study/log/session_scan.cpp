#include "study/log/session_scan.h"

#include <simdjson.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <memory>

#include "core/input_error.h"
#include "core/input_file.h"
#include "study/log/event_log.h"
#include "study/log/log_events.h"
#include "study/log/log_integrity.h"
#include "study/log/session_record.h"
#include "study/log/trial_assembly.h"

namespace fovlab {
namespace {

// The fields of one event the scan uses; everything else is skipped.
struct EventFields {
  std::string_view kind;
  std::optional<int64_t> seq;
  std::string_view chain;  // empty when absent or not a string (the chain then does not match)
  std::optional<std::string_view> mac;
  std::optional<int> trial;
  std::optional<int> block;
  std::optional<int> step;
  std::optional<int> track;
  std::string_view condition, variant, answer, name, scene;
  std::optional<double> level;
  std::optional<bool> attention_check, reference_first, ramp_toward_reference, correct, practice;
  std::vector<int> sequence;
  std::optional<int> dropped_frames;
  std::string_view present_clock;
  bool has_gaze_age = false;
  std::vector<double> gaze_age_s;  // the non-null entries
};

// An array of numbers or nulls (the per-refresh latency arrays), as check_field_types wants it;
// the numbers go to `out` when it is given. Any other element is a type error.
void number_or_null_array(simdjson::ondemand::value value, std::vector<double>* out) {
  for (auto element : value.get_array()) {
    simdjson::ondemand::value item = element.value();
    if (item.is_null()) continue;
    const double number = item.get_double();
    if (out) out->push_back(number);
  }
}

int small_int(simdjson::ondemand::value value) {
  const int64_t number = value.get_int64();
  if (number < INT32_MIN || number > INT32_MAX) throw simdjson::simdjson_error(simdjson::NUMBER_OUT_OF_RANGE);
  return static_cast<int>(number);
}

EventFields decode(simdjson::ondemand::document& document) {
  EventFields fields;
  if (document.type() != simdjson::ondemand::json_type::object) throw simdjson::simdjson_error(simdjson::TAPE_ERROR);
  simdjson::ondemand::object object = document.get_object();
  for (auto field : object) {
    const std::string_view key = field.unescaped_key();
    simdjson::ondemand::value value = field.value();
    if (key == log_keys::event) fields.kind = value.get_string();
    else if (key == log_keys::seq) {
      int64_t seq = 0;  // not an integer: left out, so the chain check fails at this line
      if (value.get_int64().get(seq) == simdjson::SUCCESS) fields.seq = seq;
    } else if (key == log_keys::chain) {
      std::string_view chain;
      if (value.get_string().get(chain) == simdjson::SUCCESS) fields.chain = chain;
    } else if (key == log_keys::mac) {
      std::string_view mac;
      if (value.get_string().get(mac) == simdjson::SUCCESS) fields.mac = mac;
    }
    else if (key == log_keys::trial) fields.trial = small_int(value);
    else if (key == log_keys::block) fields.block = small_int(value);
    else if (key == log_keys::step) fields.step = small_int(value);
    else if (key == log_keys::track) fields.track = small_int(value);
    else if (key == log_keys::condition) fields.condition = value.get_string();
    else if (key == log_keys::variant) fields.variant = value.get_string();
    else if (key == log_keys::answer) fields.answer = value.get_string();
    else if (key == log_keys::name) fields.name = value.get_string();
    else if (key == log_keys::scene) fields.scene = value.get_string();
    else if (key == log_keys::level) {
      if (!value.is_null()) fields.level = value.get_double();
    } else if (key == log_keys::attention_check) fields.attention_check = value.get_bool();
    else if (key == log_keys::reference_first) fields.reference_first = value.get_bool();
    else if (key == log_keys::ramp_toward_reference) fields.ramp_toward_reference = value.get_bool();
    else if (key == log_keys::correct) fields.correct = value.get_bool();
    else if (key == log_keys::practice) fields.practice = value.get_bool();
    else if (key == log_keys::sequence) {
      for (auto id : value.get_array()) fields.sequence.push_back(small_int(id.value()));
    }
    else if (key == log_keys::dropped_frames) fields.dropped_frames = small_int(value);
    else if (key == log_keys::present_clock) fields.present_clock = value.get_string();
    else if (key == log_keys::gaze_acquired_s) number_or_null_array(value, nullptr);
    else if (key == log_keys::gaze_age_s) {
      fields.has_gaze_age = true;
      number_or_null_array(value, &fields.gaze_age_s);
    }
  }
  // Anything after the object is not looked for here: such a line is not the writer's canonical
  // text, so its chain does not match and the log counts as edited.
  return fields;
}

// The chain of a line as the writer computed it: a hash of the previous chain and the event's text
// without its "chain" member (event_chain). Fast path: cut the member out of the line itself (the
// writer's text is canonical); when that does not reproduce the recorded chain (a line re-formatted
// by hand, say), the canonical text is rebuilt with nlohmann::json, exactly as read_event_log does
// (after the same nesting guard). `scratch` is reused between lines.
// `text` without its member `"name":"<digits hex characters>"` (and the comma joining it), or false
// when there is none of that shape.
bool cut_member(std::string_view text, std::string_view name, size_t digits, std::string& out) {
  const std::string member = "\"" + std::string(name) + "\":\"";
  const size_t at = text.find(member);
  if (at == std::string_view::npos || at + member.size() + digits + 1 > text.size()) return false;
  size_t begin = at, end = at + member.size() + digits + 1;  // the hex digits and the closing quote
  if (begin > 0 && text[begin - 1] == ',') --begin;
  else if (end < text.size() && text[end] == ',') ++end;
  out.assign(text.substr(0, begin)).append(text.substr(end));
  return true;
}

std::string line_chain(const std::string& previous, std::string_view line, bool has_mac, std::string& scratch,
                       std::string& scratch_mac, int schema_version) {
  const size_t digits = schema_version == 1 ? 16 : 64;
  if (cut_member(line, log_keys::chain, digits, scratch) && (!has_mac || cut_member(scratch, log_keys::mac, 64, scratch_mac))) {
    const std::string fast = chain_of_text(previous, has_mac ? scratch_mac : scratch, schema_version);
    const std::string member = "\"" + std::string(log_keys::chain) + "\":\"";
    const size_t at = line.find(member) + member.size();
    if (line.substr(at, digits) == fast) return fast;
  }
  if (json_nesting_depth(line) > max_event_nesting) return {};
  nlohmann::json event = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
  if (event.is_discarded() || !event.is_object()) return {};
  event.erase(log_keys::chain);
  event.erase(log_keys::mac);
  return event_chain(previous, event, schema_version);
}

// A whole event as nlohmann::json (the header, a seal: a few lines a log), after the nesting guard.
nlohmann::json parse_whole_event(std::string_view line) {
  if (json_nesting_depth(line) > max_event_nesting) return nlohmann::json(nlohmann::json::value_t::discarded);
  return nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
}

}  // namespace

namespace {

// The scan of `size` bytes at `data`, which stay readable up to size + SIMDJSON_PADDING.
ScannedSession scan_padded(const char* data, size_t size, const std::string& path, const LabKey* lab_key);

}  // namespace

ScannedSession scan_session_log(const std::string& path, const LabKey* lab_key) {
  // simdjson reads up to SIMDJSON_PADDING bytes past a document: every line is followed by the
  // rest of the file, and the file by the padding. The buffer is kept by the thread and reused, so
  // a scan of many logs neither clears nor faults in fresh memory for each.
  const int file = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);  // a FIFO must not block
  if (file < 0) throw InputError(path + ": cannot open the session log (" + std::string(std::strerror(errno)) + ")");
  thread_local std::unique_ptr<char[]> buffer;
  thread_local size_t buffer_capacity = 0;
  size_t size = 0;
  const auto ensure_capacity = [&](size_t needed) {
    if (needed <= buffer_capacity) return;
    std::unique_ptr<char[]> larger(new char[needed]);
    if (size) std::memcpy(larger.get(), buffer.get(), size);
    buffer = std::move(larger);
    buffer_capacity = needed;
  };
  uint64_t file_size = 0;
  try {
    file_size = check_input_file(file, path, session_log_kind, max_log_bytes);
  } catch (...) {
    ::close(file);
    throw;
  }
  // The size is where to start (+1 to see the end without growing); the file may still grow.
  ensure_capacity(static_cast<size_t>(file_size) + 1 + simdjson::SIMDJSON_PADDING);
  for (;;) {
    if (size > max_log_bytes) {
      ::close(file);
      throw_too_large(path, session_log_kind, max_log_bytes, "it grew while it was read");
    }
    if (size + simdjson::SIMDJSON_PADDING == buffer_capacity) ensure_capacity(2 * buffer_capacity);
    const ssize_t got = ::read(file, buffer.get() + size, buffer_capacity - simdjson::SIMDJSON_PADDING - size);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) {
      const std::string reason = std::strerror(errno);
      ::close(file);
      throw InputError(path + ": cannot read the session log (" + reason + ")");
    }
    if (got == 0) break;
    size += static_cast<size_t>(got);
  }
  ::close(file);
  return scan_padded(buffer.get(), size, path, lab_key);
}

ScannedSession scan_session_bytes(const std::string& bytes, const std::string& path_for_messages, const LabKey* lab_key) {
  std::string padded;
  padded.reserve(bytes.size() + simdjson::SIMDJSON_PADDING);
  padded = bytes;
  padded.append(simdjson::SIMDJSON_PADDING, ' ');
  return scan_padded(padded.data(), bytes.size(), path_for_messages, lab_key);
}

namespace {

ScannedSession scan_padded(const char* data, size_t size, const std::string& path, const LabKey* lab_key) {
  const size_t last_newline = std::string_view(data, size).rfind('\n');
  const size_t intact = last_newline == std::string_view::npos ? 0 : last_newline + 1;
  const size_t readable = size + simdjson::SIMDJSON_PADDING;
  ScannedSession session;
  session.path = path;
  session.torn_tail_bytes = size - intact;
  simdjson::ondemand::parser parser;
  std::string scratch, scratch_mac;

  TrialAssembly<ScannedTrial> trials;
  IntegrityTracker integrity(lab_key);
  int schema_version = 0;
  std::string chain;
  int line_number = 0;
  size_t begin = byte_order_mark_length(std::string_view(data, intact));
  while (begin < intact) {
    const size_t end = std::string_view(data, intact).find('\n', begin);
    const std::string_view line(data + begin, end - begin);
    ++line_number;
    const auto fail = [&](const std::string& what) {
      throw InputError(path + ":" + std::to_string(line_number) + ": " + what);
    };
    EventFields fields;
    try {
      simdjson::ondemand::document document = parser.iterate(line, readable - begin);
      fields = decode(document);
    } catch (const simdjson::simdjson_error& error) {
      const bool wrong_type = error.error() == simdjson::INCORRECT_TYPE || error.error() == simdjson::NUMBER_OUT_OF_RANGE;
      fail(wrong_type ? std::string("an event has a field of the wrong type (") + error.what() + ")"
                      : std::string("not a JSON event (expected one JSON object a line)"));
    }
    begin = end + 1;

    if (line_number == 1) {
      session.header = parse_whole_event(line);
      if (session.header.is_discarded()) fail("not a JSON event (expected one JSON object a line)");
      check_session_header(session.header, path);
      schema_version = session.header[log_keys::schema_version].get<int>();
      integrity.header(session.header, path);
    }
    const std::string previous_chain = chain;
    if (!session.first_chain_error_line) {
      bool consistent = fields.seq && *fields.seq == line_number - 1 && fields.chain.size() == (schema_version == 1 ? 16u : 64u);
      if (consistent) {
        const std::string expected = line_chain(chain, line, fields.mac.has_value(), scratch, scratch_mac, schema_version);
        consistent = expected == fields.chain;
        chain = expected;
      }
      if (!consistent) session.first_chain_error_line = line_number;
    }
    integrity.mac(std::string(fields.chain), fields.mac ? std::optional<std::string>(*fields.mac) : std::nullopt, line_number);
    if (line_number == 1) continue;
    if (fields.kind.empty()) fail("event: missing (expected a string naming the event)");
    const std::string kind(fields.kind);
    if (kind == SealEvent::kind) {
      const nlohmann::json seal = parse_whole_event(line);
      if (seal.is_discarded()) fail("not a JSON event (expected one JSON object a line)");
      integrity.seal(seal, line_number, previous_chain, trials.complete_count());
      continue;
    }
    integrity.event();
    if (kind == BlockStartEvent::kind) {
      session.block_names[fields.block.value_or(0)] = std::string(fields.name.empty() ? fields.scene : fields.name);
      continue;
    }
    if (kind == TrialStartEvent::kind) {
      if (!fields.trial) fail("trial_start: trial missing (expected the trial index)");
      ScannedTrial trial;
      trial.index = *fields.trial;
      trial.block = fields.block.value_or(0);
      trial.condition = fields.condition;
      trial.variant = fields.variant;
      trial.level = fields.level;
      trial.attention_check = fields.attention_check.value_or(false);
      trial.reference_first = fields.reference_first.value_or(true);
      trial.ramp_toward_reference = fields.ramp_toward_reference.value_or(true);
      trial.practice = fields.practice.value_or(false);
      trial.track = fields.track;
      trial.sequence = std::move(fields.sequence);
      trials.start(std::move(trial));
      continue;
    }
    if (!is_trial_event(kind, fields.trial.has_value())) {
      if (kind == TrackerValidationEvent::kind) {  // rare: read whole
        const nlohmann::json event = parse_whole_event(line);
        if (event.is_discarded()) fail("not a JSON event (expected one JSON object a line)");
        session.validations.push_back(parse_tracker_validation(event, FieldCheck::lenient));
      }
      if (kind == ExcludedEvent::kind) session.excluded = true;
      if (kind == SessionEndEvent::kind) session.ended = true;
      if (kind == SessionResumedEvent::kind) trials.resume();
      continue;
    }
    ScannedTrial* open = trials.open_for(fields.trial);
    if (!open) fail(kind + ": trial does not match the trial started last");
    if (kind == StimulusEvent::kind) {
      open->dropped_frames += fields.dropped_frames.value_or(0);
      if (fields.has_gaze_age) {
        ++open->stimuli_with_latency;
        open->gaze_age_s.insert(open->gaze_age_s.end(), fields.gaze_age_s.begin(), fields.gaze_age_s.end());
      }
      if (!fields.present_clock.empty() &&
          std::find(session.present_clocks.begin(), session.present_clocks.end(), fields.present_clock) ==
              session.present_clocks.end())
        session.present_clocks.emplace_back(fields.present_clock);
    }
    if (kind == ResponseEvent::kind) {
      open->answers.emplace_back(fields.answer);
      open->answer_steps.push_back(fields.step.value_or(0));
    }
    if (kind == SliderSavedEvent::kind) open->saved_level = fields.level;
    if (kind == AttentionCheckEvent::kind) open->attention_correct = fields.correct.value_or(true);
    if (kind == TrialEndEvent::kind && !trials.end())
      fail("trial_end: trial " + std::to_string(*fields.trial) + " is complete twice in this log (forged or spliced)");
  }
  if (line_number == 0) throw InputError(path + ":1: the log has no complete event (expected a session_header first)");
  session.incomplete_trial = trials.incomplete_index();
  session.integrity = integrity.finish(session.first_chain_error_line, session.torn_tail_bytes > 0);
  session.trials = trials.take_complete();
  for (const ScannedTrial& trial : session.trials)
    if (trial.attention_correct && !*trial.attention_correct) ++session.attention_errors;
  return session;
}

}  // namespace

}  // namespace fovlab
