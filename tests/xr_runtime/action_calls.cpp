// The test runtime's input: paths, action sets and actions, suggested bindings checked against each
// profile's allowlist, attaching, xrSyncActions on the session's virtual clock, action states, and
// action spaces located against reference spaces, as the OpenXR 1.0 specification describes them.
//
// The connected controller is the one FOVLAB_TEST_XR_CONTROLLER names (input_script.cpp): its
// profile is current for its /user paths once the application has suggested bindings for it, and
// only those bindings fire; the runtime does not rebind other profiles to it. The eye tracker is
// current for /user/eyes_ext when the instance enabled XR_EXT_eye_gaze_interaction and bindings
// were suggested for /interaction_profiles/ext/eye_gaze_interaction.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "tests/xr_runtime/test_runtime.h"

namespace fovlab::test_xr {
namespace {

// The specification: after xrEndSession "the application must also avoid reading input state". A
// runtime need not check it, but an application that does it anyway may read nothing, or crash a
// runtime that has released its trackers; this one refuses it, so the mistake fails a test. Hold the
// table's mutex.
XrResult refuse_input_after_end(const SessionObject& session, const char* call) {
  if (!session.ended) return XR_SUCCESS;
  std::fprintf(stderr, "fovlab test runtime: %s after xrEndSession: the application must not read input then\n", call);
  return XR_ERROR_VALIDATION_FAILURE;
}

constexpr std::string_view kEyeGazeProfile = "/interaction_profiles/ext/eye_gaze_interaction";
constexpr std::string_view kEyeGazePose = "/user/eyes_ext/input/gaze_ext/pose";

// The specification's well-formed path: '/'-separated components of lowercase letters, digits,
// '-', '_' and '.', none empty, none "." or "..", no '/' at the end.
bool path_is_well_formed(std::string_view path) {
  if (path.size() < 2 || path.size() >= XR_MAX_PATH_LENGTH || path.front() != '/' || path.back() == '/') return false;
  size_t start = 1;
  while (start <= path.size()) {
    size_t end = path.find('/', start);
    if (end == std::string_view::npos) end = path.size();
    const std::string_view component = path.substr(start, end - start);
    if (component.empty() || component == "." || component == "..") return false;
    for (const char c : component) {
      if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_' || c == '.')) return false;
    }
    start = end + 1;
  }
  return true;
}

// An action or action set name: one well-formed path component, terminated within its array.
XrResult check_name(const char* name, size_t size) {
  const size_t length = strnlen(name, size);
  if (length == 0 || length == size) return XR_ERROR_NAME_INVALID;
  const std::string path = "/" + std::string(name, length);
  return path_is_well_formed(path) && path.find('/', 1) == std::string::npos ? XR_SUCCESS : XR_ERROR_NAME_INVALID;
}

XrResult check_localized_name(const char* name, size_t size) {
  const size_t length = strnlen(name, size);
  return length == 0 || length == size ? XR_ERROR_LOCALIZED_NAME_INVALID : XR_SUCCESS;
}

// The text of `path` in the instance; nullptr for XR_NULL_PATH or a path it never handed out.
const std::string* path_text(const InstanceObject& instance, XrPath path) {
  if (path == XR_NULL_PATH || path > instance.paths.size()) return nullptr;
  return &instance.paths[path - 1];
}

// The path of `text` when the instance has handed it out, else XR_NULL_PATH.
XrPath find_path(const InstanceObject& instance, std::string_view text) {
  for (size_t i = 0; i < instance.paths.size(); ++i) {
    if (instance.paths[i] == text) return XrPath{i + 1};
  }
  return XR_NULL_PATH;
}

// The top-level /user paths of the specification (and of the extensions the instance enabled).
bool is_top_level_user_path(const InstanceObject& instance, std::string_view path) {
  if (path == "/user/hand/left" || path == "/user/hand/right" || path == "/user/head" || path == "/user/gamepad" ||
      path == "/user/treadmill")
    return true;
  return path == "/user/eyes_ext" && extension_enabled(instance, XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME);
}

// XR_SUCCESS when `path` is XR_NULL_PATH or a top-level /user path of the instance.
XrResult check_subaction_path(const InstanceObject& instance, XrPath path) {
  if (path == XR_NULL_PATH) return XR_SUCCESS;
  const std::string* text = path_text(instance, path);
  if (text == nullptr) return XR_ERROR_PATH_INVALID;
  return is_top_level_user_path(instance, *text) ? XR_SUCCESS : XR_ERROR_PATH_UNSUPPORTED;
}

InstanceObject* instance_of_action_set(HandleTable& table, uint64_t action_set) {
  const auto found = table.objects.find(action_set);
  if (found == table.objects.end() || !std::holds_alternative<ActionSetObject>(found->second.state)) return nullptr;
  return find_object<InstanceObject>(table, found->second.parent);
}

// The action set of a live action; 0 when `action` is none.
uint64_t action_set_of(HandleTable& table, uint64_t action) {
  const auto found = table.objects.find(action);
  if (found == table.objects.end() || !std::holds_alternative<ActionObject>(found->second.state)) return 0;
  return found->second.parent;
}

std::vector<uint64_t> actions_of(HandleTable& table, uint64_t action_set) {
  std::vector<uint64_t> actions;
  for (const auto& [handle, object] : table.objects) {
    if (object.parent == action_set && std::holds_alternative<ActionObject>(object.state)) actions.push_back(handle);
  }
  return actions;
}

bool attached_to(const SessionObject& session, uint64_t action_set) {
  for (const uint64_t attached : session.attached_action_sets) {
    if (attached == action_set) return true;
  }
  return false;
}

// The profile bound to `user_path` for this session now: the connected controller's for its /user
// paths, the eye tracker's for /user/eyes_ext, each only when the application suggested bindings
// for it; empty otherwise.
std::string_view current_profile(const InstanceObject& instance, const SessionObject& session,
                                 std::string_view user_path) {
  if (!session.action_sets_attached) return {};
  const auto suggested = [&](std::string_view profile) {
    const XrPath path = find_path(instance, profile);
    const auto found = instance.suggested_bindings.find(path);
    return path != XR_NULL_PATH && found != instance.suggested_bindings.end() && !found->second.empty();
  };
  const std::string_view controller = controller_profile(session.input.controller);
  const InteractionProfile* profile = find_interaction_profile(controller);
  for (const std::string_view path : profile->user_paths) {
    if (path == user_path && suggested(controller)) return controller;
  }
  if (user_path == "/user/eyes_ext" && extension_enabled(instance, XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME) &&
      suggested(kEyeGazeProfile))
    return kEyeGazeProfile;
  return {};
}

// The bindings of `action` in the profile current for their /user path, within `subaction_path`
// (XR_NULL_PATH: all of them), as text.
std::vector<std::string> live_bindings(const InstanceObject& instance, const SessionObject& session, uint64_t action,
                                       XrPath subaction_path) {
  std::vector<std::string> bindings;
  const std::string* within = path_text(instance, subaction_path);
  for (const auto& [profile_path, suggested] : instance.suggested_bindings) {
    const std::string* profile = path_text(instance, profile_path);
    for (const SuggestedBinding& binding : suggested) {
      const std::string* text = path_text(instance, binding.binding);
      if (binding.action != action || profile == nullptr || text == nullptr) continue;
      if (within != nullptr && !(text->starts_with(*within) && (*text)[within->size()] == '/')) continue;
      const size_t input = text->find("/input/");
      const size_t output = text->find("/output/");
      const std::string user_path = text->substr(0, std::min(input, output));
      if (current_profile(instance, session, user_path) == *profile) bindings.push_back(*text);
    }
  }
  return bindings;
}

// Whether a scripted press of frame `frame` fires one of `bindings` (a binding names the input, or
// its identifier without the component).
bool pressed_at(const SessionObject& session, const std::vector<std::string>& bindings, int64_t frame) {
  for (const ScriptedPress& press : session.input.presses) {
    if (press.frame != frame) continue;
    for (const std::string& binding : bindings) {
      if (press.input == binding || (press.input.starts_with(binding) && press.input[binding.size()] == '/'))
        return true;
    }
  }
  return false;
}

// The frame whose predicted display time is nearest `time` (frame_time's inverse).
int64_t frame_at(const SessionObject& session, XrTime time) {
  return std::llround(static_cast<double>(time - session.start_time) * kRefreshHz / 1e9);
}

// Whether the scripted gaze is lost at `time` (FOVLAB_TEST_XR_GAZE_LOST).
bool gaze_lost_at(const SessionObject& session, XrTime time) {
  const int64_t frame = frame_at(session, time);
  return frame >= session.input.gaze_lost_first_frame && frame <= session.input.gaze_lost_last_frame;
}

// The eye gaze pose in the head at `time`: from the head's origin, -Z turned right by yaw and up by
// pitch (FOVLAB_TEST_XR_GAZE, or FOVLAB_TEST_XR_GAZE_AWAY's within its frames).
XrPosef gaze_in_head(const SessionObject& session, XrTime time) {
  const SimulatedInput& input = session.input;
  const int64_t frame = frame_at(session, time);
  const bool away = frame >= input.gaze_away_first_frame && frame <= input.gaze_away_last_frame;
  const double yaw = (away ? input.gaze_away_yaw_deg : input.gaze_yaw_deg) * std::numbers::pi / 180.0;
  const double pitch = (away ? input.gaze_away_pitch_deg : input.gaze_pitch_deg) * std::numbers::pi / 180.0;
  // Turning right is a negative rotation about +Y; looking up a positive one about +X.
  const XrQuaternionf turn{0.0f, static_cast<float>(std::sin(-yaw / 2)), 0.0f, static_cast<float>(std::cos(-yaw / 2))};
  const XrQuaternionf tilt{static_cast<float>(std::sin(pitch / 2)), 0.0f, 0.0f,
                           static_cast<float>(std::cos(pitch / 2))};
  return {multiply(turn, tilt), {0.0f, 0.0f, 0.0f}};
}

bool tracking_lost() {
  const char* tracking = std::getenv("FOVLAB_TEST_XR_TRACKING");
  return tracking != nullptr && std::string_view(tracking) == "lost";
}

// Where `space` is in the session's LOCAL frame at `time` (the VIEW space and the eye tracker ride on
// the head, head_in_local), or false when it has no pose: an action space whose action is not active
// as of the last sync, or is not bound to the eye tracker, or while tracking is lost.
bool space_pose(HandleTable& table, const InstanceObject& instance, const SessionObject& session,
                const SpaceObject& space, XrTime time, XrPosef& pose) {
  const bool head_moves = session.input.head_yaw_deg_per_s != 0.0 || session.input.head_x_m_per_s != 0.0;
  if (space.action == 0) {
    pose = head_moves && space.type == XR_REFERENCE_SPACE_TYPE_VIEW
               ? compose(head_in_local(session, time), space.pose_in_reference)
               : space.pose_in_reference;
    return true;
  }
  const auto state = session.action_states.find(space.action);
  if (state == session.action_states.end() || !state->second.active || tracking_lost()) return false;
  const std::vector<std::string> bindings = live_bindings(instance, session, space.action, space.subaction_path);
  bool on_eye_tracker = false;
  for (const std::string& binding : bindings) on_eye_tracker = on_eye_tracker || binding == kEyeGazePose;
  if (!on_eye_tracker || action_set_of(table, space.action) == 0 || gaze_lost_at(session, time)) return false;
  const XrPosef gaze = gaze_in_head(session, time);
  const XrVector3f offset = rotate(gaze.orientation, space.pose_in_reference.position);
  pose = {multiply(gaze.orientation, space.pose_in_reference.orientation),
          {gaze.position.x + offset.x, gaze.position.y + offset.y, gaze.position.z + offset.z}};
  if (head_moves) pose = compose(head_in_local(session, time), pose);
  return true;
}

// The common checks of xrGetActionState*: the action live, of `type`, in a set attached to the
// session, the subaction path one of the action's. Hold the table's mutex.
XrResult find_action_state(HandleTable& table, uint64_t session_handle, const XrActionStateGetInfo* get_info,
                           XrActionType type, const ActionState*& state) {
  if (get_info == nullptr || get_info->type != XR_TYPE_ACTION_STATE_GET_INFO) return XR_ERROR_VALIDATION_FAILURE;
  const SessionObject* session = find_object<SessionObject>(table, session_handle);
  const InstanceObject* instance = instance_of(table, session_handle);
  const ActionObject* action = find_object<ActionObject>(table, handle_value(get_info->action));
  if (action == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (!attached_to(*session, action_set_of(table, handle_value(get_info->action))))
    return XR_ERROR_ACTIONSET_NOT_ATTACHED;
  if (action->type != type) return XR_ERROR_ACTION_TYPE_MISMATCH;
  if (get_info->subactionPath != XR_NULL_PATH) {
    if (path_text(*instance, get_info->subactionPath) == nullptr) return XR_ERROR_PATH_INVALID;
    bool declared = false;
    for (const XrPath path : action->subaction_paths) declared = declared || path == get_info->subactionPath;
    if (!declared) return XR_ERROR_PATH_UNSUPPORTED;
  }
  static const ActionState inactive;
  const auto found = session->action_states.find(handle_value(get_info->action));
  state = found == session->action_states.end() ? &inactive : &found->second;
  return XR_SUCCESS;
}

}  // namespace

XrResult XRAPI_CALL string_to_path(XrInstance instance, const char* path_string, XrPath* path) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  InstanceObject* object = find_object<InstanceObject>(table, handle_value(instance));
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (path_string == nullptr || path == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  const std::string_view text(path_string, strnlen(path_string, XR_MAX_PATH_LENGTH));
  if (!path_is_well_formed(text)) return XR_ERROR_PATH_FORMAT_INVALID;
  *path = find_path(*object, text);
  if (*path == XR_NULL_PATH) {
    object->paths.emplace_back(text);
    *path = object->paths.size();
  }
  return XR_SUCCESS;
}

XrResult XRAPI_CALL path_to_string(XrInstance instance, XrPath path, uint32_t capacity, uint32_t* count_output,
                                   char* buffer) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  const InstanceObject* object = find_object<InstanceObject>(table, handle_value(instance));
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  const std::string* text = path_text(*object, path);
  if (text == nullptr) return XR_ERROR_PATH_INVALID;
  // The two-call idiom over the characters, the terminating zero counted.
  const auto available = static_cast<uint32_t>(text->size() + 1);
  return enumerate(capacity, count_output, buffer, available, [&](char& c, uint32_t i) {
    c = i < text->size() ? (*text)[i] : '\0';
    return XR_SUCCESS;
  });
}

XrResult XRAPI_CALL create_action_set(XrInstance instance, const XrActionSetCreateInfo* create_info,
                                      XrActionSet* action_set) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  if (find_object<InstanceObject>(table, handle_value(instance)) == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (create_info == nullptr || action_set == nullptr || create_info->type != XR_TYPE_ACTION_SET_CREATE_INFO)
    return XR_ERROR_VALIDATION_FAILURE;
  if (const XrResult result = check_name(create_info->actionSetName, XR_MAX_ACTION_SET_NAME_SIZE); XR_FAILED(result))
    return result;
  if (const XrResult result =
          check_localized_name(create_info->localizedActionSetName, XR_MAX_LOCALIZED_ACTION_SET_NAME_SIZE);
      XR_FAILED(result))
    return result;
  ActionSetObject made{create_info->actionSetName, create_info->localizedActionSetName, create_info->priority, false};
  for (const auto& [handle, object] : table.objects) {
    const auto* other = std::get_if<ActionSetObject>(&object.state);
    if (other == nullptr || object.parent != handle_value(instance)) continue;
    if (other->name == made.name) return XR_ERROR_NAME_DUPLICATED;
    if (other->localized_name == made.localized_name) return XR_ERROR_LOCALIZED_NAME_DUPLICATED;
  }
  const uint64_t handle = table.next_handle++;
  table.objects.emplace(handle, Object{handle_value(instance), std::move(made)});
  *action_set = reinterpret_cast<XrActionSet>(handle);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL destroy_action_set(XrActionSet action_set) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  if (find_object<ActionSetObject>(table, handle_value(action_set)) == nullptr) return XR_ERROR_HANDLE_INVALID;
  destroy_with_children(table, handle_value(action_set));
  return XR_SUCCESS;
}

XrResult XRAPI_CALL create_action(XrActionSet action_set, const XrActionCreateInfo* create_info, XrAction* action) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  const ActionSetObject* set = find_object<ActionSetObject>(table, handle_value(action_set));
  if (set == nullptr) return XR_ERROR_HANDLE_INVALID;
  const InstanceObject* instance = instance_of_action_set(table, handle_value(action_set));
  if (create_info == nullptr || action == nullptr || create_info->type != XR_TYPE_ACTION_CREATE_INFO ||
      (create_info->countSubactionPaths != 0 && create_info->subactionPaths == nullptr))
    return XR_ERROR_VALIDATION_FAILURE;
  switch (create_info->actionType) {
    case XR_ACTION_TYPE_BOOLEAN_INPUT:
    case XR_ACTION_TYPE_FLOAT_INPUT:
    case XR_ACTION_TYPE_VECTOR2F_INPUT:
    case XR_ACTION_TYPE_POSE_INPUT:
    case XR_ACTION_TYPE_VIBRATION_OUTPUT:
      break;
    default:
      return XR_ERROR_VALIDATION_FAILURE;
  }
  if (set->attached) return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
  if (const XrResult result = check_name(create_info->actionName, XR_MAX_ACTION_NAME_SIZE); XR_FAILED(result))
    return result;
  if (const XrResult result = check_localized_name(create_info->localizedActionName, XR_MAX_LOCALIZED_ACTION_NAME_SIZE);
      XR_FAILED(result))
    return result;
  ActionObject made{create_info->actionName, create_info->localizedActionName, create_info->actionType, {}};
  for (uint32_t i = 0; i < create_info->countSubactionPaths; ++i) {
    const XrPath path = create_info->subactionPaths[i];
    if (path == XR_NULL_PATH || path_text(*instance, path) == nullptr) return XR_ERROR_PATH_INVALID;
    if (XR_FAILED(check_subaction_path(*instance, path))) return XR_ERROR_PATH_UNSUPPORTED;
    for (const XrPath earlier : made.subaction_paths) {
      if (earlier == path) return XR_ERROR_PATH_UNSUPPORTED;  // named twice
    }
    made.subaction_paths.push_back(path);
  }
  for (const uint64_t other_handle : actions_of(table, handle_value(action_set))) {
    const ActionObject* other = find_object<ActionObject>(table, other_handle);
    if (other->name == made.name) return XR_ERROR_NAME_DUPLICATED;
    if (other->localized_name == made.localized_name) return XR_ERROR_LOCALIZED_NAME_DUPLICATED;
  }
  const uint64_t handle = table.next_handle++;
  table.objects.emplace(handle, Object{handle_value(action_set), std::move(made)});
  *action = reinterpret_cast<XrAction>(handle);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL destroy_action(XrAction action) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  if (find_object<ActionObject>(table, handle_value(action)) == nullptr) return XR_ERROR_HANDLE_INVALID;
  destroy_with_children(table, handle_value(action));
  return XR_SUCCESS;
}

