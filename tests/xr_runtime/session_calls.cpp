// The test runtime's sessions: creation with a Vulkan graphics binding (XR_KHR_vulkan_enable2), the
// session state machine through xrPollEvent, reference spaces, the headset's two views, and the
// frame loop on a virtual clock (90 Hz), as the OpenXR 1.0 specification describes them.
//
// States: xrCreateSession queues IDLE then READY; the first xrWaitFrame of a running session queues
// SYNCHRONIZED; the first xrEndFrame after it queues VISIBLE then FOCUSED; with
// FOVLAB_TEST_XR_UNFOCUS_AT_FRAME=N the Nth xrWaitFrame queues VISIBLE (focus lost), and with
// FOVLAB_TEST_XR_REFOCUS_AT_FRAME=M the Mth queues FOCUSED again (the headset put back on).
// xrRequestExitSession queues the way down to STOPPING (VISIBLE, SYNCHRONIZED, STOPPING); xrEndSession
// then queues IDLE and EXITING. FOVLAB_TEST_XR_STOP_AT_FRAME=N: at the Nth xrWaitFrame the runtime
// itself queues the way down to STOPPING, as a runtime shutting down; the application must end the
// session, and xrEndSession then queues IDLE and EXITING. With FOVLAB_TEST_XR_READY_AGAIN_AFTER_POLLS=K
// that stop is not a shutdown but a pause of the runtime's own (its home screen, a proximity
// sensor): xrEndSession queues IDLE only, and once the application has been handed it, its Kth
// xrPollEvent with nothing to hand out queues READY again, from which the session begins and climbs
// to FOCUSED as at the start; "never" leaves it IDLE. A call that needs a state checks the one the
// application has been handed; reading input after xrEndSession, which the specification forbids,
// is refused (action_calls.cpp).
//
// The virtual clock and XR_KHR_convert_timespec_time: frame n is predicted for start + n / 90 s
// whatever the wall clock does, so "now" cannot be the wall clock's. The runtime pins the clock at
// each xrWaitFrame: the CLOCK_MONOTONIC instant of that call becomes half a period before the
// frame's predicted display time (the application has half a period to render and submit), and the
// virtual clock stands still until the next pin, so every frame is on time however long lavapipe
// renders it. A frame listed in FOVLAB_TEST_XR_LATE_AT_FRAMES=a,b,c (xrWaitFrame counts) is pinned
// again at its xrBeginFrame to a quarter period after its predicted display time: converted after
// that, "now" is past the display time, so the application's xrEndFrame comes late. The pins only
// go forward (the next frame's is a quarter period later still).
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "tests/xr_runtime/test_runtime.h"

