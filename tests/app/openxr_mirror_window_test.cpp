// The operator's mirror window of a headset session (`fovlab run --mirror-window`, docs/hmd.md): in
// the test runtime (tests/xr_runtime) with both validation layers on. The window tests need a display
// and skip without one; CTest's HeadsetMirrorUnderXvfb runs them under xvfb-run. Keys reach the
// mirror as an operator's would: through the X server (XTest, loaded at run time so that the tests
// link no X library), into the window under the pointer.
#include <gtest/gtest.h>

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include <GLFW/glfw3.h>
#include <nlohmann/json.hpp>

#include "display/frame_io.h"
#include "display/openxr/openxr_presenter.h"
#include "renderer/present/frame_compose.h"
#include "tests/app/headset_study_support.h"
#include "tests/support/fovlab_child.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;
using cli_test::CommandResult;
using test::headset_study;
using test::HeadsetStudy;
using test::LogFollower;

#define REQUIRE_DISPLAY()                                                                               \
  do {                                                                                                  \
    const char* display = std::getenv("DISPLAY");                                                       \
    if (!display || !*display) {                                                                        \
      if (std::getenv("FOVLAB_REQUIRE_DISPLAY")) FAIL() << "FOVLAB_REQUIRE_DISPLAY set but no DISPLAY"; \
      GTEST_SKIP() << "no DISPLAY: runs under xvfb-run (CTest: HeadsetMirrorUnderXvfb)";                \
    }                                                                                                   \
  } while (false)

// The headset study with the runtime's eye gaze ray (straight ahead) resting on a plane: what each
// eye is shown depends on the stimulus and its frame, never on when an answer came.
std::string mirrored_study() { return headset_study(test::kEyesAtDistance); }

std::vector<nlohmann::json> events_of(const fs::path& log) {
  std::vector<nlohmann::json> events;
  std::ifstream lines(log);
  for (std::string line; std::getline(lines, line);) events.push_back(nlohmann::json::parse(line));
  return events;
}

// Keys typed on the X server's keyboard (XTest), into the window under the pointer. The few Xlib and
// XTest functions are declared here and found with dlsym; empty when either library is missing.
class XKeyboard {
 public:
  XKeyboard() {
    x11_ = dlopen("libX11.so.6", RTLD_NOW | RTLD_LOCAL);
    xtst_ = dlopen("libXtst.so.6", RTLD_NOW | RTLD_LOCAL);
    if (!x11_ || !xtst_) return;
    open_ = reinterpret_cast<void* (*)(const char*)>(dlsym(x11_, "XOpenDisplay"));
    close_ = reinterpret_cast<int (*)(void*)>(dlsym(x11_, "XCloseDisplay"));
    keysym_ = reinterpret_cast<unsigned long (*)(const char*)>(dlsym(x11_, "XStringToKeysym"));
    keycode_ = reinterpret_cast<unsigned char (*)(void*, unsigned long)>(dlsym(x11_, "XKeysymToKeycode"));
    sync_ = reinterpret_cast<int (*)(void*, int)>(dlsym(x11_, "XSync"));
    key_ = reinterpret_cast<int (*)(void*, unsigned, int, unsigned long)>(dlsym(xtst_, "XTestFakeKeyEvent"));
    motion_ = reinterpret_cast<int (*)(void*, int, int, int, unsigned long)>(dlsym(xtst_, "XTestFakeMotionEvent"));
    if (open_ && close_ && keysym_ && keycode_ && sync_ && key_ && motion_) display_ = open_(nullptr);
  }
  ~XKeyboard() {
    if (display_) close_(display_);
    if (xtst_) dlclose(xtst_);
    if (x11_) dlclose(x11_);
  }
  XKeyboard(const XKeyboard&) = delete;
  XKeyboard& operator=(const XKeyboard&) = delete;