XrResult XRAPI_CALL suggest_interaction_profile_bindings(XrInstance instance,
                                                         const XrInteractionProfileSuggestedBinding* suggested) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  InstanceObject* object = find_object<InstanceObject>(table, handle_value(instance));
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (suggested == nullptr || suggested->type != XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING ||
      suggested->countSuggestedBindings == 0 || suggested->suggestedBindings == nullptr)
    return XR_ERROR_VALIDATION_FAILURE;
  const std::string* profile_text = path_text(*object, suggested->interactionProfile);
  if (profile_text == nullptr) return XR_ERROR_PATH_INVALID;
  const InteractionProfile* profile = find_interaction_profile(*profile_text);
  // A profile of an extension exists only for an instance that enabled the extension.
  if (profile == nullptr || (!profile->extension.empty() && !extension_enabled(*object, profile->extension)))
    return XR_ERROR_PATH_UNSUPPORTED;
  std::vector<SuggestedBinding> bindings;
  for (uint32_t i = 0; i < suggested->countSuggestedBindings; ++i) {
    const XrActionSuggestedBinding& binding = suggested->suggestedBindings[i];
    const uint64_t action = handle_value(binding.action);
    const uint64_t action_set = action_set_of(table, action);
    if (action_set == 0) return XR_ERROR_HANDLE_INVALID;
    if (instance_of_action_set(table, action_set) != object) return XR_ERROR_VALIDATION_FAILURE;
    if (find_object<ActionSetObject>(table, action_set)->attached) return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
    const std::string* binding_text = path_text(*object, binding.binding);
    if (binding_text == nullptr) return XR_ERROR_PATH_INVALID;
    if (!profile_has_binding(*profile, *binding_text)) return XR_ERROR_PATH_UNSUPPORTED;
    bindings.push_back({action, binding.binding});
  }
  object->suggested_bindings[suggested->interactionProfile] = std::move(bindings);  // replaces an earlier one
  return XR_SUCCESS;
}

