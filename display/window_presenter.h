#pragma once
// The presenter of a real session: a GLFW window (no OpenGL context) and a FIFO swapchain on a
// vk::Context made to present to it (renderer/vk/context.h). That context is a full renderer
// context: a session renders its stimuli on it (context()), so a gaze-contingent frame goes from
// the renderer's output buffer to the swapchain image on the GPU (present(DeviceRgba8Frame): one
// compute pass places it, integer-scaled, centred and letterboxed, in the swapchain's byte order,
// renderer/present/frame_compose.h; then one copy into the image), never through the host. Frames
// from the host (text screens, prepared stimuli) are uploaded first; a frame held by another
// device (a session rendering on one GPU and presenting on another) is read back and uploaded, and
// that copy is timed (cross_device_copies()). Keyboard, gamepad and mouse come from GLFW.
//
// Clock: glfwGetTime() relative to construction. present() returns the session time right after
// the frame was queued for presentation (vkQueuePresentKHR) and the copy into the swapchain image
// had completed (its fence). The swapchain has the fewest images the surface allows, and with FIFO
// a full queue makes the acquire block until a flip releases an image, so in steady state
// present() returns paced at the refresh rate and its time estimates the flip at which the frame
// appears (at or shortly before it): it is not a photon time (no display latency, no scan-out
// position). A present that would return less than half a refresh period after the previous one
// (the queue still filling, or a FIFO swapchain that never blocks: software presentation such as
// lavapipe on an X server or Xvfb) sleeps until one period after the previous one, so the clock
// advances by refreshes even then (emulated: no flip is observed).
//
// A headset's mirror (WindowPresenterOptions::headset_mirror, display/openxr/openxr_presenter.h) is
// the same window, swapchain and compose on a context made by someone else: the window opens first,
// the headset's runtime makes the Vulkan instance and device from surface_request() (so they can
// present to it), and attach() hands that context over. Its presents never wait for the display.
//
// Threads: GLFW requires every call (construction included) on the main thread.
#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "display/glfw_input.h"
#include "display/presenter.h"
#include "renderer/present/frame_compose.h"
#include "renderer/vk/buffer.h"
#include "renderer/vk/context.h"

struct GLFWwindow;

namespace fovlab {

struct WindowPresenterOptions {
  int width_px = 1280;  // the frame size; windowed: the window's client size (not resizable)
  int height_px = 720;
  // Full screen on the primary monitor at its current video mode. Frames are centred, scaled up by
  // the largest integer factor that fits (1 when none does; a frame larger than the screen is
  // cropped to its centre) and letterboxed with black.
  bool fullscreen = false;
  std::string title = "fovlab";
  // FIFO (vsync). false: MAILBOX, else IMMEDIATE, where the surface offers them (timing tests).
  bool vsync = true;
  // Khronos validation layer of the presenting context; default as the renderer: on in Debug
  // builds, FOVLAB_VALIDATION=0/1 overrides. Messages go to stderr and are counted.
  bool validation = vk::validation_requested_by_default();
  // Read every presented image back from the swapchain (see screenshot()); costs one image copy a
  // frame. Off: screenshot() returns the last input frame.
  bool screenshots = true;
  // Empty: automatic (a device that can render and present to the window: discrete > integrated >
  // virtual > CPU); else an index or a case-insensitive part of a device name, as --device.
  std::string device_selector;
  std::string device_flag = "--device";  // the flag that gave device_selector, for its errors
  // A headset session's mirror: the constructor opens the window only, and attach() gives it the
  // headset's context (made from surface_request()), which it does not own. A present never holds
  // back the caller: MAILBOX, else IMMEDIATE, where the surface offers them (else FIFO), the image
  // acquired with timeout 0, and a frame with no image free, or a minimised window, is skipped (the
  // window keeps its last image); no pacing to the monitor's refresh. Keys only: no gamepads (the
  // headset's runtime has them). device_selector and fullscreen are not used.
  bool headset_mirror = false;
};

// Throws InputError naming `flag` when no window can be opened here (no display, or GLFW cannot
// start on it): a session that needs one refuses before anything is written.
void check_window_can_open(const std::string& flag);

class WindowPresenter final : public Presenter {
 public:
  // Throws InputError when no window can be opened (no display) or no device can present to it.
  explicit WindowPresenter(const WindowPresenterOptions& options);
  ~WindowPresenter() override;
  WindowPresenter(const WindowPresenter&) = delete;
  WindowPresenter& operator=(const WindowPresenter&) = delete;