  explicit operator bool() const { return display_ != nullptr; }
  // The pointer to (x, y) of the screen: with no window manager, the keyboard follows it.
  void point_at(int x, int y) {
    motion_(display_, -1, x, y, 0);
    sync_(display_, 0);
  }
  // Presses and releases the key of an X keysym name ("s", "space", "Escape").
  void type(const std::string& keysym_names) {
    for (size_t start = 0; start < keysym_names.size();) {
      const size_t end = std::min(keysym_names.find(' ', start), keysym_names.size());
      const unsigned code = keycode_(display_, keysym_(keysym_names.substr(start, end - start).c_str()));
      key_(display_, code, 1, 0);
      key_(display_, code, 0, 0);
      sync_(display_, 0);
      start = end + 1;
      // GLFW takes a release and a press of one key at the same server time for the key's
      // auto-repeat, which is no press: keys typed one after another are apart in time.
      if (start < keysym_names.size()) std::this_thread::sleep_for(std::chrono::milliseconds(30));
    }
  }

 private:
  void* x11_ = nullptr;
  void* xtst_ = nullptr;
  void* display_ = nullptr;
  void* (*open_)(const char*) = nullptr;
  int (*close_)(void*) = nullptr;
  unsigned long (*keysym_)(const char*) = nullptr;
  unsigned char (*keycode_)(void*, unsigned long) = nullptr;
  int (*sync_)(void*, int) = nullptr;
  int (*key_)(void*, unsigned, int, unsigned long) = nullptr;
  int (*motion_)(void*, int, int, int, unsigned long) = nullptr;
};

class HeadsetMirror : public HeadsetStudy {
 protected:
  // `fovlab run --mirror-window` as a participant's session (no --observer), in a child process.
  // After each event of its log, `key_after` names the X keysyms to type into the mirror, separated
  // by spaces ("" for none); keys the session has not answered with an event yet are typed again
  // every 500 ms. Returns the exit code
  // (-1: it did not end within the limit).
  template <typename KeyAfter>
  int run_typing_into_the_mirror(const fs::path& config, KeyAfter key_after) {
    XKeyboard keyboard;
    EXPECT_TRUE(keyboard) << "no XTest (Debian: libxtst6) on the display";
    if (!keyboard) return -1;
    // GLFW opens the window at the screen's top-left corner; no window manager moves it.
    keyboard.point_at(20, 20);
    const pid_t pid = test::start_fovlab(
        {"run", config.string(), "--participant", "P01", "--results", results_.string(), "--mirror-window"}, "",
        output_);
    LogFollower log(results_ / "headset_cli" / "P01" / "events.jsonl");
    return test::answer_while_it_runs(pid, log, std::chrono::seconds(200), key_after,
                                      [&](const std::string& keys) { keyboard.type(keys); });
  }
  fs::path output_ = scratch_.path() / "fovlab_output.txt";
};

// The refusal is one line on stderr (the OpenXR validation layer's own line at load aside), exit 2,
// before the participant's folder exists.
TEST_F(HeadsetMirror, WithoutADisplayRefusesInOneLineBeforeAnyFolder) {
  CommandResult result =
      run_study(write("a.toml", mirrored_study()), "DISPLAY= WAYLAND_DISPLAY=", FOVLAB_TEST_XR_RUNTIME_JSON,
                " --observer simulated --mirror-window");
  const std::string layer_line = "Core Validation output type: ";
  for (size_t at; (at = result.err.find(layer_line)) != std::string::npos;)
    result.err.erase(at, result.err.find('\n', at) + 1 - at);
  cli_test::expect_one_line_error(result, "--mirror-window: cannot open a window (no display");
  EXPECT_FALSE(fs::exists(results_)) << "nothing is written before the refusal";
}

// The mirror changes nothing the participant sees: a simulated observer's session with and without
// it logs the same frames in both eyes, the same answers; both validation layers stay silent.
TEST_F(HeadsetMirror, TheEyesFramesEqualASessionWithoutIt) {
  REQUIRE_DISPLAY();
  const fs::path config = write("a.toml", mirrored_study());
  const CommandResult plain = run_study(config, "", FOVLAB_TEST_XR_RUNTIME_JSON, " --observer simulated");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  fs::rename(results_, scratch_.path() / "plain");
  const CommandResult mirrored =
      run_study(config, "", FOVLAB_TEST_XR_RUNTIME_JSON, " --observer simulated --mirror-window");
  ASSERT_EQ(mirrored.exit_code, 0) << mirrored.err;
  EXPECT_EQ(mirrored.err.find("validation"), std::string::npos) << mirrored.err;

  const auto frames_of = [](const fs::path& log) {
    std::vector<nlohmann::json> frames;
    for (const nlohmann::json& event : events_of(log)) {
      const std::string kind = event.value("event", "");
      if (kind == "stimulus")
        frames.push_back({event["trial"], event["step"], event["hash"], event["right_eye_hash"], event["gaze"]});
      if (kind == "response") frames.push_back({event["trial"], event["answer"]});
    }
    return frames;
  };
  const std::vector<nlohmann::json> expected =
      frames_of(scratch_.path() / "plain" / "headset_cli" / "P01" / "events.jsonl");
  EXPECT_GE(expected.size(), 6u) << "two trials of two stimuli and an answer each";
  EXPECT_EQ(frames_of(results_ / "headset_cli" / "P01" / "events.jsonl"), expected);
}

