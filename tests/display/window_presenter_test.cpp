// The windowed presenter under a real (or virtual: xvfb-run) X server: exact pixels through the
// swapchain, letterboxing, the clock, input plumbing, and zero validation messages. Without a
// display the window tests skip; the CTest entry WindowPresenterUnderXvfb runs them under Xvfb.
#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <string>

#include "core/image_io.h"
#include "core/input_error.h"
#include "display/frame_io.h"
#include "display/glfw_input.h"
#include "display/text_screen.h"
#include "display/window_presenter.h"
#include "renderer/vk/buffer.h"
#include "renderer/vk/context.h"
#include "tests/support/temp_dir.h"

namespace fovlab {
namespace {

bool has_display() {
  const char* display = std::getenv("DISPLAY");
  return display && *display;
}

#define REQUIRE_DISPLAY()                                                                               \
  do {                                                                                                  \
    if (!has_display()) {                                                                               \
      if (std::getenv("FOVLAB_REQUIRE_DISPLAY")) FAIL() << "FOVLAB_REQUIRE_DISPLAY set but no DISPLAY"; \
      GTEST_SKIP() << "no DISPLAY: window tests run under xvfb-run (CTest: WindowPresenterUnderXvfb)";  \
    }                                                                                                   \
  } while (false)

WindowPresenterOptions small_window() {
  WindowPresenterOptions options;
  options.width_px = 320;
  options.height_px = 180;
  options.title = "fovlab window test";
  options.validation = true;
  return options;
}

void set_pixel(Rgba8Frame& frame, int x, int y, uint8_t r, uint8_t g, uint8_t b) {
  uint8_t* p =
      frame.rgba.data() + (static_cast<size_t>(y) * static_cast<size_t>(frame.width) + static_cast<size_t>(x)) * 4;
  p[0] = r;
  p[1] = g;
  p[2] = b;
  p[3] = 255;
}

// Four quadrants with distinct R, G and B (a swapped R/B shows), and a gradient row and column
// (any value of a byte, so an sRGB conversion or rounding shows).
Rgba8Frame quadrant_pattern(int width, int height) {
  Rgba8Frame frame(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const bool right = x >= width / 2, bottom = y >= height / 2;
      if (!right && !bottom) set_pixel(frame, x, y, 230, 20, 40);
      if (right && !bottom) set_pixel(frame, x, y, 30, 210, 60);
      if (!right && bottom) set_pixel(frame, x, y, 10, 50, 220);
      if (right && bottom) set_pixel(frame, x, y, 200, 120, 7);
    }
  }
  for (int x = 0; x < width; ++x) set_pixel(frame, x, 1, static_cast<uint8_t>(x), static_cast<uint8_t>(255 - x), 128);
  for (int y = 0; y < height; ++y) set_pixel(frame, 2, y, 64, static_cast<uint8_t>(y), static_cast<uint8_t>(3 * y));
  return frame;
}

// The number of bytes that differ, with the first difference in the message.
::testing::AssertionResult same_pixels(const Rgba8Frame& actual, const Rgba8Frame& expected) {
  if (actual.width != expected.width || actual.height != expected.height) {
    return ::testing::AssertionFailure() << "size " << actual.width << "x" << actual.height << ", expected "
                                         << expected.width << "x" << expected.height;
  }
  size_t differences = 0, first = 0;
  for (size_t i = 0; i < actual.rgba.size(); ++i) {
    if (actual.rgba[i] != expected.rgba[i] && differences++ == 0) first = i;
  }
  if (differences == 0) return ::testing::AssertionSuccess();
  const size_t pixel = first / 4;
  return ::testing::AssertionFailure() << differences << " bytes differ; first at pixel (" << pixel % actual.width
                                       << ", " << pixel / actual.width << ") channel " << first % 4 << ": "
                                       << int(actual.rgba[first]) << " vs " << int(expected.rgba[first]);
}

TEST(WindowPresenter, NoDisplayIsAnInputError) {
  const char* display = std::getenv("DISPLAY");
  const std::optional<std::string> saved = display ? std::optional<std::string>(display) : std::nullopt;
  unsetenv("DISPLAY");
  unsetenv("WAYLAND_DISPLAY");
  try {
    WindowPresenter presenter(small_window());
    ADD_FAILURE() << "a window opened without DISPLAY";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "window: cannot open a window (no display; use --headless or run under xvfb-run)");
  }
  if (saved) setenv("DISPLAY", saved->c_str(), 1);
}