namespace fovlab::test_xr {
namespace {

// Hold the table's mutex.
SessionObject* find_session(HandleTable& table, XrSession session) {
  return find_object<SessionObject>(table, handle_value(session));
}

// FOVLAB_TEST_XR_LATE_AT_FRAMES=a,b,c: the frames (xrWaitFrame counts, >= 1) to make late. False,
// with the reason on stderr, when it is malformed.
bool read_late_frames(std::vector<int64_t>& frames) {
  const char* setting = std::getenv("FOVLAB_TEST_XR_LATE_AT_FRAMES");
  if (setting == nullptr) return true;
  std::string_view text(setting);
  while (!text.empty()) {
    const size_t comma = text.find(',');
    const std::string item(text.substr(0, comma));
    char* end = nullptr;
    const long long frame = std::strtoll(item.c_str(), &end, 10);
    if (item.empty() || end != item.c_str() + item.size() || frame < 1) {
      std::fprintf(stderr,
                   "fovlab test runtime: FOVLAB_TEST_XR_LATE_AT_FRAMES: expected frame numbers >= 1 "
                   "separated by commas, got \"%s\"\n",
                   setting);
      return false;
    }
    frames.push_back(frame);
    text = comma == std::string_view::npos ? std::string_view() : text.substr(comma + 1);
  }
  return true;
}

// FOVLAB_TEST_XR_READY_AGAIN_AFTER_POLLS: a count >= 1 or "never" (kNeverReadyAgain); unset, 0. False,
// with the reason on stderr, when it is malformed.
bool read_ready_again(int64_t& polls) {
  const char* setting = std::getenv("FOVLAB_TEST_XR_READY_AGAIN_AFTER_POLLS");
  polls = 0;
  if (setting == nullptr) return true;
  if (std::string_view(setting) == "never") {
    polls = kNeverReadyAgain;
    return true;
  }
  char* end = nullptr;
  const long long count = std::strtoll(setting, &end, 10);
  if (*setting == '\0' || *end != '\0' || count < 1) {
    std::fprintf(stderr,
                 "fovlab test runtime: FOVLAB_TEST_XR_READY_AGAIN_AFTER_POLLS: expected a count >= 1 or \"never\", "
                 "got \"%s\"\n",
                 setting);
    return false;
  }
  polls = count;
  return true;
}

// The frame number an environment variable names (FOVLAB_TEST_XR_*_AT_FRAME), or 0.
int64_t frame_setting(const char* variable) {
  const char* setting = std::getenv(variable);
  return setting == nullptr ? 0 : std::strtoll(setting, nullptr, 10);
}

}  // namespace

XrTime monotonic_now_ns() {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return XrTime{now.tv_sec} * 1000000000 + now.tv_nsec;
}

XrTime frame_time(const SessionObject& session, int64_t n) { return session.start_time + n * 1000000000 / kRefreshHz; }

XrTime virtual_time_of_monotonic(const SessionObject& session, XrTime monotonic_ns) {
  XrTime time = monotonic_ns;
  for (const auto& [pinned_monotonic_ns, pinned_time] : session.clock_pins) {
    if (pinned_monotonic_ns > monotonic_ns) break;
    time = pinned_time;
  }
  return time;
}

XrTime monotonic_of_virtual_time(const SessionObject& session, XrTime time) {
  XrTime monotonic_ns = time;
  for (const auto& [pinned_monotonic_ns, pinned_time] : session.clock_pins) {
    if (pinned_time > time) break;
    monotonic_ns = pinned_monotonic_ns;
  }
  return monotonic_ns;
}

namespace {

XrTime current_time(const SessionObject& session) { return frame_time(session, session.waited_frames); }

constexpr float radians(float degrees) { return degrees * std::numbers::pi_v<float> / 180.0f; }

}  // namespace

XrQuaternionf multiply(const XrQuaternionf& a, const XrQuaternionf& b) {
  return {a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y, a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
          a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w, a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z};
}

XrVector3f rotate(const XrQuaternionf& q, const XrVector3f& v) {
  const XrQuaternionf p{v.x, v.y, v.z, 0.0f};
  const XrQuaternionf conjugate{-q.x, -q.y, -q.z, q.w};
  const XrQuaternionf r = multiply(multiply(q, p), conjugate);
  return {r.x, r.y, r.z};
}

XrPosef relative_to(const XrPosef& origin, const XrPosef& pose) {
  const XrQuaternionf inverse{-origin.orientation.x, -origin.orientation.y, -origin.orientation.z,
                              origin.orientation.w};
  const XrVector3f offset{pose.position.x - origin.position.x, pose.position.y - origin.position.y,
                          pose.position.z - origin.position.z};
  return {multiply(inverse, pose.orientation), rotate(inverse, offset)};
}

XrPosef compose(const XrPosef& origin, const XrPosef& pose) {
  const XrVector3f offset = rotate(origin.orientation, pose.position);
  return {multiply(origin.orientation, pose.orientation),
          {origin.position.x + offset.x, origin.position.y + offset.y, origin.position.z + offset.z}};
}

XrPosef head_in_local(const SessionObject& session, XrTime time) {
  const double elapsed_s = static_cast<double>(time - session.start_time) * 1e-9;
  // Turning right is a negative turn about +y (x right, y up, z backwards).
  const double half_turn_rad = -0.5 * session.input.head_yaw_deg_per_s * elapsed_s * std::numbers::pi / 180.0;
  return {{0.0f, static_cast<float>(std::sin(half_turn_rad)), 0.0f, static_cast<float>(std::cos(half_turn_rad))},
          {static_cast<float>(session.input.head_x_m_per_s * elapsed_s), 0.0f, 0.0f}};
}

bool pose_is_valid(const XrPosef& pose) {
  const XrQuaternionf& q = pose.orientation;
  const float norm = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  return std::isfinite(norm) && std::fabs(norm - 1.0f) < 1e-3f && std::isfinite(pose.position.x) &&
         std::isfinite(pose.position.y) && std::isfinite(pose.position.z);
}

namespace {

bool is_view_configuration_type(XrViewConfigurationType type) {
  return type == XR_VIEW_CONFIGURATION_TYPE_PRIMARY_MONO || type == XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO ||
         type == XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO ||
         type == XR_VIEW_CONFIGURATION_TYPE_SECONDARY_MONO_FIRST_PERSON_OBSERVER_MSFT;
}

// The projection layer's checks (xrEndFrame): its space and each view's sub-image.
XrResult check_projection_layer(HandleTable& table, uint64_t session, const XrCompositionLayerProjection& layer) {
  const Object* space = nullptr;
  if (const auto found = table.objects.find(handle_value(layer.space));
      found != table.objects.end() && std::holds_alternative<SpaceObject>(found->second.state))
    space = &found->second;
  if (space == nullptr || space->parent != session) return XR_ERROR_HANDLE_INVALID;
  if (layer.viewCount != 2 || layer.views == nullptr) return XR_ERROR_VALIDATION_FAILURE;  // the stereo views
  for (uint32_t v = 0; v < layer.viewCount; ++v) {
    const XrCompositionLayerProjectionView& view = layer.views[v];
    if (view.type != XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW) return XR_ERROR_VALIDATION_FAILURE;
    if (!pose_is_valid(view.pose)) return XR_ERROR_POSE_INVALID;
    const auto found = table.objects.find(handle_value(view.subImage.swapchain));
    const SwapchainObject* swapchain =
        found == table.objects.end() ? nullptr : std::get_if<SwapchainObject>(&found->second.state);
    if (swapchain == nullptr || found->second.parent != session) return XR_ERROR_HANDLE_INVALID;
    if (swapchain->last_released < 0) return XR_ERROR_LAYER_INVALID;  // nothing released to show
    const XrRect2Di& rect = view.subImage.imageRect;
    if (rect.offset.x < 0 || rect.offset.y < 0 || rect.extent.width <= 0 || rect.extent.height <= 0 ||
        int64_t{rect.offset.x} + rect.extent.width > int64_t{swapchain->info.width} ||
        int64_t{rect.offset.y} + rect.extent.height > int64_t{swapchain->info.height})
      return XR_ERROR_SWAPCHAIN_RECT_INVALID;
    if (view.subImage.imageArrayIndex >= swapchain->info.arraySize) return XR_ERROR_VALIDATION_FAILURE;
  }
  return XR_SUCCESS;
}

}  // namespace

// Angles of the shape of the Vive Pro Eye's per-eye frusta: wider towards the temple than towards
// the nose, a little more below than above. Chosen for the test runtime, not measured on a headset.
XrFovf eye_field_of_view(uint32_t eye) {
  const float temple = radians(54.0f);
  const float nose = radians(49.0f);
  const XrFovf left_eye{-temple, nose, radians(54.0f), -radians(56.0f)};
  const XrFovf right_eye{-nose, temple, radians(54.0f), -radians(56.0f)};
  return eye == 0 ? left_eye : right_eye;
}

InstanceObject* instance_of(HandleTable& table, uint64_t session) {
  const auto found = table.objects.find(session);
  if (found == table.objects.end() || !std::holds_alternative<SessionObject>(found->second.state)) return nullptr;
  return find_object<InstanceObject>(table, found->second.parent);
}

void queue_state(HandleTable& table, uint64_t session, XrSessionState state) {
  SessionObject* object = find_object<SessionObject>(table, session);
  InstanceObject* instance = instance_of(table, session);
  if (object == nullptr || instance == nullptr) return;
  object->queued_state = state;
  instance->events.push_back({session, state, current_time(*object)});
}

XrResult XRAPI_CALL create_session(XrInstance instance, const XrSessionCreateInfo* create_info, XrSession* session) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  InstanceObject* object = find_object<InstanceObject>(table, handle_value(instance));
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (create_info == nullptr || session == nullptr || create_info->type != XR_TYPE_SESSION_CREATE_INFO ||
      create_info->createFlags != 0)
    return XR_ERROR_VALIDATION_FAILURE;
  if (!object->headset.connected || create_info->systemId != kHeadsetSystemId) return XR_ERROR_SYSTEM_INVALID;
  const XrGraphicsBindingVulkanKHR* binding = nullptr;
  for (auto* chained = static_cast<const XrBaseInStructure*>(create_info->next); chained != nullptr;
       chained = chained->next) {
    if (chained->type == XR_TYPE_GRAPHICS_BINDING_VULKAN2_KHR)
      binding = reinterpret_cast<const XrGraphicsBindingVulkanKHR*>(chained);
  }
  // Vulkan is the only graphics API this runtime offers, and only through XR_KHR_vulkan_enable2.
  if (binding == nullptr || !extension_enabled(*object, XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME))
    return XR_ERROR_GRAPHICS_DEVICE_INVALID;
  if (!object->vulkan.requirements_queried) return XR_ERROR_GRAPHICS_REQUIREMENTS_CALL_MISSING;
  // The instance, physical device and device must be the ones made through the extension.
  if (binding->instance == VK_NULL_HANDLE || binding->instance != object->vulkan.instance ||
      binding->physicalDevice != object->vulkan.physical_device || binding->device == VK_NULL_HANDLE ||
      binding->device != object->vulkan.device)
    return XR_ERROR_GRAPHICS_DEVICE_INVALID;
  if (object->session != 0) return XR_ERROR_LIMIT_REACHED;  // one session an instance

