#pragma once
// The session log: results/<study>/<participant>/events.jsonl, one JSON object a line
// (docs/log-schema.md). Every event is written with one write(2), then fsync'd before append()
// returns, so what a participant did is on disk the moment it happens. Each event carries its
// sequence number "seq" and "chain": SHA-256 of the previous event's chain and this event's text
// without "chain" (schema 1 logs: FNV-1a-64), so an edited, dropped or reordered line is detected;
// `seal` events (log_integrity.h) close each run of the session, keyed with a lab key if given.
#include <sys/types.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/input_error.h"

namespace fovlab {

// 4: every displayed frame sRGB8-encoded on the GPU by one encoder (the hashes of gt, ipr and fipr
// frames in schema 1-3 logs came from a CPU encoder, which may round a channel the other way);
// the header's display names the presenting device and the frames' path to it.
// 5: FIPR's periphery_reconstruction is new, default bilinear; a config that a schema 1-4 log carries
// reads a missing one as mid-footprint-bilinear, what those logs showed (render_method.h
// default_in_log_schema).
// 6: FIPR's near_misses is new, default promote; a config that a schema 1-5 log carries reads a
// missing one as ignore, what those logs showed.
// 8: the sampling models' equalise "on" means equal shaded samples to RMFR's (and kfr has
// equalise); a config that a schema 1-7 log carries reads "on" as the theoretical density, what those
// logs showed (render_method.h ParameterDescriptor::choice_alias).
// 9: the sampling models on a folder of the lab's images (img-rmfr, ...); the header of a session
// that shows them records each image's SHA-256 (image_hashes), which replay checks.
// 10: IPR's and FIPR's coarse_test defaults to cone (thin geometry kept), their min_filter_size to 1
// (the cone makes it redundant), FIPR's edge_depth (new) to centre-ray; a config that a schema 1-9
// log carries reads a missing one as ray, 3 and level, what those logs showed.
// 11: a session in a headset ([display] kind = "openxr"): the header's `headset` (the runtime, each
// eye's size and view, the gaze's fixation) and each stimulus event's right_eye_hash and
// right_eye_gaze beside the left eye's hash and gaze. Nothing else changed: a desktop log of schema
// 11 reads as one of 10.
// 12 (headset sessions, issue 42): a head-tracked session (headset.view_model "head-tracked") logs
// the header's headset.head_reference (the head's pose in LOCAL at the start) and each stimulus
// event's head_pose (a refresh's head relative to it, as rendered); a headset session logs each
// stimulus event's late_frames (its refreshes whose xrEndFrame came after their predicted display
// time) and the header's headset.late_frames_measured (a log without them: schema 1-11, or a
// runtime without XR_KHR_convert_timespec_time, counts none). Desktop logs are unchanged.
// 13 (headset sessions, issue 42): each stimulus event marks the right eye's refreshes shown with a
// held gaze (right_eye_invalid_gaze, as invalid_gaze marks the left's), so the report gives the
// right eye's own share; a schema 11-12 log did not record them. Desktop logs are unchanged.
inline constexpr int log_schema_version = 13;        // what this build writes
inline constexpr int oldest_log_schema_version = 1;  // the oldest it reads (resume needs the current one)

// The schema_version a session header states, or 0 when it states none this build could read
// (absent, not an integer, or outside oldest..current: 2^32 + 6 is not read as 6).
int header_schema_version(const nlohmann::json& header);

struct LabKey;

class EventLogWriter {
 public:
  // Opens for appending (creating it when missing; never through a symbolic link). `previous_chain`
  // and `next_seq` continue an existing log (resume); a new log starts with "" and 0. `lab_key`
  // (may be null) keys the seals; it must outlive the writer. The caller holds the participant's
  // lock (participant_lock.h), so no second writer exists.
  EventLogWriter(const std::string& path, std::string previous_chain, int64_t next_seq,
                 const LabKey* lab_key = nullptr);
  ~EventLogWriter();
  EventLogWriter(const EventLogWriter&) = delete;
  EventLogWriter& operator=(const EventLogWriter&) = delete;

