#pragma once
// Which OpenXR runtime is active, and what it offers a study: `fovlab devices` prints it. A plain
// summary (no OpenXR types), made by one query through the Khronos loader.
#include <cstdint>
#include <string>
#include <vector>

namespace fovlab {

// One view of the runtime's primary stereo view configuration (xrEnumerateViewConfigurationViews).
struct OpenXrEyeImageSize {
  uint32_t recommended_width_px = 0;
  uint32_t recommended_height_px = 0;
  uint32_t max_width_px = 0;
  uint32_t max_height_px = 0;
};

struct OpenXrRuntimeInfo {
  // xrCreateInstance's result (application "fovlab", no extensions), by name: "XR_SUCCESS" when a
  // runtime answered, else why the loader found none (e.g. "XR_ERROR_RUNTIME_UNAVAILABLE"). The
  // fields below are filled only on success.
  std::string instance_result;
  std::string runtime_name;     // xrGetInstanceProperties
  std::string runtime_version;  // "major.minor.patch"
  // xrGetSystem for a head-mounted display: "XR_SUCCESS", or "XR_ERROR_FORM_FACTOR_UNAVAILABLE" when
  // the runtime has no headset connected now (any other failure by its name too).
  std::string headset_result;
  std::string system_name;  // xrGetSystemProperties, when a headset is there
  // The primary stereo configuration's views, left then right; empty when the system has no such
  // configuration.
  std::vector<OpenXrEyeImageSize> stereo_eyes;
  // The instance extensions the headset display builds on (xrEnumerateInstanceExtensionProperties).
  bool offers_vulkan_enable2 = false;        // XR_KHR_vulkan_enable2: Vulkan from the runtime
  bool offers_eye_gaze_interaction = false;  // XR_EXT_eye_gaze_interaction: the headset's eye tracker
  // The first call after the instance that failed, "xrEnumerateViewConfigurationViews:
  // XR_ERROR_..."; empty when every call succeeded.
  std::string query_failure;
};

inline bool has_openxr_runtime(const OpenXrRuntimeInfo& info) { return info.instance_result == "XR_SUCCESS"; }
inline bool has_openxr_headset(const OpenXrRuntimeInfo& info) { return info.headset_result == "XR_SUCCESS"; }

// Creates and destroys one XrInstance. Never throws for a missing runtime or headset: the result
// says so. The loader picks the runtime (XR_RUNTIME_JSON, else the system's active_runtime.json).
// Sets XR_LOADER_DEBUG=none for the process unless the environment sets it, so the loader's own
// stderr lines do not follow the caller's one-line answer.
OpenXrRuntimeInfo query_openxr_runtime();

// The lines `fovlab devices` prints: "OpenXR runtime: none (XR_ERROR_RUNTIME_UNAVAILABLE)" alone, or
// the runtime's name and version, its headset (or why none) and the two extensions.
std::vector<std::string> describe_openxr_runtime(const OpenXrRuntimeInfo& info);

}  // namespace fovlab