  SessionObject made;
  // The scripted controller and gaze: a test that names a malformed script learns it here, not by
  // presses that never come.
  if (!read_simulated_input(made.input) || !read_late_frames(made.late_frames) ||
      !read_ready_again(made.ready_again_after_polls))
    return XR_ERROR_RUNTIME_FAILURE;
  if (const XrResult result = bind_session_vulkan(object->vulkan, *binding, made.vulkan); XR_FAILED(result))
    return result;
  made.start_time = monotonic_now_ns();
  const uint64_t handle = table.next_handle++;
  table.objects.emplace(handle, Object{handle_value(instance), std::move(made)});
  object->session = handle;
  queue_state(table, handle, XR_SESSION_STATE_IDLE);
  queue_state(table, handle, XR_SESSION_STATE_READY);
  *session = reinterpret_cast<XrSession>(handle);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL destroy_session(XrSession session) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  if (find_session(table, session) == nullptr) return XR_ERROR_HANDLE_INVALID;
  destroy_with_children(table, handle_value(session));
  return XR_SUCCESS;
}

XrResult XRAPI_CALL poll_event(XrInstance instance, XrEventDataBuffer* event) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  InstanceObject* object = find_object<InstanceObject>(table, handle_value(instance));
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (event == nullptr || event->type != XR_TYPE_EVENT_DATA_BUFFER) return XR_ERROR_VALIDATION_FAILURE;
  if (object->events.empty()) {
    // A stopped session's wait for READY counts the polls that found nothing (the application keeps
    // polling while IDLE, as the specification asks).
    if (SessionObject* session = find_object<SessionObject>(table, object->session);
        session != nullptr && session->idle_polls_left > 0 && --session->idle_polls_left == 0) {
      session->idle_polls_left = -1;
      queue_state(table, object->session, XR_SESSION_STATE_READY);
    }
    return XR_EVENT_UNAVAILABLE;
  }
  const QueuedStateChange change = object->events.front();
  object->events.pop_front();
  if (SessionObject* session = find_object<SessionObject>(table, change.session)) session->state = change.state;
  auto* changed = reinterpret_cast<XrEventDataSessionStateChanged*>(event);
  *changed = XrEventDataSessionStateChanged{XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED};
  changed->session = reinterpret_cast<XrSession>(change.session);
  changed->state = change.state;
  changed->time = change.time;
  return XR_SUCCESS;
}

