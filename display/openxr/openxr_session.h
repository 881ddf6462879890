#pragma once
// A headset session: the OpenXR instance with XR_KHR_vulkan_enable2, fovlab's Vulkan context made
// THROUGH the runtime (the runtime creates the VkInstance and VkDevice from the context's own create
// infos, so the renderer runs on the headset's GPU, validation layer and all), the XrSession on
// that device, a LOCAL and a VIEW reference space, and one swapchain an eye (8-bit sRGB RGBA, the images on
// the context's device). Destroyed in the order the specification asks: swapchains, space,
// session, then the Vulkan device and instance, then the XrInstance.
//
// The session's life follows the runtime's events (poll_openxr_events): READY begins it, STOPPING
// ends it, EXITING (or a loss) ends its use. docs/hmd.md.
#define XR_USE_GRAPHICS_API_VULKAN
#include <time.h>
#include <vulkan/vulkan.h>
// After Vulkan's types, as openxr_platform.h expects them.
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "display/openxr/openxr_instance.h"
#include "renderer/vk/context.h"

namespace fovlab {

struct OpenXrSessionOptions {
  // Each eye's image, in pixels; 0: the runtime's recommended size. At most the runtime's maximum.
  uint32_t eye_width_px = 0;
  uint32_t eye_height_px = 0;
  bool validation = false;  // the Vulkan validation layer (vk::ContextOptions::validation)
  // A window the session's device also presents to (a mirror, openxr_presenter.h): its instance
  // extensions and VK_KHR_swapchain are added to what fovlab hands the runtime, and the device must
  // present to its surface. None (the default): the create infos are the compute-only ones.
  std::optional<vk::SurfaceRequest> present_to;
};

// One eye's swapchain and its images.
struct OpenXrEyeSwapchain {
  XrSwapchain handle = XR_NULL_HANDLE;
  std::vector<VkImage> images;
};

struct OpenXrSession {
  // Throws InputError with one line naming what is missing: no runtime, no XR_KHR_vulkan_enable2,
  // no headset, an eye size over the runtime's maximum, no 8-bit sRGB RGBA swapchain format.
  explicit OpenXrSession(const OpenXrSessionOptions& options);
  ~OpenXrSession();
  OpenXrSession(const OpenXrSession&) = delete;
  OpenXrSession& operator=(const OpenXrSession&) = delete;

  OpenXrInstance instance;
  // Optional instance extensions, enabled when the runtime offers them: the eye tracker's gaze
  // (openxr_input.h) and XrTime from and to CLOCK_MONOTONIC.
  bool eye_gaze_enabled = false;          // XR_EXT_eye_gaze_interaction
  bool convert_timespec_enabled = false;  // XR_KHR_convert_timespec_time
  // xrConvertTimespecTimeToTimeKHR when the extension is enabled (its type spelled here, so that no
  // includer needs XR_USE_TIMESPEC before openxr_platform.h).
  XrResult(XRAPI_PTR* convert_timespec_to_time)(XrInstance, const struct timespec*, XrTime*) = nullptr;
  XrSystemId system = XR_NULL_SYSTEM_ID;
  std::unique_ptr<vk::Context> vulkan;  // made through the runtime (XR_KHR_vulkan_enable2)
  XrSession session = XR_NULL_HANDLE;
  XrSpace local_space = XR_NULL_HANDLE;
  XrSpace view_space = XR_NULL_HANDLE;  // VIEW: the head, where each eye's view is located for rendering
  uint32_t eye_width_px = 0;
  uint32_t eye_height_px = 0;
  // The runtime's recommended size of the first view (its compositor resamples any other size).
  uint32_t recommended_eye_width_px = 0;
  uint32_t recommended_eye_height_px = 0;
  std::array<OpenXrEyeSwapchain, 2> eyes;
  XrSessionState state = XR_SESSION_STATE_UNKNOWN;  // the last state the runtime reported
  bool running = false;                             // between xrBeginSession and xrEndSession
  bool exiting = false;                             // EXITING or a loss: the session is over

 private:
  void release();
};

// Handles every event the runtime has queued: a state change of the session is recorded, READY
// begins the session (primary stereo), STOPPING ends it, EXITING and LOSS_PENDING mark it over.
// Returns the states reported, in order. Throws std::runtime_error when a call fails.
std::vector<XrSessionState> poll_openxr_events(OpenXrSession& session);

// xrRequestExitSession: the runtime then takes the session down to STOPPING (poll_openxr_events).
void request_openxr_exit(OpenXrSession& session);

// The runtime's XrTime now: CLOCK_MONOTONIC converted by XR_KHR_convert_timespec_time; nullopt
// without the extension (or when the runtime cannot convert it).
std::optional<XrTime> openxr_time_now(const OpenXrSession& session);

// "XR_SESSION_STATE_FOCUSED".
const char* openxr_session_state_name(XrSessionState state);

}  // namespace fovlab