XrResult XRAPI_CALL attach_session_action_sets(XrSession session, const XrSessionActionSetsAttachInfo* attach_info) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  SessionObject* object = find_object<SessionObject>(table, handle_value(session));
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  const InstanceObject* instance = instance_of(table, handle_value(session));
  if (attach_info == nullptr || attach_info->type != XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO ||
      attach_info->countActionSets == 0 || attach_info->actionSets == nullptr)
    return XR_ERROR_VALIDATION_FAILURE;
  for (uint32_t i = 0; i < attach_info->countActionSets; ++i) {
    const uint64_t set = handle_value(attach_info->actionSets[i]);
    if (find_object<ActionSetObject>(table, set) == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (instance_of_action_set(table, set) != instance) return XR_ERROR_VALIDATION_FAILURE;
  }
  if (object->action_sets_attached) return XR_ERROR_ACTIONSETS_ALREADY_ATTACHED;
  object->action_sets_attached = true;
  for (uint32_t i = 0; i < attach_info->countActionSets; ++i) {
    const uint64_t set = handle_value(attach_info->actionSets[i]);
    find_object<ActionSetObject>(table, set)->attached = true;
    object->attached_action_sets.push_back(set);
    for (const uint64_t action : actions_of(table, set)) object->action_states[action] = ActionState{};
  }
  return XR_SUCCESS;
}

