#pragma once
// A session as its log tells it: the header, the complete trials (trial_start ... trial_end), and
// the state a resumed session continues from. Events of a trial that was cut off by a crash are not
// part of any complete trial; the resumed session runs that trial again.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "study/log/event_log.h"
#include "study/log/log_events.h"
#include "study/log/log_integrity.h"

namespace fovlab {

// The trial's events, typed (log_events.h). Fields the shared type checks do not cover
// (check_log_field_types) are read leniently: a value of the wrong type there is left at its default.
struct RecordedTrial {
  int index = 0;
  int line = 0;  // of its trial_start
  TrialStartEvent start;
  std::vector<StimulusEvent> stimuli;    // in order
  std::vector<ResponseEvent> responses;  // in order
  std::optional<AttentionCheckEvent> attention_check;
  std::vector<SliderSavedEvent> slider_saved;  // slider trials: one
  std::vector<BreakEvent> breaks;              // attention-check breaks
  TrialEndEvent end;
};

struct SessionRecord {
  nlohmann::json header;                            // the first event (session_header), as logged
  std::vector<BlockStartEvent> blocks;              // every block_start, in log order
  std::vector<TrackerValidationEvent> validations;  // every eye-tracker validation attempt, in log order
  std::vector<SessionResumedEvent> resumes;         // every session_resumed, in log order (their gaze sources)
  std::vector<RecordedTrial> trials;                // complete trials, ordered by index, one per index
  int attention_errors = 0;                         // wrong attention-check answers in complete trials
  bool excluded = false;
  bool ended = false;  // a session_end event exists
  std::string end_reason;
  int end_line = 0;           // of the last session_end
  int next_trial = 0;         // the first trial index with no complete record
  double last_time_s = 0.0;   // the latest session time in the log
  int incomplete_trial = -1;  // a trial started but not finished at the end of the log
  LogIntegrity integrity;     // sealed, unsealed or broken (log_integrity.h)
};

// Throws InputError "path:LINE: ..." when the first event is not a session header of a schema this
// build reads, or when events contradict each other (a trial_end without its start, a trial
// completed twice...). `lab_key` (may be null) checks the seals' MACs of a keyed log; a key other
// than the log's is an InputError.
SessionRecord read_session_record(const EventLogFile& log, const LabKey* lab_key = nullptr);

// The checks on a log's first event: a session_header of a schema version this build reads, whose
// study and participant are names the config's rules allow (they become folder names).
// Throws InputError "path:1: ...".
void check_session_header(const nlohmann::json& first_event, const std::string& path);

// The event kinds that belong to the trial started last ("stimulus", "response", ...). A `break`
// belongs to a trial only when it names one (attention-check breaks).
bool is_trial_event(const std::string& kind, bool names_a_trial);

}  // namespace fovlab