XrResult XRAPI_CALL begin_session(XrSession session, const XrSessionBeginInfo* begin_info) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  SessionObject* object = find_session(table, session);
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (begin_info == nullptr || begin_info->type != XR_TYPE_SESSION_BEGIN_INFO ||
      !is_view_configuration_type(begin_info->primaryViewConfigurationType))
    return XR_ERROR_VALIDATION_FAILURE;
  if (begin_info->primaryViewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO)
    return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
  if (object->running) return XR_ERROR_SESSION_RUNNING;
  if (object->state != XR_SESSION_STATE_READY) return XR_ERROR_SESSION_NOT_READY;
  object->running = true;
  object->ended = false;
  return XR_SUCCESS;
}

XrResult XRAPI_CALL end_session(XrSession session) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  SessionObject* object = find_session(table, session);
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (!object->running) return XR_ERROR_SESSION_NOT_RUNNING;
  if (object->state != XR_SESSION_STATE_STOPPING) return XR_ERROR_SESSION_NOT_STOPPING;
  object->running = false;
  object->ended = true;
  object->frame_waited = object->frame_begun = false;
  queue_state(table, handle_value(session), XR_SESSION_STATE_IDLE);
  // The runtime's own stop, scripted to offer READY again (or never): no EXITING; the session waits IDLE.
  if (object->shutting_down && !object->exit_requested && object->ready_again_after_polls != 0) {
    object->shutting_down = false;
    object->idle_polls_left = object->ready_again_after_polls;  // kNeverReadyAgain: never counts down
    return XR_SUCCESS;
  }
  if (object->exit_requested || object->shutting_down)
    queue_state(table, handle_value(session), XR_SESSION_STATE_EXITING);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL request_exit_session(XrSession session) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  SessionObject* object = find_session(table, session);
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (!object->running) return XR_ERROR_SESSION_NOT_RUNNING;
  object->exit_requested = true;
  const uint64_t handle = handle_value(session);
  if (object->queued_state == XR_SESSION_STATE_FOCUSED) queue_state(table, handle, XR_SESSION_STATE_VISIBLE);
  if (object->queued_state == XR_SESSION_STATE_VISIBLE) queue_state(table, handle, XR_SESSION_STATE_SYNCHRONIZED);
  if (object->queued_state != XR_SESSION_STATE_STOPPING) queue_state(table, handle, XR_SESSION_STATE_STOPPING);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL enumerate_reference_spaces(XrSession session, uint32_t capacity, uint32_t* count_output,
                                               XrReferenceSpaceType* spaces) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  if (find_session(table, session) == nullptr) return XR_ERROR_HANDLE_INVALID;
  return enumerate(capacity, count_output, spaces, 2, [](XrReferenceSpaceType& type, uint32_t i) {
    type = i == 0 ? XR_REFERENCE_SPACE_TYPE_VIEW : XR_REFERENCE_SPACE_TYPE_LOCAL;
    return XR_SUCCESS;
  });
}

