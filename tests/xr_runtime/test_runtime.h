#pragma once
// fovlab's test runtime: an OpenXR runtime that the Khronos loader loads through a runtime manifest
// (XR_RUNTIME_JSON), with no headset behind it. It answers the calls fovlab makes, as the
// specification says a runtime must (handles checked, structure types checked, the two-call idiom
// with XR_ERROR_SIZE_INSUFFICIENT), so that what passes here is what an independent runtime expects.
//
// The shape the later stages fill in: every object lives in one handle table (an instance now;
// sessions, spaces, swapchains, action sets and actions later, each with its parent), and every
// call is one row of one dispatch table (name, function, the extension that brings it), which
// xrGetInstanceProcAddr reads.
#define XR_USE_TIMESPEC
#define XR_USE_GRAPHICS_API_VULKAN
#include <time.h>
#include <vulkan/vulkan.h>
// After the platform's types, as openxr_platform.h expects them.
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

#include <cstdint>
#include <mutex>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
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

struct InstanceObject {
  std::vector<std::string> enabled_extensions;
  SimulatedHeadset headset;
};

// One handle's object. A variant of one alternative now; the later stages add theirs.
struct Object {
  uint64_t parent = 0;  // the handle this one was made from; 0 for an instance
  std::variant<InstanceObject> state;
};

// Every live handle of every kind. Handles are never reused, so a stale one is always invalid.
struct HandleTable {
  std::mutex mutex;
  uint64_t next_handle = 1;
  std::unordered_map<uint64_t, Object> objects;
};

HandleTable& handle_table();

// The object of `handle` when it is live and of that kind; nullptr otherwise. Hold the table's mutex.
template <typename Kind>
Kind* find_object(HandleTable& table, uint64_t handle) {
  const auto found = table.objects.find(handle);
  return found == table.objects.end() ? nullptr : std::get_if<Kind>(&found->second.state);
}

inline uint64_t handle_value(XrInstance instance) { return reinterpret_cast<uint64_t>(instance); }

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

}  // namespace fovlab::test_xr
