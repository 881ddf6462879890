// Answers and gaze in the headset (display/openxr/openxr_input.h) on the test runtime
// (tests/xr_runtime) through the Khronos loader, with the OpenXR core validation layer and the Vulkan
// validation layer on: scripted presses of each controller arrive from sync() as the protocols'
// pad_* keys, once each, at their frames' predicted display times, none before the session is
// FOCUSED; the eye tracker's gaze ray is the scripted one, from the head; a runtime without
// XR_EXT_eye_gaze_interaction gives no gaze.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "core/input_error.h"
#include "display/openxr/openxr_frame_loop.h"
#include "display/openxr/openxr_input.h"
#include "display/openxr/openxr_session.h"
#include "renderer/vk/buffer.h"
#include "tests/display/openxr/openxr_test_support.h"

namespace fovlab {
namespace {

using test::OpenXrTest;
using test::ScopedEnvironment;

using OpenXrHeadsetInput = OpenXrTest;

constexpr int kEyeSizePx = 16;

OpenXrSessionOptions small_session() {
  OpenXrSessionOptions options;
  options.eye_width_px = kEyeSizePx;
  options.eye_height_px = kEyeSizePx;
  options.validation = true;
  return options;
}

// A grey frame of the eye's size on the session's device, given to both eyes of every frame.
class GreyEyes {
 public:
  explicit GreyEyes(const vk::Context& context)
      : context_(context), buffer_(context, kEyeSizePx * kEyeSizePx * 4, vk::MemoryUse::host_upload) {
    std::memset(buffer_.mapped(), 128, kEyeSizePx * kEyeSizePx * 4);
    buffer_.flush();
  }
  OpenXrEyeFrameSource source() const {
    return [this](uint32_t, const OpenXrEyeView&) {
      return DeviceRgba8Frame{&context_, buffer_.handle(), kEyeSizePx, kEyeSizePx};
    };
  }

