#pragma once
// Shows frames and collects input. Two implementations: headless (a virtual clock that advances one
// refresh period per present; no window) and a GLFW window with a Vulkan swapchain (real clock,
// vsync). The session state machine only talks to this interface.
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/pose.h"
#include "core/rgba8_frame.h"
#include "renderer/present/device_frame.h"

namespace fovlab {

// A key or gamepad button press. Names are normalised: keyboard "a".."z", "0".."9", "space",
// "enter", "escape", "left", "right", "up", "down"; gamepad (GLFW's standard mapping) "pad_a",
// "pad_b", "pad_x", "pad_y", "pad_left", "pad_right", "pad_up", "pad_down", "pad_start", "pad_back",
// "pad_lb", "pad_rb".
struct InputEvent {
  double time_s = 0.0;  // session clock when the press was seen
  std::string key;
};

// Where a view's image was rendered from, in the presenter's world space (a headset's LOCAL space).
using ViewPose = Pose;

// One view's image for present_views: its bytes on the host, or a frame held on a device.
struct ViewFrame {
  const Rgba8Frame* host = nullptr;  // used when `device` is empty
  DeviceRgba8Frame device;
  // A world-fixed image (a head-tracked stimulus): the pose it was rendered from, which a headset's
  // compositor is given with it, so it reprojects the image to where the eye is when it is shown.
  // Empty: an image fixed to the view (head-locked), given with the pose located for each frame.
  std::optional<ViewPose> rendered_from;
};

class Presenter {
 public:
  virtual ~Presenter() = default;
  // Session clock now, in seconds since the presenter was created.
  virtual double now_s() = 0;
  // Shows the frame at the next refresh; returns the session time it was presented (after vsync).
  virtual double present(const Rgba8Frame& frame) = 0;
  // The same for a frame held on a device (a live stimulus as the renderer left it); a window on
  // that device shows it without a copy through the host.
  virtual double present(const DeviceRgba8Frame& frame) = 0;
  // How many views a stimulus is drawn for: 1 on a screen, 2 in a headset (left eye, then right).
  // present() shows one image in every view (a text screen); present_views() gives each its own.
  virtual int view_count() const { return 1; }
  // Shows each view its own frame (view_count() of them) at the next refresh; returns the session
  // time it was presented, as present() does.
  virtual double present_views(std::span<const ViewFrame> frames) {
    if (frames.size() != 1) throw std::logic_error("present_views: a presenter with one view was given several");
    return frames[0].device ? present(frames[0].device) : present(*frames[0].host);
  }
  // Key and button presses since the last call, oldest first.
  virtual std::vector<InputEvent> poll_input() = 0;
  // Waits (real clock) or advances (virtual clock) until time_s, keeping the last frame on screen.
  virtual void wait_until(double time_s) = 0;
  // The mouse cursor in frame pixels when there is a pointer over the window; nullopt otherwise.
  virtual std::optional<std::pair<double, double>> cursor_px() = 0;
  // The participant or operator asked to stop (window closed, Escape pressed 3 times within 1 s).
  virtual bool close_requested() = 0;
  // Why close_requested() said so, as the log's session_paused event records it.
  virtual std::string close_reason() const { return "the window was closed"; }
  virtual double refresh_hz() const = 0;
  virtual bool is_headless() const = 0;
  // What the times present() returns measure, as the log names it: "virtual" (the headless clock),
  // "present_wait" (VK_KHR_present_wait said the image was presented), "after_queue_present" (the
  // time after vkQueuePresentKHR returned and the frame's copy completed; no display feedback),
  // "openxr_predicted_display" (the display time the headset's runtime predicted for the frame).
  virtual std::string present_clock() const = 0;
  // Whether the frame of the last present(), present_views() or wait_until() refresh was late: sent
  // to the display after the time that call returned for it (a headset's xrEndFrame after its
  // predicted display time). nullopt where the presenter cannot tell (a window, headless, a headset
  // runtime without XR_KHR_convert_timespec_time).
  virtual std::optional<bool> last_frame_late() const { return std::nullopt; }
};

}  // namespace fovlab
