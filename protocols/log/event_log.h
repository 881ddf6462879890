#pragma once
// The session log: results/<study>/<participant>/events.jsonl, one JSON object a line
// (docs/log-schema.md). Every event is written with one write(2), then fsync'd before append()
// returns, so what a participant did is on disk the moment it happens. Each event carries its
// sequence number "seq" and "chain": FNV-1a-64 of the previous event's chain and this event's text
// without "chain", so an edited, dropped or reordered line is detected (accidental damage or a naive
// edit, not a determined forger: FNV is not a cryptographic hash).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace fovlab {

inline constexpr int log_schema_version = 1;

class EventLogWriter {
 public:
  // Opens for appending (creating it when missing). `previous_chain`/`next_seq` continue an
  // existing log (resume); a new log starts with "" and 0.
  EventLogWriter(const std::string& path, std::string previous_chain, int64_t next_seq);
  ~EventLogWriter();
  EventLogWriter(const EventLogWriter&) = delete;
  EventLogWriter& operator=(const EventLogWriter&) = delete;

  // Adds "seq" and "chain", writes the line and fsyncs. Throws std::runtime_error on I/O failure.
  void append(nlohmann::json event);
  const std::string& path() const { return path_; }
  double seconds_writing() const { return seconds_writing_; }  // time in write + fsync so far

 private:
  std::string path_;
  int fd_ = -1;
  std::string chain_;
  int64_t next_seq_ = 0;
  double seconds_writing_ = 0.0;
};

// The chain value of an event (given the previous chain), as the writer computes it.
std::string event_chain(const std::string& previous_chain, const nlohmann::json& event_without_chain);

struct EventLogFile {
  std::string path;
  std::vector<nlohmann::json> events;   // every complete, parsed line, in order
  std::vector<int> line_numbers;        // of each event (1-based)
  std::optional<std::string> torn_tail; // bytes after the last newline: a write the crash cut short
  uint64_t intact_bytes = 0;            // length of the file up to and including the last newline
  int first_chain_error_line = 0;       // 0 when every seq/chain is consistent
  std::string last_chain;               // chain of the last event ("" when none)
};

// Reads a log. A line that is not a JSON object in the middle of the file is an error:
// InputError("path:LINE: not a JSON event (...)"); an unterminated last line is returned as
// torn_tail, never parsed. A missing file is an InputError too.
EventLogFile read_event_log(const std::string& path);
// A log file itself, or every results/<study>/<participant>/events.jsonl under a folder (sorted).
// Throws InputError when there is none.
std::vector<std::string> find_session_logs(const std::string& path);

// The same from bytes already in memory (the fuzz target uses this).
EventLogFile parse_event_log(const std::string& bytes, const std::string& path_for_messages);

}  // namespace fovlab