 private:
  const vk::Context& context_;
  vk::Buffer buffer_;
};

// A press as the test sees it: the key, and the frame whose predicted display time the press carries
// (-1: no frame's).
using KeyAtFrame = std::pair<std::string, int>;

// Runs `frame_count` frames of a session with the given controller and script (lines of the
// FOVLAB_TEST_XR_INPUT file), syncing after each frame, before the events that frame brought are
// polled; `press_before` presses inputs in-process (fovlab_test_xr_press) before the frame of the
// given number.
std::vector<KeyAtFrame> run_script(const std::filesystem::path& folder, const std::string& controller,
                                   const std::vector<std::string>& script, int frame_count,
                                   const std::map<int, std::string>& press_before = {}) {
  const std::filesystem::path script_file = folder / ("input_" + controller + ".txt");
  {
    std::ofstream out(script_file);
    for (const std::string& line : script) out << line << "\n";
  }
  ScopedEnvironment controller_setting("FOVLAB_TEST_XR_CONTROLLER", controller);
  ScopedEnvironment input_setting("FOVLAB_TEST_XR_INPUT", script_file.string());
  void* runtime_library = dlopen(FOVLAB_TEST_XR_RUNTIME_LIBRARY, RTLD_NOW | RTLD_LOCAL);
  EXPECT_NE(runtime_library, nullptr) << dlerror();
  using Press = XrResult (*)(const char*);
  const auto press = reinterpret_cast<Press>(dlsym(runtime_library, "fovlab_test_xr_press"));
  EXPECT_NE(press, nullptr);

  std::vector<KeyAtFrame> seen;
  {
    OpenXrSession session(small_session());
    OpenXrInput input(session);
    const GreyEyes eyes(*session.vulkan);
    poll_openxr_events(session);  // IDLE, READY: begun
    EXPECT_TRUE(input.sync().empty()) << "no input before the session is FOCUSED";
    std::map<XrTime, int> frame_of_time;
    for (int n = 1; n <= frame_count; ++n) {
      if (const auto in_process = press_before.find(n); in_process != press_before.end() && press != nullptr) {
        EXPECT_EQ(press(in_process->second.c_str()), XR_SUCCESS) << in_process->second;
      }
      const OpenXrFrame frame = run_openxr_frame(session, eyes.source());
      frame_of_time[frame.predicted_display_time] = n;
      if (n == 1) {
        // The first frame brought FOCUSED, not yet polled; were the application's state stale the
        // other way (focus lost, not yet polled), the runtime still gives nothing: xrSyncActions
        // says XR_SESSION_NOT_FOCUSED. Pretend so.
        EXPECT_NE(session.state, XR_SESSION_STATE_FOCUSED);
        const XrSessionState polled = session.state;
        session.state = XR_SESSION_STATE_FOCUSED;
        EXPECT_TRUE(input.sync().empty()) << "the runtime's session is not FOCUSED yet";
        session.state = polled;
      } else {
        EXPECT_EQ(session.state, XR_SESSION_STATE_FOCUSED);
        for (const OpenXrButtonPress& pressed : input.sync()) {
          const auto found = frame_of_time.find(pressed.time);
          seen.emplace_back(pressed.key, found == frame_of_time.end() ? -1 : found->second);
        }
      }
      poll_openxr_events(session);
    }
    EXPECT_EQ(session.vulkan->validation_message_count(), 0u) << "Vulkan validation messages";
  }
  if (runtime_library != nullptr) dlclose(runtime_library);
  return seen;
}

TEST_F(OpenXrHeadsetInput, XboxControllerButtonsGiveTheirKeysAtTheirFrames) {
  const std::vector<std::string> script{
      "1 /user/gamepad/input/a/click",  // before FOCUSED: not given
      "4 /user/gamepad/input/b/click",
      "# comment lines and blank lines are skipped",
      "",
      "6 /user/gamepad/input/dpad_left/click",
      "6 /user/gamepad/input/shoulder_right/click",
      "7 /user/gamepad/input/x/click",
      "7 /user/gamepad/input/dpad_up/click",
      "8 /user/gamepad/input/menu/click",
      "9 /user/gamepad/input/view/click",
      "10 /user/gamepad/input/dpad_right/click",
      "10 /user/gamepad/input/dpad_down/click",
      "11 /user/gamepad/input/thumbstick_left/click",  // bound to nothing
      "11 /user/gamepad/input/shoulder_left/click",
      "13 /user/gamepad/input/a/click",
      "14 /user/gamepad/input/a/click",  // held from frame 13: one press
  };
  const std::vector<KeyAtFrame> expected{
      {"pad_b", 4},    {"pad_left", 6},   {"pad_rb", 6},    {"pad_x", 7},   {"pad_up", 7}, {"pad_start", 8},
      {"pad_back", 9}, {"pad_right", 10}, {"pad_down", 10}, {"pad_lb", 11}, {"pad_y", 12}, {"pad_a", 13},
  };
  EXPECT_EQ(run_script(scratch_.path(), "xbox", script, 16, {{12, "/user/gamepad/input/y/click"}}), expected);
}

TEST_F(OpenXrHeadsetInput, ViveControllerButtonsOfEitherHandGiveTheirKeys) {
  const std::vector<std::string> script{
      "1 /user/hand/right/input/trigger/click",  // before FOCUSED
      "3 /user/hand/right/input/trigger/click", "5 /user/hand/left/input/trackpad/click",
      "7 /user/hand/left/input/squeeze/click",  "7 /user/hand/right/input/menu/click",
      "9 /user/hand/left/input/trigger/click",
      "10 /user/hand/right/input/system/click",  // the runtime's: bound to nothing
  };
  const std::vector<KeyAtFrame> expected{{"pad_a", 3}, {"pad_b", 5}, {"pad_x", 7}, {"pad_start", 7}, {"pad_a", 9}};
  EXPECT_EQ(run_script(scratch_.path(), "vive", script, 12), expected);
}

TEST_F(OpenXrHeadsetInput, SimpleControllerSelectAndMenuGiveTheirKeys) {
  const std::vector<std::string> script{
      "1 /user/hand/left/input/select/click",  // before FOCUSED
      "4 /user/hand/left/input/select/click",  "6 /user/hand/right/input/menu/click",
      "8 /user/hand/right/input/select/click",
      "9 /user/hand/right/input/select/click",  // held: one press
      "11 /user/hand/left/input/menu/click",
  };
  const std::vector<KeyAtFrame> expected{{"pad_a", 4}, {"pad_start", 6}, {"pad_a", 8}, {"pad_start", 11}};
  EXPECT_EQ(run_script(scratch_.path(), "simple", script, 12), expected);
}

// The runtime refuses a script it cannot follow when the session is made, instead of pressing
// nothing: a malformed line, and a button the connected controller does not have.
TEST_F(OpenXrHeadsetInput, MalformedScriptFailsTheSession) {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"xbox", "x /user/gamepad/input/a/click"},           {"xbox", "0 /user/gamepad/input/a/click"},
      {"xbox", "5 /user/gamepad/input/a/click extra"},     {"xbox", "5 /user/hand/left/input/trigger/click"},
      {"simple", "5 /user/hand/left/input/trigger/click"},
  };
  for (const auto& [controller, line] : cases) {
    const std::filesystem::path script_file = scratch_.path() / "malformed.txt";
    std::ofstream(script_file) << line << "\n";
    ScopedEnvironment controller_setting("FOVLAB_TEST_XR_CONTROLLER", controller);
    ScopedEnvironment input_setting("FOVLAB_TEST_XR_INPUT", script_file.string());
    try {
      OpenXrSession session(small_session());
      ADD_FAILURE() << controller << ": \"" << line << "\" was accepted";
    } catch (const InputError& error) {
      EXPECT_STREQ(error.what(), "openxr: xrCreateSession: XR_ERROR_RUNTIME_FAILURE") << line;
    }
  }
}