TEST(WindowPresenter, PresentsPatternExactly) {
  REQUIRE_DISPLAY();
  WindowPresenter presenter(small_window());
  EXPECT_TRUE(presenter.validation_enabled());
  EXPECT_FALSE(presenter.is_headless());
  EXPECT_GT(presenter.refresh_hz(), 0.0);
  EXPECT_EQ(presenter.swapchain_extent_px(), std::make_pair(320, 180));
  const Rgba8Frame pattern = quadrant_pattern(320, 180);
  double previous_s = presenter.now_s();
  for (int i = 0; i < 5; ++i) {
    const double presented_s = presenter.present(pattern);
    EXPECT_GT(presented_s, previous_s) << "present " << i;
    // Paced by vsync (or by the presenter where the swapchain does not block): one a refresh.
    if (i > 0) {
      EXPECT_GT(presented_s - previous_s, 0.4 / presenter.refresh_hz()) << "present " << i;
    }
    previous_s = presented_s;
  }
  EXPECT_GE(presenter.now_s(), previous_s);
  EXPECT_TRUE(presenter.screenshot_is_readback()) << "device " << presenter.device_name();
  EXPECT_TRUE(same_pixels(presenter.screenshot(), pattern)) << "device " << presenter.device_name();
  EXPECT_EQ(presenter.validation_message_count(), 0u);
}

// A frame held in a buffer of `context` (host-visible memory, read by the compose pass as any
// storage buffer).
struct FrameOnDevice {
  vk::Buffer buffer;
  DeviceRgba8Frame frame;
};
FrameOnDevice on_device(const vk::Context& context, const Rgba8Frame& bytes) {
  FrameOnDevice held{vk::Buffer(context, bytes.rgba.size(), vk::MemoryUse::host_upload), {}};
  std::memcpy(held.buffer.mapped(), bytes.rgba.data(), bytes.rgba.size());
  held.buffer.flush();
  held.frame = DeviceRgba8Frame{&context, held.buffer.handle(), bytes.width, bytes.height};
  return held;
}

// A frame on the presenter's own device goes to the swapchain without the host; one on another
// device is read back and uploaded, and counted. Both show exactly, and wait_until keeps them.
TEST(WindowPresenter, PresentsFramesHeldOnItsDeviceAndOnAnother) {
  REQUIRE_DISPLAY();
  WindowPresenter presenter(small_window());
  const Rgba8Frame pattern = quadrant_pattern(320, 180);
  const FrameOnDevice same = on_device(presenter.context(), pattern);
  presenter.present(same.frame);
  EXPECT_TRUE(same_pixels(presenter.screenshot(), pattern));
  presenter.wait_until(presenter.now_s() + 3.0 / presenter.refresh_hz());  // re-presents the composed image
  EXPECT_TRUE(same_pixels(presenter.screenshot(), pattern));
  EXPECT_EQ(presenter.cross_device_copies().frames, 0);

  vk::Context other(vk::ContextOptions{"", true, std::nullopt});
  const Rgba8Frame small = quadrant_pattern(100, 50);
  const FrameOnDevice elsewhere = on_device(other, small);
  presenter.present(elsewhere.frame);
  Rgba8Frame expected(320, 180);  // x3 at (10, 15)
  for (int y = 0; y < 150; ++y)
    for (int x = 0; x < 300; ++x) {
      const uint8_t* p = small.rgba.data() + (static_cast<size_t>(y / 3) * 100 + static_cast<size_t>(x / 3)) * 4;
      set_pixel(expected, x + 10, y + 15, p[0], p[1], p[2]);
    }
  EXPECT_TRUE(same_pixels(presenter.screenshot(), expected));
  EXPECT_EQ(presenter.cross_device_copies().frames, 1);
  EXPECT_GT(presenter.cross_device_copies().seconds, 0.0);
  EXPECT_EQ(presenter.validation_message_count(), 0u);
  EXPECT_EQ(other.validation_message_count(), 0u);
}

TEST(WindowPresenter, LetterboxesASmallerFrameAtAnIntegerScale) {
  REQUIRE_DISPLAY();
  WindowPresenter presenter(small_window());
  const Rgba8Frame small = quadrant_pattern(100, 50);  // x3 = 300x150 at (10, 15) in 320x180
  presenter.present(small);
  const Rgba8Frame shot = presenter.screenshot();
  ASSERT_EQ(shot.width, 320);
  ASSERT_EQ(shot.height, 180);
  Rgba8Frame expected(320, 180);
  for (int y = 0; y < 150; ++y) {
    for (int x = 0; x < 300; ++x) {
      const uint8_t* p = small.rgba.data() + (static_cast<size_t>(y / 3) * 100 + static_cast<size_t>(x / 3)) * 4;
      set_pixel(expected, x + 10, y + 15, p[0], p[1], p[2]);
    }
  }
  EXPECT_TRUE(same_pixels(shot, expected));
  // The pointer over the frame maps back to frame pixels; over the letterbox it is nowhere.
  // (X11 pointer positions are whole screen pixels.)
  glfwSetCursorPos(presenter.glfw_window(), 10 + 3 * 20 + 2, 15 + 3 * 10);
  const auto cursor = presenter.cursor_px();
  ASSERT_TRUE(cursor.has_value());
  EXPECT_NEAR(cursor->first, 20 + 2.0 / 3.0, 1e-9);
  EXPECT_NEAR(cursor->second, 10.0, 1e-9);
  glfwSetCursorPos(presenter.glfw_window(), 5.0, 5.0);
  EXPECT_FALSE(presenter.cursor_px().has_value());
  EXPECT_EQ(presenter.validation_message_count(), 0u);
}

