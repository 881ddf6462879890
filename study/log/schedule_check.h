#pragma once
// A log's complete trials against the schedule rebuilt from its header, in index order: shared by
// the session that resumes a log, by replay, and by export and analyze (log_consistency.h), on the
// trials of either reader (the full reader's RecordedTrial, the fast scan's ScannedTrial). Adaptive
// trials are compared with the level each track derives from the answers logged before them
// (study/schedule/adaptive_progress.h).
#include <optional>
#include <string>
#include <vector>

#include "study/log/session_record.h"
#include "study/log/session_scan.h"
#include "study/schedule/adaptive_progress.h"
#include "study/schedule/study_plan.h"

namespace fovlab {

struct ScheduleCheck {
  explicit ScheduleCheck(const StudyPlan& plan) : progress(plan) {}  // nothing checked yet
  AdaptiveProgress progress;                                         // every complete trial's answer folded in
  std::vector<std::string> differences;                              // "trial N: what differs", in index order
  std::vector<int> difference_lines;  // of each difference: the log line of the trial_start it names
  int trials_checked = 0;             // the log's complete trials
  // Each of the trials as the schedule presents it (its level and sequence chosen); none for a
  // trial outside the schedule or one its track skips. Empty unless asked for (keep_presented).
  std::vector<std::optional<Trial>> presented;
  int next_trial = 0;  // after the last complete trial
  // Every trial from next_trial on is skipped (its track has stopped): nothing is left to run.
  bool schedule_done = false;
};

// What differs: a trial outside the schedule, a trial missing before a later complete one (neither
// run nor skipped by its track), a trial of a track that had stopped, and a trial_start
// whose condition, level, sequence, attention check or practice flag is not the schedule's.
// `keep_presented`: fill ScheduleCheck::presented (resume and replay use it; a copy of every trial).
ScheduleCheck check_log_against_schedule(const SessionRecord& record, const StudyPlan& plan,
                                         bool keep_presented = true);
ScheduleCheck check_log_against_schedule(const std::vector<ScannedTrial>& trials, const StudyPlan& plan,
                                         bool keep_presented = true);

}  // namespace fovlab
