#include "study/log/log_events.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <stdexcept>

#include "core/input_error.h"
#include "study/log/log_event_fields.h"

namespace fovlab {
namespace {

namespace k = log_keys;

bool is_small_int(const nlohmann::json& value) {
  return value.is_number_integer() && value.get<int64_t>() >= INT32_MIN && value.get<int64_t>() <= INT32_MAX;
}

class FieldReader;
// Reads the fields of `object`'s table (log_event_fields.h) from `in`.
template <typename Object>
void read_fields(const FieldReader& in, Object& object);

// Reads the fields of one event of kind `kind_` (see FieldCheck in the header).
class FieldReader {
 public:
  FieldReader(const nlohmann::json& json, const char* kind, FieldCheck check)
      : json_(json), kind_(kind), check_(check) {
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
  // The arrays say whether they read one (false: absent, or refused as wrong).
  template <typename T>
  bool read(const char* key, std::vector<T>& out) const {
    const nlohmann::json* value = find(key);
    if (!value) return false;
    T element{};
    if (!value->is_array() || !std::all_of(value->begin(), value->end(),
                                           [&](const nlohmann::json& item) { return accepts(item, element); })) {
      wrong(key, "an array of " + expected(element), *value);
      return false;
    }
    std::vector<T> result;
    for (const nlohmann::json& item : *value) result.push_back(convert(item, element));
    out = std::move(result);
    return true;
  }
  bool read(const char* key, std::vector<std::array<double, 2>>& out) const {
    const nlohmann::json* value = find(key);
    if (!value) return false;
    const auto pair = [](const nlohmann::json& item) {
      return item.is_array() && item.size() == 2 && item[0].is_number() && item[1].is_number();
    };
    if (!value->is_array() || !std::all_of(value->begin(), value->end(), pair)) {
      wrong(key, "an array of [x, y] pairs of numbers", *value);
      return false;
    }
    out.clear();
    for (const nlohmann::json& item : *value) out.push_back({item[0].get<double>(), item[1].get<double>()});
    return true;
  }
  // Schema 11's right eye's arrays: absent or null is nullopt, else the array as read.
  void read(const char* key, std::optional<std::vector<std::string>>& out) const { read_optional_array(key, out); }
  void read(const char* key, std::optional<std::vector<std::array<double, 2>>>& out) const {
    read_optional_array(key, out);
  }
  // Schema 12's head poses (head-tracked views): absent or null is nullopt, else seven numbers an entry.
  void read(const char* key, std::optional<std::vector<std::array<double, 7>>>& out) const {
    const nlohmann::json* value = find(key);
    if (!value || value->is_null()) return;
    const auto pose = [](const nlohmann::json& item) {
      return item.is_array() && item.size() == 7 &&
             std::all_of(item.begin(), item.end(), [](const nlohmann::json& n) { return n.is_number(); });
    };
    if (!value->is_array() || !std::all_of(value->begin(), value->end(), pose)) {
      wrong(key, "an array of [x_m, y_m, z_m, qx, qy, qz, qw] arrays of numbers", *value);
      return;
    }
    std::vector<std::array<double, 7>> poses;
    for (const nlohmann::json& item : *value) {
      std::array<double, 7> entry{};
      for (size_t i = 0; i < 7; ++i) entry[i] = item[i].get<double>();
      poses.push_back(entry);
    }
    out = std::move(poses);
  }
  template <typename T>
  void read_optional_array(const char* key, std::optional<std::vector<T>>& out) const {
    const nlohmann::json* value = find(key);
    if (!value || value->is_null()) return;
    std::vector<T> inner;
    if (read(key, inner)) out = std::move(inner);
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
             (!item.contains(k::gaze) ||
              (item[k::gaze].is_array() &&
               std::all_of(item[k::gaze].begin(), item[k::gaze].end(), [](const nlohmann::json& p) {
                 return p.is_null() || (p.is_array() && p.size() == 2 && p[0].is_number() && p[1].is_number());
               })));
    };
    if (!value->is_array() || !std::all_of(value->begin(), value->end(), entry)) {
      wrong(key, "an array of {x_px, y_px, samples, valid_samples, accuracy_deg, precision_deg, gaze} objects", *value);
      return;
    }
    out.clear();
    for (const nlohmann::json& item : *value) {
      ValidationTarget target;
      read_fields(FieldReader(item, key, FieldCheck::lenient), target);
      out.push_back(std::move(target));
    }
  }
  // A validation target's gaze: each a pair of numbers or null (ValidationTarget's check above).
  void read(const char* key, std::vector<std::optional<std::array<double, 2>>>& out) const {
    const nlohmann::json* value = find(key);
    if (!value) return;
    if (!value->is_array()) {
      wrong(key, "an array of [x, y] pairs of numbers or nulls", *value);
      return;
    }
    out.clear();
    for (const nlohmann::json& position : *value) {
      if (position.is_array() && position.size() == 2 && position[0].is_number() && position[1].is_number())
        out.push_back(std::array<double, 2>{position[0].get<double>(), position[1].get<double>()});
      else out.push_back(std::nullopt);
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
    for (const nlohmann::json& item : *value) {
      InvalidGaze invalid;
      read_fields(FieldReader(item, key, FieldCheck::lenient), invalid);
      out.push_back(std::move(invalid));
    }
  }

  bool has(const char* key) const { return find(key) != nullptr; }

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
  static T convert(const nlohmann::json& value, const T&) {
    return value.get<T>();
  }
  static std::optional<double> convert(const nlohmann::json& value, const std::optional<double>&) {
    return value.is_null() ? std::nullopt : std::optional<double>(value.get<double>());
  }

  const nlohmann::json& json_;
  const char* kind_;
  FieldCheck check_;
};

// ---- writing and reading by the tables (log_event_fields.h) ----

using log_fields::Read;
using log_fields::Write;

template <typename T>
struct IsOptional : std::false_type {};
template <typename T>
struct IsOptional<std::optional<T>> : std::true_type {};
template <typename T>
struct IsVector : std::false_type {};
template <typename T>
struct IsVector<std::vector<T>> : std::true_type {};

template <typename Object>
nlohmann::json object_json(const Object& object);

// A field's value as the writer has always logged it: the member's own JSON type (an int as an
// integer, a double as a float), an unset optional as null, the structs as objects.
template <typename T>
nlohmann::json value_json(const T& value) {
  return nlohmann::json(value);
}
template <typename T>
nlohmann::json value_json(const std::vector<T>& values);
nlohmann::json value_json(const InvalidGaze& entry) { return object_json(entry); }
nlohmann::json value_json(const ValidationTarget& target) { return object_json(target); }
template <typename T>
nlohmann::json value_json(const std::optional<T>& value) {
  return value ? value_json(*value) : nlohmann::json();
}
template <typename T>
nlohmann::json value_json(const std::vector<T>& values) {
  nlohmann::json array = nlohmann::json::array();
  for (const T& value : values) array.push_back(value_json(value));
  return array;
}

// Whether the writer writes a field holding `value` (Write).
template <typename T>
bool written(const T& value, Write write) {
  switch (write) {
    case Write::always:
      return true;
    case Write::when_set:
      if constexpr (IsOptional<T>::value) return value.has_value();
      break;
    case Write::when_true:
      if constexpr (std::is_same_v<T, bool>) return value;
      break;
    case Write::when_not_empty:
      if constexpr (std::is_same_v<T, std::string> || IsVector<T>::value) return !value.empty();
      if constexpr (std::is_same_v<T, nlohmann::json>) return value.is_object() && !value.empty();
      break;
    case Write::when_not_null:
      if constexpr (std::is_same_v<T, nlohmann::json>) return !value.is_null();
      break;
  }
  throw std::logic_error("log_event_fields.h: a Write rule that does not fit its field's type");
}

template <typename Object>
void write_fields(nlohmann::json& out, const Object& object) {
  log_fields::for_each_field<Object>([&](const auto& row) {
    const auto& value = object.*row.member;
    if (written(value, row.write)) out[row.key] = value_json(value);
  });
}

template <typename Object>
nlohmann::json object_json(const Object& object) {
  nlohmann::json json = nlohmann::json::object();
  write_fields(json, object);
  return json;
}

template <typename Event>
nlohmann::json event_json(const Event& event) {
  nlohmann::json json = {{k::event, Event::kind}};
  if (event.stamp.t) json[k::t] = *event.stamp.t;
  if (event.stamp.seq) json[k::seq] = *event.stamp.seq;
  write_fields(json, event);
  return json;
}

template <typename Object>
void read_fields(const FieldReader& in, Object& object) {
  log_fields::for_each_field<Object>([&](const auto& row) {
    using Row = std::remove_cvref_t<decltype(row)>;
    auto& member = object.*row.member;
    if constexpr (Row::read == Read::when_given) {
      if (!in.has(row.key)) return;
      typename Row::MemberType::value_type value{};
      in.read(row.key, value);
      member = std::move(value);
    } else {
      in.read(row.key, member);
    }
  });
}

template <typename Event>
Event parse_event(const nlohmann::json& json, FieldCheck check) {
  const FieldReader in(json, Event::kind, check);
  Event event;
  in.stamp(event.stamp);
  read_fields(in, event);
  return event;
}

// The line type rules (log_event_fields.h LineType) on a value.
bool has_line_type(const nlohmann::json& value, log_fields::LineType type) {
  using log_fields::LineType;
  const auto number_or_null = [](const nlohmann::json& element) { return element.is_number() || element.is_null(); };
  switch (type) {
    case LineType::small_int:
      return is_small_int(value);
    case LineType::string:
      return value.is_string();
    case LineType::boolean:
      return value.is_boolean();
    case LineType::number_or_null:
      return number_or_null(value);
    case LineType::small_int_array:
      return value.is_array() && std::all_of(value.begin(), value.end(), is_small_int);
    case LineType::number_or_null_array:
      return value.is_array() && std::all_of(value.begin(), value.end(), number_or_null);
    case LineType::numbers_lenient:
    case LineType::invalid_gaze_lenient:
      return true;  // no type check (Scan::kept)
  }
  return true;
}

}  // namespace

namespace log_fields {

const std::vector<ScannedKey>& scanned_keys() {
  static const std::vector<ScannedKey> keys = [] {
    std::vector<ScannedKey> found;
    std::vector<std::string_view> untyped;  // keys of rows the scan does not read
    const auto add_rows = [&](auto tag) {
      using Event = typename decltype(tag)::type;
      for_each_field<Event>([&](const auto& row) {
        const std::string_view key = row.key;
        const auto same = [&](const ScannedKey& known) { return known.key == key; };
        const auto known = std::find_if(found.begin(), found.end(), same);
        if (row.scan == Scan::no) {
          if (known != found.end())
            throw std::logic_error(std::string("log_event_fields.h: ") + row.key +
                                   " is read by the scan in one event, not in another");
          untyped.push_back(key);
          return;
        }
        const std::optional<LineType> type = line_type(row);
        if (!type)
          throw std::logic_error(std::string("log_event_fields.h: ") + row.key + " is scanned but has no line type");
        const ScannedKey scanned{key, *type, row.scan};
        if (std::find(untyped.begin(), untyped.end(), key) != untyped.end())
          throw std::logic_error(std::string("log_event_fields.h: ") + row.key +
                                 " is read by the scan in one event, not in another");
        if (known == found.end()) found.push_back(scanned);
        else if (known->type != scanned.type || known->scan != scanned.scan)
          throw std::logic_error(std::string("log_event_fields.h: ") + row.key + " has two types in two events");
      });
    };
    std::apply([&](auto... tags) { (add_rows(tags), ...); },
               []<typename... Events>(std::type_identity<std::variant<Events...>>) {
                 return std::tuple<Of<Events>...>{};
               }(std::type_identity<LogEvent>{}));
    return found;
  }();
  return keys;
}

int scanned_key_index(std::string_view key) {
  // By the key's first letter, then the few keys that start with it: the scan asks this for about
  // ten keys a line, most of them not scanned, so each is compared with two or three names, not twenty.
  static const std::array<std::vector<int>, 128> by_first_letter = [] {
    std::array<std::vector<int>, 128> buckets;
    const std::vector<ScannedKey>& keys = scanned_keys();
    for (size_t i = 0; i < keys.size(); ++i)
      buckets[static_cast<unsigned char>(keys[i].key.front()) % 128].push_back(int(i));
    return buckets;
  }();
  if (key.empty() || static_cast<unsigned char>(key.front()) >= 128) return -1;
  const std::vector<ScannedKey>& keys = scanned_keys();
  for (const int i : by_first_letter[static_cast<unsigned char>(key.front())])
    if (keys[i].key == key) return i;
  return -1;
}

}  // namespace log_fields

namespace {

std::optional<GazeSourceKind> logged_gaze_kind(const nlohmann::json& gaze_source, const std::string& gaze) {
  if (gaze_source.is_object()) {
    const auto kind = gaze_source.find("kind");
    if (kind != gaze_source.end() && kind->is_string()) return parse_gaze_source_kind(kind->get<std::string>());
  }
  return gaze_source_kind_of_spec(gaze);
}

}  // namespace

std::vector<GazeSourceKind> session_gaze_kinds(const nlohmann::json& header,
                                               const std::vector<SessionResumedEvent>& resumes) {
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

// ---- every event: its table (log_event_fields.h) written and read ----

nlohmann::json to_json(const SessionHeaderEvent& event) { return event_json(event); }
nlohmann::json to_json(const SessionResumedEvent& event) { return event_json(event); }
nlohmann::json to_json(const InstructionsEvent& event) { return event_json(event); }
nlohmann::json to_json(const BlockStartEvent& event) { return event_json(event); }
nlohmann::json to_json(const BreakEvent& event) { return event_json(event); }
nlohmann::json to_json(const TrialStartEvent& event) { return event_json(event); }
nlohmann::json to_json(const StimulusEvent& event) { return event_json(event); }
nlohmann::json to_json(const ResponseEvent& event) { return event_json(event); }
nlohmann::json to_json(const SliderSavedEvent& event) { return event_json(event); }
nlohmann::json to_json(const AttentionCheckEvent& event) { return event_json(event); }
nlohmann::json to_json(const TrialEndEvent& event) { return event_json(event); }
nlohmann::json to_json(const ExcludedEvent& event) { return event_json(event); }
nlohmann::json to_json(const TrackerValidationEvent& event) { return event_json(event); }
nlohmann::json to_json(const SessionPausedEvent& event) { return event_json(event); }
nlohmann::json to_json(const SessionEndEvent& event) { return event_json(event); }
nlohmann::json to_json(const SealEvent& event) { return event_json(event); }

SessionHeaderEvent parse_session_header(const nlohmann::json& json, FieldCheck check) {
  return parse_event<SessionHeaderEvent>(json, check);
}
SessionResumedEvent parse_session_resumed(const nlohmann::json& json, FieldCheck check) {
  return parse_event<SessionResumedEvent>(json, check);
}
InstructionsEvent parse_instructions(const nlohmann::json& json, FieldCheck check) {
  return parse_event<InstructionsEvent>(json, check);
}
BlockStartEvent parse_block_start(const nlohmann::json& json, FieldCheck check) {
  return parse_event<BlockStartEvent>(json, check);
}
BreakEvent parse_break(const nlohmann::json& json, FieldCheck check) { return parse_event<BreakEvent>(json, check); }
TrialStartEvent parse_trial_start(const nlohmann::json& json, FieldCheck check) {
  return parse_event<TrialStartEvent>(json, check);
}
StimulusEvent parse_stimulus(const nlohmann::json& json, FieldCheck check) {
  return parse_event<StimulusEvent>(json, check);
}
ResponseEvent parse_response(const nlohmann::json& json, FieldCheck check) {
  return parse_event<ResponseEvent>(json, check);
}
SliderSavedEvent parse_slider_saved(const nlohmann::json& json, FieldCheck check) {
  return parse_event<SliderSavedEvent>(json, check);
}
AttentionCheckEvent parse_attention_check(const nlohmann::json& json, FieldCheck check) {
  return parse_event<AttentionCheckEvent>(json, check);
}
TrialEndEvent parse_trial_end(const nlohmann::json& json, FieldCheck check) {
  return parse_event<TrialEndEvent>(json, check);
}
ExcludedEvent parse_excluded(const nlohmann::json& json, FieldCheck check) {
  return parse_event<ExcludedEvent>(json, check);
}
TrackerValidationEvent parse_tracker_validation(const nlohmann::json& json, FieldCheck check) {
  return parse_event<TrackerValidationEvent>(json, check);
}
SessionPausedEvent parse_session_paused(const nlohmann::json& json, FieldCheck check) {
  return parse_event<SessionPausedEvent>(json, check);
}
SessionEndEvent parse_session_end(const nlohmann::json& json, FieldCheck check) {
  return parse_event<SessionEndEvent>(json, check);
}
SealEvent parse_seal(const nlohmann::json& json, FieldCheck check) { return parse_event<SealEvent>(json, check); }

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
  const std::vector<log_fields::ScannedKey>& scanned = log_fields::scanned_keys();
  for (const auto& [key, value] : event.items()) {
    bool ok = true;
    if (key == k::event) {
      ok = value.is_string();
    } else if (const int index = log_fields::scanned_key_index(key); index >= 0) {
      if (scanned[index].scan == log_fields::Scan::typed) ok = has_line_type(value, scanned[index].type);
    }
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