TEST(WindowPresenter, FullscreenCentresAndLetterboxes) {
  REQUIRE_DISPLAY();
  WindowPresenterOptions options = small_window();
  options.width_px = 300;
  options.height_px = 200;
  options.fullscreen = true;
  WindowPresenter presenter(options);
  const auto [width, height] = presenter.swapchain_extent_px();  // the monitor's mode (Xvfb: 1280x720)
  ASSERT_GE(width, 300);
  ASSERT_GE(height, 200);
  const int scale = std::min(width / 300, height / 200);
  const int left = (width - 300 * scale) / 2, top = (height - 200 * scale) / 2;
  const Rgba8Frame frame = quadrant_pattern(300, 200);
  presenter.present(frame);
  presenter.present(frame);
  Rgba8Frame expected(width, height);
  for (int y = 0; y < 200 * scale; ++y) {
    for (int x = 0; x < 300 * scale; ++x) {
      const uint8_t* p =
          frame.rgba.data() + (static_cast<size_t>(y / scale) * 300 + static_cast<size_t>(x / scale)) * 4;
      set_pixel(expected, x + left, y + top, p[0], p[1], p[2]);
    }
  }
  EXPECT_TRUE(same_pixels(presenter.screenshot(), expected)) << "scale " << scale;
  // (GLFW warps the pointer only into a focused window, and without a window manager a full-screen
  // window is not focused: only the mapping of wherever the pointer is gets checked.)
  if (const auto cursor = presenter.cursor_px()) {
    EXPECT_GE(cursor->first, 0.0);
    EXPECT_LT(cursor->first, 300.0);
    EXPECT_GE(cursor->second, 0.0);
    EXPECT_LT(cursor->second, 200.0);
  }
  EXPECT_EQ(presenter.validation_message_count(), 0u);
}

TEST(WindowPresenter, RecreatesTheSwapchainWhenTheWindowChangesSize) {
  REQUIRE_DISPLAY();
  WindowPresenter presenter(small_window());
  const Rgba8Frame frame = quadrant_pattern(320, 180);
  presenter.present(frame);
  glfwSetWindowSize(presenter.glfw_window(), 400, 240);
  for (int i = 0; i < 50 && presenter.swapchain_extent_px() != std::make_pair(400, 240); ++i) {
    presenter.present(frame);
  }
  ASSERT_EQ(presenter.swapchain_extent_px(), std::make_pair(400, 240));
  presenter.present(frame);
  Rgba8Frame expected(400, 240);
  for (int y = 0; y < 180; ++y) {
    for (int x = 0; x < 320; ++x) {
      const uint8_t* p = frame.rgba.data() + (static_cast<size_t>(y) * 320 + static_cast<size_t>(x)) * 4;
      set_pixel(expected, x + 40, y + 30, p[0], p[1], p[2]);
    }
  }
  EXPECT_TRUE(same_pixels(presenter.screenshot(), expected));
  EXPECT_EQ(presenter.validation_message_count(), 0u);
}

TEST(WindowPresenter, TextScreenScreenshotSavesAsPng) {
  REQUIRE_DISPLAY();
  WindowPresenter presenter(small_window());
  const Rgba8Frame text = render_text_screen(320, 180, "Which image was sharper?\nLeft: A    Right: B");
  presenter.present(text);
  const Rgba8Frame shot = presenter.screenshot();
  EXPECT_TRUE(same_pixels(shot, text));

  const std::filesystem::path png = fovlab::testing::scratch_folder("fovlab-window-presenter") / "text_screen.png";
  write_frame_image(png, shot);
  EXPECT_TRUE(same_pixels(image_to_frame(read_image(png)), shot));
  EXPECT_EQ(presenter.validation_message_count(), 0u);
}

TEST(WindowPresenter, WaitUntilKeepsTheFrameAndAdvancesTheClock) {
  REQUIRE_DISPLAY();
  WindowPresenter presenter(small_window());
  const Rgba8Frame cross = fixation_cross_frame(320, 180);
  const double shown_s = presenter.present(cross);
  const double until_s = shown_s + 0.2;
  presenter.wait_until(until_s);
  const double after_s = presenter.now_s();
  EXPECT_GE(after_s, until_s);
  EXPECT_LT(after_s, until_s + 1.0 / presenter.refresh_hz() + 0.05) << "overshot by more than a refresh";
  EXPECT_TRUE(same_pixels(presenter.screenshot(), cross));
  presenter.wait_until(0.0);  // the past: returns at once
  EXPECT_LT(presenter.now_s() - after_s, 0.05);
  EXPECT_EQ(presenter.validation_message_count(), 0u);
}

