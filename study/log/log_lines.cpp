#include "study/log/log_lines.h"

#include <algorithm>

#include "core/input_error.h"
#include "study/log/event_log.h"
#include "study/log/log_events.h"

namespace fovlab {

LogLines::LogLines(const char* data, size_t size, size_t readable, std::string path)
    : data_(data), size_(size), readable_(std::max(readable, size)), path_(std::move(path)) {
  const size_t last_newline = std::string_view(data_, size_).rfind('\n');
  intact_ = last_newline == std::string_view::npos ? 0 : last_newline + 1;
  next_begin_ = byte_order_mark_length(std::string_view(data_, intact_));
}

bool LogLines::next() {
  if (next_begin_ >= intact_) return false;
  begin_ = next_begin_;
  end_ = std::string_view(data_, intact_).find('\n', begin_);
  next_begin_ = end_ + 1;
  ++number_;
  return true;
}

void LogLines::fail(const std::string& what) const {
  throw InputError(path_ + ":" + std::to_string(number_) + ": " + what);
}

void LogLines::not_an_event() const { fail("not a JSON event (expected one JSON object a line)"); }

void LogLines::too_deep() const {
  fail("not a session event (nested deeper than " + std::to_string(max_event_nesting) + " levels)");
}

simdjson::ondemand::object LogLines::iterate(simdjson::ondemand::parser& parser, simdjson::ondemand::document& document,
                                             std::string& padded) {
  const size_t length = end_ - begin_;
  simdjson::error_code error;
  if (begin_ + length + simdjson::SIMDJSON_PADDING <= readable_) {
    error = parser.iterate(data_ + begin_, length, readable_ - begin_).get(document);
  } else {
    padded.assign(data_ + begin_, length);
    padded.append(simdjson::SIMDJSON_PADDING, ' ');
    error = parser.iterate(padded.data(), length, padded.size()).get(document);
  }
  simdjson::ondemand::object object;
  if (error || document.get_object().get(object)) not_an_event();
  return object;
}

void LogLines::expect_end_of(simdjson::ondemand::document& document) {
  // In bounds after the object: something follows it ("{...}{...}").
  if (document.current_location().error() == simdjson::SUCCESS) not_an_event();
}

simdjson::ondemand::object LogLines::object() { return iterate(parser_, document_, padded_); }

void LogLines::expect_end() { expect_end_of(document_); }

nlohmann::json LogLines::whole_event() {
  nlohmann::json event = nlohmann::json::object();
  for (auto field : iterate(whole_parser_, whole_document_, whole_padded_)) {
    std::string_view key;
    simdjson::ondemand::value value;
    if (field.unescaped_key().get(key) || field.value().get(value)) not_an_event();
    check_value(value, 2, &event[std::string(key)]);
  }
  expect_end_of(whole_document_);
  return event;
}

void LogLines::check_value(simdjson::ondemand::value value, int depth, nlohmann::json* out) {
  simdjson::ondemand::json_type type;
  if (value.type().get(type)) not_an_event();
  switch (type) {
    case simdjson::ondemand::json_type::object: {
      if (depth > max_event_nesting) too_deep();
      simdjson::ondemand::object object;
      if (value.get_object().get(object)) not_an_event();
      if (out) *out = nlohmann::json::object();
      for (auto field : object) {
        std::string_view key;
        simdjson::ondemand::value member;
        if (field.unescaped_key().get(key) || field.value().get(member)) not_an_event();
        check_value(member, depth + 1, out ? &(*out)[std::string(key)] : nullptr);
      }
      return;
    }
    case simdjson::ondemand::json_type::array: {
      if (depth > max_event_nesting) too_deep();
      simdjson::ondemand::array array;
      if (value.get_array().get(array)) not_an_event();
      if (out) *out = nlohmann::json::array();
      for (auto element : array) {
        simdjson::ondemand::value item;
        if (element.get(item)) not_an_event();
        if (out) {
          out->push_back(nullptr);
          check_value(item, depth + 1, &out->back());
        } else {
          check_value(item, depth + 1);
        }
      }
      return;
    }
    case simdjson::ondemand::json_type::number: {
      // As nlohmann::json reads numbers: an integer >= 0 unsigned, a negative one signed, else a double.
      simdjson::ondemand::number number;
      if (value.get_number().get(number)) not_an_event();
      if (!out) return;
      switch (number.get_number_type()) {
        case simdjson::ondemand::number_type::signed_integer:
          if (number.get_int64() >= 0) *out = static_cast<uint64_t>(number.get_int64());
          else *out = number.get_int64();
          return;
        case simdjson::ondemand::number_type::unsigned_integer:
          *out = number.get_uint64();
          return;
        case simdjson::ondemand::number_type::floating_point_number:
          *out = number.get_double();
          return;
      }
      return;
    }
    case simdjson::ondemand::json_type::string: {
      std::string_view text;
      if (value.get_string().get(text)) not_an_event();
      if (out) *out = std::string(text);
      return;
    }
    case simdjson::ondemand::json_type::boolean: {
      bool flag = false;
      if (value.get_bool().get(flag)) not_an_event();
      if (out) *out = flag;
      return;
    }
    case simdjson::ondemand::json_type::null: {
      bool is_null = false;
      if (value.is_null().get(is_null) || !is_null) not_an_event();
      if (out) *out = nullptr;
      return;
    }
  }
  not_an_event();
}

namespace {

// The start of a member whose value is a string: "\"chain\":\"".
std::string member_start(const char* name) { return "\"" + std::string(name) + "\":\""; }
const std::string chain_member = member_start(log_keys::chain);
const std::string mac_member = member_start(log_keys::mac);

// `text` without its member `member` + `<digits hex characters>"` (and the comma joining it), or
// false when there is none of that shape.
bool cut_member(std::string_view text, const std::string& member, size_t digits, std::string& out) {
  const size_t at = text.find(member);
  if (at == std::string_view::npos || at + member.size() + digits + 1 > text.size()) return false;
  size_t begin = at, end = at + member.size() + digits + 1;  // the hex digits and the closing quote
  if (begin > 0 && text[begin - 1] == ',') --begin;
  else if (end < text.size() && text[end] == ',') ++end;
  out.assign(text.substr(0, begin)).append(text.substr(end));
  return true;
}

}  // namespace

void EventChain::line(LogLines& lines, std::optional<int64_t> seq, std::optional<std::string_view> recorded_chain,
                      bool has_mac, int schema_version, const nlohmann::json* event) {
  if (first_error_line_) return;
  const size_t digits = schema_version == 1 ? 16 : 64;
  bool consistent = seq && *seq == lines.number() - 1 && recorded_chain && recorded_chain->size() == digits;
  if (consistent) {
    // Fast: the line's own text with its chain (and mac) cut out, as the writer hashed it.
    std::string expected;
    const std::string_view text = lines.text();
    if (cut_member(text, chain_member, digits, scratch_) &&
        (!has_mac || cut_member(scratch_, mac_member, 64, scratch_mac_)))
      expected = chain_of_text(chain_, has_mac ? scratch_mac_ : scratch_, schema_version);
    if (expected != *recorded_chain) {
      // A line not in the writer's canonical form: its canonical text.
      nlohmann::json canonical = event ? *event : lines.whole_event();
      canonical.erase(log_keys::chain);
      canonical.erase(log_keys::mac);
      expected = event_chain(chain_, canonical, schema_version);
    }
    consistent = expected == *recorded_chain;
    if (consistent) chain_ = std::move(expected);
  }
  if (!consistent) first_error_line_ = lines.number();
  else if (lines.number() == 1) header_chain_ = chain_;
}

}  // namespace fovlab
