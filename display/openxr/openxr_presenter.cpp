#include "display/openxr/openxr_presenter.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <thread>

#include "core/input_error.h"
#include "renderer/present/device_frame.h"

namespace fovlab {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The reason a session that was focused asks to close, as the log's session_paused event says it.
std::string unfocused_reason(const OpenXrSession& session) {
  if (session.exiting) return "the headset session ended (the OpenXR runtime is exiting or lost the headset)";
  if (!session.running) return "the OpenXR runtime stopped the headset session";
  return std::string("the headset session lost focus (") + openxr_session_state_name(session.state) +
         "): the headset was taken off, or another application took it";
}

// The mirror window, opened before the session (no Vulkan yet: attach() comes once the session is).
std::unique_ptr<WindowPresenter> open_mirror(const OpenXrPresenterOptions& options) {
  if (!options.mirror_window) return nullptr;
  WindowPresenterOptions window = *options.mirror_window;
  window.headset_mirror = true;
  window.fullscreen = false;
  return std::make_unique<WindowPresenter>(window);
}

// The session's options, with the mirror's surface asked of the runtime's Vulkan when there is one.
OpenXrSessionOptions session_options(const OpenXrPresenterOptions& options, WindowPresenter* mirror) {
  OpenXrSessionOptions session = options.session;
  if (mirror) session.present_to = mirror->surface_request();
  return session;
}

}  // namespace

