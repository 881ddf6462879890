#include "analysis/study/adaptive_tracks.h"

#include "core/number_text.h"
#include "study/schedule/adaptive_progress.h"
#include "study/schedule/study_plan.h"

namespace fovlab::analysis {

std::vector<AdaptiveTrackResult> adaptive_tracks(const StudyData& data, const ParticipantData& participant) {
  if (data.config.procedures.empty()) return {};
  bool adaptive = false;
  for (const StudyTrial& trial : participant.trials) adaptive = adaptive || trial.track.has_value();
  if (!adaptive) return {};
  const StudyPlan plan = make_study_plan(data.config, participant.participant);
  AdaptiveProgress progress(plan);
  std::vector<AdaptiveTrackResult> results;
  for (size_t i = 0; i < plan.tracks.size(); ++i) {
    const AdaptiveTrack& track = plan.tracks[i];
    AdaptiveTrackResult result;
    result.track = static_cast<int>(i);
    result.block = plan.blocks.at(static_cast<size_t>(track.block)).name;
    result.procedure = data.config.procedures.at(static_cast<size_t>(track.procedure)).name;
    result.variant = track.variant;
    const bool staircase = track.kind == ProcedureConfig::Kind::staircase;
    result.kind = staircase ? "staircase" : "quest_plus";
    if (staircase) {
      result.start_level = track.grid.at(static_cast<size_t>(track.staircase.start_index));
      result.reversals_averaged = track.staircase.reversals_averaged;
    }
    results.push_back(std::move(result));
  }
  // The trials of each track in session order. The track and the interval order are the schedule's
  // (replay checks that the log agrees); a trial the schedule does not make adaptive is left out.
  std::vector<bool> levels_differ(results.size(), false);
  for (const StudyTrial& trial : participant.trials) {
    if (!trial.track || trial.index < 0 || static_cast<size_t>(trial.index) >= plan.trials.size()) continue;
    const Trial& planned = plan.trials[static_cast<size_t>(trial.index)];
    if (planned.track < 0 || planned.track != *trial.track) continue;
    const int track = planned.track;
    AdaptiveTrackResult& result = results[static_cast<size_t>(track)];
    const double derived = plan.tracks[static_cast<size_t>(track)].grid.at(static_cast<size_t>(progress.index(track)));
    // The levels reported are those shown (logged); one the procedure would not have chosen leaves
    // the track without a threshold.
    if (!trial.level || *trial.level != derived) {
      if (!levels_differ[static_cast<size_t>(track)])
        result.note = "trial " + std::to_string(trial.index) + " is logged at level " +
                      (trial.level ? format_number(*trial.level, 6) : std::string("none")) + ", the procedure gives " +
                      format_number(derived, 6) + ": no threshold (check the log with fovlab replay)";
      levels_differ[static_cast<size_t>(track)] = true;
    }
    const std::string answer = trial.answers.empty() ? std::string() : trial.answers.front();
    result.levels.push_back(trial.level.value_or(derived));
    result.seen.push_back(difference_seen(data.config.protocol, answer, planned.reference_first));
    const size_t reversals_before = progress.staircase(track).reversal_indices.size();
    progress.record(planned, answer);
    if (progress.staircase(track).reversal_indices.size() > reversals_before)
      result.reversal_trials.push_back(static_cast<int>(result.levels.size()) - 1);
  }
  for (size_t i = 0; i < results.size(); ++i) {
    AdaptiveTrackResult& result = results[i];
    const int track = static_cast<int>(i);
    result.stopped = progress.finished(track);
    if (levels_differ[i]) continue;
    if (const QuestPlus* quest = progress.quest(track)) {
      const QuestPlusEstimate estimate = quest->estimate(progress.quest_state(track).posterior);
      result.threshold = estimate.threshold_mean;
      result.threshold_lower = estimate.threshold_lower;
      result.threshold_upper = estimate.threshold_upper;
      result.slope = estimate.slope_mean;
      result.lapse = estimate.lapse_mean;
      continue;
    }
    result.threshold = staircase_threshold(plan.tracks[i].staircase, progress.staircase(track), plan.tracks[i].grid);
    if (!result.threshold && result.note.empty())
      result.note = std::to_string(result.reversal_trials.size()) + " reversals of the " +
                    std::to_string(result.reversals_averaged) + " the threshold averages";
  }
  return results;
}

}  // namespace fovlab::analysis