XrResult XRAPI_CALL get_current_interaction_profile(XrSession session, XrPath top_level_user_path,
                                                    XrInteractionProfileState* profile) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  const SessionObject* object = find_object<SessionObject>(table, handle_value(session));
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  const InstanceObject* instance = instance_of(table, handle_value(session));
  if (profile == nullptr || profile->type != XR_TYPE_INTERACTION_PROFILE_STATE) return XR_ERROR_VALIDATION_FAILURE;
  if (!object->action_sets_attached) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
  const std::string* user_path = path_text(*instance, top_level_user_path);
  if (user_path == nullptr) return XR_ERROR_PATH_INVALID;
  if (!is_top_level_user_path(*instance, *user_path)) return XR_ERROR_PATH_UNSUPPORTED;
  const std::string_view current = current_profile(*instance, *object, *user_path);
  profile->interactionProfile = current.empty() ? XR_NULL_PATH : find_path(*instance, current);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL sync_actions(XrSession session, const XrActionsSyncInfo* sync_info) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  SessionObject* object = find_object<SessionObject>(table, handle_value(session));
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (const XrResult result = refuse_input_after_end(*object, "xrSyncActions"); XR_FAILED(result)) return result;
  const InstanceObject* instance = instance_of(table, handle_value(session));
  if (sync_info == nullptr || sync_info->type != XR_TYPE_ACTIONS_SYNC_INFO ||
      (sync_info->countActiveActionSets != 0 && sync_info->activeActionSets == nullptr))
    return XR_ERROR_VALIDATION_FAILURE;
  for (uint32_t i = 0; i < sync_info->countActiveActionSets; ++i) {
    const XrActiveActionSet& active = sync_info->activeActionSets[i];
    if (find_object<ActionSetObject>(table, handle_value(active.actionSet)) == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (!attached_to(*object, handle_value(active.actionSet))) return XR_ERROR_ACTIONSET_NOT_ATTACHED;
    if (const XrResult result = check_subaction_path(*instance, active.subactionPath); XR_FAILED(result)) return result;
  }
  // The test's presses queued since the last sync, for the frame after the latest xrWaitFrame (an
  // unfocused session's too: the queue is read in order, whatever the session's state).
  if (!take_queued_presses(object->input, object->waited_frames + 1)) return XR_ERROR_RUNTIME_FAILURE;
  // An unfocused session gets no input: every action inactive.
  if (object->state != XR_SESSION_STATE_FOCUSED) {
    for (auto& [action, state] : object->action_states) state = ActionState{};
    object->last_synced_frame = object->waited_frames;
    return XR_SESSION_NOT_FOCUSED;
  }
  const int64_t now = object->waited_frames;
  for (auto& [action, state] : object->action_states) {
    const ActionObject* action_object = find_object<ActionObject>(table, action);
    const XrActiveActionSet* active = nullptr;
    for (uint32_t i = 0; i < sync_info->countActiveActionSets; ++i) {
      if (handle_value(sync_info->activeActionSets[i].actionSet) == action_set_of(table, action))
        active = &sync_info->activeActionSets[i];
    }
    const ActionState before = state;
    if (action_object == nullptr || active == nullptr) {
      state = ActionState{};  // destroyed, or its set not synchronised this time
      continue;
    }
    const std::vector<std::string> bindings = live_bindings(*instance, *object, action, active->subactionPath);
    if (action_object->type == XR_ACTION_TYPE_POSE_INPUT) {
      bool on_pose = false;
      for (const std::string& binding : bindings) on_pose = on_pose || binding.ends_with("/pose");
      state = ActionState{on_pose, false, false, 0};
      continue;
    }
    std::vector<std::string> buttons;
    for (const std::string& binding : bindings) {
      if (!binding.ends_with("/pose")) buttons.push_back(binding);
    }
    if (action_object->type != XR_ACTION_TYPE_BOOLEAN_INPUT || buttons.empty()) {
      state = ActionState{};
      continue;
    }
    state.active = true;
    state.current = pressed_at(*object, buttons, now);
    // Against the state the last sync gave, inactive (released) included: a button already down
    // when the session gains focus is a press the application has not seen.
    state.changed = before.current != state.current;
    if (state.changed) {
      // The state began at the earliest frame since the last sync from which it has held.
      int64_t since = now;
      while (since - 1 > object->last_synced_frame && pressed_at(*object, buttons, since - 1) == state.current) --since;
      state.last_change_time = frame_time(*object, since);
    } else if (!before.active) {
      state.last_change_time = 0;
    }
  }
  object->last_synced_frame = now;
  return XR_SUCCESS;
}

