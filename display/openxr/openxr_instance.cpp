#include "display/openxr/openxr_instance.h"

#include <openxr/openxr_reflection.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

namespace fovlab {

OpenXrInstance::OpenXrInstance(OpenXrInstance&& other) noexcept : handle(std::exchange(other.handle, XR_NULL_HANDLE)) {}

OpenXrInstance& OpenXrInstance::operator=(OpenXrInstance&& other) noexcept {
  if (this != &other) {
    if (handle != XR_NULL_HANDLE) xrDestroyInstance(handle);
    handle = std::exchange(other.handle, XR_NULL_HANDLE);
  }
  return *this;
}

OpenXrInstance::~OpenXrInstance() {
  if (handle != XR_NULL_HANDLE) xrDestroyInstance(handle);
}

OpenXrInstanceResult create_openxr_instance(const std::string& application_name,
                                            const std::vector<std::string>& extensions) {
  XrInstanceCreateInfo create_info{XR_TYPE_INSTANCE_CREATE_INFO};
  // The name is cut to fit its fixed array (XR_MAX_APPLICATION_NAME_SIZE, with the terminating zero).
  const size_t name_bytes = std::min(application_name.size(), sizeof(create_info.applicationInfo.applicationName) - 1);
  std::copy_n(application_name.data(), name_bytes, create_info.applicationInfo.applicationName);
  std::copy_n("fovlab", 7, create_info.applicationInfo.engineName);
  create_info.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
  std::vector<const char*> extension_names;
  for (const std::string& extension : extensions) extension_names.push_back(extension.c_str());
  create_info.enabledExtensionCount = static_cast<uint32_t>(extension_names.size());
  create_info.enabledExtensionNames = extension_names.empty() ? nullptr : extension_names.data();

  OpenXrInstanceResult made;
  XrInstance instance = XR_NULL_HANDLE;
  made.result = xrCreateInstance(&create_info, &instance);
  if (XR_SUCCEEDED(made.result)) made.instance = OpenXrInstance(instance);
  return made;
}

std::string openxr_result_name(XrResult result) {
  switch (result) {
#define FOVLAB_OPENXR_RESULT_NAME(name, value) \
  case name:                                   \
    return #name;
    XR_LIST_ENUM_XrResult(FOVLAB_OPENXR_RESULT_NAME)
#undef FOVLAB_OPENXR_RESULT_NAME
        default : break;
  }
  // The specification's fallback: the number as it is, so a failure's keeps its minus sign.
  return (XR_SUCCEEDED(result) ? "XR_UNKNOWN_SUCCESS_" : "XR_UNKNOWN_FAILURE_") + std::to_string(result);
}

}  // namespace fovlab