  // Adds "seq", "chain" and, with a lab key, "mac"; writes the line and fsyncs. A `seal` event also
  // gets "last_chain". On failure (a full disk...) the file is cut back to what it was, so no
  // partial line is left, and FileError says which operation failed and why.
  // After each fsync the log's name must still lead to the file this writer holds open: when another
  // program replaced or removed it (a rename onto it, an editor's save), every event this writer's
  // file holds is copied from the open descriptor to events.jsonl.recovered-N beside it (fsync'd),
  // and an InputError says where; the session stops there. The next run of the participant
  // resumes from that copy (protocols/session/session.cpp). A log written over in place (the same
  // file, another size) stops the session too, the file left as it is.
  void append(nlohmann::json event);
  const std::string& path() const { return path_; }
  double seconds_writing() const { return seconds_writing_; }  // time in write + fsync so far

 private:
  // Throws InputError (after the copy) when the log's name no longer leads to fd_'s file, or when
  // the file is no longer the size this writer made it.
  void check_still_named();

  std::string path_;
  int fd_ = -1;
  dev_t device_ = 0;  // of the file opened: the name must keep leading to it
  ino_t inode_ = 0;
  off_t size_ = 0;  // bytes on disk, all complete lines
  std::string chain_;
  int64_t next_seq_ = 0;
  const LabKey* lab_key_ = nullptr;
  double seconds_writing_ = 0.0;
};

// The chain value of an event (given the previous chain) in a log of this schema version, as the
// writer computes it: FNV-1a-64 in schema 1, else SHA-256 (hex), of the previous chain followed by
// the event's text without "chain" and "mac" (keys sorted, as nlohmann::json writes them).
std::string chain_of_text(const std::string& previous_chain, std::string_view text, int schema_version);
std::string event_chain(const std::string& previous_chain, const nlohmann::json& event_without_chain,
                        int schema_version = log_schema_version);

// The largest log a reader takes (a 216-trial FIPR session logs about 5 MB): a bigger file, or one
// that is not a regular file, is refused before it is read (core/input_file.h, which both readers
// use), so a forged or runaway file cannot exhaust memory.
inline constexpr uint64_t max_log_bytes = uint64_t{1} << 30;
inline constexpr const char* session_log_kind = "a session log (events.jsonl)";

// Events nest 3 levels deep and a header's config 4; a line with an array or object deeper than
// this (the line's own object is level 1) is refused by every reader, whichever field it is in, and
// no reader recurses deeper (log_lines.h: a line of a million '[' cannot overflow the stack).
inline constexpr int max_event_nesting = 32;
// A UTF-8 byte-order mark at the start of a log (an editor put it there; fovlab writes none) is
// skipped by every reader: the length to skip.
size_t byte_order_mark_length(std::string_view bytes);

struct EventLogFile {
  std::string path;
  std::vector<nlohmann::json> events;    // every complete, parsed line, in order
  std::vector<int> line_numbers;         // of each event (1-based)
  std::optional<std::string> torn_tail;  // bytes after the last newline: a write the crash cut short
  int schema_version = 0;                // of the header (0: none readable); says how the chain is made
  uint64_t intact_bytes = 0;             // length of the file up to and including the last newline
  int first_chain_error_line = 0;        // 0 when every seq/chain is consistent
  std::string last_chain;                // chain of the last event ("" when none)
  std::string header_chain;              // the session's identity (log_lines.h EventChain::header_chain)
};

// Reads a log, line by line as the fast scan does (log_lines.h: the same grammar, nesting cap and
// seq/chain rule). A line that is not one JSON object, or nests deeper than max_event_nesting, is
// an error: InputError("path:LINE: not a JSON event (...)"); an unterminated last line is returned
// as torn_tail, never parsed. A missing file is an InputError too.
EventLogFile read_event_log(const std::string& path);
// A log file itself, or every results/<study>/<participant>/events.jsonl under a folder (sorted).
// Throws InputError when there is none.
std::vector<std::string> find_session_logs(const std::string& path);

// The same from bytes already in memory (the fuzz target uses this).
EventLogFile parse_event_log(const std::string& bytes, const std::string& path_for_messages);

}  // namespace fovlab
