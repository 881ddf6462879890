#pragma once
// How large a session's log (events.jsonl) of a plan can grow, so that a study whose log the readers
// could not take back (max_log_bytes, study/log/event_log.h: 1 GiB) is refused before it runs, by
// `fovlab validate`, rather than after hundreds of thousands of trials.
//
// The estimate is an upper bound built from the widths of the logged fields (docs/log-schema.md),
// each at its widest: every event's seq, t, chain and a lab key's mac (260 bytes); a stimulus event's
// arrays, 140 bytes a refresh (its present time, animation frame, hash, gaze, gaze time and age at
// 17 significant digits, and an invalid-gaze entry); a trial's start, answers and end; the header
// (the config's and conditions file's text, escaped, and every planned stimulus). A slider trial is
// counted at two actions a ladder step (the participant decides how many). Logs of every protocol
// stay below it (StudyCli.LogsOfEveryProtocolStayWithinTheEstimate, tests/app/study_cli_test.cpp,
// compares it with real sessions' logs). Not counted: what a stopped and resumed session adds
// (pause, resume and seal events, the interrupted trial run again), a few kilobytes a stop.
#include <cstdint>
#include <string>

#include "study/schedule/study_plan.h"

namespace fovlab {

struct LogSizeEstimate {
  uint64_t bytes = 0;               // the whole log at most
  uint64_t widest_trial_bytes = 0;  // the largest trial's events at most
};

LogSizeEstimate estimate_log_size(const StudyPlan& plan);

// InputError when the estimate exceeds max_log_bytes, one line: "<source>: 4500000 trials: a
// session's log would take up to N bytes (estimated from the plan), more than the N bytes (1 GiB) the
// log readers take (max_log_bytes); expected fewer trials ([protocol] repeats, the conditions),
// shorter stimuli ([stimulus] duration_s) or a lower [display] refresh_hz".
void check_log_fits_readers(const StudyPlan& plan, const std::string& source);

}  // namespace fovlab
