#include "study/schedule/adaptive_progress.h"

namespace fovlab {

AdaptiveProgress::AdaptiveProgress(const StudyPlan& plan) : plan_(&plan) {
  for (const AdaptiveTrack& track : plan.tracks) {
    staircases_.push_back(start_staircase(track.staircase));
    if (track.kind == ProcedureConfig::Kind::quest_plus) {
      // Tracks of the same rule and levels (a procedure's variant in several blocks) share a table.
      std::shared_ptr<const QuestPlus> quest;
      for (size_t i = 0; i < quests_.size() && !quest; ++i)
        if (quests_[i] && plan.tracks[i].quest == track.quest && plan.tracks[i].grid == track.grid) quest = quests_[i];
      if (!quest) quest = std::make_shared<const QuestPlus>(track.quest, track.grid);
      quest_states_.push_back(quest->start());
      quests_.push_back(std::move(quest));
    } else {
      quest_states_.emplace_back();
      quests_.emplace_back();
    }
  }
}

int AdaptiveProgress::index(int track) const {
  return quest(track) ? quest_state(track).index : staircase(track).index;
}

bool AdaptiveProgress::finished(int track) const {
  return quest(track) ? quest_state(track).finished : staircase(track).finished;
}

std::optional<Trial> AdaptiveProgress::presented(const Trial& planned) const {
  if (planned.track < 0) return planned;
  if (finished(planned.track)) return std::nullopt;
  const AdaptiveTrack& track = plan_->tracks.at(static_cast<size_t>(planned.track));
  const size_t at = static_cast<size_t>(index(planned.track));
  Trial trial = planned;
  trial.level = track.grid.at(at);
  trial.condition = condition_name(trial.variant, trial.level);
  const int test = track.grid_stimuli.at(at);
  trial.sequence =
      trial.reference_first ? std::vector<int>{trial.reference, test} : std::vector<int>{test, trial.reference};
  return trial;
}

void AdaptiveProgress::record(const Trial& planned, const std::string& answer) {
  if (planned.track < 0) return;
  const size_t at = static_cast<size_t>(planned.track);
  const AdaptiveTrack& track = plan_->tracks.at(at);
  const bool seen = difference_seen(plan_->config.protocol, answer, planned.reference_first);
  if (const QuestPlus* rule = quests_[at].get()) quest_states_[at] = rule->next(std::move(quest_states_[at]), seen);
  else
    staircases_[at] = next_staircase_state(track.staircase, staircases_[at], seen, static_cast<int>(track.grid.size()));
}

bool difference_seen(const ProtocolConfig& protocol, const std::string& answer, bool reference_first) {
  return protocol.rules().in_favour_of_test(answer, reference_first) == false;
}

}  // namespace fovlab
