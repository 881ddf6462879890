#pragma once
// One headset frame: xrWaitFrame and xrBeginFrame (paced by the runtime), the two eyes' views from
// xrLocateViews in the session's LOCAL space (for the projection layer) and in its VIEW space (each
// eye relative to the head, what the renderer's head-locked eye view takes), each eye's frame copied into its acquired swapchain
// image (acquire, wait, copy, release), and xrEndFrame with one projection layer. A frame the
// runtime says not to render (shouldRender false: not yet visible, or hidden), or whose views have no
// valid pose (XrViewState's valid bits), is ended with no layer.
#include <array>
#include <functional>
#include <optional>

#include "display/openxr/openxr_session.h"
#include "renderer/present/device_frame.h"

namespace fovlab {

// An eye's view as the runtime located it for the frame's predicted display time: in the LOCAL
// space (the projection layer's) and in the VIEW space (relative to the head: eye_view_from_openxr).
struct OpenXrEyeView {
  XrView in_local{XR_TYPE_VIEW};
  XrView in_head{XR_TYPE_VIEW};
};

// An eye's image for one frame: a frame on the session's Vulkan device (OpenXrSession::vulkan) of
// the eye's size, e.g. the offscreen renderer's display output for that eye's view. Called for eye 0
// (left), then 1; the frame need only stay valid until the next call.
using OpenXrEyeFrameSource = std::function<DeviceRgba8Frame(uint32_t eye, const OpenXrEyeView& view)>;

struct OpenXrFrame {
  XrTime predicted_display_time = 0;
  XrDuration predicted_display_period = 0;
  bool rendered = false;                  // the eyes were drawn and a projection layer submitted
  bool discarded = false;                 // xrBeginFrame said the previous frame was discarded (XR_FRAME_DISCARDED)
  bool views_valid = false;               // xrLocateViews gave valid orientations and positions in both spaces
                                          // (only asked when shouldRender); without them nothing is rendered
  std::array<XrView, 2> views{};          // as xrLocateViews gave them in LOCAL space (when rendered)
  std::array<XrView, 2> views_in_head{};  // and in VIEW space
  std::array<uint32_t, 2> image_index{};  // each eye's swapchain image the frame went into
  // The runtime's time right before xrEndFrame (openxr_time_now: XR_KHR_convert_timespec_time), and
  // whether that was after predicted_display_time: the frame reached the compositor too late to be
  // shown then. Without the extension: no time, and not late (not measured).
  std::optional<XrTime> end_frame_time;
  bool late = false;
};

// Runs one frame of a running session. Each eye's projection view is given the pose its image was
// rendered from when `rendered_from` has one for it (a world-fixed image, in LOCAL), else the pose
// located for this frame (an image fixed to the view). Throws std::invalid_argument for an eye frame
// of the wrong size or device, std::runtime_error when a call fails.
OpenXrFrame run_openxr_frame(OpenXrSession& session, const OpenXrEyeFrameSource& eye_frame,
                             const std::array<std::optional<XrPosef>, 2>& rendered_from = {});

// The head (the session's VIEW space) located in its LOCAL space at `time` (xrLocateSpace), as the
// runtime predicts it for that time: the head-tracked view model's poses. nullopt when the location
// lacks the orientation or position valid bit (no pose to give). std::runtime_error when the call fails.
std::optional<XrPosef> locate_head_in_local(const OpenXrSession& session, XrTime time);

}  // namespace fovlab