XrResult XRAPI_CALL get_action_state_boolean(XrSession session, const XrActionStateGetInfo* get_info,
                                             XrActionStateBoolean* state) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  const SessionObject* object = find_object<SessionObject>(table, handle_value(session));
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (const XrResult result = refuse_input_after_end(*object, "xrGetActionStateBoolean"); XR_FAILED(result))
    return result;
  if (state == nullptr || state->type != XR_TYPE_ACTION_STATE_BOOLEAN) return XR_ERROR_VALIDATION_FAILURE;
  const ActionState* found = nullptr;
  if (const XrResult result =
          find_action_state(table, handle_value(session), get_info, XR_ACTION_TYPE_BOOLEAN_INPUT, found);
      XR_FAILED(result))
    return result;
  state->currentState = found->current ? XR_TRUE : XR_FALSE;
  state->changedSinceLastSync = found->changed ? XR_TRUE : XR_FALSE;
  state->lastChangeTime = found->last_change_time;
  state->isActive = found->active ? XR_TRUE : XR_FALSE;
  return XR_SUCCESS;
}

XrResult XRAPI_CALL get_action_state_pose(XrSession session, const XrActionStateGetInfo* get_info,
                                          XrActionStatePose* state) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  const SessionObject* object = find_object<SessionObject>(table, handle_value(session));
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (const XrResult result = refuse_input_after_end(*object, "xrGetActionStatePose"); XR_FAILED(result)) return result;
  if (state == nullptr || state->type != XR_TYPE_ACTION_STATE_POSE) return XR_ERROR_VALIDATION_FAILURE;
  const ActionState* found = nullptr;
  if (const XrResult result =
          find_action_state(table, handle_value(session), get_info, XR_ACTION_TYPE_POSE_INPUT, found);
      XR_FAILED(result))
    return result;
  state->isActive = found->active ? XR_TRUE : XR_FALSE;
  return XR_SUCCESS;
}