OpenXrPresenter::OpenXrPresenter(const OpenXrPresenterOptions& options)
    : mirror_(open_mirror(options)), session_(session_options(options, mirror_.get())) {
  // Should the constructor throw, the members go in reverse order, the session's device before the
  // mirror: the mirror's swapchain and buffers on that device must go first.
  struct MirrorFirst {
    std::unique_ptr<WindowPresenter>& mirror;
    bool constructed = false;
    ~MirrorFirst() {
      if (!constructed) mirror.reset();
    }
  } mirror_first{mirror_};
  if (mirror_) mirror_->attach(*session_.vulkan);
  input_ = std::make_unique<OpenXrInput>(session_);
  const VkDeviceSize eye_bytes = VkDeviceSize{session_.eye_width_px} * session_.eye_height_px * 4;
  for (vk::Buffer& held : held_) {
    held = vk::Buffer(*session_.vulkan, eye_bytes, vk::MemoryUse::host_upload);
    // Black, opaque: what the eyes see until the first screen.
    auto* pixels = static_cast<uint32_t*>(held.mapped());
    std::fill(pixels, pixels + eye_bytes / 4, 0xff000000u);
    held.flush();
  }
  // The runtime takes the session through READY (begun by poll_openxr_events), SYNCHRONIZED and
  // VISIBLE to FOCUSED as frames are submitted; on a headset, FOCUSED may wait for the participant.
  const Clock::time_point start = Clock::now();
  poll_openxr_events(session_);
  while (session_.state != XR_SESSION_STATE_FOCUSED) {
    if (session_.exiting)
      throw InputError("openxr: the runtime ended the headset session before it was focused (" +
                       std::string(openxr_session_state_name(session_.state)) + ")");
    if (seconds_since(start) > options.focus_timeout_s)
      throw InputError("openxr: the headset session was not focused within " +
                       std::to_string(static_cast<int>(options.focus_timeout_s)) + " s (it is " +
                       openxr_session_state_name(session_.state) +
                       "): put the headset on, and close other applications using it");
    if (session_.running) {
      run_frame();
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    poll_openxr_events(session_);
  }
  presses_.clear();  // nothing pressed before the study starts counts
  focused_ = true;
  mirror_first.constructed = true;
}

OpenXrPresenter::~OpenXrPresenter() {
  // The specification's way down: request the exit, keep submitting frames until the runtime says
  // STOPPING (poll_openxr_events then ends the session), then wait for EXITING.
  try {
    mirror_.reset();  // its swapchain and buffers on the session's device
    input_.reset();
    if (!session_.running) return;
    request_openxr_exit(session_);
    const Clock::time_point start = Clock::now();
    while (session_.running && seconds_since(start) < 5.0) {
      run_openxr_frame(session_, held_frames(), held_rendered_from_);
      poll_openxr_events(session_);
    }
  } catch (const std::exception&) {
    // The session, its swapchains and the instance are destroyed by OpenXrSession regardless.
  }
}

void OpenXrPresenter::hold(uint32_t eye, const ViewFrame& frame) {
  const int width = static_cast<int>(session_.eye_width_px), height = static_cast<int>(session_.eye_height_px);
  const int frame_width = frame.device ? frame.device.width : frame.host ? frame.host->width : 0;
  const int frame_height = frame.device ? frame.device.height : frame.host ? frame.host->height : 0;
  if (frame_width != width || frame_height != height)
    throw std::invalid_argument("openxr: a " + std::to_string(frame_width) + "x" + std::to_string(frame_height) +
                                " frame for a headset of " + std::to_string(width) + "x" + std::to_string(height) +
                                " pixels an eye");
  held_rendered_from_[eye].reset();
  if (eye == 0) mirror_shows_held_ = false;
  if (const std::optional<ViewPose>& pose = frame.rendered_from) {
    const auto f = [](double value) { return static_cast<float>(value); };
    held_rendered_from_[eye] = XrPosef{{f(pose->orientation[0]), f(pose->orientation[1]), f(pose->orientation[2]),
                                        f(pose->orientation[3])},
                                       {f(pose->position_m[0]), f(pose->position_m[1]), f(pose->position_m[2])}};
  }
  vk::Buffer& held = held_[eye];
  if (!frame.device) {
    std::memcpy(held.mapped(), frame.host->rgba.data(), held.size_bytes());
    held.flush();
    return;
  }
  if (frame.device.context != session_.vulkan.get())
    throw std::invalid_argument("openxr: an eye's frame on another device than the headset session's");
  // The compositor's copy reads the held buffer on the device, so no host barrier.
  copy_device_frame(frame.device, held, false);
}

OpenXrEyeFrameSource OpenXrPresenter::held_frames() {
  return [this](uint32_t eye, const OpenXrEyeView&) {
    return DeviceRgba8Frame{session_.vulkan.get(), held_[eye].handle(), static_cast<int>(session_.eye_width_px),
                            static_cast<int>(session_.eye_height_px)};
  };
}

double OpenXrPresenter::run_frame() {
  last_frame_ = run_openxr_frame(session_, held_frames(), held_rendered_from_);
  if (clock_zero_ == 0) {
    clock_zero_ = last_frame_.predicted_display_time;
    refresh_hz_ = 1e9 / static_cast<double>(last_frame_.predicted_display_period);
  }
  now_s_ = session_time_s(last_frame_.predicted_display_time);
  follow_session_state();
  for (const OpenXrButtonPress& press : input_->sync()) presses_.push_back({session_time_s(press.time), press.key});
  if (mirror_) update_mirror();
  return now_s_;
}

void OpenXrPresenter::update_mirror() {
  // Right after xrEndFrame, in the time the next xrWaitFrame would spend waiting anyway; the
  // present itself never waits for the window's display.
  if (!mirror_shows_held_) {
    mirror_->present(DeviceRgba8Frame{session_.vulkan.get(), held_[0].handle(), static_cast<int>(session_.eye_width_px),
                                      static_cast<int>(session_.eye_height_px)});
    mirror_shows_held_ = mirror_->last_present_shown();
  }
  // Keys are seen when GLFW's events are pumped, once a frame: timed on the session clock, as the
  // controller's presses are.
  for (InputEvent& key : mirror_->poll_input()) presses_.push_back({now_s_, std::move(key.key)});
  if (!mirror_->close_requested()) return;
  if (mirror_->escape_repeated()) {
    if (close_reason_.empty()) close_reason_ = mirror_->close_reason();
    return;
  }
  std::fprintf(stderr,
               "fovlab: the mirror window was closed; the session goes on in the headset (answers from the "
               "controller)\n");
  mirror_.reset();
}

void OpenXrPresenter::follow_session_state() {
  poll_openxr_events(session_);
  if (close_reason_.empty() && focused_ && (session_.exiting || session_.state != XR_SESSION_STATE_FOCUSED))
    close_reason_ = unfocused_reason(session_);
}

double OpenXrPresenter::present(const Rgba8Frame& frame) {
  const ViewFrame both{&frame, {}};
  return present_views(std::array{both, both});
}

double OpenXrPresenter::present(const DeviceRgba8Frame& frame) {
  const ViewFrame both{nullptr, frame};
  return present_views(std::array{both, both});
}

double OpenXrPresenter::present_views(std::span<const ViewFrame> frames) {
  if (frames.size() != 2) throw std::logic_error("openxr: present_views takes the two eyes' frames");
  for (uint32_t eye = 0; eye < 2; ++eye) hold(eye, frames[eye]);
  // A session that is no longer running (the runtime stopped it) has no frame to show it in; the
  // session asks close_requested() after each present and pauses.
  if (!session_.running) return now_s_;
  return run_frame();
}

std::vector<InputEvent> OpenXrPresenter::poll_input() {
  // Presses arrive with the frames (run_frame); a session waiting on an answer keeps them coming
  // (wait_until).
  std::vector<InputEvent> presses;
  presses.swap(presses_);
  return presses;
}

std::optional<bool> OpenXrPresenter::last_frame_late() const {
  if (!measures_late_frames()) return std::nullopt;
  return last_frame_.rendered && last_frame_.late;
}

bool OpenXrPresenter::may_regain_focus() const {
  // Not running (STOPPING ended it, IDLE since): the runtime may offer READY again, and the session
  // climbs back to FOCUSED as it did at the start. Only EXITING, LOSS_PENDING or an instance loss
  // pending (session_.exiting) say it will not.
  if (session_.exiting) return false;
  if (!session_.running) return true;
  return session_.state != XR_SESSION_STATE_FOCUSED;
}

bool OpenXrPresenter::wait_for_focus(const Rgba8Frame& screen, double timeout_s, const std::function<bool()>& quit) {
  const ViewFrame both{&screen, {}};
  for (uint32_t eye = 0; eye < 2; ++eye) hold(eye, both);
  // While the runtime runs the session its frames keep coming though nobody looks (a compositor
  // with no frames shows its own "not responding" screen, and may stop the session), and the wait is
  // counted on their clock. Stopped, the session has no frame loop (xrWaitFrame is not allowed until
  // xrBeginSession again), so the wait polls the runtime's events, counted on the wall clock, until
  // READY (poll_openxr_events begins the session) or the end; the frames then take it to FOCUSED.
  double waited_s = 0.0;
  bool after_stop = false;  // the next frame is the first since the session began again
  while (may_regain_focus()) {
    if ((quit && quit()) || waited_s >= timeout_s) return false;
    if (session_.running) {
      const double before_s = now_s_;
      run_frame();
      // The first frame after a stop is predicted past the whole stop, already counted on the wall.
      if (!after_stop) waited_s += now_s_ - before_s;
      after_stop = false;
    } else {
      const Clock::time_point idle_start = Clock::now();
      // The specification asks an IDLE session to keep polling at a reasonable cadence; 10 ms keeps
      // Ctrl-C and READY prompt without spinning a core.
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      follow_session_state();
      if (mirror_) update_mirror();  // the operator's window stays live (its keys are cleared on return)
      after_stop = true;
      waited_s += seconds_since(idle_start);
    }
  }
  if (!session_.running || session_.exiting || session_.state != XR_SESSION_STATE_FOCUSED) return false;
  close_reason_.clear();
  presses_.clear();  // pressed while the participant was away, or putting the headset on
  return true;
}

void OpenXrPresenter::wait_until(double time_s) {
  // Whole refreshes, as the headless presenter: frames repeating the held images until the one
  // displayed at or after time_s.
  const double half_period_s = 0.5 / refresh_hz_;
  while (session_.running && now_s_ + half_period_s < time_s) run_frame();
}

}  // namespace fovlab
