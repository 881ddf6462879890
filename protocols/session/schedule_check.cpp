#include "protocols/session/schedule_check.h"

#include <nlohmann/json.hpp>

#include "core/number_text.h"

namespace fovlab {
namespace {

std::string level_text(std::optional<double> level) { return level ? format_number(*level, 9) : "none"; }

}  // namespace

ScheduleCheck check_log_against_schedule(const SessionRecord& record, const StudyPlan& plan) {
  ScheduleCheck check(plan);
  const int trial_count = static_cast<int>(plan.trials.size());
  int next = 0;  // the next schedule index to account for
  for (const RecordedTrial& recorded : record.trials) {
    const std::string where = "trial " + std::to_string(recorded.index);
    check.presented.emplace_back();
    if (recorded.index < 0 || recorded.index >= trial_count) {
      check.differences.push_back(where + ": not in this study's plan (" + std::to_string(trial_count) + " trials)");
      continue;
    }
    // The trials before this one that the log does not hold must have been skipped.
    for (; next < recorded.index; ++next)
      if (check.progress.presented(plan.trials[static_cast<size_t>(next)]))
        check.differences.push_back("trial " + std::to_string(next) + ": missing from the log before trial " +
                                    std::to_string(recorded.index) + " (the schedule runs it)");
    next = recorded.index + 1;
    const Trial& planned = plan.trials[static_cast<size_t>(recorded.index)];
    const std::optional<Trial>& presented = check.presented.back() = check.progress.presented(planned);
    if (!presented) {
      check.differences.push_back(where + ": its track had stopped before it (the schedule skips it)");
      continue;
    }
    const TrialStartEvent& start = recorded.start;
    // (The level is compared for adaptive trials: logs of schema 1 and 2 wrote no level.)
    const bool level_differs = planned.track >= 0 && start.level != presented->level;
    const std::optional<int> track = planned.track >= 0 ? std::optional<int>(planned.track) : std::nullopt;
    // An adaptive trial's answer is read by its interval order (analysis/study/adaptive_tracks).
    if (planned.track >= 0 && start.reference_first != std::optional<bool>(planned.reference_first))
      check.differences.push_back(where + ": trial_start's reference_first is not the schedule's");
    if (start.track != track)
      check.differences.push_back(where + ": trial_start's track (" + (start.track ? std::to_string(*start.track) : "none") +
                                  ") is not the schedule's (" + (track ? std::to_string(*track) : "none") + ")");
    if (start.condition != presented->condition || start.sequence != presented->sequence || level_differs ||
        start.attention_check != presented->attention_check ||
        start.practice != presented->practice)
      check.differences.push_back(where + ": trial_start (" + start.condition + ", level " + level_text(start.level) +
                                  ", sequence " + nlohmann::json(start.sequence).dump() +
                                  ") differs from the schedule rebuilt from the header (" + presented->condition +
                                  ", level " + level_text(presented->level) + ", sequence " +
                                  nlohmann::json(presented->sequence).dump() + ")");
    check.progress.record(planned, recorded.responses.empty() ? std::string() : recorded.responses.front().answer);
  }
  check.next_trial = next;
  check.schedule_done = true;
  for (int index = next; index < trial_count; ++index)
    if (check.progress.presented(plan.trials[static_cast<size_t>(index)])) check.schedule_done = false;
  return check;
}

}  // namespace fovlab
