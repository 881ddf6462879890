#include "protocols/stimuli/plan_renderable.h"

#include "protocols/stimuli/image_sequence.h"
#include "protocols/stimuli/stimulus_library.h"
#include "protocols/stimuli/stimulus_settings.h"

namespace fovlab {

void check_plan_renderable(const StudyPlan& plan, const std::string& source, PlanUse use) {
  // A config whose prepared frames would not fit in this machine's memory cannot run here: said
  // now, not after minutes of rendering.
  if (use == PlanUse::session) check_prepared_frames_fit(planned_specs(plan), source);
  check_sampling_maps(plan.stimuli, source);
  check_image_sequences(plan, source);
}

}  // namespace fovlab
