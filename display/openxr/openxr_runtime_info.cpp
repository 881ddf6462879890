#include "display/openxr/openxr_runtime_info.h"

#include <openxr/openxr.h>

#include <cstdlib>
#include <cstring>
#include <string_view>
#include <vector>

#include "display/openxr/openxr_instance.h"

namespace fovlab {
namespace {

// The extension names as the specification spells them (openxr_platform.h declares the Vulkan one
// only beside Vulkan's headers, which this query does not need).
constexpr std::string_view kVulkanEnable2 = "XR_KHR_vulkan_enable2";
constexpr std::string_view kEyeGazeInteraction = XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME;

std::string version_text(XrVersion version) {
  return std::to_string(XR_VERSION_MAJOR(version)) + "." + std::to_string(XR_VERSION_MINOR(version)) + "." +
         std::to_string(XR_VERSION_PATCH(version));
}

// Records the first failed call; true when `result` succeeded.
bool succeeded(OpenXrRuntimeInfo& info, const char* call, XrResult result) {
  if (XR_SUCCEEDED(result)) return true;
  if (info.query_failure.empty()) info.query_failure = std::string(call) + ": " + openxr_result_name(result);
  return false;
}

void read_extensions(OpenXrRuntimeInfo& info) {
  // The two-call idiom: the count, then that many.
  uint32_t count = 0;
  if (!succeeded(info, "xrEnumerateInstanceExtensionProperties",
                 xrEnumerateInstanceExtensionProperties(nullptr, 0, &count, nullptr)))
    return;
  std::vector<XrExtensionProperties> extensions(count, XrExtensionProperties{XR_TYPE_EXTENSION_PROPERTIES});
  if (!succeeded(info, "xrEnumerateInstanceExtensionProperties",
                 xrEnumerateInstanceExtensionProperties(nullptr, count, &count, extensions.data())))
    return;
  extensions.resize(count);
  for (const XrExtensionProperties& extension : extensions) {
    const std::string_view name(extension.extensionName, strnlen(extension.extensionName, XR_MAX_EXTENSION_NAME_SIZE));
    if (name == kVulkanEnable2) info.offers_vulkan_enable2 = true;
    if (name == kEyeGazeInteraction) info.offers_eye_gaze_interaction = true;
  }
}

void read_stereo_views(OpenXrRuntimeInfo& info, XrInstance instance, XrSystemId system) {
  uint32_t count = 0;
  if (!succeeded(info, "xrEnumerateViewConfigurations",
                 xrEnumerateViewConfigurations(instance, system, 0, &count, nullptr)))
    return;
  std::vector<XrViewConfigurationType> configurations(count);
  if (!succeeded(info, "xrEnumerateViewConfigurations",
                 xrEnumerateViewConfigurations(instance, system, count, &count, configurations.data())))
    return;
  configurations.resize(count);
  bool has_stereo = false;
  for (XrViewConfigurationType configuration : configurations)
    has_stereo = has_stereo || configuration == XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
  if (!has_stereo) return;  // no stereo views to list: stereo_eyes stays empty
  const XrViewConfigurationType stereo = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
  if (!succeeded(info, "xrEnumerateViewConfigurationViews",
                 xrEnumerateViewConfigurationViews(instance, system, stereo, 0, &count, nullptr)))
    return;
  std::vector<XrViewConfigurationView> views(count, XrViewConfigurationView{XR_TYPE_VIEW_CONFIGURATION_VIEW});
  if (!succeeded(info, "xrEnumerateViewConfigurationViews",
                 xrEnumerateViewConfigurationViews(instance, system, stereo, count, &count, views.data())))
    return;
  views.resize(count);
  for (const XrViewConfigurationView& view : views) {
    info.stereo_eyes.push_back({view.recommendedImageRectWidth, view.recommendedImageRectHeight, view.maxImageRectWidth,
                                view.maxImageRectHeight});
  }
}

}  // namespace

OpenXrRuntimeInfo query_openxr_runtime() {
  // The loader writes its own error lines to stderr when it finds no runtime; the caller names the
  // result in one line instead. An XR_LOADER_DEBUG the user set is kept (set it to see the reasons).
  setenv("XR_LOADER_DEBUG", "none", 0);
  OpenXrRuntimeInfo info;
  OpenXrInstanceResult made = create_openxr_instance("fovlab", {});
  info.instance_result = openxr_result_name(made.result);
  if (!has_openxr_runtime(info)) return info;
  const XrInstance instance = made.instance.handle;

  XrInstanceProperties properties{XR_TYPE_INSTANCE_PROPERTIES};
  if (succeeded(info, "xrGetInstanceProperties", xrGetInstanceProperties(instance, &properties))) {
    info.runtime_name.assign(properties.runtimeName, strnlen(properties.runtimeName, XR_MAX_RUNTIME_NAME_SIZE));
    info.runtime_version = version_text(properties.runtimeVersion);
  }
  read_extensions(info);

  XrSystemGetInfo system_info{XR_TYPE_SYSTEM_GET_INFO};
  system_info.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
  XrSystemId system = XR_NULL_SYSTEM_ID;
  const XrResult system_result = xrGetSystem(instance, &system_info, &system);
  info.headset_result = openxr_result_name(system_result);
  if (XR_FAILED(system_result)) return info;  // no headset now is no failure of the query

  XrSystemProperties system_properties{XR_TYPE_SYSTEM_PROPERTIES};
  if (succeeded(info, "xrGetSystemProperties", xrGetSystemProperties(instance, system, &system_properties))) {
    info.system_name.assign(system_properties.systemName,
                            strnlen(system_properties.systemName, XR_MAX_SYSTEM_NAME_SIZE));
  }
  read_stereo_views(info, instance, system);
  return info;
}

std::vector<std::string> describe_openxr_runtime(const OpenXrRuntimeInfo& info) {
  if (!has_openxr_runtime(info)) return {"OpenXR runtime: none (" + info.instance_result + ")"};
  std::vector<std::string> lines{"OpenXR runtime: " + info.runtime_name + " " + info.runtime_version};
  if (!has_openxr_headset(info)) {
    const bool unplugged = info.headset_result == "XR_ERROR_FORM_FACTOR_UNAVAILABLE";
    lines.push_back(std::string("  headset: ") + (unplugged ? "none connected" : "none") + " (" + info.headset_result +
                    ")");
  } else {
    std::string eyes;
    for (const OpenXrEyeImageSize& eye : info.stereo_eyes) {
      eyes += (eyes.empty() ? "" : ", ") + std::to_string(eye.recommended_width_px) + "x" +
              std::to_string(eye.recommended_height_px);
    }
    lines.push_back(
        "  headset: " + info.system_name + ", " +
        (eyes.empty() ? "no primary stereo view configuration" : "stereo views " + eyes + " px (recommended)"));
  }
  auto yes_no = [](bool offered) { return offered ? "yes" : "no"; };
  lines.push_back(std::string("  XR_KHR_vulkan_enable2: ") + yes_no(info.offers_vulkan_enable2) +
                  ", XR_EXT_eye_gaze_interaction: " + yes_no(info.offers_eye_gaze_interaction));
  if (!info.query_failure.empty()) lines.push_back("  query stopped at " + info.query_failure);
  return lines;
}

}  // namespace fovlab
