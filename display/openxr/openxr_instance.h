#pragma once
// An XrInstance made through the Khronos loader, destroyed with its owner, and the names of OpenXR
// results. The instance is the root of every other OpenXR handle (system, session, swapchains,
// actions), so the later parts of the headset display hold one of these.
#include <openxr/openxr.h>

#include <string>
#include <vector>

namespace fovlab {

// Owns one XrInstance: xrDestroyInstance when it goes. Move-only.
struct OpenXrInstance {
  XrInstance handle = XR_NULL_HANDLE;

  OpenXrInstance() = default;
  explicit OpenXrInstance(XrInstance instance) : handle(instance) {}
  OpenXrInstance(const OpenXrInstance&) = delete;
  OpenXrInstance& operator=(const OpenXrInstance&) = delete;
  OpenXrInstance(OpenXrInstance&& other) noexcept;
  OpenXrInstance& operator=(OpenXrInstance&& other) noexcept;
  ~OpenXrInstance();
};

// What xrCreateInstance returned, and the instance when it succeeded.
struct OpenXrInstanceResult {
  XrResult result = XR_ERROR_RUNTIME_FAILURE;
  OpenXrInstance instance;
};

// xrCreateInstance through the loader for OpenXR 1.0, with the application's name and the given
// instance extensions (none for a query of the runtime). The loader enables the API layers that
// XR_ENABLE_API_LAYERS names.
OpenXrInstanceResult create_openxr_instance(const std::string& application_name,
                                            const std::vector<std::string>& extensions);

// "XR_ERROR_FORM_FACTOR_UNAVAILABLE": the result's name as the specification spells it, without an
// instance (xrResultToString needs one; a failed xrCreateInstance has none). A value the headers do
// not name is written as xrResultToString's fallback: "XR_UNKNOWN_FAILURE_-1000999" (or _SUCCESS_).
std::string openxr_result_name(XrResult result);

}  // namespace fovlab
