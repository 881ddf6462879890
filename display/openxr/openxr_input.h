#pragma once
// A headset session's input through OpenXR's action system: the answer buttons the protocols know
// as gamepad keys ("pad_a" .. "pad_rb", the names display/glfw_input.cpp gives a desktop gamepad's
// buttons), bound on an Xbox controller, a Vive controller and Khronos's simple controller, and the
// eye tracker's gaze ray (XR_EXT_eye_gaze_interaction) where the headset has one. docs/hmd.md,
// "Answers and gaze in the headset", has the bindings.
//
// One action set, "fovlab", attached to the session when this is made: make it before the first
// xrSyncActions and keep it for the session's life (OpenXR attaches action sets once a session).
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "display/openxr/openxr_session.h"

namespace fovlab {

// A button pressed since the last sync: its answer key and when the runtime says it went down.
struct OpenXrButtonPress {
  std::string key;  // "pad_a"
  XrTime time = 0;  // the action's lastChangeTime
};

// The eye tracker's gaze in the session's VIEW space (the head, metres; +x right, +y up, -z ahead).
struct OpenXrGazeRay {
  std::array<double, 3> origin_m{};
  std::array<double, 3> direction{};  // unit: the gaze pose's -Z axis
  XrTime sample_time = 0;             // when the sample is from (XrEyeGazeSampleTimeEXT; 0: not given)
};

class OpenXrInput {
 public:
  // Creates the action set and its actions, suggests each profile's bindings, makes the gaze's action
  // space when the session enabled XR_EXT_eye_gaze_interaction and the system supports eye gaze
  // interaction, and attaches the set to the session. Throws std::runtime_error when a call fails.
  explicit OpenXrInput(OpenXrSession& session);
  ~OpenXrInput();
  OpenXrInput(const OpenXrInput&) = delete;
  OpenXrInput& operator=(const OpenXrInput&) = delete;

  // xrSyncActions while the session is FOCUSED (an unfocused session is given no input: nothing is
  // returned then), and each button that went down since the last sync, oldest first. Throws
  // std::runtime_error when a call fails.
  std::vector<OpenXrButtonPress> sync();

  // The gaze at `time` (e.g. a frame's predicted display time), located in the session's VIEW space;
  // nullopt without an eye tracker, while the session is not running (no input may be read after
  // xrEndSession), while the gaze action is inactive (as of the last sync()), or when
  // the runtime does not vouch for the pose (its orientation and position valid and tracked bits).
  std::optional<OpenXrGazeRay> locate_gaze(XrTime time);

  bool has_eye_gaze() const { return gaze_space_ != XR_NULL_HANDLE; }

 private:
  void release();

  OpenXrSession& session_;
  XrActionSet action_set_ = XR_NULL_HANDLE;
  std::vector<XrAction> buttons_;  // one a key of openxr_answer_keys(), in its order
  XrAction gaze_action_ = XR_NULL_HANDLE;
  XrSpace gaze_space_ = XR_NULL_HANDLE;
};

// The answer keys the buttons give, in the order sync() breaks ties between presses of one time.
const std::vector<std::string>& openxr_answer_keys();

}  // namespace fovlab
