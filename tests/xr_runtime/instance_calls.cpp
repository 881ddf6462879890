// The test runtime's instance and system calls: what `fovlab devices` asks (instance properties, the
// headset system, its stereo views, the extensions), with the specification's checks and results.
#include <openxr/openxr_reflection.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "tests/xr_runtime/test_runtime.h"

namespace fovlab::test_xr {
namespace {

constexpr char kRuntimeName[] = "fovlab test runtime";
constexpr XrVersion kRuntimeVersion = XR_MAKE_VERSION(0, 1, 0);

// Copies `text` into a fixed array of `size` bytes, cut to fit with its terminating zero.
void copy_text(char* destination, size_t size, std::string_view text) {
  const size_t length = std::min(text.size(), size - 1);
  std::memcpy(destination, text.data(), length);
  destination[length] = '\0';
}

// Output structures are the caller's: their type must be the one asked for before anything is written.
template <typename Structure>
bool structure_types_are(const Structure* elements, uint32_t capacity, uint32_t available, XrStructureType type) {
  if (elements == nullptr || capacity < available) return true;  // nothing is written: enumerate() says why
  for (uint32_t i = 0; i < available; ++i) {
    if (elements[i].type != type) return false;
  }
  return true;
}

// The instance's headset when `system_id` is the one xrGetSystem hands out while it is connected.
bool system_is_valid(const InstanceObject& instance, XrSystemId system_id) {
  return instance.headset.connected && system_id == kHeadsetSystemId;
}

SimulatedHeadset headset_from_environment() {
  SimulatedHeadset headset;
  const char* setting = std::getenv("FOVLAB_TEST_XR_HEADSET");
  if (setting != nullptr && std::string_view(setting) == "absent") headset.connected = false;
  return headset;
}

}  // namespace

bool extension_enabled(const InstanceObject& instance, std::string_view name) {
  for (const std::string& extension : instance.enabled_extensions) {
    if (extension == name) return true;
  }
  return false;
}

XrResult XRAPI_CALL enumerate_instance_extension_properties(const char* layer_name, uint32_t capacity,
                                                            uint32_t* count_output, XrExtensionProperties* properties) {
  if (layer_name != nullptr) return XR_ERROR_API_LAYER_NOT_PRESENT;  // a runtime has no layers
  const std::span<const ExtensionEntry> extensions = offered_extensions();
  const auto available = static_cast<uint32_t>(extensions.size());
  if (!structure_types_are(properties, capacity, available, XR_TYPE_EXTENSION_PROPERTIES))
    return XR_ERROR_VALIDATION_FAILURE;
  return enumerate(capacity, count_output, properties, available, [&](XrExtensionProperties& property, uint32_t i) {
    copy_text(property.extensionName, XR_MAX_EXTENSION_NAME_SIZE, extensions[i].name);
    property.extensionVersion = extensions[i].spec_version;
    return XR_SUCCESS;
  });
}

XrResult XRAPI_CALL create_instance(const XrInstanceCreateInfo* create_info, XrInstance* instance) {
  if (create_info == nullptr || instance == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  if (create_info->type != XR_TYPE_INSTANCE_CREATE_INFO || create_info->createFlags != 0)
    return XR_ERROR_VALIDATION_FAILURE;
  const XrApplicationInfo& application = create_info->applicationInfo;
  const size_t name_length = strnlen(application.applicationName, XR_MAX_APPLICATION_NAME_SIZE);
  if (name_length == XR_MAX_APPLICATION_NAME_SIZE) return XR_ERROR_VALIDATION_FAILURE;  // not terminated
  if (name_length == 0) return XR_ERROR_NAME_INVALID;
  if (XR_VERSION_MAJOR(application.apiVersion) != 1 || XR_VERSION_MINOR(application.apiVersion) != 0)
    return XR_ERROR_API_VERSION_UNSUPPORTED;
  if (create_info->enabledExtensionCount != 0 && create_info->enabledExtensionNames == nullptr)
    return XR_ERROR_VALIDATION_FAILURE;
  // API layers are the loader's business: the runtime ignores enabledApiLayerNames.
  InstanceObject object;
  for (uint32_t i = 0; i < create_info->enabledExtensionCount; ++i) {
    const char* name = create_info->enabledExtensionNames[i];
    if (name == nullptr) return XR_ERROR_VALIDATION_FAILURE;
    bool offered = false;
    for (const ExtensionEntry& extension : offered_extensions()) offered = offered || extension.name == name;
    if (!offered) return XR_ERROR_EXTENSION_NOT_PRESENT;
    object.enabled_extensions.emplace_back(name);
  }
  object.headset = headset_from_environment();

  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  const uint64_t handle = table.next_handle++;
  table.objects.emplace(handle, Object{0, std::move(object)});
  *instance = reinterpret_cast<XrInstance>(handle);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL destroy_instance(XrInstance instance) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  const uint64_t handle = handle_value(instance);
  if (find_object<InstanceObject>(table, handle) == nullptr) return XR_ERROR_HANDLE_INVALID;
  // Destroying a handle destroys its children, and theirs. The Vulkan instance and device that
  // XR_KHR_vulkan_enable2 made are the application's to destroy.
  destroy_with_children(table, handle);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL get_instance_properties(XrInstance instance, XrInstanceProperties* properties) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  if (find_object<InstanceObject>(table, handle_value(instance)) == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (properties == nullptr || properties->type != XR_TYPE_INSTANCE_PROPERTIES) return XR_ERROR_VALIDATION_FAILURE;
  properties->runtimeVersion = kRuntimeVersion;
  copy_text(properties->runtimeName, XR_MAX_RUNTIME_NAME_SIZE, kRuntimeName);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL result_to_string(XrInstance instance, XrResult value, char buffer[XR_MAX_RESULT_STRING_SIZE]) {
  {
    HandleTable& table = handle_table();
    std::lock_guard lock(table.mutex);
    if (find_object<InstanceObject>(table, handle_value(instance)) == nullptr) return XR_ERROR_HANDLE_INVALID;
  }
  if (buffer == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  switch (value) {
#define FOVLAB_TEST_XR_RESULT(name, number)              \
  case name:                                             \
    copy_text(buffer, XR_MAX_RESULT_STRING_SIZE, #name); \
    return XR_SUCCESS;
    XR_LIST_ENUM_XrResult(FOVLAB_TEST_XR_RESULT)
#undef FOVLAB_TEST_XR_RESULT
        default : break;
  }
  // The specification's text for a value it does not name: the number as it is.
  const std::string unknown =
      (XR_SUCCEEDED(value) ? "XR_UNKNOWN_SUCCESS_" : "XR_UNKNOWN_FAILURE_") + std::to_string(value);
  copy_text(buffer, XR_MAX_RESULT_STRING_SIZE, unknown);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL structure_type_to_string(XrInstance instance, XrStructureType value,
                                             char buffer[XR_MAX_STRUCTURE_NAME_SIZE]) {
  {
    HandleTable& table = handle_table();
    std::lock_guard lock(table.mutex);
    if (find_object<InstanceObject>(table, handle_value(instance)) == nullptr) return XR_ERROR_HANDLE_INVALID;
  }
  if (buffer == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  switch (value) {
#define FOVLAB_TEST_XR_STRUCTURE(name, number)            \
  case name:                                              \
    copy_text(buffer, XR_MAX_STRUCTURE_NAME_SIZE, #name); \
    return XR_SUCCESS;
    XR_LIST_ENUM_XrStructureType(FOVLAB_TEST_XR_STRUCTURE)
#undef FOVLAB_TEST_XR_STRUCTURE
        default : break;
  }
  copy_text(buffer, XR_MAX_STRUCTURE_NAME_SIZE, "XR_UNKNOWN_STRUCTURE_TYPE_" + std::to_string(value));
  return XR_SUCCESS;
}

XrResult XRAPI_CALL get_system(XrInstance instance, const XrSystemGetInfo* get_info, XrSystemId* system_id) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  const InstanceObject* object = find_object<InstanceObject>(table, handle_value(instance));
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (get_info == nullptr || system_id == nullptr || get_info->type != XR_TYPE_SYSTEM_GET_INFO)
    return XR_ERROR_VALIDATION_FAILURE;
  switch (get_info->formFactor) {
    case XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY:
      if (!object->headset.connected) return XR_ERROR_FORM_FACTOR_UNAVAILABLE;  // supported, not plugged in
      *system_id = kHeadsetSystemId;
      return XR_SUCCESS;
    case XR_FORM_FACTOR_HANDHELD_DISPLAY:
      return XR_ERROR_FORM_FACTOR_UNSUPPORTED;
    default:
      return XR_ERROR_VALIDATION_FAILURE;  // not a form factor at all
  }
}

XrResult XRAPI_CALL get_system_properties(XrInstance instance, XrSystemId system_id, XrSystemProperties* properties) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  const InstanceObject* object = find_object<InstanceObject>(table, handle_value(instance));
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (!system_is_valid(*object, system_id)) return XR_ERROR_SYSTEM_INVALID;
  if (properties == nullptr || properties->type != XR_TYPE_SYSTEM_PROPERTIES) return XR_ERROR_VALIDATION_FAILURE;
  const SimulatedHeadset& headset = object->headset;
  properties->systemId = system_id;
  properties->vendorId = 0;
  copy_text(properties->systemName, XR_MAX_SYSTEM_NAME_SIZE, headset.system_name);
  properties->graphicsProperties.maxSwapchainImageWidth = headset.max_eye_width_px;
  properties->graphicsProperties.maxSwapchainImageHeight = headset.max_eye_height_px;
  properties->graphicsProperties.maxLayerCount = XR_MIN_COMPOSITION_LAYERS_SUPPORTED;
  properties->trackingProperties.orientationTracking = XR_TRUE;
  properties->trackingProperties.positionTracking = XR_TRUE;
  // Structures chained on `next` that the runtime knows, from the extensions the instance enabled;
  // any other is left alone, as the specification asks.
  for (auto* chained = static_cast<XrBaseOutStructure*>(properties->next); chained != nullptr;
       chained = chained->next) {
    if (chained->type == XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT &&
        extension_enabled(*object, XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME)) {
      reinterpret_cast<XrSystemEyeGazeInteractionPropertiesEXT*>(chained)->supportsEyeGazeInteraction = XR_TRUE;
    }
  }
  return XR_SUCCESS;
}

XrResult XRAPI_CALL enumerate_view_configurations(XrInstance instance, XrSystemId system_id, uint32_t capacity,
                                                  uint32_t* count_output, XrViewConfigurationType* types) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  const InstanceObject* object = find_object<InstanceObject>(table, handle_value(instance));
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (!system_is_valid(*object, system_id)) return XR_ERROR_SYSTEM_INVALID;
  return enumerate(capacity, count_output, types, 1, [](XrViewConfigurationType& type, uint32_t) {
    type = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
    return XR_SUCCESS;
  });
}

XrResult XRAPI_CALL enumerate_view_configuration_views(XrInstance instance, XrSystemId system_id,
                                                       XrViewConfigurationType type, uint32_t capacity,
                                                       uint32_t* count_output, XrViewConfigurationView* views) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  const InstanceObject* object = find_object<InstanceObject>(table, handle_value(instance));
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (!system_is_valid(*object, system_id)) return XR_ERROR_SYSTEM_INVALID;
  switch (type) {
    case XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO:
      break;
    case XR_VIEW_CONFIGURATION_TYPE_PRIMARY_MONO:
    case XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO:
    case XR_VIEW_CONFIGURATION_TYPE_SECONDARY_MONO_FIRST_PERSON_OBSERVER_MSFT:
      return XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED;
    default:
      return XR_ERROR_VALIDATION_FAILURE;  // not a view configuration type at all
  }
  if (!structure_types_are(views, capacity, 2, XR_TYPE_VIEW_CONFIGURATION_VIEW)) return XR_ERROR_VALIDATION_FAILURE;
  const SimulatedHeadset& headset = object->headset;
  return enumerate(capacity, count_output, views, 2, [&](XrViewConfigurationView& view, uint32_t) {
    view.recommendedImageRectWidth = headset.eye_width_px;
    view.recommendedImageRectHeight = headset.eye_height_px;
    view.maxImageRectWidth = headset.max_eye_width_px;
    view.maxImageRectHeight = headset.max_eye_height_px;
    view.recommendedSwapchainSampleCount = 1;
    view.maxSwapchainSampleCount = 1;
    return XR_SUCCESS;
  });
}

XrResult XRAPI_CALL convert_timespec_time_to_time(XrInstance instance, const struct timespec* timespec_time,
                                                  XrTime* time) {
  {
    HandleTable& table = handle_table();
    std::lock_guard lock(table.mutex);
    if (find_object<InstanceObject>(table, handle_value(instance)) == nullptr) return XR_ERROR_HANDLE_INVALID;
  }
  if (timespec_time == nullptr || time == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  const XrTime nanoseconds = XrTime{timespec_time->tv_sec} * 1000000000 + timespec_time->tv_nsec;
  if (nanoseconds <= 0) return XR_ERROR_TIME_INVALID;
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  // On the session's virtual clock while the instance has one (session_calls.cpp).
  const InstanceObject* object = find_object<InstanceObject>(table, handle_value(instance));
  const SessionObject* session = object ? find_object<SessionObject>(table, object->session) : nullptr;
  *time = session ? virtual_time_of_monotonic(*session, nanoseconds) : nanoseconds;
  return XR_SUCCESS;
}

XrResult XRAPI_CALL convert_time_to_timespec_time(XrInstance instance, XrTime time, struct timespec* timespec_time) {
  {
    HandleTable& table = handle_table();
    std::lock_guard lock(table.mutex);
    if (find_object<InstanceObject>(table, handle_value(instance)) == nullptr) return XR_ERROR_HANDLE_INVALID;
  }
  if (timespec_time == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  if (time <= 0) return XR_ERROR_TIME_INVALID;
  XrTime monotonic_ns = time;
  {
    HandleTable& table = handle_table();
    std::lock_guard lock(table.mutex);
    const InstanceObject* object = find_object<InstanceObject>(table, handle_value(instance));
    if (const SessionObject* session = object ? find_object<SessionObject>(table, object->session) : nullptr)
      monotonic_ns = monotonic_of_virtual_time(*session, time);
  }
  timespec_time->tv_sec = static_cast<time_t>(monotonic_ns / 1000000000);
  timespec_time->tv_nsec = static_cast<long>(monotonic_ns % 1000000000);
  return XR_SUCCESS;
}

}  // namespace fovlab::test_xr