XrResult XRAPI_CALL create_reference_space(XrSession session, const XrReferenceSpaceCreateInfo* create_info,
                                           XrSpace* space) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  if (find_session(table, session) == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (create_info == nullptr || space == nullptr || create_info->type != XR_TYPE_REFERENCE_SPACE_CREATE_INFO)
    return XR_ERROR_VALIDATION_FAILURE;
  switch (create_info->referenceSpaceType) {
    case XR_REFERENCE_SPACE_TYPE_VIEW:
    case XR_REFERENCE_SPACE_TYPE_LOCAL:
      break;
    case XR_REFERENCE_SPACE_TYPE_STAGE:
    case XR_REFERENCE_SPACE_TYPE_UNBOUNDED_MSFT:
    case XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO:
      return XR_ERROR_REFERENCE_SPACE_UNSUPPORTED;
    default:
      return XR_ERROR_VALIDATION_FAILURE;
  }
  if (!pose_is_valid(create_info->poseInReferenceSpace)) return XR_ERROR_POSE_INVALID;
  const uint64_t handle = table.next_handle++;
  table.objects.emplace(handle, Object{handle_value(session), SpaceObject{create_info->referenceSpaceType,
                                                                          create_info->poseInReferenceSpace}});
  *space = reinterpret_cast<XrSpace>(handle);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL destroy_space(XrSpace space) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  if (find_object<SpaceObject>(table, handle_value(space)) == nullptr) return XR_ERROR_HANDLE_INVALID;
  destroy_with_children(table, handle_value(space));
  return XR_SUCCESS;
}