TEST(WindowPresenter, CloseRequestAndInput) {
  REQUIRE_DISPLAY();
  WindowPresenter presenter(small_window());
  presenter.present(black_frame(320, 180));
  EXPECT_TRUE(presenter.poll_input().empty());  // nobody at the keyboard of a test
  EXPECT_FALSE(presenter.close_requested());
  glfwSetWindowShouldClose(presenter.glfw_window(), GLFW_TRUE);
  EXPECT_TRUE(presenter.close_requested());
  EXPECT_THROW(presenter.present(Rgba8Frame{}), std::invalid_argument);
  EXPECT_EQ(presenter.validation_message_count(), 0u);
}

TEST(WindowPresenter, ThreeEscapesCloseAndSaySo) {
  // Issue 18: a session stopped with Escape was logged as "the window was closed".
  REQUIRE_DISPLAY();
  WindowPresenter presenter(small_window());
  presenter.present(black_frame(320, 180));
  EXPECT_EQ(presenter.close_reason(), "the window was closed");  // what a close would say
  for (int i = 0; i < 3; ++i) presenter.on_key(GLFW_KEY_ESCAPE, nullptr);
  EXPECT_TRUE(presenter.close_requested());
  EXPECT_EQ(presenter.close_reason(), "Escape was pressed 3 times within 1 s");
  EXPECT_EQ(presenter.validation_message_count(), 0u);
}

TEST(WindowInput, KeyNames) {
  EXPECT_EQ(glfw_key_name(GLFW_KEY_A, nullptr), "a");
  EXPECT_EQ(glfw_key_name(GLFW_KEY_Z, "y"), "y");  // the layout's label wins (German keyboard)
  EXPECT_EQ(glfw_key_name(GLFW_KEY_Y, "Z"), "z");
  EXPECT_EQ(glfw_key_name(GLFW_KEY_Q, "\xD0\xB9"), "q");  // a Cyrillic label: the US position
  EXPECT_EQ(glfw_key_name(GLFW_KEY_7, nullptr), "7");
  EXPECT_EQ(glfw_key_name(GLFW_KEY_KP_3, "3"), "3");
  EXPECT_EQ(glfw_key_name(GLFW_KEY_SPACE, nullptr), "space");
  EXPECT_EQ(glfw_key_name(GLFW_KEY_ENTER, nullptr), "enter");
  EXPECT_EQ(glfw_key_name(GLFW_KEY_KP_ENTER, nullptr), "enter");
  EXPECT_EQ(glfw_key_name(GLFW_KEY_ESCAPE, nullptr), "escape");
  EXPECT_EQ(glfw_key_name(GLFW_KEY_LEFT, nullptr), "left");
  EXPECT_EQ(glfw_key_name(GLFW_KEY_RIGHT, nullptr), "right");
  EXPECT_EQ(glfw_key_name(GLFW_KEY_UP, nullptr), "up");
  EXPECT_EQ(glfw_key_name(GLFW_KEY_DOWN, nullptr), "down");
  EXPECT_EQ(glfw_key_name(GLFW_KEY_F1, nullptr), "");
  EXPECT_EQ(glfw_key_name(GLFW_KEY_LEFT_SHIFT, nullptr), "");
}

TEST(WindowInput, GamepadButtonNames) {
  std::vector<std::string> names;
  for (const auto& [button, name] : glfw_gamepad_buttons()) {
    EXPECT_GE(button, 0);
    EXPECT_LE(button, GLFW_GAMEPAD_BUTTON_LAST);
    names.push_back(name);
  }
  EXPECT_EQ(names, (std::vector<std::string>{"pad_a", "pad_b", "pad_x", "pad_y", "pad_left", "pad_right", "pad_up",
                                             "pad_down", "pad_start", "pad_back", "pad_lb", "pad_rb"}));
}

TEST(WindowInput, ThreeEscapesWithinOneSecondClose) {
  EscapeRepeatDetector slow;
  EXPECT_FALSE(slow.press(0.0));
  EXPECT_FALSE(slow.press(0.6));
  EXPECT_FALSE(slow.press(1.2));  // the first fell out of the second
  EXPECT_TRUE(slow.press(1.5));
  EscapeRepeatDetector fast;
  EXPECT_FALSE(fast.press(10.0));
  EXPECT_FALSE(fast.press(10.1));
  EXPECT_TRUE(fast.press(10.2));
  EXPECT_FALSE(fast.press(10.3));  // starts counting again
}

}  // namespace
}  // namespace fovlab
