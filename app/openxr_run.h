#pragma once
// fovlab run with [display] kind = "openxr": what the OpenXR runtime must offer, each refusal one
// line (exit 2) before anything is written (docs/hmd.md, "Refusals"). The session then opens the
// headset itself (protocols/session/session.h run_session), with its own refusals.
#include <string>

#include "study/config/study_config.h"

namespace fovlab::app {

// `gaze_option`: run's --gaze ("" when not given). Throws InputError naming what the runtime lacks.
void check_openxr_runtime_for(const StudyConfig& config, const std::string& gaze_option);

}  // namespace fovlab::app