// LOCAL's origin is the head at the session's start, and the VIEW space is the head, so a still head
// (the default) has both see the eyes at -+IPD/2 along x; FOVLAB_TEST_XR_HEAD moves the head in LOCAL
// at the time asked for (head_in_local), and the views with it.
XrResult XRAPI_CALL locate_views(XrSession session, const XrViewLocateInfo* locate_info, XrViewState* view_state,
                                 uint32_t capacity, uint32_t* count_output, XrView* views) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  if (find_session(table, session) == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (locate_info == nullptr || view_state == nullptr || locate_info->type != XR_TYPE_VIEW_LOCATE_INFO ||
      view_state->type != XR_TYPE_VIEW_STATE || !is_view_configuration_type(locate_info->viewConfigurationType))
    return XR_ERROR_VALIDATION_FAILURE;
  if (locate_info->viewConfigurationType != XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO)
    return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
  if (locate_info->displayTime <= 0) return XR_ERROR_TIME_INVALID;
  const auto found = table.objects.find(handle_value(locate_info->space));
  const SpaceObject* space = found == table.objects.end() ? nullptr : std::get_if<SpaceObject>(&found->second.state);
  if (space == nullptr || found->second.parent != handle_value(session)) return XR_ERROR_HANDLE_INVALID;
  if (views != nullptr && capacity >= 2 && (views[0].type != XR_TYPE_VIEW || views[1].type != XR_TYPE_VIEW))
    return XR_ERROR_VALIDATION_FAILURE;
  // FOVLAB_TEST_XR_TRACKING=lost, read at each call: no valid pose to give (the flags cleared, the
  // poses identity), as a runtime before its tracking starts.
  const char* tracking = std::getenv("FOVLAB_TEST_XR_TRACKING");
  const bool lost = tracking != nullptr && std::string_view(tracking) == "lost";
  view_state->viewStateFlags =
      lost ? 0
           : XR_VIEW_STATE_ORIENTATION_VALID_BIT | XR_VIEW_STATE_POSITION_VALID_BIT |
                 XR_VIEW_STATE_ORIENTATION_TRACKED_BIT | XR_VIEW_STATE_POSITION_TRACKED_BIT;
  const SessionObject& located_session = *find_session(table, session);
  const bool head_moves =
      located_session.input.head_yaw_deg_per_s != 0.0 || located_session.input.head_x_m_per_s != 0.0;
  const XrPosef head = head_in_local(located_session, locate_info->displayTime);
  return enumerate(capacity, count_output, views, 2, [&](XrView& view, uint32_t eye) {
    const float x = (eye == 0 ? -0.5f : 0.5f) * kInterpupillaryDistanceM;
    const XrPosef eye_in_head{{0.0f, 0.0f, 0.0f, 1.0f}, {x, 0.0f, 0.0f}};
    // The eye and the space, both in LOCAL: a VIEW space rides on the head.
    const XrPosef eye_in_local = head_moves ? compose(head, eye_in_head) : eye_in_head;
    const XrPosef space_in_local = head_moves && space->type == XR_REFERENCE_SPACE_TYPE_VIEW
                                       ? compose(head, space->pose_in_reference)
                                       : space->pose_in_reference;
    view.pose =
        lost ? XrPosef{{0.0f, 0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 0.0f}} : relative_to(space_in_local, eye_in_local);
    view.fov = eye_field_of_view(eye);
    return XR_SUCCESS;
  });
}