// An action space may be made before its set is attached (the specification's own examples do);
// it is located only while its action is active.
XrResult XRAPI_CALL create_action_space(XrSession session, const XrActionSpaceCreateInfo* create_info, XrSpace* space) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  if (find_object<SessionObject>(table, handle_value(session)) == nullptr) return XR_ERROR_HANDLE_INVALID;
  const InstanceObject* instance = instance_of(table, handle_value(session));
  if (create_info == nullptr || space == nullptr || create_info->type != XR_TYPE_ACTION_SPACE_CREATE_INFO)
    return XR_ERROR_VALIDATION_FAILURE;
  const ActionObject* action = find_object<ActionObject>(table, handle_value(create_info->action));
  if (action == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (instance_of_action_set(table, action_set_of(table, handle_value(create_info->action))) != instance)
    return XR_ERROR_VALIDATION_FAILURE;
  if (action->type != XR_ACTION_TYPE_POSE_INPUT) return XR_ERROR_ACTION_TYPE_MISMATCH;
  if (create_info->subactionPath != XR_NULL_PATH) {
    if (path_text(*instance, create_info->subactionPath) == nullptr) return XR_ERROR_PATH_INVALID;
    bool declared = false;
    for (const XrPath path : action->subaction_paths) declared = declared || path == create_info->subactionPath;
    if (!declared) return XR_ERROR_PATH_UNSUPPORTED;
  }
  if (!pose_is_valid(create_info->poseInActionSpace)) return XR_ERROR_POSE_INVALID;
  SpaceObject made;
  made.pose_in_reference = create_info->poseInActionSpace;
  made.action = handle_value(create_info->action);
  made.subaction_path = create_info->subactionPath;
  const uint64_t handle = table.next_handle++;
  table.objects.emplace(handle, Object{handle_value(session), made});
  *space = reinterpret_cast<XrSpace>(handle);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL locate_space(XrSpace space, XrSpace base_space, XrTime time, XrSpaceLocation* location) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  const auto found_space = table.objects.find(handle_value(space));
  const auto found_base = table.objects.find(handle_value(base_space));
  if (found_space == table.objects.end() || found_base == table.objects.end()) return XR_ERROR_HANDLE_INVALID;
  const SpaceObject* located = std::get_if<SpaceObject>(&found_space->second.state);
  const SpaceObject* base = std::get_if<SpaceObject>(&found_base->second.state);
  if (located == nullptr || base == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (found_space->second.parent != found_base->second.parent) return XR_ERROR_VALIDATION_FAILURE;
  if (location == nullptr || location->type != XR_TYPE_SPACE_LOCATION) return XR_ERROR_VALIDATION_FAILURE;
  if (time <= 0) return XR_ERROR_TIME_INVALID;
  const uint64_t session_handle = found_space->second.parent;
  const SessionObject* session = find_object<SessionObject>(table, session_handle);
  const InstanceObject* instance = instance_of(table, session_handle);

  XrPosef space_in_local{};
  XrPosef base_in_local{};
  // While tracking is lost only a space located against itself, or reference spaces of one type,
  // keep their (fixed) relation.
  const bool same_kind = located->action == 0 && base->action == 0 && located->type == base->type;
  const bool tracked = space_pose(table, *instance, *session, *located, time, space_in_local) &&
                       space_pose(table, *instance, *session, *base, time, base_in_local) &&
                       (same_kind || !tracking_lost());
  if (tracked) {
    location->pose = relative_to(base_in_local, space_in_local);
    location->locationFlags = XR_SPACE_LOCATION_ORIENTATION_VALID_BIT | XR_SPACE_LOCATION_POSITION_VALID_BIT |
                              XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT | XR_SPACE_LOCATION_POSITION_TRACKED_BIT;
  } else {
    location->pose = XrPosef{{0.0f, 0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 0.0f}};
    location->locationFlags = 0;
  }
  // Structures chained on `next` that the runtime knows; any other is left alone.
  const bool gaze = located->action != 0 || base->action != 0;
  for (auto* chained = static_cast<XrBaseOutStructure*>(location->next); chained != nullptr; chained = chained->next) {
    if (chained->type == XR_TYPE_EYE_GAZE_SAMPLE_TIME_EXT &&
        extension_enabled(*instance, XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME)) {
      // The simulated tracker has a sample for any time asked; 0 when there is none.
      reinterpret_cast<XrEyeGazeSampleTimeEXT*>(chained)->time = gaze && tracked ? time : 0;
    } else if (chained->type == XR_TYPE_SPACE_VELOCITY) {
      reinterpret_cast<XrSpaceVelocity*>(chained)->velocityFlags = 0;  // no velocities simulated
    }
  }
  return XR_SUCCESS;
}

}  // namespace fovlab::test_xr

// Test-only: presses `input_path` (a button of the connected controller, e.g.
// "/user/gamepad/input/y/click") during the next frame of every live session: the frame after its
// latest xrWaitFrame. XR_ERROR_PATH_UNSUPPORTED for an input the controller does not have,
// XR_ERROR_HANDLE_INVALID when no session exists.
extern "C" __attribute__((visibility("default"))) XrResult fovlab_test_xr_press(const char* input_path) {
  using namespace fovlab::test_xr;
  if (input_path == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  bool pressed = false;
  for (auto& [handle, object] : table.objects) {
    auto* session = std::get_if<SessionObject>(&object.state);
    if (session == nullptr) continue;
    if (!is_controller_button(session->input.controller, input_path)) return XR_ERROR_PATH_UNSUPPORTED;
    session->input.presses.push_back({session->waited_frames + 1, input_path});
    pressed = true;
  }
  return pressed ? XR_SUCCESS : XR_ERROR_HANDLE_INVALID;
}
