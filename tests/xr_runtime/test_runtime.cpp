// The loader's entry into the test runtime (the negotiation), the dispatch table and
// xrGetInstanceProcAddr. The calls themselves are in instance_calls.cpp.
#include "tests/xr_runtime/test_runtime.h"

#include <array>
#include <cstring>

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

std::span<const ExtensionEntry> offered_extensions() {
  static const std::array<ExtensionEntry, 3> extensions{{
      {XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME, XR_KHR_vulkan_enable2_SPEC_VERSION},
      {XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME, XR_EXT_eye_gaze_interaction_SPEC_VERSION},
      {XR_KHR_CONVERT_TIMESPEC_TIME_EXTENSION_NAME, XR_KHR_convert_timespec_time_SPEC_VERSION},
  }};
  return extensions;
}

std::span<const DispatchEntry> dispatch_table() {
  static const std::array<DispatchEntry, 14> table{{
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