// Deviation, stated: the specification has a second xrWaitFrame before the first frame's
// xrBeginFrame block; a single-threaded test runtime would hang there, so it answers
// XR_ERROR_CALL_ORDER_INVALID instead.
XrResult XRAPI_CALL wait_frame(XrSession session, const XrFrameWaitInfo* wait_info, XrFrameState* frame_state) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  SessionObject* object = find_session(table, session);
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if ((wait_info != nullptr && wait_info->type != XR_TYPE_FRAME_WAIT_INFO) || frame_state == nullptr ||
      frame_state->type != XR_TYPE_FRAME_STATE)
    return XR_ERROR_VALIDATION_FAILURE;
  if (!object->running) return XR_ERROR_SESSION_NOT_RUNNING;
  if (object->frame_waited) return XR_ERROR_CALL_ORDER_INVALID;
  object->waited_frames += 1;
  object->frame_waited = true;
  object->clock_pins.emplace_back(monotonic_now_ns(),
                                  frame_time(*object, object->waited_frames) - kDisplayPeriodNs / 2);
  frame_state->predictedDisplayTime = current_time(*object);
  frame_state->predictedDisplayPeriod = kDisplayPeriodNs;
  frame_state->shouldRender =
      object->state == XR_SESSION_STATE_VISIBLE || object->state == XR_SESSION_STATE_FOCUSED ? XR_TRUE : XR_FALSE;
  if (object->queued_state == XR_SESSION_STATE_READY && !object->exit_requested)
    queue_state(table, handle_value(session), XR_SESSION_STATE_SYNCHRONIZED);
  // FOVLAB_TEST_XR_UNFOCUS_AT_FRAME=N: at the session's Nth xrWaitFrame a focused session loses the
  // focus (VISIBLE), as when the headset is taken off or another application takes it; it stays so.
  const uint64_t handle = handle_value(session);
  if (frame_setting("FOVLAB_TEST_XR_UNFOCUS_AT_FRAME") == object->waited_frames &&
      object->queued_state == XR_SESSION_STATE_FOCUSED)
    queue_state(table, handle, XR_SESSION_STATE_VISIBLE);
  // FOVLAB_TEST_XR_REFOCUS_AT_FRAME=M: the focus comes back at the Mth (the headset put back on).
  if (frame_setting("FOVLAB_TEST_XR_REFOCUS_AT_FRAME") == object->waited_frames &&
      object->queued_state == XR_SESSION_STATE_VISIBLE && !object->exit_requested && !object->shutting_down)
    queue_state(table, handle, XR_SESSION_STATE_FOCUSED);
  // FOVLAB_TEST_XR_STOP_AT_FRAME=N: the runtime shuts down, through each state to STOPPING.
  if (frame_setting("FOVLAB_TEST_XR_STOP_AT_FRAME") == object->waited_frames && !object->exit_requested &&
      !object->shutting_down) {
    object->shutting_down = true;
    if (object->queued_state == XR_SESSION_STATE_FOCUSED) queue_state(table, handle, XR_SESSION_STATE_VISIBLE);
    if (object->queued_state == XR_SESSION_STATE_VISIBLE) queue_state(table, handle, XR_SESSION_STATE_SYNCHRONIZED);
    queue_state(table, handle, XR_SESSION_STATE_STOPPING);
  }
  return XR_SUCCESS;
}