// Keys typed into the mirror answer as on the desktop: the log's responses carry the keyboard's key
// names; the session ends, both validation layers silent.
TEST_F(HeadsetMirror, KeysTypedIntoTheMirrorAnswer) {
  REQUIRE_DISPLAY();
  const fs::path config = write("a.toml", mirrored_study());
  std::map<int, int> stimuli_of_trial;
  int answers = 0;
  const int exit_code = run_typing_into_the_mirror(config, [&](const nlohmann::json& event) -> std::string {
    const std::string kind = event.value("event", "");
    if (kind == "session_header") return "space";  // the instructions take any answer key
    if (kind == "trial_start") stimuli_of_trial[event["trial"].get<int>()] = static_cast<int>(event["sequence"].size());
    if (kind == "stimulus" && event["step"].get<int>() + 1 == stimuli_of_trial[event["trial"].get<int>()])
      return answers++ % 2 == 0 ? "d" : "s";  // "different", then "same"
    return {};
  });
  const std::string output = cli_test::read_all(output_);
  ASSERT_EQ(exit_code, 0) << output;
  EXPECT_EQ(output.find("validation"), std::string::npos) << output;
  std::vector<std::pair<std::string, std::string>> responses;  // key, answer
  for (const nlohmann::json& event : events_of(results_ / "headset_cli" / "P01" / "events.jsonl")) {
    if (event.value("event", "") == "response") {
      responses.emplace_back(event.value("key", ""), event.value("answer", ""));
      EXPECT_GT(event.value("rt_s", 0.0), 0.0) << event.dump();
    }
    if (event.value("event", "") == "session_end") {
      EXPECT_EQ(event.value("reason", ""), "completed") << event.dump();
    }
  }
  const std::vector<std::pair<std::string, std::string>> expected{{"d", "different"}, {"s", "same"}};
  EXPECT_EQ(responses, expected);
}

// Escape typed 3 times within 1 s into the mirror pauses the session as on the desktop: the log says
// why, is sealed, and the run exits (the headset still focused: nothing to wait for).
TEST_F(HeadsetMirror, ThreeEscapesInTheMirrorPauseTheSession) {
  REQUIRE_DISPLAY();
  const fs::path config = write("a.toml", mirrored_study());
  int escapes = 0;
  const int exit_code = run_typing_into_the_mirror(config, [&](const nlohmann::json& event) -> std::string {
    const std::string kind = event.value("event", "");
    if (kind == "session_header") return "space";
    if (kind == "trial_start" && escapes == 0) {
      ++escapes;
      return "Escape Escape Escape";
    }
    return {};
  });
  const std::string output = cli_test::read_all(output_);
  EXPECT_EQ(exit_code, 0) << output;
  EXPECT_NE(output.find("paused after"), std::string::npos) << output;
  bool paused = false;
  for (const nlohmann::json& event : events_of(results_ / "headset_cli" / "P01" / "events.jsonl"))
    if (event.value("event", "") == "session_paused") {
      paused = true;
      EXPECT_NE(event.dump().find("Escape was pressed 3 times within 1 s"), std::string::npos) << event.dump();
    }
  EXPECT_TRUE(paused);
}