  // headset_mirror: the window system's instance extensions and the window's surface, for the
  // context that attach() will be given (vk::ContextOptions::present_to).
  vk::SurfaceRequest surface_request();
  // headset_mirror: `context`, made from surface_request(), becomes the presenting context and the
  // swapchain is made on its surface. It must outlive this presenter, whose swapchain, buffers and
  // command buffer are on it. Throws std::logic_error when called twice or on a window that made its
  // own context.
  void attach(vk::Context& context);

  double now_s() override;
  // Any frame size works (centred, integer-scaled, letterboxed or cropped to the swapchain).
  // Throws std::invalid_argument when rgba.size() is not width * height * 4.
  double present(const Rgba8Frame& frame) override;
  // A frame on a device: on context() it is composed onto the swapchain image directly; on another
  // device it is read back and uploaded (timed: cross_device_copies()). Its buffer must stay as it is
  // until the next present (wait_until re-presents the composed image, or the frame again after a
  // swapchain change). Throws std::invalid_argument for an empty frame.
  double present(const DeviceRgba8Frame& frame) override;
  // Key presses are time-stamped when GLFW delivers them: events are pumped in every present(),
  // wait_until(), poll_input(), cursor_px() and close_requested(), so at refresh resolution during
  // a trial. Gamepad buttons (every connected gamepad, GLFW's standard mapping) are sampled at the
  // same pumps, edge-detected. A single Escape is delivered as "escape" too.
  std::vector<InputEvent> poll_input() override;
  // Re-presents the last frame while at least one refresh period remains (the clock advances by
  // real refreshes and the window stays responsive), then sleeps in short slices, pumping events,
  // until now_s() >= time_s; never overshoots by a whole refresh. Re-presents are limited to the
  // refresh rate when the swapchain does not pace them (e.g. software X servers).
  void wait_until(double time_s) override;
  // The pointer in frame pixels (x right, y down, from the frame's top-left corner; divided by the
  // fullscreen scale, so fractional there) while it is over the window and inside the frame's
  // rectangle; nullopt otherwise (letterbox included).
  std::optional<std::pair<double, double>> cursor_px() override;
  // The window was closed, or Escape was pressed 3 times within 1 s.
  bool close_requested() override;
  // Whether the last present reached the window: false when a headset mirror skipped it (no image
  // free at once, or the window minimised) or the window was minimised.
  bool last_present_shown() const { return last_present_shown_; }
  // Escape was pressed 3 times within 1 s (close_requested() is true for that or a closed window).
  bool escape_repeated() const { return escape_close_; }
  // A key press as GLFW's key callback delivers it (tests press keys through it).
  void on_key(int key, const char* layout_name);
  std::string close_reason() const override {
    return escape_close_ ? "Escape was pressed 3 times within 1 s" : "the window was closed";
  }
  // The primary monitor's refresh rate (glfwGetVideoMode), 60 when unknown.
  double refresh_hz() const override { return refresh_hz_; }
  bool is_headless() const override { return false; }
  // "after_queue_present" (the clock above); VK_KHR_present_wait is not used yet (lavapipe does not
  // offer it).
  std::string present_clock() const override { return "after_queue_present"; }

  // The last presented swapchain image as read back from the GPU (the whole swapchain extent,
  // letterbox included, R/B in frame order): copied out of the swapchain image in the same
  // submission, after the frame was written and before the present, so it is what the swapchain
  // held, not the input.
  // When the swapchain images cannot be transfer sources (or options.screenshots is off) this is
  // the last input frame instead: screenshot_is_readback() says which. Empty before any present.
  Rgba8Frame screenshot() const;
  bool screenshot_is_readback() const;

