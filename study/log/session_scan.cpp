#include "study/log/session_scan.h"

#include <simdjson.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <memory>
#include <stdexcept>

#include "core/input_error.h"
#include "core/input_file.h"
#include "study/log/event_log.h"
#include "study/log/log_event_fields.h"
#include "study/log/log_events.h"
#include "study/log/log_integrity.h"
#include "study/log/log_lines.h"
#include "study/log/session_record.h"
#include "study/log/trial_assembly.h"

namespace fovlab {
namespace {

namespace lf = log_fields;

// A value the scan read of a key of log_fields::scanned_keys(), as its line type gives it.
struct LineValue {
  bool present = false;
  int integer = 0;                             // small_int
  bool boolean = false;                        // boolean
  std::optional<double> number;                // number_or_null
  std::string_view text;                       // string
  std::vector<int> integers;                   // small_int_array
  std::vector<std::optional<double>> numbers;  // number_or_null_array
  std::vector<double> doubles;                 // numbers_lenient
  std::vector<InvalidGaze> invalid_gaze;       // invalid_gaze_lenient
};

// What the scan reads of one event: the envelope, and the value of every scanned key (by its
// index in log_fields::scanned_keys()); every other value is only checked (LogLines::check_value).
struct EventFields {
  std::string_view kind;
  std::optional<int64_t> seq;
  std::optional<std::string_view> chain;
  std::optional<std::string_view> mac;
  std::optional<int> trial;  // the trial it names (is_trial_event, TrialAssembly)
  std::vector<LineValue> values;
};

// An array of numbers or nulls (the per-refresh latency arrays), as check_field_types wants it.
// Any other element is a type error.
void number_or_null_array(simdjson::ondemand::value value, std::vector<std::optional<double>>& out) {
  for (auto element : value.get_array()) {
    simdjson::ondemand::value item = element.value();
    if (item.is_null()) out.push_back(std::nullopt);
    else out.push_back(double(item.get_double()));
  }
}

// A stimulus event's present_s, which the full reader reads leniently (a value of another type is
// left at its default there, not refused): the numbers go to `out` when every entry is one; any
// other value is only checked, as `lines` checks every value it does not keep.
void present_times(LogLines& lines, simdjson::ondemand::value value, std::vector<double>& out) {
  simdjson::ondemand::json_type type;
  if (value.type().get(type) != simdjson::SUCCESS || type != simdjson::ondemand::json_type::array) {
    lines.check_value(value, 2);
    return;
  }
  bool numbers = true;
  for (auto element : value.get_array()) {
    simdjson::ondemand::value item = element.value();
    double number = 0.0;
    if (numbers && item.type().get(type) == simdjson::SUCCESS && type == simdjson::ondemand::json_type::number &&
        item.get_double().get(number) == simdjson::SUCCESS) {
      out.push_back(number);
      continue;
    }
    numbers = false;
    lines.check_value(item, 3);
  }
  if (!numbers) out.clear();
}

// A stimulus event's invalid_gaze, which the full reader reads leniently: kept only when every
// entry is an object with a 32-bit integer "i" and a string "reason" (the last of a key given twice
// counts, as in the full reader); otherwise left empty, and every value only checked.
void invalid_gaze_marks(LogLines& lines, simdjson::ondemand::value value, std::vector<InvalidGaze>& out) {
  simdjson::ondemand::json_type type;
  if (value.type().get(type) != simdjson::SUCCESS || type != simdjson::ondemand::json_type::array) {
    lines.check_value(value, 2);
    return;
  }
  bool marks = true;
  for (auto element : value.get_array()) {
    simdjson::ondemand::value item = element.value();
    if (!marks || item.type().get(type) != simdjson::SUCCESS || type != simdjson::ondemand::json_type::object) {
      marks = false;
      lines.check_value(item, 3);
      continue;
    }
    std::optional<int64_t> index;  // the last "i" given, when a 64-bit integer
    std::optional<std::string_view> reason;
    for (auto field : item.get_object()) {
      const std::string_view key = field.unescaped_key();
      simdjson::ondemand::value member = field.value();
      int64_t number = 0;
      std::string_view text;
      if (key == log_keys::invalid_index) {
        index.reset();
        if (member.get_int64().get(number) == simdjson::SUCCESS) index = number;
        else lines.check_value(member, 4);
      } else if (key == log_keys::reason) {
        reason.reset();
        if (member.get_string().get(text) == simdjson::SUCCESS) reason = text;
        else lines.check_value(member, 4);
      } else {
        lines.check_value(member, 4);
      }
    }
    if (!index || *index < INT32_MIN || *index > INT32_MAX || !reason) {
      marks = false;
      continue;
    }
    out.push_back({static_cast<int>(*index), std::string(*reason)});
  }
  if (!marks) out.clear();
}

int small_int(simdjson::ondemand::value value) {
  const int64_t number = value.get_int64();
  if (number < INT32_MIN || number > INT32_MAX) throw simdjson::simdjson_error(simdjson::NUMBER_OUT_OF_RANGE);
  return static_cast<int>(number);
}

// One value of a scanned key, read with the type its line type requires (a wrong one throws
// simdjson's INCORRECT_TYPE or NUMBER_OUT_OF_RANGE, as check_log_field_types refuses it).
void read_value(LogLines& lines, simdjson::ondemand::value value, lf::LineType type, LineValue& out) {
  // A key's slot is always read as its one line type, so only that type's member is set (a key
  // given twice: the last counts, as in LogLines::whole_event).
  out.present = true;
  switch (type) {
    case lf::LineType::small_int:
      out.integer = small_int(value);
      break;
    case lf::LineType::string:
      out.text = value.get_string();
      break;
    case lf::LineType::boolean:
      out.boolean = value.get_bool();
      break;
    case lf::LineType::number_or_null:
      out.number.reset();
      if (!value.is_null()) out.number = double(value.get_double());
      break;
    case lf::LineType::small_int_array:
      out.integers.clear();
      for (auto id : value.get_array()) out.integers.push_back(small_int(id.value()));
      break;
    case lf::LineType::number_or_null_array:
      out.numbers.clear();
      number_or_null_array(value, out.numbers);
      break;
    case lf::LineType::numbers_lenient:
      out.doubles.clear();
      present_times(lines, value, out.doubles);
      break;
    case lf::LineType::invalid_gaze_lenient:
      out.invalid_gaze.clear();
      invalid_gaze_marks(lines, value, out.invalid_gaze);
      break;
  }
}

// Reads the line's envelope and every scanned key (log_fields::scanned_keys(): the typed ones
// with the types check_log_field_types requires); every other value checked by `lines`, so the
// line is refused exactly when the full reader refuses it.
void decode(LogLines& lines, EventFields& fields) {
  static const int trial_index = lf::scanned_key_index(log_keys::trial);
  const std::vector<lf::ScannedKey>& scanned = lf::scanned_keys();
  fields.kind = {};
  fields.seq.reset();
  fields.chain.reset();
  fields.mac.reset();
  fields.trial.reset();
  fields.values.resize(scanned.size());
  for (LineValue& value : fields.values) value.present = false;
  for (auto field : lines.object()) {
    const std::string_view key = field.unescaped_key();
    simdjson::ondemand::value value = field.value();
    if (key == log_keys::event) {
      fields.kind = value.get_string();
    } else if (key == log_keys::seq) {
      int64_t seq = 0;  // not an integer: left out, so the chain check fails at this line
      if (value.get_int64().get(seq) == simdjson::SUCCESS) fields.seq = seq;
      else lines.check_value(value, 2);
    } else if (key == log_keys::chain || key == log_keys::mac) {
      std::string_view text;  // not a string: left out (the chain, or the MAC, then does not hold)
      if (value.get_string().get(text) == simdjson::SUCCESS)
        (key == log_keys::chain ? fields.chain : fields.mac) = text;
      else lines.check_value(value, 2);
    } else if (const int index = lf::scanned_key_index(key); index >= 0) {
      read_value(lines, value, scanned[index].type, fields.values[index]);
    } else {
      lines.check_value(value, 2);
    }
  }
  lines.expect_end();
  if (fields.values[trial_index].present) fields.trial = fields.values[trial_index].integer;
}

// A scanned value into a member of the type its table row gives it (the arrays moved out).
void assign(int& out, LineValue& value) { out = value.integer; }
void assign(std::optional<int>& out, LineValue& value) { out = value.integer; }
void assign(bool& out, LineValue& value) { out = value.boolean; }
void assign(std::optional<bool>& out, LineValue& value) { out = value.boolean; }
void assign(std::optional<double>& out, LineValue& value) { out = value.number; }
void assign(std::string& out, LineValue& value) { out = value.text; }
void assign(std::optional<std::string>& out, LineValue& value) { out = std::string(value.text); }
void assign(std::vector<int>& out, LineValue& value) { out = std::move(value.integers); }
void assign(std::vector<double>& out, LineValue& value) { out = std::move(value.doubles); }
void assign(std::vector<InvalidGaze>& out, LineValue& value) { out = std::move(value.invalid_gaze); }
void assign(std::optional<std::vector<std::optional<double>>>& out, LineValue& value) {
  out = std::move(value.numbers);
}

// The event of the line as the scan reads it: the fields its table marks typed or kept (the
// others at their defaults), as the full reader's parse_* gives them. Once a line: it moves the
// line's arrays out.
template <typename Event>
Event scanned_event(EventFields& fields) {
  static const std::vector<int> indices = [] {  // each row's scanned key (-1: not scanned)
    std::vector<int> found;
    lf::for_each_field<Event>(
        [&](const auto& row) { found.push_back(row.scan == lf::Scan::no ? -1 : lf::scanned_key_index(row.key)); });
    return found;
  }();
  Event event;
  size_t row_number = 0;
  lf::for_each_field<Event>([&](const auto& row) {
    const int index = indices[row_number++];
    if constexpr (requires(LineValue & value) { assign(event.*row.member, value); }) {
      if (index >= 0 && fields.values[index].present) assign(event.*row.member, fields.values[index]);
    } else {
      if (index >= 0) throw std::logic_error(std::string("session_scan: no reading for the scanned field ") + row.key);
    }
  });
  return event;
}

}  // namespace

namespace {

// The scan of `size` bytes at `data`, which stay readable up to size + SIMDJSON_PADDING; the
// chain of every line up to the first that breaks it goes to `line_chains` when given.
ScannedSession scan_padded(const char* data, size_t size, const std::string& path, const LabKey* lab_key,
                           std::vector<std::string>* line_chains = nullptr);

// The log at `path`, read into a buffer of this thread (reused by its next call) followed by
// SIMDJSON_PADDING readable bytes; returns the buffer and the log's size.
std::pair<const char*, size_t> read_padded(const std::string& path) {
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
  return {buffer.get(), size};
}

}  // namespace

ScannedSession scan_session_log(const std::string& path, const LabKey* lab_key) {
  const auto [data, size] = read_padded(path);
  return scan_padded(data, size, path, lab_key);
}

std::vector<std::string> scan_line_chains(const std::string& path) {
  const auto [data, size] = read_padded(path);
  std::vector<std::string> chains;
  scan_padded(data, size, path, nullptr, &chains);
  return chains;
}

ScannedSession scan_session_bytes(const std::string& bytes, const std::string& path_for_messages,
                                  const LabKey* lab_key) {
  std::string padded;
  padded.reserve(bytes.size() + simdjson::SIMDJSON_PADDING);
  padded = bytes;
  padded.append(simdjson::SIMDJSON_PADDING, ' ');
  return scan_padded(padded.data(), bytes.size(), path_for_messages, lab_key);
}

namespace {

ScannedSession scan_padded(const char* data, size_t size, const std::string& path, const LabKey* lab_key,
                           std::vector<std::string>* line_chains) {
  LogLines lines(data, size, size + simdjson::SIMDJSON_PADDING, path);
  ScannedSession session;
  session.path = path;
  session.torn_tail_bytes = lines.torn_tail_bytes();

  TrialAssembly<ScannedTrial> trials;
  IntegrityTracker integrity(lab_key);
  EventChain chain;
  int schema_version = 0;
  std::string previous_chain;
  EventFields fields;  // reused line after line (its arrays keep their memory)
  while (lines.next()) {
    const int line_number = lines.number();
    const auto fail = [&](const std::string& what) { lines.fail(what); };
    try {
      decode(lines, fields);
    } catch (const simdjson::simdjson_error& error) {
      const bool wrong_type =
          error.error() == simdjson::INCORRECT_TYPE || error.error() == simdjson::NUMBER_OUT_OF_RANGE;
      if (!wrong_type) lines.not_an_event();
      fail(std::string("an event has a field of the wrong type (") + error.what() + ")");
    }

    if (line_number == 1) {
      session.header = lines.whole_event();
      check_session_header(session.header, path);
      schema_version = header_schema_version(session.header);
      integrity.header(session.header, path);
    }
    previous_chain = chain.last_chain();
    chain.line(lines, fields.seq, fields.chain, fields.mac.has_value(), schema_version,
               line_number == 1 ? &session.header : nullptr);
    if (line_chains && !chain.first_error_line()) line_chains->push_back(chain.last_chain());
    integrity.mac(fields.chain.value_or(std::string_view()), fields.mac, line_number);
    if (line_number == 1) continue;
    if (fields.kind.empty()) fail("event: missing (expected a string naming the event)");
    const std::string kind(fields.kind);
    if (kind == SealEvent::kind) {
      integrity.seal(lines.whole_event(), line_number, previous_chain, trials.complete_count());
      continue;
    }
    integrity.event();
    if (kind == BlockStartEvent::kind) {
      const BlockStartEvent block = scanned_event<BlockStartEvent>(fields);
      session.block_names[block.block] = block.name.empty() ? block.scene : block.name;
      continue;
    }
    if (kind == TrialStartEvent::kind) {
      if (!fields.trial) fail("trial_start: trial missing (expected the trial index)");
      TrialStartEvent start = scanned_event<TrialStartEvent>(fields);
      ScannedTrial trial;
      trial.index = start.trial;
      trial.line = line_number;
      trial.block = start.block;
      trial.condition = std::move(start.condition);
      trial.variant = std::move(start.variant);
      trial.level = start.level;
      trial.attention_check = start.attention_check;
      trial.reference_first = start.reference_first;
      trial.ramp_toward_reference = start.ramp_toward_reference.value_or(true);
      trial.practice = start.practice;
      trial.track = start.track;
      trial.sequence = std::move(start.sequence);
      trials.start(std::move(trial));
      continue;
    }
    if (!is_trial_event(kind, fields.trial.has_value())) {
      if (kind == TrackerValidationEvent::kind)  // rare: read whole
        session.validations.push_back(parse_tracker_validation(lines.whole_event(), FieldCheck::lenient));
      if (kind == ExcludedEvent::kind) session.excluded = true;
      if (kind == SessionEndEvent::kind) {  // once a run: read whole
        session.ended = true;
        session.end_reason = parse_session_end(lines.whole_event(), FieldCheck::lenient).reason;
        session.end_line = line_number;
      }
      if (kind == SessionResumedEvent::kind) {  // once a run: read whole
        trials.resume();
        session.resumes.push_back(parse_session_resumed(lines.whole_event(), FieldCheck::lenient));
      }
      continue;
    }
    ScannedTrial* open = trials.open_for(fields.trial);
    if (!open) fail(kind + ": trial does not match the trial started last");
    if (kind == StimulusEvent::kind) {
      const StimulusEvent stimulus = scanned_event<StimulusEvent>(fields);
      open->dropped_frames += stimulus.dropped_frames;
      if (stimulus.late_frames) open->late_frames = open->late_frames.value_or(0) + *stimulus.late_frames;
      for (size_t i = 1; i < stimulus.present_s.size(); ++i)
        open->frame_interval_s.push_back(stimulus.present_s[i] - stimulus.present_s[i - 1]);
      open->gaze_refreshes += static_cast<int64_t>(stimulus.present_s.size());
      for (const InvalidGaze& invalid : stimulus.invalid_gaze)
        ++(invalid.reason == "off_screen" ? open->gaze_off_image : open->gaze_invalid_other);
      for (const InvalidGaze& invalid : stimulus.right_eye_invalid_gaze)
        ++(invalid.reason == "off_screen" ? open->right_gaze_off_image : open->right_gaze_invalid_other);
      if (stimulus.gaze_age_s) {
        ++open->stimuli_with_latency;
        for (const std::optional<double>& age : *stimulus.gaze_age_s)
          if (age) open->gaze_age_s.push_back(*age);  // a refresh without a sample (null) left out
      }
      if (stimulus.present_clock && !stimulus.present_clock->empty() &&
          std::find(session.present_clocks.begin(), session.present_clocks.end(), *stimulus.present_clock) ==
              session.present_clocks.end())
        session.present_clocks.push_back(*stimulus.present_clock);
    }
    if (kind == ResponseEvent::kind) {
      const ResponseEvent response = scanned_event<ResponseEvent>(fields);
      open->answers.push_back(response.answer);
      open->answer_steps.push_back(response.step);
    }
    if (kind == SliderSavedEvent::kind) open->saved_level = scanned_event<SliderSavedEvent>(fields).level;
    if (kind == AttentionCheckEvent::kind)
      open->attention_correct = scanned_event<AttentionCheckEvent>(fields).correct.value_or(true);
    if (kind == TrialEndEvent::kind && !trials.end())
      fail("trial_end: trial " + std::to_string(*fields.trial) + " is complete twice in this log (forged or spliced)");
  }
  if (lines.number() == 0)
    throw InputError(path + ":1: the log has no complete event (expected a session_header first)");
  session.line_count = lines.number();
  session.first_chain_error_line = chain.first_error_line();
  session.header_chain = chain.header_chain();
  session.incomplete_trial = trials.incomplete_index();
  session.integrity = integrity.finish(session.first_chain_error_line, session.torn_tail_bytes > 0);
  session.trials = trials.take_complete();
  for (const ScannedTrial& trial : session.trials)
    if (trial.attention_correct && !*trial.attention_correct) ++session.attention_errors;
  return session;
}

}  // namespace

}  // namespace fovlab
