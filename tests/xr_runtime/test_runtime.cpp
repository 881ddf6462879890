// The loader's entry into the test runtime (the negotiation), the dispatch table and
// xrGetInstanceProcAddr. The calls themselves are in instance_calls.cpp.
#include "tests/xr_runtime/test_runtime.h"

#include <array>
#include <cstdlib>
#include <cstring>
#include <string_view>
#include <vector>

#include "tests/xr_runtime/loader_negotiation.h"

namespace fovlab::test_xr {
namespace {

// OpenXR 1.0, any patch: the specification ignores the patch in these versions.
constexpr XrVersion kApiVersion = XR_MAKE_VERSION(1, 0, 0);

template <typename Function>
PFN_xrVoidFunction void_function(Function* function) {
  return reinterpret_cast<PFN_xrVoidFunction>(function);
}

}  // namespace

HandleTable& handle_table() {
  static HandleTable table;
  return table;
}

// FOVLAB_TEST_XR_VULKAN=absent in the environment takes XR_KHR_vulkan_enable2 off the list: a
// runtime that cannot hand Vulkan to the application. FOVLAB_TEST_XR_EYE_GAZE=absent takes
// XR_EXT_eye_gaze_interaction off: a headset without an eye tracker. FOVLAB_TEST_XR_CONVERT_TIMESPEC=absent
// takes XR_KHR_convert_timespec_time off: a runtime whose XrTime the application cannot read "now" in.
std::span<const ExtensionEntry> offered_extensions() {
  static const std::array<ExtensionEntry, 3> extensions{{
      {XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME, XR_KHR_vulkan_enable2_SPEC_VERSION},
      {XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME, XR_EXT_eye_gaze_interaction_SPEC_VERSION},
      {XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME, XR_KHR_convert_timespec_time_SPEC_VERSION},
  }};
  const auto absent = [](const char* variable) {
    const char* setting = std::getenv(variable);
    return setting != nullptr && std::string_view(setting) == "absent";
  };
  static std::vector<ExtensionEntry> offered;  // read anew each call, as the environment says now
  offered.clear();
  for (const ExtensionEntry& extension : extensions) {
    if (extension.name == XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME && absent("FOVLAB_TEST_XR_VULKAN")) continue;
    if (extension.name == XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME && absent("FOVLAB_TEST_XR_EYE_GAZE")) continue;
    if (extension.name == XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME && absent("FOVLAB_TEST_XR_CONVERT_TIMESPEC"))
      continue;
    offered.push_back(extension);
  }
  return offered;
}

void destroy_with_children(HandleTable& table, uint64_t handle) {
  std::vector<uint64_t> doomed{handle};
  for (size_t i = 0; i < doomed.size(); ++i) {
    for (const auto& [child, object] : table.objects) {
      if (object.parent == doomed[i]) doomed.push_back(child);
    }
  }
  // Children first: a swapchain's images go before the session that holds the device's queue.
  for (auto gone = doomed.rbegin(); gone != doomed.rend(); ++gone) {
    const auto found = table.objects.find(*gone);
    if (found == table.objects.end()) continue;
    release_vulkan_objects(table, found->second);
    if (std::holds_alternative<SessionObject>(found->second.state)) {
      if (InstanceObject* instance = find_object<InstanceObject>(table, found->second.parent)) {
        instance->session = 0;
        std::erase_if(instance->events, [&](const QueuedStateChange& event) { return event.session == *gone; });
      }
    }
    table.objects.erase(found);
  }
}

std::span<const DispatchEntry> dispatch_table() {
  constexpr std::string_view kVulkan2 = XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME;
  static const std::array<DispatchEntry, 52> table{{
      {"xrGetInstanceProcAddr", void_function(&get_instance_proc_addr), "", false},
      {"xrEnumerateInstanceExtensionProperties", void_function(&enumerate_instance_extension_properties), "", true},
      {"xrCreateInstance", void_function(&create_instance), "", true},
      {"xrDestroyInstance", void_function(&destroy_instance), "", false},
      {"xrGetInstanceProperties", void_function(&get_instance_properties), "", false},
      {"xrResultToString", void_function(&result_to_string), "", false},
      {"xrStructureTypeToString", void_function(&structure_type_to_string), "", false},
      {"xrGetSystem", void_function(&get_system), "", false},
      {"xrGetSystemProperties", void_function(&get_system_properties), "", false},
      {"xrEnumerateViewConfigurations", void_function(&enumerate_view_configurations), "", false},
      {"xrEnumerateViewConfigurationViews", void_function(&enumerate_view_configuration_views), "", false},
      {"xrConvertTimespecTimeToTimeKHR", void_function(&convert_timespec_time_to_time),
       XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME, false},
      {"xrConvertTimeToTimespecTimeKHR", void_function(&convert_time_to_timespec_time),
       XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME, false},
      {"xrGetVulkanGraphicsRequirements2KHR", void_function(&get_vulkan_graphics_requirements2), kVulkan2, false},
      {"xrCreateVulkanInstanceKHR", void_function(&create_vulkan_instance), kVulkan2, false},
      {"xrGetVulkanGraphicsDevice2KHR", void_function(&get_vulkan_graphics_device2), kVulkan2, false},
      {"xrCreateVulkanDeviceKHR", void_function(&create_vulkan_device), kVulkan2, false},
      {"xrCreateSession", void_function(&create_session), "", false},
      {"xrDestroySession", void_function(&destroy_session), "", false},
      {"xrPollEvent", void_function(&poll_event), "", false},
      {"xrBeginSession", void_function(&begin_session), "", false},
      {"xrEndSession", void_function(&end_session), "", false},
      {"xrRequestExitSession", void_function(&request_exit_session), "", false},
      {"xrEnumerateReferenceSpaces", void_function(&enumerate_reference_spaces), "", false},
      {"xrCreateReferenceSpace", void_function(&create_reference_space), "", false},
      {"xrDestroySpace", void_function(&destroy_space), "", false},
      {"xrLocateViews", void_function(&locate_views), "", false},
      {"xrWaitFrame", void_function(&wait_frame), "", false},
      {"xrBeginFrame", void_function(&begin_frame), "", false},
      {"xrEndFrame", void_function(&end_frame), "", false},
      {"xrEnumerateSwapchainFormats", void_function(&enumerate_swapchain_formats), "", false},
      {"xrCreateSwapchain", void_function(&create_swapchain), "", false},
      {"xrDestroySwapchain", void_function(&destroy_swapchain), "", false},
      {"xrEnumerateSwapchainImages", void_function(&enumerate_swapchain_images), "", false},
      {"xrAcquireSwapchainImage", void_function(&acquire_swapchain_image), "", false},
      {"xrWaitSwapchainImage", void_function(&wait_swapchain_image), "", false},
      {"xrReleaseSwapchainImage", void_function(&release_swapchain_image), "", false},
      {"xrStringToPath", void_function(&string_to_path), "", false},
      {"xrPathToString", void_function(&path_to_string), "", false},
      {"xrCreateActionSet", void_function(&create_action_set), "", false},
      {"xrDestroyActionSet", void_function(&destroy_action_set), "", false},
      {"xrCreateAction", void_function(&create_action), "", false},
      {"xrDestroyAction", void_function(&destroy_action), "", false},
      {"xrSuggestInteractionProfileBindings", void_function(&suggest_interaction_profile_bindings), "", false},
      {"xrAttachSessionActionSets", void_function(&attach_session_action_sets), "", false},
      {"xrGetCurrentInteractionProfile", void_function(&get_current_interaction_profile), "", false},
      {"xrSyncActions", void_function(&sync_actions), "", false},
      {"xrGetActionStateBoolean", void_function(&get_action_state_boolean), "", false},
      {"xrGetActionStatePose", void_function(&get_action_state_pose), "", false},
      {"xrCreateActionSpace", void_function(&create_action_space), "", false},
      {"xrLocateSpace", void_function(&locate_space), "", false},
      // xrEnumerateApiLayerProperties is the loader's own: a runtime has no layers to list.
      {"xrEnumerateApiLayerProperties", nullptr, "", true},
  }};
  return table;
}

XrResult XRAPI_CALL get_instance_proc_addr(XrInstance instance, const char* name, PFN_xrVoidFunction* function) {
  if (name == nullptr || function == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  *function = nullptr;
  const DispatchEntry* entry = nullptr;
  for (const DispatchEntry& row : dispatch_table()) {
    if (row.name == name) entry = &row;
  }
  if (instance == XR_NULL_HANDLE) {
    // Before an instance, only the global functions: anything else needs a valid instance.
    if (entry == nullptr || !entry->global)
      return entry == nullptr ? XR_ERROR_FUNCTION_UNSUPPORTED : XR_ERROR_HANDLE_INVALID;
  } else {
    HandleTable& table = handle_table();
    std::lock_guard lock(table.mutex);
    const InstanceObject* object = find_object<InstanceObject>(table, handle_value(instance));
    if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
    if (entry == nullptr) return XR_ERROR_FUNCTION_UNSUPPORTED;
    if (!entry->extension.empty()) {
      bool enabled = false;
      for (const std::string& extension : object->enabled_extensions)
        enabled = enabled || extension == entry->extension;
      if (!enabled) return XR_ERROR_FUNCTION_UNSUPPORTED;
    }
  }
  if (entry->function == nullptr) return XR_ERROR_FUNCTION_UNSUPPORTED;
  *function = entry->function;
  return XR_SUCCESS;
}

}  // namespace fovlab::test_xr

// The negotiation (the loader specification): the loader says which interface and API versions it
// speaks; the runtime picks its own within them and hands over its xrGetInstanceProcAddr. Both
// structures are checked field by field as the specification requires.
extern "C" __attribute__((visibility("default"))) XrResult XRAPI_CALL xrNegotiateLoaderRuntimeInterface(
    const XrNegotiateLoaderInfo* loader_info, XrNegotiateRuntimeRequest* runtime_request) {
  using fovlab::test_xr::kApiVersion;
  if (loader_info == nullptr || runtime_request == nullptr) return XR_ERROR_INITIALIZATION_FAILED;
  if (loader_info->structType != XR_LOADER_INTERFACE_STRUCT_LOADER_INFO ||
      loader_info->structVersion != XR_LOADER_INFO_STRUCT_VERSION ||
      loader_info->structSize != sizeof(XrNegotiateLoaderInfo))
    return XR_ERROR_INITIALIZATION_FAILED;
  if (runtime_request->structType != XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST ||
      runtime_request->structVersion != XR_RUNTIME_INFO_STRUCT_VERSION ||
      runtime_request->structSize != sizeof(XrNegotiateRuntimeRequest))
    return XR_ERROR_INITIALIZATION_FAILED;
  // The one interface version there is, and OpenXR 1.0 (major and minor compared; patch ignored).
  const auto major_minor = [](XrVersion version) { return version & ~XrVersion{0xffffffff}; };
  if (loader_info->minInterfaceVersion > XR_CURRENT_LOADER_RUNTIME_VERSION ||
      loader_info->maxInterfaceVersion < XR_CURRENT_LOADER_RUNTIME_VERSION)
    return XR_ERROR_INITIALIZATION_FAILED;
  if (major_minor(loader_info->minApiVersion) > major_minor(kApiVersion) ||
      major_minor(loader_info->maxApiVersion) < major_minor(kApiVersion))
    return XR_ERROR_INITIALIZATION_FAILED;
  runtime_request->runtimeInterfaceVersion = XR_CURRENT_LOADER_RUNTIME_VERSION;
  runtime_request->runtimeApiVersion = kApiVersion;
  runtime_request->getInstanceProcAddr = &fovlab::test_xr::get_instance_proc_addr;
  return XR_SUCCESS;
}

// Test-only: the last projection layer xrEndFrame accepted, one view at a time, as the compositor
// read it from the swapchain image. Returns XR_ERROR_VALIDATION_FAILURE for a view it does not have
// and XR_ERROR_SIZE_INSUFFICIENT (with the sizes written) when `capacity` is under the view's bytes;
// `frames` gets how many projection layers have been submitted since the library was loaded.
extern "C" __attribute__((visibility("default"))) XrResult fovlab_test_xr_last_projection_view(
    uint32_t view, uint32_t* width, uint32_t* height, int64_t* format, uint8_t* bytes, uint64_t capacity,
    int64_t* frames) {
  fovlab::test_xr::HandleTable& table = fovlab::test_xr::handle_table();
  std::lock_guard lock(table.mutex);
  if (frames != nullptr) *frames = table.projection_layers_submitted;
  if (view >= table.last_projection.size() || width == nullptr || height == nullptr || format == nullptr)
    return XR_ERROR_VALIDATION_FAILURE;
  const fovlab::test_xr::SubmittedView& submitted = table.last_projection[view];
  *width = submitted.width;
  *height = submitted.height;
  *format = submitted.format;
  if (bytes == nullptr || capacity < submitted.bytes.size()) return XR_ERROR_SIZE_INSUFFICIENT;
  std::memcpy(bytes, submitted.bytes.data(), submitted.bytes.size());
  return XR_SUCCESS;
}

// Test-only: the pose the last projection layer gave for `view` (its layer's space), as
// [x, y, z, qx, qy, qz, qw]. XR_ERROR_VALIDATION_FAILURE for a view it does not have.
extern "C" __attribute__((visibility("default"))) XrResult fovlab_test_xr_last_projection_pose(uint32_t view,
                                                                                                 float* pose) {
  fovlab::test_xr::HandleTable& table = fovlab::test_xr::handle_table();
  std::lock_guard lock(table.mutex);
  if (view >= table.last_projection.size() || pose == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  const XrPosef& given = table.last_projection[view].pose;
  const float values[7] = {given.position.x,    given.position.y,    given.position.z,   given.orientation.x,
                           given.orientation.y, given.orientation.z, given.orientation.w};
  std::memcpy(pose, values, sizeof(values));
  return XR_SUCCESS;
}
