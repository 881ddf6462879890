#pragma once
// The adaptive blocks' tracks (staircases, QUEST+) as a session's answers arrive (docs/config.md,
// [procedure.NAME]). An adaptive trial of the schedule names its track and leaves its level open;
// the level it is presented at is a pure function of the schedule and the answers of that track's
// earlier trials. The session folds in each answer as it is logged, a resumed session folds in the
// log's complete trials, replay does the same and compares every logged level with the one
// derived, and the analysis takes each track's threshold from the same state.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "study/schedule/quest_plus.h"
#include "study/schedule/staircase.h"
#include "study/schedule/study_plan.h"

namespace fovlab {

class AdaptiveProgress {
 public:
  explicit AdaptiveProgress(const StudyPlan& plan);

  // The trial as it is presented: a planned trial of constant stimuli as it is; an adaptive one at
  // its track's next level (level, condition "variant/level=X", and the sequence with the reference
  // in its planned interval). nullopt when its track has stopped: the trial is skipped.
  std::optional<Trial> presented(const Trial& planned) const;
  // Folds in the answer of a complete trial (nothing for a trial that is not adaptive). An answer
  // that sees no difference, and a missed one (""), count as not seen.
  void record(const Trial& planned, const std::string& answer);

  // A track's state: its next level's grid index, whether it has stopped, and the state of its kind.
  int index(int track) const;
  bool finished(int track) const;
  const StaircaseState& staircase(int track) const { return staircases_.at(static_cast<size_t>(track)); }
  const QuestPlusState& quest_state(int track) const { return quest_states_.at(static_cast<size_t>(track)); }
  // A QUEST+ track's tabulated rule (null for a staircase).
  const QuestPlus* quest(int track) const { return quests_.at(static_cast<size_t>(track)).get(); }

 private:
  const StudyPlan* plan_;                                 // a pointer: a progress is assignable
  std::vector<StaircaseState> staircases_;                // per track (unused for QUEST+)
  std::vector<std::shared_ptr<const QuestPlus>> quests_;  // per track (null for a staircase); shared by copies
  std::vector<QuestPlusState> quest_states_;              // per track (unused for a staircase)
};

// Whether a comparison answer says the difference was seen: the answer is against the test
// (protocol_rules' in_favour_of_test is false). A missed answer ("") is not seen.
bool difference_seen(const ProtocolConfig& protocol, const std::string& answer, bool reference_first);

}  // namespace fovlab
