#pragma once
// Whether a study plan's stimuli can be rendered on this machine, checked before anything is
// rendered or written: the one check that run (the session), validate, prerender and replay share,
// each for the use it makes of the stimuli. The checks that need the rendering device (the frame
// size against its limits) are each family's, at StimulusLibrary::prepare.
#include <string>

#include "study/schedule/study_plan.h"

namespace fovlab {

// What the caller does with the plan's stimuli.
enum class PlanUse {
  session,    // run and validate: gaze-independent frames are prepared in memory before the first trial
  prerender,  // the path-traced frames are rendered into the cache, none kept in memory
  replay,     // frames are rendered again from a log, as the session rendered them
};

// InputError (one line, starting with `source`, the config's path or the log's config_toml) when:
// - session: the prepared frames would not fit in the memory available (check_prepared_frames_fit);
// - every use: a sampling model cannot make its map (check_sampling_maps: equalise with no
//   solution on this display);
// - every use: an image stimulus's folder is missing or empty, or an image does not decode, is not
//   the display's size, or there are too few (check_image_sequences).
void check_plan_renderable(const StudyPlan& plan, const std::string& source, PlanUse use);

}  // namespace fovlab
