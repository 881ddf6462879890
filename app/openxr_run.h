#pragma once
// fovlab run with [display] kind = "openxr": what the OpenXR runtime must offer, each refusal one
// line (exit 2) before anything is written (docs/hmd.md, "Refusals"). Running a study in the
// headset is the next stage of issue 42, so a runtime that offers everything gets a refusal that
// says so, after the headset session has opened and closed.
#include <string>

#include "study/config/study_config.h"

namespace fovlab::app {

// `gaze_option`: run's --gaze ("" when not given); `validation`: the Vulkan validation layer.
[[noreturn]] void refuse_openxr_run(const StudyConfig& config, const std::string& gaze_option, bool validation);

}  // namespace fovlab::app
