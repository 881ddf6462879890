#include "app/openxr_run.h"

#include <optional>
#include <string>

#include "core/input_error.h"
#include "display/openxr/openxr_runtime_info.h"
#include "study/stimulus/render_method.h"

namespace fovlab::app {
namespace {

// The session's gaze needs no eye tracker: --gaze names a trace or a synthetic source, or (without
// --gaze) the config's [gaze] require allows one.
bool names_trace_or_synthetic(const StudyConfig& config, const std::string& gaze_option) {
  if (!gaze_option.empty()) {
    const std::optional<GazeSourceKind> kind = gaze_source_kind_of_spec(gaze_option);
    return kind == GazeSourceKind::trace || kind == GazeSourceKind::synthetic;
  }
  return config.gaze.allows(GazeSourceKind::trace) || config.gaze.allows(GazeSourceKind::synthetic);
}

std::string method_following_gaze(const StudyConfig& config) {
  const RenderMethod test = config.stimulus.test.method;
  return std::string(describe(describe(test).depends_on_gaze ? test : config.stimulus.reference.method).name);
}

}  // namespace

void check_openxr_runtime_for(const StudyConfig& config, const std::string& gaze_option) {
  const OpenXrRuntimeInfo runtime = query_openxr_runtime();
  const std::string& path = config.source_path;
  if (!has_openxr_runtime(runtime))
    throw InputError("openxr: no OpenXR runtime (" + runtime.instance_result + "); " + path +
                     " runs in a headset ([display] kind = \"openxr\"): make a runtime active (SteamVR or Monado), "
                     "or name its manifest in XR_RUNTIME_JSON (docs/hmd.md)");
  const std::string name = runtime.runtime_name + " " + runtime.runtime_version;
  if (!runtime.offers_vulkan_enable2)
    throw InputError("openxr: the OpenXR runtime (" + name +
                     ") does not offer XR_KHR_vulkan_enable2; fovlab renders through Vulkan, so it cannot run " + path +
                     " on this runtime");
  if (!has_openxr_headset(runtime))
    throw InputError("openxr: no headset (xrGetSystem: " + runtime.headset_result + ") on the OpenXR runtime " + name +
                     "; connect one to run " + path);
  if (is_gaze_contingent(config) && !runtime.offers_eye_gaze_interaction &&
      !names_trace_or_synthetic(config, gaze_option))
    throw InputError(path + ": a gaze-contingent study (" + method_following_gaze(config) +
                     " follows the gaze) needs the headset's eye gaze, and the OpenXR runtime " + name +
                     " does not offer XR_EXT_eye_gaze_interaction; name a trace or synthetic source ([gaze] require, "
                     "--gaze trace:FILE or synthetic; docs/gaze.md)");
  // The eye size against the runtime's maximum: the session checks it too, but only the config
  // knows the key to name.
  const HeadsetDisplayConfig& headset = config.display.headset;
  for (const OpenXrEyeImageSize& eye : runtime.stereo_eyes) {
    if (uint32_t(headset.eye_width_px) > eye.max_width_px || uint32_t(headset.eye_height_px) > eye.max_height_px)
      throw InputError(path + ":" + std::to_string(headset.eye_size_line) + ": display.eye_width_px: expected an eye " +
                       "image of at most the runtime's " + std::to_string(eye.max_width_px) + "x" +
                       std::to_string(eye.max_height_px) + " (" + name + "), got " +
                       std::to_string(headset.eye_width_px) + "x" + std::to_string(headset.eye_height_px));
  }
}

}  // namespace fovlab::app
