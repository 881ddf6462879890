#pragma once
// The line level of a session log (docs/log-schema.md), one piece of code under both of its
// readers: the full reader (event_log.h parse_event_log: resume, replay, export) and the fast scan
// (session_scan.h: analyze). Where a line begins and ends, the byte-order mark, the torn tail, the
// JSON grammar (simdjson; every value of a line is checked, whether a reader keeps it or not), the
// nesting cap, "one JSON object a line" and the seq/chain rule are decided here once; a reader only
// chooses which fields it keeps (the full reader all of them, as nlohmann::json; the scan a few).
// So a line one reader refuses, the other refuses too, with the same words.
#include <simdjson.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace fovlab {

class LogLines {
 public:
  // `size` bytes of a log at `data`, readable up to `readable` (>= size) bytes from `data`: simdjson
  // reads up to SIMDJSON_PADDING bytes past a line, so a line closer than that to `readable` is
  // copied into a padded buffer of its own first. `path` names the log in messages.
  LogLines(const char* data, size_t size, size_t readable, std::string path);
  LogLines(const LogLines&) = delete;
  LogLines& operator=(const LogLines&) = delete;

  // Moves to the next complete line (a byte-order mark at the start skipped, the torn tail never a
  // line); false after the last.
  bool next();
  int number() const { return number_; }  // of the current line, 1-based
  std::string_view text() const { return {data_ + begin_, end_ - begin_}; }
  size_t intact_bytes() const { return intact_; }  // up to and including the last newline
  size_t torn_tail_bytes() const { return size_ - intact_; }
  const std::string& path() const { return path_; }

  // The current line's JSON object, to iterate once (simdjson On-Demand; a reader reads the fields
  // it keeps and passes every other value to check_value). Throws not_an_event() when the line is
  // not an object.
  simdjson::ondemand::object object();
  // After the object's last field: throws not_an_event() when anything but white space follows it.
  void expect_end();
  // The whole current line as nlohmann::json, every value checked as check_value does, then
  // expect_end(): what the full reader keeps of every line, and the scan of a few (the header, a
  // seal). Reads the line with a parser of its own, so what object() gave stays valid.
  nlohmann::json whole_event();
  // A value at nesting level `depth` (the line's object is level 1, its members' arrays and objects
  // level 2, ...): every part of it checked as JSON (numbers, literals, strings, commas), and no
  // array or object deeper than max_event_nesting. Copied into `out` when it is given. Throws
  // not_an_event() or too_deep().
  void check_value(simdjson::ondemand::value value, int depth, nlohmann::json* out = nullptr);

  // InputError "PATH:LINE: WHAT".
  [[noreturn]] void fail(const std::string& what) const;
  [[noreturn]] void not_an_event() const;  // "not a JSON event (expected one JSON object a line)"
  [[noreturn]] void too_deep() const;      // "not a session event (nested deeper than 32 levels)"

 private:
  const char* data_;
  size_t size_, readable_, intact_;
  std::string path_;
  // The current line as a document of `parser` (its copy in `padded` when it lies near the end of
  // what is readable), as an object.
  simdjson::ondemand::object iterate(simdjson::ondemand::parser& parser, simdjson::ondemand::document& document,
                                     std::string& padded);
  void expect_end_of(simdjson::ondemand::document& document);

  size_t begin_ = 0, end_ = 0, next_begin_ = 0;
  int number_ = 0;
  simdjson::ondemand::parser parser_, whole_parser_;  // object(); whole_event()
  simdjson::ondemand::document document_, whole_document_;
  std::string padded_, whole_padded_;  // a line near the end of what is readable, with room for simdjson's padding
};

// The seq/chain rule (event_log.h): every event carries "seq", its position in the log (0 for the
// header), and "chain", the hash of the previous event's chain and the event's canonical text
// without "chain" and "mac" (FNV-1a-64 in schema 1 logs, SHA-256 since). The first line where
// either does not hold is where the log's chain breaks; nothing after it is computed.
class EventChain {
 public:
  // A line: its text, its "seq" (nullopt: absent, or not an integer), its "chain" (nullopt: absent,
  // or not a string) and whether it has a string "mac". The canonical text is the line's own with
  // its chain and mac members cut out when that reproduces the recorded chain (the writer's text is
  // canonical), else the whole event (`event`, or `lines.whole_event()` when null) without them,
  // written by nlohmann::json (a line re-formatted by hand). `schema_version` says which hash (the
  // header's; 0: none readable).
  void line(LogLines& lines, std::optional<int64_t> seq, std::optional<std::string_view> recorded_chain, bool has_mac,
            int schema_version, const nlohmann::json* event = nullptr);
  int first_error_line() const { return first_error_line_; }  // 0 while every line holds
  const std::string& last_chain() const { return chain_; }    // of the last line checked ("" before any)
  // The header's chain: it commits the header's whole text (study, participant, seeds, config, start
  // time, device...), so it names the session: two logs whose first lines have the same chain are
  // logs of one session. "" when the header's own chain does not hold.
  const std::string& header_chain() const { return header_chain_; }

 private:
  std::string chain_, header_chain_, scratch_, scratch_mac_;
  int first_error_line_ = 0;
};

}  // namespace fovlab