TEST_F(OpenXrHeadsetInput, GazeRayIsTheScriptedOneFromTheHead) {
  const double yaw_deg = 12.5;
  const double pitch_deg = -7.25;
  ScopedEnvironment gaze_setting("FOVLAB_TEST_XR_GAZE", "12.5,-7.25");
  OpenXrSession session(small_session());
  EXPECT_TRUE(session.eye_gaze_enabled);
  EXPECT_TRUE(session.convert_timespec_enabled);
  OpenXrInput input(session);
  ASSERT_TRUE(input.has_eye_gaze());
  const GreyEyes eyes(*session.vulkan);
  poll_openxr_events(session);
  OpenXrFrame frame = run_openxr_frame(session, eyes.source());
  input.sync();
  EXPECT_FALSE(input.locate_gaze(frame.predicted_display_time)) << "no gaze before the session is FOCUSED";
  poll_openxr_events(session);
  ASSERT_EQ(session.state, XR_SESSION_STATE_FOCUSED);

  frame = run_openxr_frame(session, eyes.source());
  input.sync();
  const std::optional<OpenXrGazeRay> gaze = input.locate_gaze(frame.predicted_display_time);
  ASSERT_TRUE(gaze);
  const double yaw = yaw_deg * std::numbers::pi / 180.0;
  const double pitch = pitch_deg * std::numbers::pi / 180.0;
  EXPECT_NEAR(gaze->direction[0], std::cos(pitch) * std::sin(yaw), 1e-6) << "right of ahead";
  EXPECT_NEAR(gaze->direction[1], std::sin(pitch), 1e-6) << "below ahead";
  EXPECT_NEAR(gaze->direction[2], -std::cos(pitch) * std::cos(yaw), 1e-6);
  for (const double coordinate : gaze->origin_m) EXPECT_NEAR(coordinate, 0.0, 1e-6) << "from the head";
  EXPECT_EQ(gaze->sample_time, frame.predicted_display_time);

  // Without tracking the runtime clears the location's bits: no gaze, until tracking is back.
  ::setenv("FOVLAB_TEST_XR_TRACKING", "lost", 1);
  const bool lost_gaze = input.locate_gaze(frame.predicted_display_time).has_value();
  ::unsetenv("FOVLAB_TEST_XR_TRACKING");
  EXPECT_FALSE(lost_gaze);
  EXPECT_TRUE(input.locate_gaze(frame.predicted_display_time));

  request_openxr_exit(session);
  poll_openxr_events(session);
  EXPECT_EQ(session.vulkan->validation_message_count(), 0u) << "Vulkan validation messages";
}

