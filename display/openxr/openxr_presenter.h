#pragma once
// A headset as a session's presenter (display/presenter.h): the OpenXR session, paced by the runtime
// (xrWaitFrame), showing each eye the frame it was given, and repeating the last ones while the
// session waits (a headset's compositor needs a frame every refresh). The session clock is the
// runtime's: a frame is presented at the display time the runtime predicted for it, counted from
// the first frame's; now_s() is the last frame's. Text screens (present) show the same image in both
// eyes; stimuli (present_views) each eye its own. Answers come from the controller's actions and
// the gaze ray from XR_EXT_eye_gaze_interaction (openxr_input.h). A session that leaves FOCUSED (the
// headset taken off, another application in front, the runtime stopping) asks to close: the study
// pauses, as when a window is closed. wait_for_focus then waits for the focus to return: keeping the
// frames coming while the runtime still runs the session, or, once the runtime has stopped it
// (STOPPING: ended at once), polling its events until it offers READY again (begun again, then
// frames until FOCUSED); the session then goes on in the same run. A session that is over (EXITING,
// a loss) or a wait that runs out is resumed by running the study again. A mirror window
// (OpenXrPresenterOptions::mirror_window) shows the operator the left eye and takes the keyboard
// beside the controller. docs/hmd.md.
#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "display/openxr/openxr_frame_loop.h"
#include "display/openxr/openxr_input.h"
#include "display/openxr/openxr_session.h"
#include "display/presenter.h"
#include "display/window_presenter.h"
#include "renderer/vk/buffer.h"

namespace fovlab {

struct OpenXrPresenterOptions {
  OpenXrSessionOptions session;
  // Wall seconds to wait for the runtime to focus the session (the participant putting the headset
  // on) before refusing to start.
  double focus_timeout_s = 60.0;
  // A desktop window for the operator (apparatus, not the study): it shows the left eye's image as
  // the headset is given it, 1:1 or integer-scaled, centred and letterboxed (a larger image: its
  // centre), and its keys reach poll_input() as a desktop window's do, timed at the frame after
  // which they were seen (now_s()); Escape 3 times within 1 s asks to close as on the desktop.
  // Opened before the session, so that the runtime makes the Vulkan instance and device able to
  // present to it; presents never wait (WindowPresenterOptions::headset_mirror, set here). Closing
  // the window only closes the mirror: the study goes on in the headset, answered on the controller.
  // Throws InputError when no window can be opened. None: no window, and nothing else changes.
  std::optional<WindowPresenterOptions> mirror_window;
};

class OpenXrPresenter final : public Presenter {
 public:
  // Opens the session and runs black frames until the runtime focuses it. Throws InputError when
  // no session can be had (OpenXrSession's refusals) or it is not focused in time.
  explicit OpenXrPresenter(const OpenXrPresenterOptions& options);
  // Asks the runtime to end the session and runs frames until it has (at most a few seconds).
  ~OpenXrPresenter() override;
  OpenXrPresenter(const OpenXrPresenter&) = delete;
  OpenXrPresenter& operator=(const OpenXrPresenter&) = delete;

  OpenXrSession& session() { return session_; }
  vk::Context& context() { return *session_.vulkan; }
  OpenXrInput& input() { return *input_; }
  // The mirror window while it is open; nullptr without one, or once its window was closed.
  WindowPresenter* mirror() { return mirror_.get(); }

  double now_s() override { return now_s_; }
  double present(const Rgba8Frame& frame) override;
  double present(const DeviceRgba8Frame& frame) override;
  int view_count() const override { return 2; }
  double present_views(std::span<const ViewFrame> frames) override;
  std::vector<InputEvent> poll_input() override;
  void wait_until(double time_s) override;
  std::optional<std::pair<double, double>> cursor_px() override { return std::nullopt; }
  bool close_requested() override { return !close_reason_.empty(); }
  std::string close_reason() const override { return close_reason_; }
  double refresh_hz() const override { return refresh_hz_; }
  bool is_headless() const override { return false; }
  std::string present_clock() const override { return "openxr_predicted_display"; }
  // The last frame's xrEndFrame after its predicted display time; measured only with
  // XR_KHR_convert_timespec_time (measures_late_frames), and only of a frame that showed the eyes.
  std::optional<bool> last_frame_late() const override;
  bool measures_late_frames() const { return session_.convert_timespec_to_time != nullptr; }

