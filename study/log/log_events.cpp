#include "study/log/log_events.h"

#include <algorithm>
#include <cstdint>

#include "core/input_error.h"

namespace fovlab {
namespace {

namespace k = log_keys;

bool is_small_int(const nlohmann::json& value) {
  return value.is_number_integer() && value.get<int64_t>() >= INT32_MIN && value.get<int64_t>() <= INT32_MAX;
}

// Reads the fields of one event of kind `kind_` (see FieldCheck in the header).
class FieldReader {
 public:
  FieldReader(const nlohmann::json& json, const char* kind, FieldCheck check) : json_(json), kind_(kind), check_(check) {
    if (!json_.is_object()) throw InputError(std::string(kind_) + ": expected a JSON object");
  }

  void stamp(EventStamp& out) const {
    if (const nlohmann::json* value = find(k::t)) {
      if (value->is_number()) out.t = value->get<double>();
      else wrong(k::t, "a number", *value);
    }
    if (const nlohmann::json* value = find(k::seq)) {
      if (value->is_number_integer()) out.seq = value->get<int64_t>();
      else wrong(k::seq, "an integer", *value);
    }
  }

  void read(const char* key, int& out) const {
    if (const nlohmann::json* value = find(key)) {
      if (is_small_int(*value)) out = value->get<int>();
      else wrong(key, "a 32-bit integer", *value);
    }
  }
  void read(const char* key, int64_t& out) const {
    if (const nlohmann::json* value = find(key)) {
      if (value->is_number_integer()) out = value->get<int64_t>();
      else wrong(key, "an integer", *value);
    }
  }
  void read(const char* key, uint64_t& out) const {
    if (const nlohmann::json* value = find(key)) {
      if (value->is_number_unsigned() || (value->is_number_integer() && value->get<int64_t>() >= 0))
        out = value->get<uint64_t>();
      else wrong(key, "an unsigned integer", *value);
    }
  }
  void read(const char* key, double& out) const {
    if (const nlohmann::json* value = find(key)) {
      if (value->is_number()) out = value->get<double>();
      else wrong(key, "a number", *value);
    }
  }
  void read(const char* key, bool& out) const {
    if (const nlohmann::json* value = find(key)) {
      if (value->is_boolean()) out = value->get<bool>();
      else wrong(key, "true or false", *value);
    }
  }
  void read(const char* key, std::string& out) const {
    if (const nlohmann::json* value = find(key)) {
      if (value->is_string()) out = value->get<std::string>();
      else wrong(key, "a string", *value);
    }
  }
  void read(const char* key, nlohmann::json& out) const {
    if (const nlohmann::json* value = find(key)) out = *value;
  }
  // A null is nullopt; absent too.
  template <typename T>
  void read(const char* key, std::optional<T>& out) const {
    const nlohmann::json* value = find(key);
    if (!value || value->is_null()) return;
    T inner{};
    const bool accepted = accepts(*value, inner);
    read(key, inner);  // the scalar's own check and words (strict: throws when not accepted)
    if (accepted) out = inner;
  }
  template <typename T>
  void read(const char* key, std::vector<T>& out) const {
    const nlohmann::json* value = find(key);
    if (!value) return;
    T element{};
    if (!value->is_array() || !std::all_of(value->begin(), value->end(), [&](const nlohmann::json& item) { return accepts(item, element); })) {
      wrong(key, "an array of " + expected(element), *value);
      return;
    }
    std::vector<T> result;
    for (const nlohmann::json& item : *value) result.push_back(convert(item, element));
    out = std::move(result);
  }
  void read(const char* key, std::vector<std::array<double, 2>>& out) const {
    const nlohmann::json* value = find(key);
    if (!value) return;
    const auto pair = [](const nlohmann::json& item) {
      return item.is_array() && item.size() == 2 && item[0].is_number() && item[1].is_number();
    };
    if (!value->is_array() || !std::all_of(value->begin(), value->end(), pair)) {
      wrong(key, "an array of [x, y] pairs of numbers", *value);
      return;
    }
    out.clear();
    for (const nlohmann::json& item : *value) out.push_back({item[0].get<double>(), item[1].get<double>()});
  }
  void read(const char* key, std::vector<ValidationTarget>& out) const {
    const nlohmann::json* value = find(key);
    if (!value) return;
    const auto number_or_null = [](const nlohmann::json& item, const char* name) {
      return !item.contains(name) || item[name].is_number() || item[name].is_null();
    };
    const auto entry = [&](const nlohmann::json& item) {
      return item.is_object() && item.contains(k::x_px) && item[k::x_px].is_number() && item.contains(k::y_px) &&
             item[k::y_px].is_number() && (!item.contains(k::samples) || is_small_int(item[k::samples])) &&
             (!item.contains(k::valid_samples) || is_small_int(item[k::valid_samples])) &&
             number_or_null(item, k::accuracy_deg) && number_or_null(item, k::precision_deg) &&
             (!item.contains(k::gaze) || (item[k::gaze].is_array() &&
                                          std::all_of(item[k::gaze].begin(), item[k::gaze].end(), [](const nlohmann::json& p) {
                                            return p.is_null() || (p.is_array() && p.size() == 2 && p[0].is_number() &&
                                                                   p[1].is_number());
                                          })));
    };
    if (!value->is_array() || !std::all_of(value->begin(), value->end(), entry)) {
      wrong(key, "an array of {x_px, y_px, samples, valid_samples, accuracy_deg, precision_deg, gaze} objects", *value);
      return;
    }
    out.clear();
    for (const nlohmann::json& item : *value) {
      const FieldReader target(item, key, FieldCheck::lenient);
      ValidationTarget result;
      target.read(k::x_px, result.x_px);
      target.read(k::y_px, result.y_px);
      target.read(k::samples, result.samples);
      target.read(k::valid_samples, result.valid_samples);
      target.read(k::accuracy_deg, result.accuracy_deg);
      target.read(k::precision_deg, result.precision_deg);
      if (const auto gaze = item.find(k::gaze); gaze != item.end() && gaze->is_array())
        for (const nlohmann::json& position : *gaze) {
          if (position.is_array() && position.size() == 2 && position[0].is_number() && position[1].is_number())
            result.gaze.push_back(std::array<double, 2>{position[0].get<double>(), position[1].get<double>()});
          else
            result.gaze.push_back(std::nullopt);
        }
      out.push_back(result);
    }
  }
  void read(const char* key, std::vector<InvalidGaze>& out) const {
    const nlohmann::json* value = find(key);
    if (!value) return;
    const auto entry = [](const nlohmann::json& item) {
      return item.is_object() && item.contains(k::invalid_index) && is_small_int(item[k::invalid_index]) &&
             item.contains(k::reason) && item[k::reason].is_string();
    };
    if (!value->is_array() || !std::all_of(value->begin(), value->end(), entry)) {
      wrong(key, "an array of {i, reason} objects", *value);
      return;
    }
    out.clear();
    for (const nlohmann::json& item : *value)
      out.push_back({item[k::invalid_index].get<int>(), item[k::reason].get<std::string>()});
  }