// In a child process: the 1.0.20 loader keeps the runtime's extension list as it first loaded it
// (openxr_session_test.cpp). Exit codes: 0 as expected, 3 the session enabled eye gaze, 4 the input
// has it, 5 a gaze was located, 6 Vulkan validation messages.
TEST_F(OpenXrHeadsetInput, NoGazeWithoutTheEyeGazeExtension) {
  const auto run_without_eye_tracker = [] {
    setenv("FOVLAB_TEST_XR_EYE_GAZE", "absent", 1);
    int code = 0;
    {
      OpenXrSession session(small_session());
      OpenXrInput input(session);
      const GreyEyes eyes(*session.vulkan);
      poll_openxr_events(session);
      bool gaze_located = false;
      for (int n = 0; n < 3; ++n) {
        const OpenXrFrame frame = run_openxr_frame(session, eyes.source());
        input.sync();
        gaze_located = gaze_located || input.locate_gaze(frame.predicted_display_time).has_value();
        poll_openxr_events(session);
      }
      if (session.state != XR_SESSION_STATE_FOCUSED) code = 7;
      if (gaze_located) code = 5;
      if (input.has_eye_gaze()) code = 4;
      if (session.eye_gaze_enabled) code = 3;
      if (session.vulkan->validation_message_count() != 0) code = 6;
    }
    std::fprintf(stderr, "exit %d\n", code);
    std::fflush(stderr);
    std::_Exit(code);
  };
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(run_without_eye_tracker(), ::testing::ExitedWithCode(0), "exit 0");
}

