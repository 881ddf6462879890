#include "study/log/schedule_check.h"

#include <nlohmann/json.hpp>

#include "core/number_text.h"

namespace fovlab {
namespace {

std::string level_text(std::optional<double> level) { return level ? format_number(*level, 9) : "none"; }

// What the check reads of a logged trial, from either reader's trials.
struct LoggedStart {
  int index = 0;
  int line = 0;  // of its trial_start
  const std::string* condition = nullptr;
  std::optional<double> level;
  const std::vector<int>* sequence = nullptr;
  bool attention_check = false;
  bool practice = false;
  std::optional<int> track;
  std::optional<bool> reference_first;
  const std::string* first_answer = nullptr;  // none: no answer logged
};

const std::string no_answer;

LoggedStart logged_start(const RecordedTrial& trial) {
  const TrialStartEvent& start = trial.start;
  return {trial.index,           trial.line,
          &start.condition,      start.level,
          &start.sequence,       start.attention_check,
          start.practice,        start.track,
          start.reference_first, trial.responses.empty() ? nullptr : &trial.responses.front().answer};
}

LoggedStart logged_start(const ScannedTrial& trial) {
  return {trial.index,           trial.line,
          &trial.condition,      trial.level,
          &trial.sequence,       trial.attention_check,
          trial.practice,        trial.track,
          trial.reference_first, trial.answers.empty() ? nullptr : &trial.answers.front()};
}

ScheduleCheck check_starts(const std::vector<LoggedStart>& logged, const StudyPlan& plan, bool keep_presented) {
  ScheduleCheck check(plan);
  check.trials_checked = static_cast<int>(logged.size());
  const auto differs = [&](const LoggedStart& trial, const std::string& what) {
    check.differences.push_back(what);
    check.difference_lines.push_back(trial.line);
  };
  // Whether the schedule runs a planned trial now (a trial of constant stimuli always; an adaptive
  // one unless its track has stopped), without copying it.
  const auto runs = [&](const Trial& planned) {
    return planned.track < 0 || check.progress.presented(planned).has_value();
  };
  const int trial_count = static_cast<int>(plan.trials.size());
  int next = 0;  // the next schedule index to account for
  for (const LoggedStart& start : logged) {
    const std::string where = "trial " + std::to_string(start.index);
    if (keep_presented) check.presented.emplace_back();
    if (start.index < 0 || start.index >= trial_count) {
      differs(start, where + ": not in this study's plan (" + std::to_string(trial_count) + " trials)");
      continue;
    }
    // The trials before this one that the log does not hold must have been skipped.
    for (; next < start.index; ++next)
      if (runs(plan.trials[static_cast<size_t>(next)]))
        differs(start, "trial " + std::to_string(next) + ": missing from the log before trial " +
                           std::to_string(start.index) + " (the schedule runs it)");
    next = start.index + 1;
    const Trial& planned = plan.trials[static_cast<size_t>(start.index)];
    // A trial of constant stimuli is presented as planned (no copy); an adaptive one at its track's level.
    std::optional<Trial> adaptive;
    if (planned.track >= 0) adaptive = check.progress.presented(planned);
    const Trial* presented = planned.track < 0 ? &planned : adaptive ? &*adaptive : nullptr;
    if (keep_presented && presented) check.presented.back() = *presented;
    if (!presented) {
      differs(start, where + ": its track had stopped before it (the schedule skips it)");
      continue;
    }
    // (The level is compared for adaptive trials: logs of schema 1 and 2 wrote no level.)
    const bool level_differs = planned.track >= 0 && start.level != presented->level;
    const std::optional<int> track = planned.track >= 0 ? std::optional<int>(planned.track) : std::nullopt;
    // An adaptive trial's answer is read by its interval order (analysis/study/adaptive_tracks).
    if (planned.track >= 0 && start.reference_first != std::optional<bool>(planned.reference_first))
      differs(start, where + ": trial_start's reference_first is not the schedule's");
    if (start.track != track)
      differs(start, where + ": trial_start's track (" + (start.track ? std::to_string(*start.track) : "none") +
                         ") is not the schedule's (" + (track ? std::to_string(*track) : "none") + ")");
    if (*start.condition != presented->condition || *start.sequence != presented->sequence || level_differs ||
        start.attention_check != presented->attention_check || start.practice != presented->practice)
      differs(start, where + ": trial_start (" + *start.condition + ", level " + level_text(start.level) +
                         ", sequence " + nlohmann::json(*start.sequence).dump() +
                         ") differs from the schedule rebuilt from the header (" + presented->condition + ", level " +
                         level_text(presented->level) + ", sequence " + nlohmann::json(presented->sequence).dump() +
                         ")");
    check.progress.record(planned, start.first_answer ? *start.first_answer : no_answer);
  }
  check.next_trial = next;
  check.schedule_done = true;
  for (int index = next; index < trial_count; ++index)
    if (runs(plan.trials[static_cast<size_t>(index)])) check.schedule_done = false;
  return check;
}

template <typename LoggedTrial>
ScheduleCheck check_trials(const std::vector<LoggedTrial>& trials, const StudyPlan& plan, bool keep_presented) {
  std::vector<LoggedStart> logged;
  logged.reserve(trials.size());
  for (const LoggedTrial& trial : trials) logged.push_back(logged_start(trial));
  return check_starts(logged, plan, keep_presented);
}

}  // namespace

ScheduleCheck check_log_against_schedule(const SessionRecord& record, const StudyPlan& plan, bool keep_presented) {
  return check_trials(record.trials, plan, keep_presented);
}

ScheduleCheck check_log_against_schedule(const std::vector<ScannedTrial>& trials, const StudyPlan& plan,
                                         bool keep_presented) {
  return check_trials(trials, plan, keep_presented);
}

}  // namespace fovlab
