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
#include "study/log/log_lines.h"
#include "study/log/session_record.h"
#include "study/log/trial_assembly.h"

namespace fovlab {
namespace {

// The fields of one event the scan uses; every other value is only checked (LogLines::check_value).
struct EventFields {
  std::string_view kind;
  std::optional<int64_t> seq;
  std::optional<std::string_view> chain;
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
  std::vector<double> present_s;   // a stimulus event's present times (empty unless every entry is a number)
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

int small_int(simdjson::ondemand::value value) {
  const int64_t number = value.get_int64();
  if (number < INT32_MIN || number > INT32_MAX) throw simdjson::simdjson_error(simdjson::NUMBER_OUT_OF_RANGE);
  return static_cast<int>(number);
}

// The keys the scan keeps.
enum class Key {
  other, event, seq, chain, mac, trial, block, step, track, condition, variant, answer, name, scene, level,
  attention_check, reference_first, ramp_toward_reference, correct, practice, sequence, dropped_frames,
  present_clock, gaze_acquired_s, gaze_age_s, present_s
};

// Which kept key `key` is, by its first letter and then the few keys that start with it (a line has
// about ten keys, most of them not kept: each is compared with two or three names, not twenty-four).
Key key_of(std::string_view key) {
  namespace k = log_keys;
  const auto is = [&](const char* name) { return key == name; };
  if (key.empty()) return Key::other;
  switch (key.front()) {
    case 'a': return is(k::answer) ? Key::answer : is(k::attention_check) ? Key::attention_check : Key::other;
    case 'b': return is(k::block) ? Key::block : Key::other;
    case 'c': return is(k::chain) ? Key::chain : is(k::condition) ? Key::condition : is(k::correct) ? Key::correct : Key::other;
    case 'd': return is(k::dropped_frames) ? Key::dropped_frames : Key::other;
    case 'e': return is(k::event) ? Key::event : Key::other;
    case 'g': return is(k::gaze_acquired_s) ? Key::gaze_acquired_s : is(k::gaze_age_s) ? Key::gaze_age_s : Key::other;
    case 'l': return is(k::level) ? Key::level : Key::other;
    case 'm': return is(k::mac) ? Key::mac : Key::other;
    case 'n': return is(k::name) ? Key::name : Key::other;
    case 'p':
      return is(k::practice)        ? Key::practice
             : is(k::present_clock) ? Key::present_clock
             : is(k::present_s)     ? Key::present_s
                                    : Key::other;
    case 'r':
      return is(k::reference_first)         ? Key::reference_first
             : is(k::ramp_toward_reference) ? Key::ramp_toward_reference
                                            : Key::other;
    case 's':
      return is(k::seq) ? Key::seq : is(k::step) ? Key::step : is(k::scene) ? Key::scene : is(k::sequence) ? Key::sequence : Key::other;
    case 't': return is(k::trial) ? Key::trial : is(k::track) ? Key::track : Key::other;
    case 'v': return is(k::variant) ? Key::variant : Key::other;
    default: return Key::other;
  }
}

// The fields the scan keeps, read with the types check_log_field_types requires (a wrong one throws
// simdjson's INCORRECT_TYPE or NUMBER_OUT_OF_RANGE); every other value checked by `lines`, so the
// line is refused exactly when the full reader refuses it.
EventFields decode(LogLines& lines) {
  EventFields fields;
  for (auto field : lines.object()) {
    const std::string_view key = field.unescaped_key();
    simdjson::ondemand::value value = field.value();
    switch (key_of(key)) {
      case Key::other: lines.check_value(value, 2); break;
      case Key::event: fields.kind = value.get_string(); break;
      case Key::seq: {
        int64_t seq = 0;  // not an integer: left out, so the chain check fails at this line
        if (value.get_int64().get(seq) == simdjson::SUCCESS) fields.seq = seq;
        else lines.check_value(value, 2);
        break;
      }
      case Key::chain:
      case Key::mac: {
        std::string_view text;  // not a string: left out (the chain, or the MAC, then does not hold)
        if (value.get_string().get(text) == simdjson::SUCCESS) (key == log_keys::chain ? fields.chain : fields.mac) = text;
        else lines.check_value(value, 2);
        break;
      }
      case Key::trial: fields.trial = small_int(value); break;
      case Key::block: fields.block = small_int(value); break;
      case Key::step: fields.step = small_int(value); break;
      case Key::track: fields.track = small_int(value); break;
      case Key::condition: fields.condition = value.get_string(); break;
      case Key::variant: fields.variant = value.get_string(); break;
      case Key::answer: fields.answer = value.get_string(); break;
      case Key::name: fields.name = value.get_string(); break;
      case Key::scene: fields.scene = value.get_string(); break;
      case Key::level:
        if (!value.is_null()) fields.level = value.get_double();
        break;
      case Key::attention_check: fields.attention_check = value.get_bool(); break;
      case Key::reference_first: fields.reference_first = value.get_bool(); break;
      case Key::ramp_toward_reference: fields.ramp_toward_reference = value.get_bool(); break;
      case Key::correct: fields.correct = value.get_bool(); break;
      case Key::practice: fields.practice = value.get_bool(); break;
      case Key::sequence:
        for (auto id : value.get_array()) fields.sequence.push_back(small_int(id.value()));
        break;
      case Key::dropped_frames: fields.dropped_frames = small_int(value); break;
      case Key::present_clock: fields.present_clock = value.get_string(); break;
      case Key::gaze_acquired_s: number_or_null_array(value, nullptr); break;
      case Key::gaze_age_s:
        fields.has_gaze_age = true;
        number_or_null_array(value, &fields.gaze_age_s);
        break;
      case Key::present_s: present_times(lines, value, fields.present_s); break;
    }
  }
  lines.expect_end();
  return fields;
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

ScannedSession scan_session_bytes(const std::string& bytes, const std::string& path_for_messages, const LabKey* lab_key) {
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
  while (lines.next()) {
    const int line_number = lines.number();
    const auto fail = [&](const std::string& what) { lines.fail(what); };
    EventFields fields;
    try {
      fields = decode(lines);
    } catch (const simdjson::simdjson_error& error) {
      const bool wrong_type = error.error() == simdjson::INCORRECT_TYPE || error.error() == simdjson::NUMBER_OUT_OF_RANGE;
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
      session.block_names[fields.block.value_or(0)] = std::string(fields.name.empty() ? fields.scene : fields.name);
      continue;
    }
    if (kind == TrialStartEvent::kind) {
      if (!fields.trial) fail("trial_start: trial missing (expected the trial index)");
      ScannedTrial trial;
      trial.index = *fields.trial;
      trial.line = line_number;
      trial.block = fields.block.value_or(0);
      trial.condition = fields.condition;
      trial.variant = fields.variant;
      trial.level = fields.level;
      trial.attention_check = fields.attention_check.value_or(false);
      trial.reference_first = fields.reference_first;
      trial.ramp_toward_reference = fields.ramp_toward_reference.value_or(true);
      trial.practice = fields.practice.value_or(false);
      trial.track = fields.track;
      trial.sequence = std::move(fields.sequence);
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
      open->dropped_frames += fields.dropped_frames.value_or(0);
      for (size_t i = 1; i < fields.present_s.size(); ++i)
        open->frame_interval_s.push_back(fields.present_s[i] - fields.present_s[i - 1]);
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
  if (lines.number() == 0) throw InputError(path + ":1: the log has no complete event (expected a session_header first)");
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
