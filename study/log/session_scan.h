#pragma once
// A fast read of a session log for analysing many of them (fovlab analyze reads a million trials):
// every line is still checked as the full reader checks it (the line level is one piece of code
// under both, log_lines.h: the JSON grammar of every value, the nesting cap, one object a line, its
// seq, the hash chain), but only the fields a trial summary needs are decoded (the rows the event
// tables mark for the scan, log_event_fields.h, into the same structs), with simdjson's
// On-Demand API; of the per-refresh arrays of stimulus events only the gaze ages, the present
// times' intervals and the invalid gaze marks' reasons (and the acquisition times, for their types)
// are kept, the rest checked and dropped, never built. Trials are assembled by the rules of session_record.h
// (complete at trial_end; a session_resumed drops the trial a crash cut off);
// tests/study/log/session_scan_test.cpp checks that both readers agree on every protocol.
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "study/log/log_events.h"
#include "study/log/log_integrity.h"

namespace fovlab {

struct ScannedTrial {
  int index = 0;
  int line = 0;  // of its trial_start
  int block = 0;
  std::string condition;
  std::string variant;
  std::optional<double> level;
  bool attention_check = false;
  std::optional<bool> reference_first;  // as logged (none: the protocol has no interval order)
  bool ramp_toward_reference = true;
  bool practice = false;                  // a practice trial (never analysed)
  std::optional<int> track;               // an adaptive trial: its track in the schedule
  std::vector<int> sequence;              // stimulus ids in presentation order
  std::vector<std::string> answers;       // response events, in order
  std::vector<int> answer_steps;          // their `step`
  std::optional<double> saved_level;      // slider_saved
  std::optional<bool> attention_correct;  // attention_check
  // Of the trial's stimulus events: every refresh's gaze sample age at present time, in seconds
  // (schema 3; refreshes without a sample, null in the log, left out), the refresh periods missed,
  // and how many of those events recorded ages at all (0 in schema 1-2 logs: not recorded).
  std::vector<double> gaze_age_s;
  int64_t dropped_frames = 0;
  int stimuli_with_latency = 0;
  // Schema 12, a headset session whose runtime measured them: the refreshes ended after their
  // predicted display time (the stimulus events' late_frames); nullopt: none of its events says.
  std::optional<int64_t> late_frames;
  // The gaze of its stimulus events' refreshes (present_s entries): how many there were, and how many
  // of those the log marks invalid (invalid_gaze, the left eye's sample in a headset), split into the
  // ones whose pixel fell off the image ("off_screen") and the rest (no sample, not tracked, not
  // finite); a headset's right eye likewise (right_eye_invalid_gaze, schema 13: none before).
  int64_t gaze_refreshes = 0;
  int64_t gaze_off_image = 0;
  int64_t gaze_invalid_other = 0;
  int64_t right_gaze_off_image = 0;
  int64_t right_gaze_invalid_other = 0;
  // The intervals between consecutive refreshes of each stimulus event (its present_s: every
  // schema), in seconds; the gap between two stimuli is not one.
  std::vector<double> frame_interval_s;
};

struct ScannedSession {
  std::string path;
  nlohmann::json header;                   // the first event, whole
  std::map<int, std::string> block_names;  // block index -> name, or its scene when unnamed
  std::vector<ScannedTrial> trials;        // complete trials, ordered by index, one per index
  int attention_errors = 0;                // wrong attention-check answers in complete trials
  bool excluded = false;
  bool ended = false;
  std::string end_reason;                           // of the last session_end ("completed", "excluded")
  int end_line = 0;                                 // its line
  int incomplete_trial = -1;                        // a trial started but not finished at the end of the log
  size_t torn_tail_bytes = 0;                       // bytes after the last newline (never read)
  std::vector<TrackerValidationEvent> validations;  // every eye-tracker validation attempt, in log order
  std::vector<SessionResumedEvent> resumes;         // every session_resumed, in log order (their gaze sources)
  std::vector<std::string> present_clocks;          // the stimulus events' present_clock values, first seen first
  int first_chain_error_line = 0;                   // 0 when every seq/chain is consistent
  int line_count = 0;                               // complete lines
  std::string header_chain;                         // the session's identity (log_lines.h EventChain::header_chain)
  LogIntegrity integrity;                           // sealed, unsealed or broken (log_integrity.h)
};

// Throws InputError "path:LINE: ..." for what read_event_log and read_session_record reject (a line
// that is not one JSON object, no session header, another schema version, a trial event outside
// its trial, a field of the wrong type).
// `lab_key` (may be null) checks the seals' MACs of a keyed log.
ScannedSession scan_session_log(const std::string& path, const LabKey* lab_key = nullptr);
// The chain of every line of the log at `path`, in order, up to the first line whose seq or chain
// does not hold (session_copies.h compares logs of one session with it). Throws as
// scan_session_log does.
std::vector<std::string> scan_line_chains(const std::string& path);
// The same from bytes already in memory (the fuzz target and the corpus replay use this).
ScannedSession scan_session_bytes(const std::string& bytes, const std::string& path_for_messages,
                                  const LabKey* lab_key = nullptr);

}  // namespace fovlab