 private:
  const nlohmann::json* find(const char* key) const {
    const auto found = json_.find(key);
    return found == json_.end() ? nullptr : &*found;
  }
  void wrong(const char* key, const std::string& what, const nlohmann::json& value) const {
    if (check_ == FieldCheck::lenient) return;
    throw InputError(std::string(kind_) + ": " + key + ": expected " + what + ", got " + value.dump().substr(0, 40));
  }
  static bool accepts(const nlohmann::json& value, int) { return is_small_int(value); }
  static bool accepts(const nlohmann::json& value, double) { return value.is_number(); }
  static bool accepts(const nlohmann::json& value, bool) { return value.is_boolean(); }
  static bool accepts(const nlohmann::json& value, const std::string&) { return value.is_string(); }
  static bool accepts(const nlohmann::json& value, const std::optional<double>&) {
    return value.is_number() || value.is_null();
  }
  static std::string expected(int) { return "32-bit integers"; }
  static std::string expected(double) { return "numbers"; }
  static std::string expected(bool) { return "booleans"; }
  static std::string expected(const std::string&) { return "strings"; }
  static std::string expected(const std::optional<double>&) { return "numbers or nulls"; }
  template <typename T>
  static T convert(const nlohmann::json& value, const T&) { return value.get<T>(); }
  static std::optional<double> convert(const nlohmann::json& value, const std::optional<double>&) {
    return value.is_null() ? std::nullopt : std::optional<double>(value.get<double>());
  }

