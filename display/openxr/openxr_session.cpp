#include "display/openxr/openxr_session.h"

#include <openxr/openxr_reflection.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "core/input_error.h"

namespace fovlab {
namespace {

constexpr XrViewConfigurationType kStereo = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
// openxr_platform.h names it only with XR_USE_TIMESPEC, which this file does not need otherwise.
constexpr char kConvertTimespecTime[] = "XR_KHR_convert_timespec_time";

// A call that should not fail once the session exists: a failure is the runtime's, not the user's.
void check(XrResult result, const char* call) {
  if (XR_FAILED(result)) throw std::runtime_error(std::string("openxr: ") + call + ": " + openxr_result_name(result));
}

// A refusal before the session exists: what the user must change (a runtime, a headset, a size).
void refuse_unless(XrResult result, const char* call) {
  if (XR_FAILED(result)) throw InputError(std::string("openxr: ") + call + ": " + openxr_result_name(result));
}

// The same for a runtime call that made a Vulkan object: both it and the Vulkan creation it made.
void refuse_unless_made(XrResult result, VkResult vulkan_result, const char* call) {
  if (XR_FAILED(result) || vulkan_result != VK_SUCCESS)
    throw InputError(std::string("openxr: ") + call + ": " + openxr_result_name(result) + " (VkResult " +
                     std::to_string(vulkan_result) + ")");
}

template <typename Function>
Function extension_function(XrInstance instance, const char* name) {
  PFN_xrVoidFunction function = nullptr;
  refuse_unless(xrGetInstanceProcAddr(instance, name, &function), name);
  return reinterpret_cast<Function>(function);
}

bool runtime_offers(const char* extension) {
  uint32_t count = 0;
  refuse_unless(xrEnumerateInstanceExtensionProperties(nullptr, 0, &count, nullptr),
                "no OpenXR runtime (xrEnumerateInstanceExtensionProperties)");
  std::vector<XrExtensionProperties> properties(count, XrExtensionProperties{XR_TYPE_EXTENSION_PROPERTIES});
  refuse_unless(xrEnumerateInstanceExtensionProperties(nullptr, count, &count, properties.data()),
                "xrEnumerateInstanceExtensionProperties");
  return std::any_of(properties.begin(), properties.begin() + count, [&](const XrExtensionProperties& property) {
    return std::string(property.extensionName) == extension;
  });
}

std::string vulkan_version_text(XrVersion version) {
  return std::to_string(XR_VERSION_MAJOR(version)) + "." + std::to_string(XR_VERSION_MINOR(version));
}

// fovlab's context, with its instance and device created by the runtime (XR_KHR_vulkan_enable2).
vk::VulkanCreator creator_through_runtime(XrInstance instance, XrSystemId system) {
  const auto create_instance = extension_function<PFN_xrCreateVulkanInstanceKHR>(instance, "xrCreateVulkanInstanceKHR");
  const auto graphics_device =
      extension_function<PFN_xrGetVulkanGraphicsDevice2KHR>(instance, "xrGetVulkanGraphicsDevice2KHR");
  const auto create_device = extension_function<PFN_xrCreateVulkanDeviceKHR>(instance, "xrCreateVulkanDeviceKHR");
  vk::VulkanCreator creator;
  creator.create_instance = [=](const VkInstanceCreateInfo& vulkan_info) {
    XrVulkanInstanceCreateInfoKHR info{XR_TYPE_VULKAN_INSTANCE_CREATE_INFO_KHR};
    info.systemId = system;
    info.pfnGetInstanceProcAddr = &vkGetInstanceProcAddr;
    info.vulkanCreateInfo = &vulkan_info;
    VkInstance made = VK_NULL_HANDLE;
    VkResult vulkan_result = VK_SUCCESS;
    refuse_unless_made(create_instance(instance, &info, &made, &vulkan_result), vulkan_result, "xrCreateVulkanInstanceKHR");
    return made;
  };
  creator.choose_physical_device = [=](VkInstance vulkan_instance) {
    XrVulkanGraphicsDeviceGetInfoKHR info{XR_TYPE_VULKAN_GRAPHICS_DEVICE_GET_INFO_KHR};
    info.systemId = system;
    info.vulkanInstance = vulkan_instance;
    VkPhysicalDevice chosen = VK_NULL_HANDLE;
    refuse_unless(graphics_device(instance, &info, &chosen), "xrGetVulkanGraphicsDevice2KHR");
    return chosen;
  };
  creator.create_device = [=](VkPhysicalDevice physical_device, const VkDeviceCreateInfo& vulkan_info) {
    XrVulkanDeviceCreateInfoKHR info{XR_TYPE_VULKAN_DEVICE_CREATE_INFO_KHR};
    info.systemId = system;
    info.pfnGetInstanceProcAddr = &vkGetInstanceProcAddr;
    info.vulkanPhysicalDevice = physical_device;
    info.vulkanCreateInfo = &vulkan_info;
    VkDevice made = VK_NULL_HANDLE;
    VkResult vulkan_result = VK_SUCCESS;
    refuse_unless_made(create_device(instance, &info, &made, &vulkan_result), vulkan_result, "xrCreateVulkanDeviceKHR");
    return made;
  };
  return creator;
}

}  // namespace

OpenXrSession::OpenXrSession(const OpenXrSessionOptions& options) {
  try {
    if (!runtime_offers(XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME))
      throw InputError(
          "openxr: the OpenXR runtime does not offer XR_KHR_vulkan_enable2; fovlab renders through Vulkan, so it "
          "cannot run a headset session on this runtime");
    std::vector<std::string> extensions{XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME};
    eye_gaze_enabled = runtime_offers(XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME);
    if (eye_gaze_enabled) extensions.emplace_back(XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME);
    convert_timespec_enabled = runtime_offers(kConvertTimespecTime);
    if (convert_timespec_enabled) extensions.emplace_back(kConvertTimespecTime);
    OpenXrInstanceResult made = create_openxr_instance("fovlab", extensions);
    refuse_unless(made.result, "xrCreateInstance");
    instance = std::move(made.instance);
    if (convert_timespec_enabled)
      convert_timespec_to_time =
          extension_function<decltype(convert_timespec_to_time)>(instance.handle, "xrConvertTimespecTimeToTimeKHR");

    XrSystemGetInfo system_info{XR_TYPE_SYSTEM_GET_INFO};
    system_info.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
    refuse_unless(xrGetSystem(instance.handle, &system_info, &system), "no headset (xrGetSystem)");
    uint32_t view_count = 0;
    refuse_unless(xrEnumerateViewConfigurationViews(instance.handle, system, kStereo, 0, &view_count, nullptr),
                  "no stereo views (xrEnumerateViewConfigurationViews)");
    std::vector<XrViewConfigurationView> views(view_count, XrViewConfigurationView{XR_TYPE_VIEW_CONFIGURATION_VIEW});
    refuse_unless(
        xrEnumerateViewConfigurationViews(instance.handle, system, kStereo, view_count, &view_count, views.data()),
        "xrEnumerateViewConfigurationViews");
    if (view_count != 2)
      throw InputError("openxr: the headset's stereo configuration has " + std::to_string(view_count) +
                       " views; expected 2");
    recommended_eye_width_px = views[0].recommendedImageRectWidth;
    recommended_eye_height_px = views[0].recommendedImageRectHeight;
    eye_width_px = options.eye_width_px != 0 ? options.eye_width_px : recommended_eye_width_px;
    eye_height_px = options.eye_height_px != 0 ? options.eye_height_px : recommended_eye_height_px;
    for (const XrViewConfigurationView& view : views) {
      if (eye_width_px > view.maxImageRectWidth || eye_height_px > view.maxImageRectHeight)
        throw InputError("openxr: eye image " + std::to_string(eye_width_px) + "x" + std::to_string(eye_height_px) +
                         ": expected at most the runtime's " + std::to_string(view.maxImageRectWidth) + "x" +
                         std::to_string(view.maxImageRectHeight));
    }

    // The Vulkan versions the runtime takes; fovlab's instance asks for 1.3 and needs 1.1.
    const auto requirements = extension_function<PFN_xrGetVulkanGraphicsRequirements2KHR>(
        instance.handle, "xrGetVulkanGraphicsRequirements2KHR");
    XrGraphicsRequirementsVulkan2KHR required{XR_TYPE_GRAPHICS_REQUIREMENTS_VULKAN2_KHR};
    refuse_unless(requirements(instance.handle, system, &required), "xrGetVulkanGraphicsRequirements2KHR");
    if (XR_VERSION_MAJOR(required.minApiVersionSupported) > 1 ||
        (XR_VERSION_MAJOR(required.maxApiVersionSupported) == 1 &&
         XR_VERSION_MINOR(required.maxApiVersionSupported) < 1))
      throw InputError("openxr: the runtime takes Vulkan " + vulkan_version_text(required.minApiVersionSupported) +
                       " to " + vulkan_version_text(required.maxApiVersionSupported) + "; fovlab needs 1.1 or later");

    vk::ContextOptions context_options;
    context_options.validation = options.validation;
    context_options.present_to = options.present_to;
    context_options.created_by = creator_through_runtime(instance.handle, system);
    vulkan = std::make_unique<vk::Context>(context_options);

    XrGraphicsBindingVulkan2KHR binding{XR_TYPE_GRAPHICS_BINDING_VULKAN2_KHR};
    binding.instance = vulkan->instance;
    binding.physicalDevice = vulkan->physical_device;
    binding.device = vulkan->device;
    binding.queueFamilyIndex = vulkan->queue_family;
    binding.queueIndex = 0;
    XrSessionCreateInfo session_info{XR_TYPE_SESSION_CREATE_INFO};
    session_info.next = &binding;
    session_info.systemId = system;
    refuse_unless(xrCreateSession(instance.handle, &session_info, &session), "xrCreateSession");

    XrReferenceSpaceCreateInfo space_info{XR_TYPE_REFERENCE_SPACE_CREATE_INFO};
    space_info.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_LOCAL;
    space_info.poseInReferenceSpace.orientation.w = 1.0f;
    check(xrCreateReferenceSpace(session, &space_info, &local_space), "xrCreateReferenceSpace");
    // The head: the eyes located in it are the head-locked view model's eyes (openxr_eye_view.h).
    space_info.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_VIEW;
    check(xrCreateReferenceSpace(session, &space_info, &view_space), "xrCreateReferenceSpace");

    // The eyes' frames are sRGB-encoded bytes: an sRGB format keeps them as they are and tells the
    // compositor to decode them.
    uint32_t format_count = 0;
    check(xrEnumerateSwapchainFormats(session, 0, &format_count, nullptr), "xrEnumerateSwapchainFormats");
    std::vector<int64_t> formats(format_count);
    check(xrEnumerateSwapchainFormats(session, format_count, &format_count, formats.data()),
          "xrEnumerateSwapchainFormats");
    if (std::find(formats.begin(), formats.end(), int64_t{VK_FORMAT_R8G8B8A8_SRGB}) == formats.end())
      throw InputError(
          "openxr: the runtime offers no VK_FORMAT_R8G8B8A8_SRGB swapchain; fovlab's frames are 8-bit sRGB RGBA");
    for (OpenXrEyeSwapchain& eye : eyes) {
      XrSwapchainCreateInfo swapchain_info{XR_TYPE_SWAPCHAIN_CREATE_INFO};
      swapchain_info.usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT;
      swapchain_info.format = VK_FORMAT_R8G8B8A8_SRGB;
      swapchain_info.sampleCount = 1;
      swapchain_info.width = eye_width_px;
      swapchain_info.height = eye_height_px;
      swapchain_info.faceCount = 1;
      swapchain_info.arraySize = 1;
      swapchain_info.mipCount = 1;
      check(xrCreateSwapchain(session, &swapchain_info, &eye.handle), "xrCreateSwapchain");
      uint32_t image_count = 0;
      check(xrEnumerateSwapchainImages(eye.handle, 0, &image_count, nullptr), "xrEnumerateSwapchainImages");
      std::vector<XrSwapchainImageVulkan2KHR> images(image_count,
                                                     XrSwapchainImageVulkan2KHR{XR_TYPE_SWAPCHAIN_IMAGE_VULKAN2_KHR});
      check(xrEnumerateSwapchainImages(eye.handle, image_count, &image_count,
                                       reinterpret_cast<XrSwapchainImageBaseHeader*>(images.data())),
            "xrEnumerateSwapchainImages");
      for (const XrSwapchainImageVulkan2KHR& image : images) eye.images.push_back(image.image);
    }
  } catch (...) {
    release();
    throw;
  }
}

OpenXrSession::~OpenXrSession() { release(); }

void OpenXrSession::release() {
  if (vulkan && vulkan->device) vkDeviceWaitIdle(vulkan->device);
  for (OpenXrEyeSwapchain& eye : eyes) {
    if (eye.handle != XR_NULL_HANDLE) xrDestroySwapchain(eye.handle);
    eye = OpenXrEyeSwapchain{};
  }
  if (view_space != XR_NULL_HANDLE) xrDestroySpace(view_space);
  view_space = XR_NULL_HANDLE;
  if (local_space != XR_NULL_HANDLE) xrDestroySpace(local_space);
  local_space = XR_NULL_HANDLE;
  if (session != XR_NULL_HANDLE) xrDestroySession(session);
  session = XR_NULL_HANDLE;
  vulkan.reset();  // the device and instance the runtime made, destroyed by their owner
  convert_timespec_to_time = nullptr;
  instance = OpenXrInstance{};
}

std::vector<XrSessionState> poll_openxr_events(OpenXrSession& session) {
  std::vector<XrSessionState> states;
  for (;;) {
    XrEventDataBuffer event{XR_TYPE_EVENT_DATA_BUFFER};
    const XrResult result = xrPollEvent(session.instance.handle, &event);
    check(result, "xrPollEvent");
    if (result == XR_EVENT_UNAVAILABLE) return states;
    if (event.type == XR_TYPE_EVENT_DATA_INSTANCE_LOSS_PENDING) session.exiting = true;
    if (event.type != XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED) continue;
    const auto& changed = reinterpret_cast<const XrEventDataSessionStateChanged&>(event);
    if (changed.session != session.session) continue;
    session.state = changed.state;
    states.push_back(changed.state);
    switch (changed.state) {
      case XR_SESSION_STATE_READY: {
        XrSessionBeginInfo begin{XR_TYPE_SESSION_BEGIN_INFO};
        begin.primaryViewConfigurationType = kStereo;
        check(xrBeginSession(session.session, &begin), "xrBeginSession");
        session.running = true;
        break;
      }
      case XR_SESSION_STATE_STOPPING:
        check(xrEndSession(session.session), "xrEndSession");
        session.running = false;
        break;
      case XR_SESSION_STATE_EXITING:
      case XR_SESSION_STATE_LOSS_PENDING:
        session.exiting = true;
        break;
      default:
        break;
    }
  }
}

void request_openxr_exit(OpenXrSession& session) {
  check(xrRequestExitSession(session.session), "xrRequestExitSession");
}

std::optional<XrTime> openxr_time_now(const OpenXrSession& session) {
  if (session.convert_timespec_to_time == nullptr) return std::nullopt;
  timespec now{};
  if (clock_gettime(CLOCK_MONOTONIC, &now) != 0) return std::nullopt;
  XrTime time = 0;
  if (XR_FAILED(session.convert_timespec_to_time(session.instance.handle, &now, &time))) return std::nullopt;
  return time;
}

const char* openxr_session_state_name(XrSessionState state) {
  switch (state) {
#define FOVLAB_OPENXR_STATE_NAME(name, value) \
  case name:                                  \
    return #name;
    XR_LIST_ENUM_XrSessionState(FOVLAB_OPENXR_STATE_NAME)
#undef FOVLAB_OPENXR_STATE_NAME
        default : return "XR_SESSION_STATE_UNKNOWN";
  }
}

}  // namespace fovlab