  // Whether the session is not FOCUSED but may be again in this run: running but unfocused (VISIBLE,
  // SYNCHRONIZED, READY: the headset taken off, another application in front), or stopped by the
  // runtime (ended at STOPPING, IDLE since: it may offer READY again). False while it is focused,
  // and once it is over (EXITING, LOSS_PENDING, the instance's loss pending).
  bool may_regain_focus() const;
  // Shows `screen` (the eye size) in both eyes and waits for the runtime to focus the session again:
  // running its frames while it runs the session; while stopped, polling its events (no frame loop)
  // until READY, when the session is begun again and its frames run on. Focused: the close request
  // is withdrawn, presses made until then are dropped, and it returns true. Returns false, the close
  // request kept, when the session is over (EXITING, a loss), when `timeout_s` have passed (the
  // session clock's seconds while frames run, which follow the headset's refreshes; the wall
  // clock's while stopped), or when `quit()` (asked every frame or poll) says so. A failing call
  // (an instance lost) throws std::runtime_error.
  bool wait_for_focus(const Rgba8Frame& screen, double timeout_s, const std::function<bool()>& quit);

  // The session time of an XrTime of this runtime (a gaze sample's, a button press's).
  double session_time_s(XrTime time) const { return static_cast<double>(time - clock_zero_) * 1e-9; }
  XrTime runtime_time(double session_time_s) const {
    return clock_zero_ + static_cast<XrTime>(std::llround(session_time_s * 1e9));
  }
  // The last frame run, with the views the runtime located for it.
  const OpenXrFrame& last_frame() const { return last_frame_; }
  // The display time the next frame is expected at: the last frame's predicted display time plus its
  // predicted period (the next xrWaitFrame's own prediction is not known before that frame is waited
  // for, and the frame's image must be rendered before). Head-tracked views are located for it.
  XrTime next_display_time() const {
    return last_frame_.predicted_display_time + last_frame_.predicted_display_period;
  }

 private:
  // Copies `frame` (eye size, on the host or the session's device) into the eye's own buffer, which
  // the frame loop copies into the eye's swapchain image at every frame until the next one.
  void hold(uint32_t eye, const ViewFrame& frame);
  // What each eye holds, as the frame loop asks for it.
  OpenXrEyeFrameSource held_frames();
  // One frame showing what the eyes hold; then the runtime's events and the controller's presses.
  // Returns the frame's predicted display time on the session clock.
  double run_frame();
  // The runtime's events: a session no longer FOCUSED asks to close.
  void follow_session_state();
  // The left eye's held image into the mirror window (when it changed, or was not shown yet), and
  // its keys into presses_; a closed mirror is let go, Escape 3 times asks to close.
  void update_mirror();

  // Before session_, whose device it presents on: opened before the session is made (its surface
  // goes into the runtime's Vulkan instance), and let go first (~OpenXrPresenter), before the device.
  std::unique_ptr<WindowPresenter> mirror_;
  bool mirror_shows_held_ = false;  // the mirror shows what the eyes hold now
  OpenXrSession session_;
  std::unique_ptr<OpenXrInput> input_;
  std::array<vk::Buffer, 2> held_;  // each eye's frame, host-visible (RGBA8, eye size)
  std::array<std::optional<XrPosef>, 2> held_rendered_from_;  // each eye's frame's pose in LOCAL, if world-fixed
  XrTime clock_zero_ = 0;           // the predicted display time of the first frame
  double now_s_ = 0.0;
  double refresh_hz_ = 0.0;
  OpenXrFrame last_frame_;
  bool focused_ = false;  // the runtime has focused the session (the constructor's end)
  std::vector<InputEvent> presses_;
  std::string close_reason_;
};

}  // namespace fovlab