  const nlohmann::json& json_;
  const char* kind_;
  FieldCheck check_;
};

nlohmann::json start(const char* kind, const EventStamp& stamp) {
  nlohmann::json json = {{k::event, kind}};
  if (stamp.t) json[k::t] = *stamp.t;
  if (stamp.seq) json[k::seq] = *stamp.seq;
  return json;
}

template <typename T>
nlohmann::json or_null(const std::optional<T>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json();
}

nlohmann::json numbers_or_nulls(const std::vector<std::optional<double>>& values) {
  nlohmann::json array = nlohmann::json::array();
  for (const std::optional<double>& value : values) array.push_back(or_null(value));
  return array;
}

}  // namespace

namespace {

std::optional<GazeSourceKind> logged_gaze_kind(const nlohmann::json& gaze_source, const std::string& gaze) {
  if (gaze_source.is_object()) {
    const auto kind = gaze_source.find("kind");
    if (kind != gaze_source.end() && kind->is_string()) return parse_gaze_source_kind(kind->get<std::string>());
  }
  return gaze_source_kind_of_spec(gaze);
}

}  // namespace

std::vector<GazeSourceKind> session_gaze_kinds(const nlohmann::json& header, const std::vector<SessionResumedEvent>& resumes) {
  std::vector<GazeSourceKind> kinds;
  const auto add = [&](std::optional<GazeSourceKind> kind) {
    if (kind && std::find(kinds.begin(), kinds.end(), *kind) == kinds.end()) kinds.push_back(*kind);
  };
  const auto gaze = header.find(k::gaze);
  add(logged_gaze_kind(header.value(k::gaze_source, nlohmann::json()),
                       gaze != header.end() && gaze->is_string() ? gaze->get<std::string>() : std::string()));
  for (const SessionResumedEvent& resumed : resumes) add(logged_gaze_kind(resumed.gaze_source, resumed.gaze));
  return kinds;
}

std::string gaze_kinds_text(const std::vector<GazeSourceKind>& kinds) {
  std::string text;
  for (GazeSourceKind kind : kinds) text += (text.empty() ? "" : "+") + std::string(gaze_source_kind_name(kind));
  return text;
}

// ---- to_json: the keys and value types the writer has always logged ----

nlohmann::json to_json(const SessionHeaderEvent& event) {
  nlohmann::json json = start(SessionHeaderEvent::kind, event.stamp);
  json[k::schema_version] = event.schema_version;
  json[k::lab_key_id] = or_null(event.lab_key_id);
  json[k::fovlab_version] = event.fovlab_version;
  json[k::study] = event.study;
  json[k::participant] = event.participant;
  json[k::study_seed] = event.study_seed;
  json[k::session_seed] = event.session_seed;
  json[k::config_path] = event.config_path;
  json[k::config_hash] = event.config_hash;
  json[k::config_toml] = event.config_toml;
  json[k::protocol] = event.protocol;
  json[k::trial_count] = event.trial_count;
  json[k::scene_hashes] = event.scene_hashes;
  json[k::stimuli] = event.stimuli;
  json[k::device] = event.device;
  json[k::display] = event.display;
  json[k::presenter] = event.presenter;
  json[k::gaze] = event.gaze;
  json[k::observer] = event.observer;
  json[k::started_utc] = event.started_utc;
  // Only when there are some: a header without fields keeps the bytes earlier builds wrote.
  if (event.participant_fields.is_object() && !event.participant_fields.empty())
    json[k::participant_fields] = event.participant_fields;
  if (!event.conditions_csv.empty()) json[k::conditions_csv] = event.conditions_csv;
  // Schema 7; absent from a header of an earlier schema, which then writes back its own bytes.
  if (!event.gaze_source.is_null()) json[k::gaze_source] = event.gaze_source;
  if (!event.gaze_validation.is_null()) json[k::gaze_validation] = event.gaze_validation;
  return json;
}

nlohmann::json to_json(const SessionResumedEvent& event) {
  nlohmann::json json = start(SessionResumedEvent::kind, event.stamp);
  json[k::next_trial] = event.next_trial;
  json[k::discarded_trial] = or_null(event.discarded_trial);
  json[k::torn_line_set_aside] = or_null(event.torn_line_set_aside);
  json[k::gaze] = event.gaze;
  json[k::started_utc] = event.started_utc;
  if (!event.gaze_source.is_null()) json[k::gaze_source] = event.gaze_source;
  return json;
}

nlohmann::json to_json(const TrackerValidationEvent& event) {
  nlohmann::json json = start(TrackerValidationEvent::kind, event.stamp);
  json[k::reason] = event.reason;
  json[k::attempt] = event.attempt;
  json[k::start_s] = event.start_s;
  nlohmann::json targets = nlohmann::json::array();
  for (const ValidationTarget& target : event.targets) {
    nlohmann::json gaze = nlohmann::json::array();
    for (const auto& position : target.gaze) gaze.push_back(position ? nlohmann::json(*position) : nlohmann::json());
    targets.push_back({{k::x_px, target.x_px}, {k::y_px, target.y_px}, {k::samples, target.samples},
                       {k::valid_samples, target.valid_samples}, {k::accuracy_deg, or_null(target.accuracy_deg)},
                       {k::precision_deg, or_null(target.precision_deg)}, {k::gaze, std::move(gaze)}});
  }
  json[k::targets] = std::move(targets);
  json[k::accuracy_deg] = or_null(event.accuracy_deg);
  json[k::precision_deg] = or_null(event.precision_deg);
  json[k::max_accuracy_deg] = event.max_accuracy_deg;
  json[k::max_precision_deg] = event.max_precision_deg;
  json[k::passed] = event.passed;
  if (event.stopped) json[k::stopped] = true;
  return json;
}

nlohmann::json to_json(const InstructionsEvent& event) {
  nlohmann::json json = start(InstructionsEvent::kind, event.stamp);
  json[k::shown_s] = event.shown_s;
  return json;
}

nlohmann::json to_json(const BlockStartEvent& event) {
  nlohmann::json json = start(BlockStartEvent::kind, event.stamp);
  json[k::block] = event.block;
  json[k::name] = event.name;
  json[k::scene] = event.scene;
  return json;
}

nlohmann::json to_json(const BreakEvent& event) {
  nlohmann::json json = start(BreakEvent::kind, event.stamp);
  json[k::reason] = event.reason;
  if (event.trial) json[k::trial] = *event.trial;
  json[k::start_s] = event.start_s;
  json[k::duration_s] = event.duration_s;
  return json;
}

nlohmann::json to_json(const TrialStartEvent& event) {
  nlohmann::json json = start(TrialStartEvent::kind, event.stamp);
  json[k::trial] = event.trial;
  json[k::block] = event.block;
  json[k::condition] = event.condition;
  json[k::variant] = event.variant;
  if (event.level) json[k::level] = *event.level;
  json[k::attention_check] = event.attention_check;
  json[k::sequence] = event.sequence;
  json[k::reference] = event.reference;
  if (event.reference_first) json[k::reference_first] = *event.reference_first;
  if (event.ramp_toward_reference) json[k::ramp_toward_reference] = *event.ramp_toward_reference;
  if (event.slider_start) json[k::slider_start] = *event.slider_start;
  if (event.practice) json[k::practice] = true;
  if (event.track) json[k::track] = *event.track;
  return json;
}

nlohmann::json to_json(const StimulusEvent& event) {
  nlohmann::json json = start(StimulusEvent::kind, event.stamp);
  json[k::trial] = event.trial;
  json[k::step] = event.step;
  json[k::stimulus] = event.stimulus;
  json[k::onset_s] = event.onset_s;
  json[k::present_s] = event.present_s;
  json[k::frame] = event.frame;
  json[k::hash] = event.hash;
  nlohmann::json gaze = nlohmann::json::array();
  for (const auto& [x, y] : event.gaze) gaze.push_back({x, y});
  json[k::gaze] = gaze;
  nlohmann::json invalid = nlohmann::json::array();
  for (const InvalidGaze& entry : event.invalid_gaze)
    invalid.push_back({{k::invalid_index, entry.index}, {k::reason, entry.reason}});
  json[k::invalid_gaze] = invalid;
  json[k::dropped_frames] = event.dropped_frames;
  if (event.gaze_acquired_s) json[k::gaze_acquired_s] = numbers_or_nulls(*event.gaze_acquired_s);
  if (event.gaze_age_s) json[k::gaze_age_s] = numbers_or_nulls(*event.gaze_age_s);
  if (event.present_clock) json[k::present_clock] = *event.present_clock;
  return json;
}

nlohmann::json to_json(const ResponseEvent& event) {
  nlohmann::json json = start(ResponseEvent::kind, event.stamp);
  json[k::trial] = event.trial;
  json[k::step] = event.step;
  json[k::answer] = event.answer;
  json[k::key] = event.key;
  if (event.rt_s) json[k::rt_s] = *event.rt_s;
  return json;
}

nlohmann::json to_json(const SliderSavedEvent& event) {
  nlohmann::json json = start(SliderSavedEvent::kind, event.stamp);
  json[k::trial] = event.trial;
  json[k::ladder_index] = event.ladder_index;
  json[k::stimulus] = event.stimulus;
  if (event.level) json[k::level] = *event.level;
  return json;
}

nlohmann::json to_json(const AttentionCheckEvent& event) {
  nlohmann::json json = start(AttentionCheckEvent::kind, event.stamp);
  json[k::trial] = event.trial;
  if (event.correct) json[k::correct] = *event.correct;
  json[k::errors] = event.errors;
  return json;
}

nlohmann::json to_json(const TrialEndEvent& event) {
  nlohmann::json json = start(TrialEndEvent::kind, event.stamp);
  json[k::trial] = event.trial;
  return json;
}

nlohmann::json to_json(const ExcludedEvent& event) {
  nlohmann::json json = start(ExcludedEvent::kind, event.stamp);
  json[k::errors] = event.errors;
  json[k::max_errors] = event.max_errors;
  return json;
}

nlohmann::json to_json(const SessionPausedEvent& event) {
  nlohmann::json json = start(SessionPausedEvent::kind, event.stamp);
  json[k::reason] = event.reason;
  return json;
}

nlohmann::json to_json(const SessionEndEvent& event) {
  nlohmann::json json = start(SessionEndEvent::kind, event.stamp);
  json[k::reason] = event.reason;
  json[k::completed_trials] = event.completed_trials;
  return json;
}

nlohmann::json to_json(const SealEvent& event) {
  nlohmann::json json = start(SealEvent::kind, event.stamp);
  json[k::trials_complete] = event.trials_complete;
  if (!event.last_chain.empty()) json[k::last_chain] = event.last_chain;
  return json;
}

// ---- parse ----

SessionHeaderEvent parse_session_header(const nlohmann::json& json, FieldCheck check) {
  const FieldReader in(json, SessionHeaderEvent::kind, check);
  SessionHeaderEvent event;
  in.stamp(event.stamp);
  in.read(k::schema_version, event.schema_version);
  in.read(k::lab_key_id, event.lab_key_id);
  in.read(k::fovlab_version, event.fovlab_version);
  in.read(k::study, event.study);
  in.read(k::participant, event.participant);
  in.read(k::study_seed, event.study_seed);
  in.read(k::session_seed, event.session_seed);
  in.read(k::config_path, event.config_path);
  in.read(k::config_hash, event.config_hash);
  in.read(k::config_toml, event.config_toml);
  in.read(k::protocol, event.protocol);
  in.read(k::trial_count, event.trial_count);
  in.read(k::scene_hashes, event.scene_hashes);
  in.read(k::stimuli, event.stimuli);
  in.read(k::device, event.device);
  in.read(k::display, event.display);
  in.read(k::presenter, event.presenter);
  in.read(k::gaze, event.gaze);
  in.read(k::observer, event.observer);
  in.read(k::started_utc, event.started_utc);
  in.read(k::participant_fields, event.participant_fields);
  in.read(k::conditions_csv, event.conditions_csv);
  in.read(k::gaze_source, event.gaze_source);
  in.read(k::gaze_validation, event.gaze_validation);
  return event;
}

SessionResumedEvent parse_session_resumed(const nlohmann::json& json, FieldCheck check) {
  const FieldReader in(json, SessionResumedEvent::kind, check);
  SessionResumedEvent event;
  in.stamp(event.stamp);
  in.read(k::next_trial, event.next_trial);
  in.read(k::discarded_trial, event.discarded_trial);
  in.read(k::torn_line_set_aside, event.torn_line_set_aside);
  in.read(k::gaze, event.gaze);
  in.read(k::started_utc, event.started_utc);
  in.read(k::gaze_source, event.gaze_source);
  return event;
}

InstructionsEvent parse_instructions(const nlohmann::json& json, FieldCheck check) {
  const FieldReader in(json, InstructionsEvent::kind, check);
  InstructionsEvent event;
  in.stamp(event.stamp);
  in.read(k::shown_s, event.shown_s);
  return event;
}

BlockStartEvent parse_block_start(const nlohmann::json& json, FieldCheck check) {
  const FieldReader in(json, BlockStartEvent::kind, check);
  BlockStartEvent event;
  in.stamp(event.stamp);
  in.read(k::block, event.block);
  in.read(k::name, event.name);
  in.read(k::scene, event.scene);
  return event;
}

TrackerValidationEvent parse_tracker_validation(const nlohmann::json& json, FieldCheck check) {
  const FieldReader in(json, TrackerValidationEvent::kind, check);
  TrackerValidationEvent event;
  in.stamp(event.stamp);
  in.read(k::reason, event.reason);
  in.read(k::attempt, event.attempt);
  in.read(k::start_s, event.start_s);
  in.read(k::targets, event.targets);
  in.read(k::accuracy_deg, event.accuracy_deg);
  in.read(k::precision_deg, event.precision_deg);
  in.read(k::max_accuracy_deg, event.max_accuracy_deg);
  in.read(k::max_precision_deg, event.max_precision_deg);
  in.read(k::passed, event.passed);
  in.read(k::stopped, event.stopped);
  return event;
}

BreakEvent parse_break(const nlohmann::json& json, FieldCheck check) {
  const FieldReader in(json, BreakEvent::kind, check);
  BreakEvent event;
  in.stamp(event.stamp);
  in.read(k::reason, event.reason);
  in.read(k::trial, event.trial);
  in.read(k::start_s, event.start_s);
  in.read(k::duration_s, event.duration_s);
  return event;
}

TrialStartEvent parse_trial_start(const nlohmann::json& json, FieldCheck check) {
  const FieldReader in(json, TrialStartEvent::kind, check);
  TrialStartEvent event;
  in.stamp(event.stamp);
  in.read(k::trial, event.trial);
  in.read(k::block, event.block);
  in.read(k::condition, event.condition);
  in.read(k::variant, event.variant);
  in.read(k::level, event.level);
  in.read(k::attention_check, event.attention_check);
  in.read(k::sequence, event.sequence);
  in.read(k::reference, event.reference);
  in.read(k::reference_first, event.reference_first);
  in.read(k::ramp_toward_reference, event.ramp_toward_reference);
  in.read(k::slider_start, event.slider_start);
  in.read(k::practice, event.practice);
  in.read(k::track, event.track);
  return event;
}

StimulusEvent parse_stimulus(const nlohmann::json& json, FieldCheck check) {
  const FieldReader in(json, StimulusEvent::kind, check);
  StimulusEvent event;
  in.stamp(event.stamp);
  in.read(k::trial, event.trial);
  in.read(k::step, event.step);
  in.read(k::stimulus, event.stimulus);
  in.read(k::onset_s, event.onset_s);
  in.read(k::present_s, event.present_s);
  in.read(k::frame, event.frame);
  in.read(k::hash, event.hash);
  in.read(k::gaze, event.gaze);
  in.read(k::invalid_gaze, event.invalid_gaze);
  in.read(k::dropped_frames, event.dropped_frames);
  if (json.contains(k::gaze_acquired_s)) {
    std::vector<std::optional<double>> values;
    in.read(k::gaze_acquired_s, values);
    event.gaze_acquired_s = std::move(values);
  }
  if (json.contains(k::gaze_age_s)) {
    std::vector<std::optional<double>> values;
    in.read(k::gaze_age_s, values);
    event.gaze_age_s = std::move(values);
  }
  if (json.contains(k::present_clock)) {
    std::string clock;
    in.read(k::present_clock, clock);
    event.present_clock = clock;
  }
  return event;
}

ResponseEvent parse_response(const nlohmann::json& json, FieldCheck check) {
  const FieldReader in(json, ResponseEvent::kind, check);
  ResponseEvent event;
  in.stamp(event.stamp);
  in.read(k::trial, event.trial);
  in.read(k::step, event.step);
  in.read(k::answer, event.answer);
  in.read(k::key, event.key);
  in.read(k::rt_s, event.rt_s);
  return event;
}

SliderSavedEvent parse_slider_saved(const nlohmann::json& json, FieldCheck check) {
  const FieldReader in(json, SliderSavedEvent::kind, check);
  SliderSavedEvent event;
  in.stamp(event.stamp);
  in.read(k::trial, event.trial);
  in.read(k::ladder_index, event.ladder_index);
  in.read(k::stimulus, event.stimulus);
  in.read(k::level, event.level);
  return event;
}

AttentionCheckEvent parse_attention_check(const nlohmann::json& json, FieldCheck check) {
  const FieldReader in(json, AttentionCheckEvent::kind, check);
  AttentionCheckEvent event;
  in.stamp(event.stamp);
  in.read(k::trial, event.trial);
  in.read(k::correct, event.correct);
  in.read(k::errors, event.errors);
  return event;
}

TrialEndEvent parse_trial_end(const nlohmann::json& json, FieldCheck check) {
  const FieldReader in(json, TrialEndEvent::kind, check);
  TrialEndEvent event;
  in.stamp(event.stamp);
  in.read(k::trial, event.trial);
  return event;
}

ExcludedEvent parse_excluded(const nlohmann::json& json, FieldCheck check) {
  const FieldReader in(json, ExcludedEvent::kind, check);
  ExcludedEvent event;
  in.stamp(event.stamp);
  in.read(k::errors, event.errors);
  in.read(k::max_errors, event.max_errors);
  return event;
}

SessionPausedEvent parse_session_paused(const nlohmann::json& json, FieldCheck check) {
  const FieldReader in(json, SessionPausedEvent::kind, check);
  SessionPausedEvent event;
  in.stamp(event.stamp);
  in.read(k::reason, event.reason);
  return event;
}

SessionEndEvent parse_session_end(const nlohmann::json& json, FieldCheck check) {
  const FieldReader in(json, SessionEndEvent::kind, check);
  SessionEndEvent event;
  in.stamp(event.stamp);
  in.read(k::reason, event.reason);
  in.read(k::completed_trials, event.completed_trials);
  return event;
}

SealEvent parse_seal(const nlohmann::json& json, FieldCheck check) {
  const FieldReader in(json, SealEvent::kind, check);
  SealEvent event;
  in.stamp(event.stamp);
  in.read(k::trials_complete, event.trials_complete);
  in.read(k::last_chain, event.last_chain);
  return event;
}

nlohmann::json to_json(const LogEvent& event) {
  return std::visit([](const auto& typed) { return to_json(typed); }, event);
}

LogEvent parse_log_event(const nlohmann::json& json, FieldCheck check) {
  const std::string kind = event_kind(json);
  if (kind == SessionHeaderEvent::kind) return parse_session_header(json, check);
  if (kind == SessionResumedEvent::kind) return parse_session_resumed(json, check);
  if (kind == InstructionsEvent::kind) return parse_instructions(json, check);
  if (kind == BlockStartEvent::kind) return parse_block_start(json, check);
  if (kind == BreakEvent::kind) return parse_break(json, check);
  if (kind == TrialStartEvent::kind) return parse_trial_start(json, check);
  if (kind == StimulusEvent::kind) return parse_stimulus(json, check);
  if (kind == ResponseEvent::kind) return parse_response(json, check);
  if (kind == SliderSavedEvent::kind) return parse_slider_saved(json, check);
  if (kind == AttentionCheckEvent::kind) return parse_attention_check(json, check);
  if (kind == TrialEndEvent::kind) return parse_trial_end(json, check);
  if (kind == ExcludedEvent::kind) return parse_excluded(json, check);
  if (kind == TrackerValidationEvent::kind) return parse_tracker_validation(json, check);
  if (kind == SessionPausedEvent::kind) return parse_session_paused(json, check);
  if (kind == SessionEndEvent::kind) return parse_session_end(json, check);
  if (kind == SealEvent::kind) return parse_seal(json, check);
  throw InputError(std::string(log_keys::event) + ": " +
                   (kind.empty() ? std::string("missing (expected a string naming the event)")
                                 : "\"" + kind.substr(0, 40) + "\" is not an event of the log schema"));
}

std::string event_kind(const nlohmann::json& event) {
  if (!event.is_object()) return {};
  const auto found = event.find(k::event);
  return found != event.end() && found->is_string() ? found->get<std::string>() : std::string();
}

std::string check_log_field_types(const nlohmann::json& event) {
  for (const auto& [key, value] : event.items()) {
    bool ok = true;
    if (key == k::trial || key == k::block || key == k::step || key == k::track) ok = is_small_int(value);
    else if (key == k::event || key == k::condition || key == k::variant || key == k::answer || key == k::name ||
             key == k::scene)
      ok = value.is_string();
    else if (key == k::level) ok = value.is_number() || value.is_null();
    else if (key == k::attention_check || key == k::reference_first || key == k::ramp_toward_reference ||
             key == k::correct || key == k::practice)
      ok = value.is_boolean();
    else if (key == k::sequence) ok = value.is_array() && std::all_of(value.begin(), value.end(), is_small_int);
    else if (key == k::dropped_frames) ok = is_small_int(value);
    else if (key == k::present_clock) ok = value.is_string();
    else if (key == k::gaze_acquired_s || key == k::gaze_age_s)
      ok = value.is_array() && std::all_of(value.begin(), value.end(), [](const nlohmann::json& element) {
             return element.is_number() || element.is_null();
           });
    if (!ok) return "an event has a field of the wrong type (" + key + ": " + value.dump().substr(0, 40) + ")";
  }
  return {};
}

std::string observer_kind(const nlohmann::json& header) {
  const auto observer = header.find(log_keys::observer);
  if (observer != header.end() && *observer == "human") return "human";
  if (observer != header.end() && observer->is_object()) return "simulated";
  throw InputError(std::string("session_header: ") + log_keys::observer +
                   ": expected \"human\" or a simulated observer's model, got " +
                   (observer == header.end() ? std::string("nothing") : observer->dump().substr(0, 40)));
}

}  // namespace fovlab