  // The device that presents; a session renders on it too (and so does bench-present).
  vk::Context& context() { return *context_; }
  uint32_t validation_message_count() const { return context_->validation_message_count(); }
  bool validation_enabled() const { return context_->validation_enabled(); }
  std::string device_name() const { return context_->description.name; }
  // Frames presented from another device (read back there, uploaded here) and the seconds those
  // copies took, on the steady clock.
  struct CrossDeviceCopies {
    int frames = 0;
    double seconds = 0.0;
  };
  CrossDeviceCopies cross_device_copies() const { return cross_device_copies_; }
  VkFormat swapchain_format() const { return format_; }
  std::pair<int, int> swapchain_extent_px() const {
    return {static_cast<int>(extent_.width), static_cast<int>(extent_.height)};
  }
  // The GLFW window, for tests and for callers that need GLFW directly (cursor warps, icons).
  GLFWwindow* glfw_window() const { return window_; }

 private:
  // What the next compose reads: a buffer on context() (the upload buffer, or a device frame's).
  struct ComposeSource {
    VkBuffer buffer = VK_NULL_HANDLE;
    int width = 0, height = 0;
  };
  void create_window();
  void create_context();
  void create_present_objects();  // the composer, command buffer, fence and semaphore on context_
  void create_swapchain();
  void destroy_swapchain(bool keep_handle_for_recreation);
  void recreate_swapchain();
  void release();
  ComposeSource upload(const Rgba8Frame& frame);
  // Acquires an image, composes `source` into composed_ (unless `recompose` is false and composed_
  // already holds the last frame at this extent), copies it into the image and presents it.
  double present_source(const ComposeSource& source, bool recompose);
  double present_again();
  void pump_events();
  void poll_gamepads();

  static void key_callback(GLFWwindow* window, int key, int scancode, int action, int mods);

  WindowPresenterOptions options_;
  GLFWwindow* window_ = nullptr;
  bool glfw_initialised_ = false;
  double clock_origin_s_ = 0.0;
  double refresh_hz_ = 60.0;

  std::unique_ptr<vk::Context> own_context_;  // empty for a headset mirror, whose context is the headset's
  vk::Context* context_ = nullptr;
  std::unique_ptr<FrameComposer> composer_;
  VkCommandBuffer command_buffer_ = VK_NULL_HANDLE;
  VkFence frame_fence_ = VK_NULL_HANDLE;
  VkSemaphore image_available_ = VK_NULL_HANDLE;

  VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  VkColorSpaceKHR colour_space_ = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
  bool format_is_bgra_ = false;
  bool can_read_back_ = false;
  VkPresentModeKHR present_mode_ = VK_PRESENT_MODE_FIFO_KHR;
  VkExtent2D extent_{0, 0};
  std::vector<VkImage> images_;
  std::vector<VkSemaphore> render_finished_;  // one per swapchain image
  bool swapchain_stale_ = false;

  vk::Buffer upload_;    // host frames, packed RGBA8
  vk::Buffer composed_;  // the swapchain image's pixels as composed, kept for re-presents
  VkExtent2D composed_extent_{0, 0};
  vk::Buffer readback_;  // screenshots: the swapchain image after the copy
  // The last frame shown: its bytes when it came from the host (or another device), else the device frame.
  Rgba8Frame last_frame_;
  DeviceRgba8Frame last_device_frame_;
  int last_width_ = 0, last_height_ = 0;
  bool has_presented_ = false;
  bool last_present_read_back_ = false;
  bool last_present_shown_ = false;
  VkExtent2D readback_extent_{0, 0};
  bool readback_is_bgra_ = false;
  double last_present_s_ = -1.0;
  CrossDeviceCopies cross_device_copies_;

  std::deque<InputEvent> events_;
  EscapeRepeatDetector escape_detector_;
  bool escape_close_ = false;
  std::array<std::array<unsigned char, 15>, 16> gamepad_buttons_{};  // GLFW's 16 joysticks x 15 buttons
};

}  // namespace fovlab
