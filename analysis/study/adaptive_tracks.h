#pragma once
// Each adaptive track of a participant (staircase or QUEST+), from the log's trials
// (docs/analysis.md): the levels and answers in order, a staircase's reversals, and the threshold
// by the procedure's own rule. The track is re-derived from the answers through the session's own
// AdaptiveProgress (study/schedule/adaptive_progress.h), so the threshold is the rule's, never a
// value the log claims. The levels reported are the logged ones (those shown); a level the procedure
// would not have chosen leaves its track without a threshold, with a note (fovlab replay names the
// trial). Each trial's track and interval order are the schedule's.
#include <vector>

#include "analysis/study/analysis_result.h"
#include "analysis/study/study_data.h"

namespace fovlab::analysis {

std::vector<AdaptiveTrackResult> adaptive_tracks(const StudyData& data, const ParticipantData& participant);

}  // namespace fovlab::analysis