// In the process: the mirror shows the left eye as the headset is given it, integer-scaled, centred
// and letterboxed, read back from the window's swapchain; its keys reach poll_input() beside the
// controller's on the session clock; the screenshot is saved for a person to look at.
TEST_F(HeadsetMirror, ShowsTheLeftEyeLetterboxed) {
  REQUIRE_DISPLAY();
  OpenXrPresenterOptions options;
  options.session.eye_width_px = 64;
  options.session.eye_height_px = 72;
  options.session.validation = true;
  WindowPresenterOptions window;
  window.width_px = 200;  // the eye twice over (128x144) with black around it
  window.height_px = 160;
  window.title = "fovlab mirror test";
  window.validation = true;
  window.screenshots = true;
  options.mirror_window = window;
  OpenXrPresenter headset(options);
  ASSERT_NE(headset.mirror(), nullptr);

  // Each eye a pattern of its own: the left a gradient, the right a flat grey.
  Rgba8Frame left(64, 72), right(64, 72);
  for (int y = 0; y < 72; ++y)
    for (int x = 0; x < 64; ++x) {
      uint8_t* pixel = &left.rgba[4 * (static_cast<size_t>(y) * 64 + x)];
      pixel[0] = static_cast<uint8_t>(4 * x);
      pixel[1] = static_cast<uint8_t>(3 * y);
      pixel[2] = static_cast<uint8_t>((x / 8 + y / 8) % 2 ? 255 : 40);
      pixel[3] = 255;
    }
  for (size_t i = 0; i < right.rgba.size(); i += 4) right.rgba[i] = right.rgba[i + 1] = right.rgba[i + 2] = 128;
  for (size_t i = 3; i < right.rgba.size(); i += 4) right.rgba[i] = 255;
  const std::array<ViewFrame, 2> eyes{ViewFrame{&left, {}, {}}, ViewFrame{&right, {}, {}}};
  const double shown_s = headset.present_views(eyes);
  headset.wait_until(shown_s + 0.05);  // frames repeating the held images; the mirror is not redrawn

  const Rgba8Frame shot = headset.mirror()->screenshot();
  ASSERT_TRUE(headset.mirror()->screenshot_is_readback());
  ASSERT_EQ(shot.width, 200);
  ASSERT_EQ(shot.height, 160);
  const FramePlacement placed = place_frame(64, 72, 200, 160);
  EXPECT_EQ(placed.scale, 2);
  int wrong = 0;
  for (int y = 0; y < 160; ++y)
    for (int x = 0; x < 200; ++x) {
      const int fx = x - placed.dst_x, fy = y - placed.dst_y;
      const bool inside = fx >= 0 && fy >= 0 && fx < 128 && fy < 144;
      for (int c = 0; c < 4; ++c) {
        const uint8_t expected =
            inside ? left.rgba[4 * (static_cast<size_t>(fy / 2) * 64 + fx / 2) + c] : (c == 3 ? 255 : 0);
        wrong += shot.rgba[4 * (static_cast<size_t>(y) * 200 + x) + c] != expected ? 1 : 0;
      }
    }
  EXPECT_EQ(wrong, 0) << "the mirror is the left eye, twice over, centred on black";
  // Kept after the test (the scratch folders are not), overwritten by the next run.
  const fs::path saved = fs::temp_directory_path() / "fovlab_headset_mirror_window.png";
  write_frame_image(saved, shot);
  std::printf("mirror window screenshot: %s\n", saved.c_str());

  // A key in the mirror (as GLFW's key callback gives it) comes out with the controller's presses,
  // timed at the frame after which it was seen.
  headset.mirror()->on_key(GLFW_KEY_D, nullptr);
  headset.wait_until(headset.now_s() + 0.02);
  const std::vector<InputEvent> keys = headset.poll_input();
  ASSERT_EQ(keys.size(), 1u);
  EXPECT_EQ(keys[0].key, "d");
  EXPECT_GT(keys[0].time_s, shown_s);
  EXPECT_LE(keys[0].time_s, headset.now_s());
  EXPECT_FALSE(headset.close_requested());

  // The operator closes the mirror: only the mirror goes; the headset's frames and the session go on.
  glfwSetWindowShouldClose(headset.mirror()->glfw_window(), GLFW_TRUE);
  const double closed_s = headset.now_s();
  headset.wait_until(closed_s + 0.05);
  EXPECT_EQ(headset.mirror(), nullptr);
  EXPECT_FALSE(headset.close_requested());
  EXPECT_GT(headset.present_views(eyes), closed_s + 0.04);
  EXPECT_EQ(headset.context().validation_message_count(), 0u);
}

}  // namespace
}  // namespace fovlab