// The runtime's side of the action calls, as the specification gives their results for misuse
// (results a runtime returns, not valid-usage rules, so the validation layer stays silent).
TEST_F(OpenXrHeadsetInput, RuntimeAnswersMisuseWithTheSpecificationsResults) {
  OpenXrSession session(small_session());
  const XrInstance instance = session.instance.handle;
  const auto path = [&](const char* text) {
    XrPath made = XR_NULL_PATH;
    EXPECT_EQ(xrStringToPath(instance, text, &made), XR_SUCCESS) << text;
    return made;
  };
  XrPath unused = XR_NULL_PATH;
  EXPECT_EQ(xrStringToPath(instance, "/user/Gamepad", &unused), XR_ERROR_PATH_FORMAT_INVALID);
  EXPECT_EQ(xrStringToPath(instance, "/user/gamepad/", &unused), XR_ERROR_PATH_FORMAT_INVALID);
  EXPECT_EQ(xrStringToPath(instance, "/user//gamepad", &unused), XR_ERROR_PATH_FORMAT_INVALID);
  const XrPath gamepad = path("/user/gamepad");
  EXPECT_EQ(path("/user/gamepad"), gamepad) << "one path a string";
  uint32_t length = 0;
  ASSERT_EQ(xrPathToString(instance, gamepad, 0, &length, nullptr), XR_SUCCESS);
  EXPECT_EQ(length, 14u) << "with the terminating zero";
  std::string text(length, '?');
  ASSERT_EQ(xrPathToString(instance, gamepad, length, &length, text.data()), XR_SUCCESS);
  EXPECT_STREQ(text.c_str(), "/user/gamepad");

  XrActionSetCreateInfo set_info{XR_TYPE_ACTION_SET_CREATE_INFO};
  std::strcpy(set_info.actionSetName, "misuse");
  std::strcpy(set_info.localizedActionSetName, "Misuse");
  XrActionSet action_set = XR_NULL_HANDLE;
  ASSERT_EQ(xrCreateActionSet(instance, &set_info, &action_set), XR_SUCCESS);
  const auto make_action = [&](const char* name, XrActionType type, XrAction* action) {
    XrActionCreateInfo info{XR_TYPE_ACTION_CREATE_INFO};
    info.actionType = type;
    std::strcpy(info.actionName, name);
    std::strcpy(info.localizedActionName, name);
    return xrCreateAction(action_set, &info, action);
  };
  XrAction button = XR_NULL_HANDLE;
  XrAction pose = XR_NULL_HANDLE;
  XrAction refused = XR_NULL_HANDLE;
  ASSERT_EQ(make_action("button", XR_ACTION_TYPE_BOOLEAN_INPUT, &button), XR_SUCCESS);
  ASSERT_EQ(make_action("pose", XR_ACTION_TYPE_POSE_INPUT, &pose), XR_SUCCESS);
  EXPECT_EQ(make_action("button", XR_ACTION_TYPE_BOOLEAN_INPUT, &refused), XR_ERROR_NAME_DUPLICATED);
  EXPECT_EQ(make_action("Button", XR_ACTION_TYPE_BOOLEAN_INPUT, &refused), XR_ERROR_NAME_INVALID);

  const auto suggest = [&](const char* profile, XrAction action, const char* binding) {
    const XrActionSuggestedBinding suggested_binding{action, path(binding)};
    XrInteractionProfileSuggestedBinding suggested{XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING};
    suggested.interactionProfile = path(profile);
    suggested.countSuggestedBindings = 1;
    suggested.suggestedBindings = &suggested_binding;
    return xrSuggestInteractionProfileBindings(instance, &suggested);
  };
  const char* xbox = "/interaction_profiles/microsoft/xbox_controller";
  EXPECT_EQ(suggest(xbox, button, "/user/hand/left/input/trigger/click"), XR_ERROR_PATH_UNSUPPORTED);
  EXPECT_EQ(suggest(xbox, button, "/user/gamepad/input/trigger/click"), XR_ERROR_PATH_UNSUPPORTED);
  EXPECT_EQ(suggest("/interaction_profiles/khr/simple_controller", button, "/user/hand/left/input/trigger/click"),
            XR_ERROR_PATH_UNSUPPORTED);
  EXPECT_EQ(suggest("/interaction_profiles/fovlab/no_such_controller", button, "/user/gamepad/input/a/click"),
            XR_ERROR_PATH_UNSUPPORTED);
  ASSERT_EQ(suggest(xbox, button, "/user/gamepad/input/a/click"), XR_SUCCESS);

  const XrActiveActionSet active{action_set, XR_NULL_PATH};
  XrActionsSyncInfo sync_info{XR_TYPE_ACTIONS_SYNC_INFO};
  sync_info.countActiveActionSets = 1;
  sync_info.activeActionSets = &active;
  EXPECT_EQ(xrSyncActions(session.session, &sync_info), XR_ERROR_ACTIONSET_NOT_ATTACHED);
  XrInteractionProfileState profile{XR_TYPE_INTERACTION_PROFILE_STATE};
  EXPECT_EQ(xrGetCurrentInteractionProfile(session.session, gamepad, &profile), XR_ERROR_ACTIONSET_NOT_ATTACHED);

  XrSessionActionSetsAttachInfo attach{XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO};
  attach.countActionSets = 1;
  attach.actionSets = &action_set;
  ASSERT_EQ(xrAttachSessionActionSets(session.session, &attach), XR_SUCCESS);
  EXPECT_EQ(xrAttachSessionActionSets(session.session, &attach), XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);
  EXPECT_EQ(make_action("late", XR_ACTION_TYPE_BOOLEAN_INPUT, &refused), XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);
  EXPECT_EQ(suggest(xbox, button, "/user/gamepad/input/b/click"), XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);

  ASSERT_EQ(xrGetCurrentInteractionProfile(session.session, gamepad, &profile), XR_SUCCESS);
  EXPECT_EQ(profile.interactionProfile, path(xbox)) << "the connected controller, bindings suggested";
  ASSERT_EQ(xrGetCurrentInteractionProfile(session.session, path("/user/hand/left"), &profile), XR_SUCCESS);
  EXPECT_EQ(profile.interactionProfile, XR_NULL_PATH);
  EXPECT_EQ(xrGetCurrentInteractionProfile(session.session, path("/user/gamepad/input"), &profile),
            XR_ERROR_PATH_UNSUPPORTED);

  XrActionStateGetInfo get_info{XR_TYPE_ACTION_STATE_GET_INFO};
  get_info.action = pose;
  XrActionStateBoolean state{XR_TYPE_ACTION_STATE_BOOLEAN};
  EXPECT_EQ(xrGetActionStateBoolean(session.session, &get_info, &state), XR_ERROR_ACTION_TYPE_MISMATCH);
  XrActionSpaceCreateInfo space_info{XR_TYPE_ACTION_SPACE_CREATE_INFO};
  space_info.action = button;
  space_info.poseInActionSpace.orientation.w = 1.0f;
  XrSpace space = XR_NULL_HANDLE;
  EXPECT_EQ(xrCreateActionSpace(session.session, &space_info, &space), XR_ERROR_ACTION_TYPE_MISMATCH);
  EXPECT_EQ(xrSyncActions(session.session, &sync_info), XR_SESSION_NOT_FOCUSED) << "the session is not running";
  EXPECT_EQ(xrDestroyActionSet(action_set), XR_SUCCESS);
  EXPECT_EQ(session.vulkan->validation_message_count(), 0u) << "Vulkan validation messages";
}

}  // namespace
}  // namespace fovlab
