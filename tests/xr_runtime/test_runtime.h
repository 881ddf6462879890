#pragma once
// fovlab's test runtime: an OpenXR runtime that the Khronos loader loads through a runtime manifest
// (XR_RUNTIME_JSON), with no headset behind it. It answers the calls fovlab makes, as the
// specification says a runtime must (handles checked, structure types checked, the two-call idiom
// with XR_ERROR_SIZE_INSUFFICIENT), so that what passes here is what an independent runtime expects.
//
// Every object lives in one handle table (instances, sessions, spaces, swapchains, action sets and
// actions, each with its parent), and every call is one row of one dispatch table (name,
// function, the extension that brings it), which xrGetInstanceProcAddr reads.
#define XR_USE_TIMESPEC
#define XR_USE_GRAPHICS_API_VULKAN
#include <time.h>
#include <vulkan/vulkan.h>
// After the platform's types, as openxr_platform.h expects them.
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

#include <array>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <variant>
#include <vector>

namespace fovlab::test_xr {

// The simulated headset: the HTC Vive Pro Eye of Polychronakis et al. 2023 (1440x1600 pixels per
// eye). FOVLAB_TEST_XR_HEADSET=absent in the environment at xrCreateInstance unplugs it, so that
// xrGetSystem says XR_ERROR_FORM_FACTOR_UNAVAILABLE (a runtime with no headset).
struct SimulatedHeadset {
  bool connected = true;
  std::string system_name = "fovlab test HMD (HTC Vive Pro Eye geometry)";
  uint32_t eye_width_px = 1440;
  uint32_t eye_height_px = 1600;
  uint32_t max_eye_width_px = 2880;  // twice each side: what a study may ask for, supersampled
  uint32_t max_eye_height_px = 3200;
};

// The one system an instance has, when its headset is connected.
constexpr XrSystemId kHeadsetSystemId = 1;

// The headset's refresh: 90 Hz (the Vive Pro Eye of Polychronakis et al. 2023). Frame n of a
// session is predicted for its start time plus n * 10^9 / 90 ns, rounded down, so the virtual clock
// does not drift.
constexpr int64_t kRefreshHz = 90;
constexpr XrDuration kDisplayPeriodNs = 1000000000 / kRefreshHz;

// What XR_KHR_vulkan_enable2 made for an instance: the application's Vulkan instance and device,
// created by the runtime, and the physical device it chose (the headset's GPU).
struct InstanceVulkan {
  bool requirements_queried = false;  // xrGetVulkanGraphicsRequirements2KHR was called (before a session)
  PFN_vkGetInstanceProcAddr get_instance_proc_addr = nullptr;
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
};

// A state change waiting in the instance's event queue.
struct QueuedStateChange {
  uint64_t session = 0;
  XrSessionState state = XR_SESSION_STATE_UNKNOWN;
  XrTime time = 0;
};

// One suggested binding of an interaction profile (xrSuggestInteractionProfileBindings).
struct SuggestedBinding {
  uint64_t action = 0;
  XrPath binding = XR_NULL_PATH;
};

struct InstanceObject {
  std::vector<std::string> enabled_extensions;
  SimulatedHeadset headset;
  InstanceVulkan vulkan;
  std::deque<QueuedStateChange> events;
  uint64_t session = 0;  // the instance's one session, 0 when it has none
  // The instance's paths: XrPath n is paths[n - 1] (xrStringToPath hands out each string once).
  std::vector<std::string> paths;
  // The latest suggestion for each interaction profile, by the profile's path.
  std::map<XrPath, std::vector<SuggestedBinding>> suggested_bindings;
};

// The device functions the runtime calls on the application's VkDevice (vulkan_calls.cpp).
struct DeviceFunctions {
// clang-format off
#define FOVLAB_TEST_XR_DEVICE_FUNCTIONS(X) \
  X(vkGetDeviceQueue) X(vkCreateImage) X(vkDestroyImage) X(vkGetImageMemoryRequirements) \
  X(vkBindImageMemory) X(vkAllocateMemory) X(vkFreeMemory) X(vkCreateBuffer) \
  X(vkDestroyBuffer) X(vkGetBufferMemoryRequirements) X(vkBindBufferMemory) X(vkMapMemory) \
  X(vkUnmapMemory) X(vkCreateCommandPool) X(vkDestroyCommandPool) X(vkAllocateCommandBuffers) \
  X(vkBeginCommandBuffer) X(vkEndCommandBuffer) X(vkCmdPipelineBarrier) X(vkCmdCopyImageToBuffer) \
  X(vkQueueSubmit) X(vkCreateFence) X(vkDestroyFence) X(vkWaitForFences) \
  X(vkFreeCommandBuffers)
  // clang-format on
#define FOVLAB_TEST_XR_MEMBER(name) PFN_##name name = nullptr;
  FOVLAB_TEST_XR_DEVICE_FUNCTIONS(FOVLAB_TEST_XR_MEMBER)
#undef FOVLAB_TEST_XR_MEMBER
  VkPhysicalDeviceMemoryProperties memory_properties{};
};

// The session's graphics binding (XrGraphicsBindingVulkan2KHR) and what the runtime needs of it.
struct SessionVulkan {
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  uint32_t queue_family = 0;
  VkCommandPool command_pool = VK_NULL_HANDLE;  // the runtime's own, for its layout changes and copies
  DeviceFunctions functions;
};

// One view of the last projection layer xrEndFrame accepted, as the compositor read it.
struct SubmittedView {
  uint32_t width = 0;
  uint32_t height = 0;
  int64_t format = 0;          // the swapchain's VkFormat
  std::vector<uint8_t> bytes;  // the image rect's texels, row-major, top row first
  XrPosef pose{};
  XrFovf fov{};
};

// The controller the test runtime's headset has "connected" (FOVLAB_TEST_XR_CONTROLLER), by its
// interaction profile.
enum class SimulatedController { xbox, vive, simple };

// An input pressed during one frame of the session (FOVLAB_TEST_XR_INPUT, fovlab_test_xr_press).
struct ScriptedPress {
  int64_t frame = 0;  // the session's n-th xrWaitFrame
  std::string input;  // e.g. "/user/gamepad/input/a/click"
};

// What the session's scripted devices do, read from the environment when the session is created
// (input_script.cpp).
struct SimulatedInput {
  SimulatedController controller = SimulatedController::xbox;
  std::vector<ScriptedPress> presses;
  std::string press_queue;       // FOVLAB_TEST_XR_PRESS_QUEUE: a file of presses the test appends to
  int64_t press_queue_read = 0;  // its bytes taken so far (whole lines)
  double gaze_yaw_deg = 0.0;    // right positive
  double gaze_pitch_deg = 0.0;  // up positive
  // FOVLAB_TEST_XR_GAZE_AWAY: for the gaze located at the predicted display times of frames
  // first..last, this direction instead; FOVLAB_TEST_XR_GAZE_LOST: no gaze location for those frames
  // (not tracked). An empty range (last < first): none.
  int64_t gaze_away_first_frame = 0, gaze_away_last_frame = -1;
  double gaze_away_yaw_deg = 0.0, gaze_away_pitch_deg = 0.0;
  int64_t gaze_lost_first_frame = 0, gaze_lost_last_frame = -1;
  // FOVLAB_TEST_XR_HEAD: the head turning (right positive) and moving along LOCAL's x at constant
  // rates on the virtual clock, from LOCAL's origin at the session's start.
  double head_yaw_deg_per_s = 0.0;
  double head_x_m_per_s = 0.0;
};

// An action's state as of the session's last xrSyncActions.
struct ActionState {
  bool active = false;
  bool current = false;  // boolean actions: pressed
  bool changed = false;  // since the sync before
  XrTime last_change_time = 0;
};

struct SessionObject {
  SessionVulkan vulkan;
  SimulatedInput input;
  std::vector<uint64_t> attached_action_sets;  // empty until xrAttachSessionActionSets
  bool action_sets_attached = false;
  std::map<uint64_t, ActionState> action_states;           // by action, for the attached sets' actions
  int64_t last_synced_frame = 0;                           // waited_frames at the last xrSyncActions
  XrSessionState state = XR_SESSION_STATE_UNKNOWN;         // as the application has seen it (xrPollEvent)
  XrSessionState queued_state = XR_SESSION_STATE_UNKNOWN;  // the last one queued
  bool running = false;                                    // between xrBeginSession and xrEndSession
  bool ended = false;                                      // after xrEndSession, until xrBeginSession
  bool exit_requested = false;
  XrTime start_time = 0;      // the virtual clock's origin
  int64_t waited_frames = 0;  // xrWaitFrame calls so far
  bool frame_waited = false;  // an xrWaitFrame not yet followed by xrBeginFrame
  bool frame_begun = false;   // an xrBeginFrame not yet followed by xrEndFrame
  int64_t ended_frames = 0;
  // The virtual clock as XR_KHR_convert_timespec_time converts to it (instance_calls.cpp): each
  // xrWaitFrame, and each late frame's xrBeginFrame, pins the CLOCK_MONOTONIC instant of the call
  // to an XrTime; between pins the virtual clock stands still. In order: {monotonic ns, XrTime}.
  std::vector<std::pair<XrTime, XrTime>> clock_pins;
  std::vector<int64_t> late_frames;  // FOVLAB_TEST_XR_LATE_AT_FRAMES, read at xrCreateSession
  bool shutting_down = false;        // FOVLAB_TEST_XR_STOP_AT_FRAME: EXITING follows xrEndSession
  // FOVLAB_TEST_XR_READY_AGAIN_AFTER_POLLS, read at xrCreateSession: 0 when unset (a stop is a
  // shutdown, EXITING follows xrEndSession), kNeverReadyAgain for "never" (the session stays IDLE),
  // else the empty xrPollEvent calls after the stop's IDLE was handed out before READY is queued.
  int64_t ready_again_after_polls = 0;
  int64_t idle_polls_left = -1;  // counting down to READY after a stop's xrEndSession; -1: not counting
};

// FOVLAB_TEST_XR_READY_AGAIN_AFTER_POLLS=never: stopped, the session is never offered READY again.
inline constexpr int64_t kNeverReadyAgain = -1;

struct SpaceObject {
  XrReferenceSpaceType type = XR_REFERENCE_SPACE_TYPE_VIEW;
  XrPosef pose_in_reference{};  // for an action space: poseInActionSpace
  uint64_t action = 0;          // an action space's pose action; 0 for a reference space
  XrPath subaction_path = XR_NULL_PATH;
};

struct ActionSetObject {
  std::string name;
  std::string localized_name;
  uint32_t priority = 0;
  bool attached = false;  // to a session: from then on the set and its actions are immutable
};

struct ActionObject {
  std::string name;
  std::string localized_name;
  XrActionType type = XR_ACTION_TYPE_BOOLEAN_INPUT;
  std::vector<XrPath> subaction_paths;
};

struct SwapchainImage {
  VkImage image = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
};

struct SwapchainObject {
  XrSwapchainCreateInfo info{};  // next cleared
  VkFormat format = VK_FORMAT_UNDEFINED;
  std::vector<SwapchainImage> images;
  std::deque<uint32_t> acquired;  // acquired, not yet waited, oldest first
  std::deque<uint32_t> waited;    // waited, not yet released, oldest first
  uint32_t next_index = 0;        // the next image to acquire
  int64_t last_released = -1;     // the image a layer may show; -1 before the first release
};

// One handle's object, each kind with its parent.
struct Object {
  uint64_t parent = 0;  // the handle this one was made from; 0 for an instance
  std::variant<InstanceObject, SessionObject, SpaceObject, SwapchainObject, ActionSetObject, ActionObject> state;
};

// Every live handle of every kind. Handles are never reused, so a stale one is always invalid.
struct HandleTable {
  std::mutex mutex;
  uint64_t next_handle = 1;
  std::unordered_map<uint64_t, Object> objects;
  std::vector<SubmittedView> last_projection;  // fovlab_test_xr_last_projection_view reads it
  int64_t projection_layers_submitted = 0;
};

HandleTable& handle_table();

// The object of `handle` when it is live and of that kind; nullptr otherwise. Hold the table's mutex.
template <typename Kind>
Kind* find_object(HandleTable& table, uint64_t handle) {
  const auto found = table.objects.find(handle);
  return found == table.objects.end() ? nullptr : std::get_if<Kind>(&found->second.state);
}

template <typename Handle>
uint64_t handle_value(Handle handle) {
  return reinterpret_cast<uint64_t>(handle);
}

// The handle's object and every descendant's, released (a swapchain's images freed on the
// application's device) and erased. Hold the table's mutex.
void destroy_with_children(HandleTable& table, uint64_t handle);
// A swapchain's images, freed: called for each object destroy_with_children erases.
void release_vulkan_objects(HandleTable& table, Object& object);

// The session's instance; nullptr when `session` is not a live session. Hold the table's mutex.
InstanceObject* instance_of(HandleTable& table, uint64_t session);
bool extension_enabled(const InstanceObject& instance, std::string_view name);
// Queues a state change of `session` on its instance; it takes effect for the application when
// xrPollEvent hands it over.
void queue_state(HandleTable& table, uint64_t session, XrSessionState state);
// The session's view of the application's device (XrGraphicsBindingVulkan2KHR): queue, the
// runtime's command pool, the device functions (vulkan_calls.cpp).
XrResult bind_session_vulkan(const InstanceVulkan& instance, const XrGraphicsBindingVulkanKHR& binding,
                             SessionVulkan& vulkan);
// `count` images of the swapchain's format and size on the application's device, in
// VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL.
XrResult create_swapchain_images(const SessionVulkan& vulkan, SwapchainObject& swapchain, VkImageUsageFlags usage,
                                 uint32_t count);
// xrEndFrame's compositor: copies the rect of each view's last released image to the host.
XrResult read_projection_views(HandleTable& table, SessionObject& session, const XrCompositionLayerProjection& layer,
                               std::vector<SubmittedView>& views);

// One row of the dispatch table. `global`: callable with XR_NULL_HANDLE as the instance (the three
// functions the specification allows before an instance exists). `extension`: empty for the core
// API, else the instance extension that must be enabled for xrGetInstanceProcAddr to return it.
struct DispatchEntry {
  std::string_view name;
  PFN_xrVoidFunction function;
  std::string_view extension;
  bool global = false;
};

std::span<const DispatchEntry> dispatch_table();

// The instance extensions the runtime offers, with their specification versions.
struct ExtensionEntry {
  std::string_view name;
  uint32_t spec_version;
};
std::span<const ExtensionEntry> offered_extensions();

// The two-call idiom of every xrEnumerate* call: `available` elements, written by fill(element, i)
// when the caller's capacity holds them all.
template <typename Element, typename Fill>
XrResult enumerate(uint32_t capacity, uint32_t* count_output, Element* elements, uint32_t available, Fill fill) {
  if (count_output == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  if (capacity != 0 && elements == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  *count_output = available;
  if (capacity == 0) return XR_SUCCESS;
  if (capacity < available) return XR_ERROR_SIZE_INSUFFICIENT;
  for (uint32_t i = 0; i < available; ++i) {
    const XrResult result = fill(elements[i], i);
    if (XR_FAILED(result)) return result;
  }
  return XR_SUCCESS;
}

// The calls, one per dispatch row (instance_calls.cpp).
XrResult XRAPI_CALL get_instance_proc_addr(XrInstance instance, const char* name, PFN_xrVoidFunction* function);
XrResult XRAPI_CALL enumerate_instance_extension_properties(const char* layer_name, uint32_t capacity,
                                                            uint32_t* count_output, XrExtensionProperties* properties);
XrResult XRAPI_CALL create_instance(const XrInstanceCreateInfo* create_info, XrInstance* instance);
XrResult XRAPI_CALL destroy_instance(XrInstance instance);
XrResult XRAPI_CALL get_instance_properties(XrInstance instance, XrInstanceProperties* properties);
XrResult XRAPI_CALL result_to_string(XrInstance instance, XrResult value, char buffer[XR_MAX_RESULT_STRING_SIZE]);
XrResult XRAPI_CALL structure_type_to_string(XrInstance instance, XrStructureType value,
                                             char buffer[XR_MAX_STRUCTURE_NAME_SIZE]);
XrResult XRAPI_CALL get_system(XrInstance instance, const XrSystemGetInfo* get_info, XrSystemId* system_id);
XrResult XRAPI_CALL get_system_properties(XrInstance instance, XrSystemId system_id, XrSystemProperties* properties);
XrResult XRAPI_CALL enumerate_view_configurations(XrInstance instance, XrSystemId system_id, uint32_t capacity,
                                                  uint32_t* count_output, XrViewConfigurationType* types);
XrResult XRAPI_CALL enumerate_view_configuration_views(XrInstance instance, XrSystemId system_id,
                                                       XrViewConfigurationType type, uint32_t capacity,
                                                       uint32_t* count_output, XrViewConfigurationView* views);
// XR_KHR_convert_timespec_time: the runtime's XrTime is CLOCK_MONOTONIC in nanoseconds.
XrResult XRAPI_CALL convert_timespec_time_to_time(XrInstance instance, const struct timespec* timespec_time,
                                                  XrTime* time);
XrResult XRAPI_CALL convert_time_to_timespec_time(XrInstance instance, XrTime time, struct timespec* timespec_time);

// XR_KHR_vulkan_enable2 (vulkan_calls.cpp).
XrResult XRAPI_CALL get_vulkan_graphics_requirements2(XrInstance instance, XrSystemId system_id,
                                                      XrGraphicsRequirementsVulkanKHR* requirements);
XrResult XRAPI_CALL create_vulkan_instance(XrInstance instance, const XrVulkanInstanceCreateInfoKHR* create_info,
                                           VkInstance* vulkan_instance, VkResult* vulkan_result);
XrResult XRAPI_CALL get_vulkan_graphics_device2(XrInstance instance, const XrVulkanGraphicsDeviceGetInfoKHR* get_info,
                                                VkPhysicalDevice* physical_device);
XrResult XRAPI_CALL create_vulkan_device(XrInstance instance, const XrVulkanDeviceCreateInfoKHR* create_info,
                                         VkDevice* vulkan_device, VkResult* vulkan_result);

// Sessions, events, spaces, views and the frame loop (session_calls.cpp).
XrResult XRAPI_CALL create_session(XrInstance instance, const XrSessionCreateInfo* create_info, XrSession* session);
XrResult XRAPI_CALL destroy_session(XrSession session);
XrResult XRAPI_CALL poll_event(XrInstance instance, XrEventDataBuffer* event);
XrResult XRAPI_CALL begin_session(XrSession session, const XrSessionBeginInfo* begin_info);
XrResult XRAPI_CALL end_session(XrSession session);
XrResult XRAPI_CALL request_exit_session(XrSession session);
XrResult XRAPI_CALL enumerate_reference_spaces(XrSession session, uint32_t capacity, uint32_t* count_output,
                                               XrReferenceSpaceType* spaces);
XrResult XRAPI_CALL create_reference_space(XrSession session, const XrReferenceSpaceCreateInfo* create_info,
                                           XrSpace* space);
XrResult XRAPI_CALL destroy_space(XrSpace space);
XrResult XRAPI_CALL locate_views(XrSession session, const XrViewLocateInfo* locate_info, XrViewState* view_state,
                                 uint32_t capacity, uint32_t* count_output, XrView* views);
XrResult XRAPI_CALL wait_frame(XrSession session, const XrFrameWaitInfo* wait_info, XrFrameState* frame_state);
XrResult XRAPI_CALL begin_frame(XrSession session, const XrFrameBeginInfo* begin_info);
XrResult XRAPI_CALL end_frame(XrSession session, const XrFrameEndInfo* end_info);

// Swapchains (swapchain_calls.cpp).
XrResult XRAPI_CALL enumerate_swapchain_formats(XrSession session, uint32_t capacity, uint32_t* count_output,
                                                int64_t* formats);
XrResult XRAPI_CALL create_swapchain(XrSession session, const XrSwapchainCreateInfo* create_info,
                                     XrSwapchain* swapchain);
XrResult XRAPI_CALL destroy_swapchain(XrSwapchain swapchain);
XrResult XRAPI_CALL enumerate_swapchain_images(XrSwapchain swapchain, uint32_t capacity, uint32_t* count_output,
                                               XrSwapchainImageBaseHeader* images);
XrResult XRAPI_CALL acquire_swapchain_image(XrSwapchain swapchain, const XrSwapchainImageAcquireInfo* acquire_info,
                                            uint32_t* index);
XrResult XRAPI_CALL wait_swapchain_image(XrSwapchain swapchain, const XrSwapchainImageWaitInfo* wait_info);
XrResult XRAPI_CALL release_swapchain_image(XrSwapchain swapchain, const XrSwapchainImageReleaseInfo* release_info);

// Paths, actions, bindings, action states and spaces located relative to each other (action_calls.cpp).
XrResult XRAPI_CALL string_to_path(XrInstance instance, const char* path_string, XrPath* path);
XrResult XRAPI_CALL path_to_string(XrInstance instance, XrPath path, uint32_t capacity, uint32_t* count_output,
                                   char* buffer);
XrResult XRAPI_CALL create_action_set(XrInstance instance, const XrActionSetCreateInfo* create_info,
                                      XrActionSet* action_set);
XrResult XRAPI_CALL destroy_action_set(XrActionSet action_set);
XrResult XRAPI_CALL create_action(XrActionSet action_set, const XrActionCreateInfo* create_info, XrAction* action);
XrResult XRAPI_CALL destroy_action(XrAction action);
XrResult XRAPI_CALL suggest_interaction_profile_bindings(XrInstance instance,
                                                         const XrInteractionProfileSuggestedBinding* suggested);
XrResult XRAPI_CALL attach_session_action_sets(XrSession session, const XrSessionActionSetsAttachInfo* attach_info);
XrResult XRAPI_CALL get_current_interaction_profile(XrSession session, XrPath top_level_user_path,
                                                    XrInteractionProfileState* profile);
XrResult XRAPI_CALL sync_actions(XrSession session, const XrActionsSyncInfo* sync_info);
XrResult XRAPI_CALL get_action_state_boolean(XrSession session, const XrActionStateGetInfo* get_info,
                                             XrActionStateBoolean* state);
XrResult XRAPI_CALL get_action_state_pose(XrSession session, const XrActionStateGetInfo* get_info,
                                          XrActionStatePose* state);
XrResult XRAPI_CALL create_action_space(XrSession session, const XrActionSpaceCreateInfo* create_info, XrSpace* space);
XrResult XRAPI_CALL locate_space(XrSpace space, XrSpace base_space, XrTime time, XrSpaceLocation* location);

// An interaction profile the runtime knows, with its allowlist (the specification's "Interaction
// Profile Paths"): the top-level /user paths and the input and output subpaths each of them has.
struct InteractionProfile {
  std::string_view path;
  std::span<const std::string_view> user_paths;
  std::span<const std::string_view> components;  // "/input/a/click", "/output/haptic"
  std::string_view extension;                    // empty for a core profile
};
// nullptr for a profile the runtime does not know.
const InteractionProfile* find_interaction_profile(std::string_view path);
// Whether `binding` (a /user path plus a subpath) is in the profile's allowlist, either whole or as
// an identifier without its component ("/user/hand/left/input/trigger"), which the specification
// lets the runtime resolve.
bool profile_has_binding(const InteractionProfile& profile, std::string_view binding);

// The session's scripted controller and gaze from the environment (input_script.cpp): false, with
// the reason written to stderr, when a setting or a line of the input file is malformed.
bool read_simulated_input(SimulatedInput& input);
// The lines appended to the press queue since the last call, each pressed during `next_frame`:
// false, with the reason written to stderr, for a line that names no button of the controller.
bool take_queued_presses(SimulatedInput& input, int64_t next_frame);
// Whether `input` is a button (a .../click input) of the controller's interaction profile.
bool is_controller_button(SimulatedController controller, std::string_view input);
// "/interaction_profiles/microsoft/xbox_controller" for xbox, and so on.
std::string_view controller_profile(SimulatedController controller);

// Pose arithmetic shared by the view and space calls (session_calls.cpp).
XrQuaternionf multiply(const XrQuaternionf& a, const XrQuaternionf& b);
XrVector3f rotate(const XrQuaternionf& q, const XrVector3f& v);
// `pose` (in the reference space) seen from a space whose origin is `origin` in that reference space.
XrPosef relative_to(const XrPosef& origin, const XrPosef& pose);
bool pose_is_valid(const XrPosef& pose);
// `pose` given in a space whose origin is `origin` (both in one reference space): origin * pose.
XrPosef compose(const XrPosef& origin, const XrPosef& pose);
// The head (the VIEW space's origin) in the session's LOCAL space at `time`: still at LOCAL's origin
// unless FOVLAB_TEST_XR_HEAD moves it (SimulatedInput), from the session's start.
XrPosef head_in_local(const SessionObject& session, XrTime time);
// The predicted display time of the session's frame `n` (1 for the first xrWaitFrame).
XrTime frame_time(const SessionObject& session, int64_t n);
// The CLOCK_MONOTONIC time in nanoseconds.
XrTime monotonic_now_ns();
// XR_KHR_convert_timespec_time on the session's virtual clock: a CLOCK_MONOTONIC time (ns) as the
// XrTime of the last pin at or before it (clock_pins); before the first pin, itself (the clock
// starts at CLOCK_MONOTONIC when the session is made). And back: an XrTime as the monotonic instant
// of the last pin at or before it.
XrTime virtual_time_of_monotonic(const SessionObject& session, XrTime monotonic_ns);
XrTime monotonic_of_virtual_time(const SessionObject& session, XrTime time);

// The simulated headset's views (session_calls.cpp): the eyes at -+IPD/2 along x of the head, each
// with its asymmetric field of view (the angles are stated in docs/hmd.md).
constexpr float kInterpupillaryDistanceM = 0.063f;
XrFovf eye_field_of_view(uint32_t eye);

}  // namespace fovlab::test_xr