XrResult XRAPI_CALL begin_frame(XrSession session, const XrFrameBeginInfo* begin_info) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  SessionObject* object = find_session(table, session);
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (begin_info != nullptr && begin_info->type != XR_TYPE_FRAME_BEGIN_INFO) return XR_ERROR_VALIDATION_FAILURE;
  if (!object->running) return XR_ERROR_SESSION_NOT_RUNNING;
  if (!object->frame_waited) return XR_ERROR_CALL_ORDER_INVALID;
  object->frame_waited = false;
  // A frame to make late: the clock jumps past its display time now, before the application renders.
  if (std::find(object->late_frames.begin(), object->late_frames.end(), object->waited_frames) !=
      object->late_frames.end())
    object->clock_pins.emplace_back(monotonic_now_ns(),
                                    frame_time(*object, object->waited_frames) + kDisplayPeriodNs / 4);
  if (object->frame_begun) return XR_FRAME_DISCARDED;  // the previous frame was never ended
  object->frame_begun = true;
  return XR_SUCCESS;
}

XrResult XRAPI_CALL end_frame(XrSession session, const XrFrameEndInfo* end_info) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  SessionObject* object = find_session(table, session);
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (end_info == nullptr || end_info->type != XR_TYPE_FRAME_END_INFO ||
      (end_info->layerCount != 0 && end_info->layers == nullptr))
    return XR_ERROR_VALIDATION_FAILURE;
  if (!object->running) return XR_ERROR_SESSION_NOT_RUNNING;
  if (!object->frame_begun) return XR_ERROR_CALL_ORDER_INVALID;
  if (end_info->displayTime <= 0) return XR_ERROR_TIME_INVALID;
  if (end_info->environmentBlendMode != XR_ENVIRONMENT_BLEND_MODE_OPAQUE)
    return XR_ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED;
  if (end_info->layerCount > XR_MIN_COMPOSITION_LAYERS_SUPPORTED) return XR_ERROR_LAYER_LIMIT_EXCEEDED;
  const XrCompositionLayerProjection* projection = nullptr;
  for (uint32_t i = 0; i < end_info->layerCount; ++i) {
    const XrCompositionLayerBaseHeader* layer = end_info->layers[i];
    if (layer == nullptr) return XR_ERROR_LAYER_INVALID;
    if (layer->type != XR_TYPE_COMPOSITION_LAYER_PROJECTION) return XR_ERROR_LAYER_INVALID;  // no quads yet
    const auto* candidate = reinterpret_cast<const XrCompositionLayerProjection*>(layer);
    if (const XrResult result = check_projection_layer(table, handle_value(session), *candidate); XR_FAILED(result))
      return result;
    projection = candidate;
  }
  if (projection != nullptr) {
    std::vector<SubmittedView> views;
    if (const XrResult result = read_projection_views(table, *object, *projection, views); XR_FAILED(result))
      return result;
    table.last_projection = std::move(views);
    table.projection_layers_submitted += 1;
  }
  object->frame_begun = false;
  object->ended_frames += 1;
  if (object->queued_state == XR_SESSION_STATE_SYNCHRONIZED && !object->exit_requested) {
    queue_state(table, handle_value(session), XR_SESSION_STATE_VISIBLE);
    queue_state(table, handle_value(session), XR_SESSION_STATE_FOCUSED);
  }
  return XR_SUCCESS;
}

}  // namespace fovlab::test_xr
