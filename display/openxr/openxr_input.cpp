#include "display/openxr/openxr_input.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>

namespace fovlab {
namespace {

void check_input_call(XrResult result, const char* call) {
  if (XR_FAILED(result)) throw std::runtime_error(std::string("openxr: ") + call + ": " + openxr_result_name(result));
}

// A button of a controller and the answer key it gives.
struct ButtonBinding {
  const char* key;
  const char* input;
};

// The Xbox controller: every button the desktop gamepad maps (display/glfw_input.cpp), menu as
// start and view as back.
constexpr ButtonBinding kXboxController[] = {
    {"pad_a", "/user/gamepad/input/a/click"},
    {"pad_b", "/user/gamepad/input/b/click"},
    {"pad_x", "/user/gamepad/input/x/click"},
    {"pad_y", "/user/gamepad/input/y/click"},
    {"pad_left", "/user/gamepad/input/dpad_left/click"},
    {"pad_right", "/user/gamepad/input/dpad_right/click"},
    {"pad_up", "/user/gamepad/input/dpad_up/click"},
    {"pad_down", "/user/gamepad/input/dpad_down/click"},
    {"pad_start", "/user/gamepad/input/menu/click"},
    {"pad_back", "/user/gamepad/input/view/click"},
    {"pad_lb", "/user/gamepad/input/shoulder_left/click"},
    {"pad_rb", "/user/gamepad/input/shoulder_right/click"},
};

// A Vive wand has four buttons an application may use (its system button is the runtime's): the
// trigger as the main answer, the trackpad's press as the second, the grip as the third, the menu
// button as start. Either hand gives the same keys.
constexpr ButtonBinding kViveController[] = {
    {"pad_a", "/user/hand/left/input/trigger/click"},  {"pad_a", "/user/hand/right/input/trigger/click"},
    {"pad_b", "/user/hand/left/input/trackpad/click"}, {"pad_b", "/user/hand/right/input/trackpad/click"},
    {"pad_x", "/user/hand/left/input/squeeze/click"},  {"pad_x", "/user/hand/right/input/squeeze/click"},
    {"pad_start", "/user/hand/left/input/menu/click"}, {"pad_start", "/user/hand/right/input/menu/click"},
};

// Khronos's simple controller has two buttons: select answers, menu is start.
constexpr ButtonBinding kSimpleController[] = {
    {"pad_a", "/user/hand/left/input/select/click"},
    {"pad_a", "/user/hand/right/input/select/click"},
    {"pad_start", "/user/hand/left/input/menu/click"},
    {"pad_start", "/user/hand/right/input/menu/click"},
};

struct ProfileBindings {
  const char* profile;
  std::span<const ButtonBinding> buttons;
};

constexpr ProfileBindings kProfiles[] = {
    {"/interaction_profiles/microsoft/xbox_controller", kXboxController},
    {"/interaction_profiles/htc/vive_controller", kViveController},
    {"/interaction_profiles/khr/simple_controller", kSimpleController},
};

XrPath to_path(XrInstance instance, const char* text) {
  XrPath path = XR_NULL_PATH;
  check_input_call(xrStringToPath(instance, text, &path), "xrStringToPath");
  return path;
}

// Copies `text` into one of the create infos' fixed arrays (the names here are short constants).
template <size_t Size>
void copy_name(char (&destination)[Size], const std::string& text) {
  const size_t length = std::min(text.size(), Size - 1);
  std::memcpy(destination, text.data(), length);
  destination[length] = '\0';
}

XrAction create_action(XrActionSet action_set, XrActionType type, const std::string& name,
                       const std::string& localized_name) {
  XrActionCreateInfo info{XR_TYPE_ACTION_CREATE_INFO};
  info.actionType = type;
  copy_name(info.actionName, name);
  copy_name(info.localizedActionName, localized_name);
  XrAction action = XR_NULL_HANDLE;
  check_input_call(xrCreateAction(action_set, &info, &action), "xrCreateAction");
  return action;
}

bool system_supports_eye_gaze(const OpenXrSession& session) {
  XrSystemEyeGazeInteractionPropertiesEXT eye_gaze{XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT};
  XrSystemProperties properties{XR_TYPE_SYSTEM_PROPERTIES, &eye_gaze};
  check_input_call(xrGetSystemProperties(session.instance.handle, session.system, &properties),
                   "xrGetSystemProperties");
  return eye_gaze.supportsEyeGazeInteraction == XR_TRUE;
}

}  // namespace

const std::vector<std::string>& openxr_answer_keys() {
  static const std::vector<std::string> keys{"pad_a",  "pad_b",    "pad_x",     "pad_y",    "pad_left", "pad_right",
                                             "pad_up", "pad_down", "pad_start", "pad_back", "pad_lb",   "pad_rb"};
  return keys;
}

OpenXrInput::OpenXrInput(OpenXrSession& session) : session_(session) {
  const XrInstance instance = session.instance.handle;
  try {
    XrActionSetCreateInfo set_info{XR_TYPE_ACTION_SET_CREATE_INFO};
    copy_name(set_info.actionSetName, "fovlab");
    copy_name(set_info.localizedActionSetName, "fovlab answers and gaze");
    check_input_call(xrCreateActionSet(instance, &set_info, &action_set_), "xrCreateActionSet");
    const std::vector<std::string>& keys = openxr_answer_keys();
    for (const std::string& key : keys)
      buttons_.push_back(create_action(action_set_, XR_ACTION_TYPE_BOOLEAN_INPUT, key, "answer " + key));

    for (const ProfileBindings& profile : kProfiles) {
      std::vector<XrActionSuggestedBinding> bindings;
      for (const ButtonBinding& button : profile.buttons) {
        const auto key = std::find(keys.begin(), keys.end(), button.key);
        bindings.push_back({buttons_.at(static_cast<size_t>(key - keys.begin())), to_path(instance, button.input)});
      }
      XrInteractionProfileSuggestedBinding suggested{XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING};
      suggested.interactionProfile = to_path(instance, profile.profile);
      suggested.countSuggestedBindings = static_cast<uint32_t>(bindings.size());
      suggested.suggestedBindings = bindings.data();
      check_input_call(xrSuggestInteractionProfileBindings(instance, &suggested),
                       "xrSuggestInteractionProfileBindings");
    }

    // The eye tracker's profile exists only on an instance with the extension; a system may still
    // have no eye tracker behind it.
    if (session.eye_gaze_enabled && system_supports_eye_gaze(session)) {
      gaze_action_ = create_action(action_set_, XR_ACTION_TYPE_POSE_INPUT, "gaze", "eye gaze");
      const XrActionSuggestedBinding binding{gaze_action_, to_path(instance, "/user/eyes_ext/input/gaze_ext/pose")};
      XrInteractionProfileSuggestedBinding suggested{XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING};
      suggested.interactionProfile = to_path(instance, "/interaction_profiles/ext/eye_gaze_interaction");
      suggested.countSuggestedBindings = 1;
      suggested.suggestedBindings = &binding;
      check_input_call(xrSuggestInteractionProfileBindings(instance, &suggested),
                       "xrSuggestInteractionProfileBindings");
    }

    XrSessionActionSetsAttachInfo attach{XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO};
    attach.countActionSets = 1;
    attach.actionSets = &action_set_;
    check_input_call(xrAttachSessionActionSets(session.session, &attach), "xrAttachSessionActionSets");

    if (gaze_action_ != XR_NULL_HANDLE) {
      XrActionSpaceCreateInfo space_info{XR_TYPE_ACTION_SPACE_CREATE_INFO};
      space_info.action = gaze_action_;
      space_info.poseInActionSpace.orientation.w = 1.0f;
      check_input_call(xrCreateActionSpace(session.session, &space_info, &gaze_space_), "xrCreateActionSpace");
    }
  } catch (...) {
    release();
    throw;
  }
}

OpenXrInput::~OpenXrInput() { release(); }

void OpenXrInput::release() {
  // The handles went with the instance if the session was released first.
  if (session_.instance.handle != XR_NULL_HANDLE) {
    if (gaze_space_ != XR_NULL_HANDLE) xrDestroySpace(gaze_space_);
    if (gaze_action_ != XR_NULL_HANDLE) xrDestroyAction(gaze_action_);
    for (const XrAction button : buttons_) xrDestroyAction(button);
    if (action_set_ != XR_NULL_HANDLE) xrDestroyActionSet(action_set_);
  }
  gaze_space_ = XR_NULL_HANDLE;
  gaze_action_ = XR_NULL_HANDLE;
  buttons_.clear();
  action_set_ = XR_NULL_HANDLE;
}

std::vector<OpenXrButtonPress> OpenXrInput::sync() {
  std::vector<OpenXrButtonPress> presses;
  if (session_.state != XR_SESSION_STATE_FOCUSED) return presses;
  const XrActiveActionSet active{action_set_, XR_NULL_PATH};
  XrActionsSyncInfo sync_info{XR_TYPE_ACTIONS_SYNC_INFO};
  sync_info.countActiveActionSets = 1;
  sync_info.activeActionSets = &active;
  const XrResult synced = xrSyncActions(session_.session, &sync_info);
  check_input_call(synced, "xrSyncActions");
  // Focus may have gone since the last poll of events: the runtime says so, and gives nothing.
  if (synced == XR_SESSION_NOT_FOCUSED) return presses;
  const std::vector<std::string>& keys = openxr_answer_keys();
  for (size_t i = 0; i < buttons_.size(); ++i) {
    XrActionStateGetInfo get_info{XR_TYPE_ACTION_STATE_GET_INFO};
    get_info.action = buttons_[i];
    XrActionStateBoolean state{XR_TYPE_ACTION_STATE_BOOLEAN};
    check_input_call(xrGetActionStateBoolean(session_.session, &get_info, &state), "xrGetActionStateBoolean");
    if (state.isActive && state.changedSinceLastSync && state.currentState)
      presses.push_back({keys[i], state.lastChangeTime});
  }
  std::stable_sort(presses.begin(), presses.end(),
                   [](const OpenXrButtonPress& a, const OpenXrButtonPress& b) { return a.time < b.time; });
  return presses;
}

std::optional<OpenXrGazeRay> OpenXrInput::locate_gaze(XrTime time) {
  // After xrEndSession (the runtime stopped the session) the specification forbids reading input.
  if (!has_eye_gaze() || !session_.running) return std::nullopt;
  XrActionStateGetInfo get_info{XR_TYPE_ACTION_STATE_GET_INFO};
  get_info.action = gaze_action_;
  XrActionStatePose state{XR_TYPE_ACTION_STATE_POSE};
  check_input_call(xrGetActionStatePose(session_.session, &get_info, &state), "xrGetActionStatePose");
  if (!state.isActive) return std::nullopt;

  XrEyeGazeSampleTimeEXT sample_time{XR_TYPE_EYE_GAZE_SAMPLE_TIME_EXT};
  XrSpaceLocation location{XR_TYPE_SPACE_LOCATION, &sample_time};
  check_input_call(xrLocateSpace(gaze_space_, session_.view_space, time, &location), "xrLocateSpace");
  // Only a nominal, tracked gaze: a sub-nominal one (tracked bits clear) is not good enough to
  // place a fovea.
  constexpr XrSpaceLocationFlags vouched =
      XR_SPACE_LOCATION_ORIENTATION_VALID_BIT | XR_SPACE_LOCATION_POSITION_VALID_BIT |
      XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT | XR_SPACE_LOCATION_POSITION_TRACKED_BIT;
  if ((location.locationFlags & vouched) != vouched) return std::nullopt;

  OpenXrGazeRay ray;
  const XrPosef& pose = location.pose;
  ray.origin_m = {pose.position.x, pose.position.y, pose.position.z};
  // The pose's -Z axis: minus the third column of the orientation's rotation matrix.
  const double x = pose.orientation.x, y = pose.orientation.y, z = pose.orientation.z, w = pose.orientation.w;
  const std::array<double, 3> forward{-2.0 * (x * z + w * y), -2.0 * (y * z - w * x), -(1.0 - 2.0 * (x * x + y * y))};
  const double length = std::sqrt(forward[0] * forward[0] + forward[1] * forward[1] + forward[2] * forward[2]);
  ray.direction = {forward[0] / length, forward[1] / length, forward[2] / length};
  ray.sample_time = sample_time.time;
  return ray;
}

}  // namespace fovlab
