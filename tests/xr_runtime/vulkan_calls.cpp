// XR_KHR_vulkan_enable2 in the test runtime: the application's Vulkan instance and device are
// created here, from the application's create infos plus what the runtime needs, through the
// application's vkGetInstanceProcAddr (so the Vulkan validation layer the application enabled sees
// every call the runtime makes); the physical device is the runtime's choice. Also the Vulkan work
// of the swapchains and the compositor's read of a submitted layer.
#include <algorithm>
#include <cstring>
#include <string_view>
#include <vector>

#include "tests/xr_runtime/test_runtime.h"

namespace fovlab::test_xr {
namespace {

// What the runtime adds to the application's lists: a compositor in another process shares the
// swapchain images' memory, which needs external memory (core in Vulkan 1.1, named here as a real
// runtime names it).
constexpr const char* kRuntimeInstanceExtensions[] = {VK_KHR_EXTERNAL_MEMORY_CAPABILITIES_EXTENSION_NAME};
constexpr const char* kRuntimeDeviceExtensions[] = {VK_KHR_EXTERNAL_MEMORY_EXTENSION_NAME};

// The application's names, then the runtime's that the application did not already name.
std::vector<const char*> merged_names(const char* const* application, uint32_t count,
                                      std::span<const char* const> runtime) {
  std::vector<const char*> names(application, application + count);
  for (const char* name : runtime) {
    const bool named =
        std::any_of(names.begin(), names.end(), [&](const char* other) { return std::string_view(other) == name; });
    if (!named) names.push_back(name);
  }
  return names;
}

// The instance and headset system an XR_KHR_vulkan_enable2 call names, checked as every such call
// checks them.
XrResult checked_instance(HandleTable& table, XrInstance instance, XrSystemId system_id, InstanceObject** object) {
  *object = find_object<InstanceObject>(table, handle_value(instance));
  if (*object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (!extension_enabled(**object, XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME)) return XR_ERROR_FUNCTION_UNSUPPORTED;
  if (!(*object)->headset.connected || system_id != kHeadsetSystemId) return XR_ERROR_SYSTEM_INVALID;
  return XR_SUCCESS;
}

template <typename Function>
Function instance_function(const InstanceVulkan& vulkan, const char* name) {
  return reinterpret_cast<Function>(vulkan.get_instance_proc_addr(vulkan.instance, name));
}

uint32_t memory_type(const VkPhysicalDeviceMemoryProperties& properties, uint32_t allowed,
                     VkMemoryPropertyFlags wanted) {
  for (uint32_t i = 0; i < properties.memoryTypeCount; ++i) {
    if ((allowed & (1u << i)) && (properties.memoryTypes[i].propertyFlags & wanted) == wanted) return i;
  }
  return UINT32_MAX;
}

VkImageMemoryBarrier layout_change(VkImage image, VkImageLayout from, VkImageLayout to, VkAccessFlags src_access,
                                   VkAccessFlags dst_access) {
  VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  barrier.srcAccessMask = src_access;
  barrier.dstAccessMask = dst_access;
  barrier.oldLayout = from;
  barrier.newLayout = to;
  barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image;
  barrier.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  return barrier;
}

// Records `record` into a one-time command buffer of the runtime's pool, submits it on the
// session's queue and waits for it.
template <typename Record>
bool submit_and_wait(const SessionVulkan& vulkan, Record record) {
  const DeviceFunctions& vk = vulkan.functions;
  VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  allocate.commandPool = vulkan.command_pool;
  allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocate.commandBufferCount = 1;
  VkCommandBuffer commands = VK_NULL_HANDLE;
  if (vk.vkAllocateCommandBuffers(vulkan.device, &allocate, &commands) != VK_SUCCESS) return false;
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vk.vkBeginCommandBuffer(commands, &begin);
  record(commands);
  vk.vkEndCommandBuffer(commands);
  VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence = VK_NULL_HANDLE;
  bool done = vk.vkCreateFence(vulkan.device, &fence_info, nullptr, &fence) == VK_SUCCESS;
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &commands;
  done = done && vk.vkQueueSubmit(vulkan.queue, 1, &submit, fence) == VK_SUCCESS;
  done = done && vk.vkWaitForFences(vulkan.device, 1, &fence, VK_TRUE, UINT64_MAX) == VK_SUCCESS;
  if (fence != VK_NULL_HANDLE) vk.vkDestroyFence(vulkan.device, fence, nullptr);
  vk.vkFreeCommandBuffers(vulkan.device, vulkan.command_pool, 1, &commands);
  return done;
}

}  // namespace

XrResult XRAPI_CALL get_vulkan_graphics_requirements2(XrInstance instance, XrSystemId system_id,
                                                      XrGraphicsRequirementsVulkanKHR* requirements) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  InstanceObject* object = nullptr;
  if (const XrResult result = checked_instance(table, instance, system_id, &object); XR_FAILED(result)) return result;
  if (requirements == nullptr || requirements->type != XR_TYPE_GRAPHICS_REQUIREMENTS_VULKAN2_KHR)
    return XR_ERROR_VALIDATION_FAILURE;
  // Vulkan 1.1 to 1.3: what lavapipe and the desktop drivers fovlab runs on offer.
  requirements->minApiVersionSupported = XR_MAKE_VERSION(1, 1, 0);
  requirements->maxApiVersionSupported = XR_MAKE_VERSION(1, 3, 0);
  object->vulkan.requirements_queried = true;
  return XR_SUCCESS;
}

XrResult XRAPI_CALL create_vulkan_instance(XrInstance instance, const XrVulkanInstanceCreateInfoKHR* create_info,
                                           VkInstance* vulkan_instance, VkResult* vulkan_result) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  InstanceObject* object = nullptr;
  if (create_info == nullptr || vulkan_instance == nullptr || vulkan_result == nullptr)
    return XR_ERROR_VALIDATION_FAILURE;
  if (const XrResult result = checked_instance(table, instance, create_info->systemId, &object); XR_FAILED(result))
    return result;
  if (create_info->type != XR_TYPE_VULKAN_INSTANCE_CREATE_INFO_KHR || create_info->createFlags != 0 ||
      create_info->pfnGetInstanceProcAddr == nullptr || create_info->vulkanCreateInfo == nullptr)
    return XR_ERROR_VALIDATION_FAILURE;
  const auto vk_create_instance =
      reinterpret_cast<PFN_vkCreateInstance>(create_info->pfnGetInstanceProcAddr(VK_NULL_HANDLE, "vkCreateInstance"));
  if (vk_create_instance == nullptr) return XR_ERROR_RUNTIME_FAILURE;
  VkInstanceCreateInfo info = *create_info->vulkanCreateInfo;
  const std::vector<const char*> extensions =
      merged_names(info.ppEnabledExtensionNames, info.enabledExtensionCount, kRuntimeInstanceExtensions);
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  *vulkan_result = vk_create_instance(&info, create_info->vulkanAllocator, vulkan_instance);
  if (*vulkan_result != VK_SUCCESS) return XR_ERROR_RUNTIME_FAILURE;  // vulkan_result says why
  object->vulkan.get_instance_proc_addr = create_info->pfnGetInstanceProcAddr;
  object->vulkan.instance = *vulkan_instance;
  object->vulkan.physical_device = VK_NULL_HANDLE;
  object->vulkan.device = VK_NULL_HANDLE;
  return XR_SUCCESS;
}

XrResult XRAPI_CALL get_vulkan_graphics_device2(XrInstance instance, const XrVulkanGraphicsDeviceGetInfoKHR* get_info,
                                                VkPhysicalDevice* physical_device) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  InstanceObject* object = nullptr;
  if (get_info == nullptr || physical_device == nullptr) return XR_ERROR_VALIDATION_FAILURE;
  if (const XrResult result = checked_instance(table, instance, get_info->systemId, &object); XR_FAILED(result))
    return result;
  if (get_info->type != XR_TYPE_VULKAN_GRAPHICS_DEVICE_GET_INFO_KHR || get_info->vulkanInstance == VK_NULL_HANDLE)
    return XR_ERROR_VALIDATION_FAILURE;
  // The runtime can only look at an instance it made (it holds that instance's vkGetInstanceProcAddr).
  if (get_info->vulkanInstance != object->vulkan.instance) return XR_ERROR_GRAPHICS_DEVICE_INVALID;
  InstanceVulkan& vulkan = object->vulkan;
  const auto enumerate = instance_function<PFN_vkEnumeratePhysicalDevices>(vulkan, "vkEnumeratePhysicalDevices");
  const auto properties = instance_function<PFN_vkGetPhysicalDeviceProperties>(vulkan, "vkGetPhysicalDeviceProperties");
  const auto families = instance_function<PFN_vkGetPhysicalDeviceQueueFamilyProperties>(
      vulkan, "vkGetPhysicalDeviceQueueFamilyProperties");
  uint32_t count = 0;
  enumerate(vulkan.instance, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  enumerate(vulkan.instance, &count, devices.data());
  // The headset's GPU: a discrete one if there is one, else the first device with a graphics queue
  // (lavapipe here), as a compositor needs graphics.
  VkPhysicalDevice chosen = VK_NULL_HANDLE;
  bool chosen_discrete = false;
  for (VkPhysicalDevice device : devices) {
    uint32_t family_count = 0;
    families(device, &family_count, nullptr);
    std::vector<VkQueueFamilyProperties> family_properties(family_count);
    families(device, &family_count, family_properties.data());
    const bool graphics =
        std::any_of(family_properties.begin(), family_properties.end(),
                    [](const VkQueueFamilyProperties& f) { return f.queueFlags & VK_QUEUE_GRAPHICS_BIT; });
    if (!graphics) continue;
    VkPhysicalDeviceProperties device_properties{};
    properties(device, &device_properties);
    const bool discrete = device_properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU;
    if (chosen == VK_NULL_HANDLE || (discrete && !chosen_discrete)) {
      chosen = device;
      chosen_discrete = discrete;
    }
  }
  if (chosen == VK_NULL_HANDLE) return XR_ERROR_RUNTIME_FAILURE;
  vulkan.physical_device = chosen;
  *physical_device = chosen;
  return XR_SUCCESS;
}

XrResult XRAPI_CALL create_vulkan_device(XrInstance instance, const XrVulkanDeviceCreateInfoKHR* create_info,
                                         VkDevice* vulkan_device, VkResult* vulkan_result) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  InstanceObject* object = nullptr;
  if (create_info == nullptr || vulkan_device == nullptr || vulkan_result == nullptr)
    return XR_ERROR_VALIDATION_FAILURE;
  if (const XrResult result = checked_instance(table, instance, create_info->systemId, &object); XR_FAILED(result))
    return result;
  if (create_info->type != XR_TYPE_VULKAN_DEVICE_CREATE_INFO_KHR || create_info->createFlags != 0 ||
      create_info->pfnGetInstanceProcAddr == nullptr || create_info->vulkanCreateInfo == nullptr)
    return XR_ERROR_VALIDATION_FAILURE;
  // The device must be on the physical device xrGetVulkanGraphicsDevice2KHR chose.
  if (object->vulkan.physical_device == VK_NULL_HANDLE ||
      create_info->vulkanPhysicalDevice != object->vulkan.physical_device)
    return XR_ERROR_GRAPHICS_DEVICE_INVALID;
  const auto vk_create_device = instance_function<PFN_vkCreateDevice>(object->vulkan, "vkCreateDevice");
  VkDeviceCreateInfo info = *create_info->vulkanCreateInfo;
  const std::vector<const char*> extensions =
      merged_names(info.ppEnabledExtensionNames, info.enabledExtensionCount, kRuntimeDeviceExtensions);
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  *vulkan_result =
      vk_create_device(create_info->vulkanPhysicalDevice, &info, create_info->vulkanAllocator, vulkan_device);
  if (*vulkan_result != VK_SUCCESS) return XR_ERROR_RUNTIME_FAILURE;
  object->vulkan.device = *vulkan_device;
  return XR_SUCCESS;
}

// The session's view of the application's device: its queue, the runtime's command pool and the
// device functions, all through the application's vkGetInstanceProcAddr.
XrResult bind_session_vulkan(const InstanceVulkan& instance, const XrGraphicsBindingVulkanKHR& binding,
                             SessionVulkan& vulkan) {
  const auto get_device_proc_addr = instance_function<PFN_vkGetDeviceProcAddr>(instance, "vkGetDeviceProcAddr");
  const auto memory_properties =
      instance_function<PFN_vkGetPhysicalDeviceMemoryProperties>(instance, "vkGetPhysicalDeviceMemoryProperties");
  if (get_device_proc_addr == nullptr || memory_properties == nullptr) return XR_ERROR_RUNTIME_FAILURE;
  vulkan.device = binding.device;
  vulkan.queue_family = binding.queueFamilyIndex;
  DeviceFunctions& vk = vulkan.functions;
#define FOVLAB_TEST_XR_LOAD(name)                                                      \
  vk.name = reinterpret_cast<PFN_##name>(get_device_proc_addr(binding.device, #name)); \
  if (vk.name == nullptr) return XR_ERROR_RUNTIME_FAILURE;
  FOVLAB_TEST_XR_DEVICE_FUNCTIONS(FOVLAB_TEST_XR_LOAD)
#undef FOVLAB_TEST_XR_LOAD
  memory_properties(binding.physicalDevice, &vk.memory_properties);
  vk.vkGetDeviceQueue(binding.device, binding.queueFamilyIndex, binding.queueIndex, &vulkan.queue);
  VkCommandPoolCreateInfo pool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool.queueFamilyIndex = binding.queueFamilyIndex;
  pool.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
  if (vk.vkCreateCommandPool(binding.device, &pool, nullptr, &vulkan.command_pool) != VK_SUCCESS)
    return XR_ERROR_RUNTIME_FAILURE;
  return XR_SUCCESS;
}

// Each image on the application's device, with memory of its own, in the layout an acquired colour
// image must have (XR_KHR_vulkan_enable2: VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL). The runtime
// adds the usage its compositor needs (colour attachment for that layout, transfer source for its
// read).
XrResult create_swapchain_images(const SessionVulkan& vulkan, SwapchainObject& swapchain, VkImageUsageFlags usage,
                                 uint32_t count) {
  const DeviceFunctions& vk = vulkan.functions;
  for (uint32_t i = 0; i < count; ++i) {
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = swapchain.format;
    info.extent = {swapchain.info.width, swapchain.info.height, 1};
    info.mipLevels = swapchain.info.mipCount;
    info.arrayLayers = swapchain.info.arraySize;
    info.samples = VK_SAMPLE_COUNT_1_BIT;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    SwapchainImage image;
    if (vk.vkCreateImage(vulkan.device, &info, nullptr, &image.image) != VK_SUCCESS) return XR_ERROR_RUNTIME_FAILURE;
    swapchain.images.push_back(image);
    VkMemoryRequirements requirements{};
    vk.vkGetImageMemoryRequirements(vulkan.device, image.image, &requirements);
    uint32_t type = memory_type(vk.memory_properties, requirements.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    if (type == UINT32_MAX) type = memory_type(vk.memory_properties, requirements.memoryTypeBits, 0);
    VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    allocate.allocationSize = requirements.size;
    allocate.memoryTypeIndex = type;
    if (vk.vkAllocateMemory(vulkan.device, &allocate, nullptr, &swapchain.images.back().memory) != VK_SUCCESS)
      return XR_ERROR_RUNTIME_FAILURE;
    if (vk.vkBindImageMemory(vulkan.device, image.image, swapchain.images.back().memory, 0) != VK_SUCCESS)
      return XR_ERROR_RUNTIME_FAILURE;
  }
  const bool done = submit_and_wait(vulkan, [&](VkCommandBuffer commands) {
    std::vector<VkImageMemoryBarrier> barriers;
    for (const SwapchainImage& image : swapchain.images) {
      barriers.push_back(layout_change(image.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                                       0, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT));
      barriers.back().subresourceRange.levelCount = swapchain.info.mipCount;
      barriers.back().subresourceRange.layerCount = swapchain.info.arraySize;
    }
    vk.vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0,
                            nullptr, 0, nullptr, static_cast<uint32_t>(barriers.size()), barriers.data());
  });
  return done ? XR_SUCCESS : XR_ERROR_RUNTIME_FAILURE;
}

void release_vulkan_objects(HandleTable& table, Object& object) {
  if (auto* swapchain = std::get_if<SwapchainObject>(&object.state)) {
    // Its parent is its session, still there: children are released first.
    const SessionObject* session = find_object<SessionObject>(table, object.parent);
    if (session == nullptr) return;
    const DeviceFunctions& vk = session->vulkan.functions;
    for (const SwapchainImage& image : swapchain->images) {
      if (image.image != VK_NULL_HANDLE) vk.vkDestroyImage(session->vulkan.device, image.image, nullptr);
      if (image.memory != VK_NULL_HANDLE) vk.vkFreeMemory(session->vulkan.device, image.memory, nullptr);
    }
    swapchain->images.clear();
  } else if (auto* session = std::get_if<SessionObject>(&object.state)) {
    if (session->vulkan.command_pool != VK_NULL_HANDLE)
      session->vulkan.functions.vkDestroyCommandPool(session->vulkan.device, session->vulkan.command_pool, nullptr);
    session->vulkan.command_pool = VK_NULL_HANDLE;
  }
}

// The compositor's read of one view: the image's rect copied to a host buffer, the image back in
// the colour attachment layout afterwards, as the application left it.
XrResult read_projection_views(HandleTable& table, SessionObject& session, const XrCompositionLayerProjection& layer,
                               std::vector<SubmittedView>& views) {
  const SessionVulkan& vulkan = session.vulkan;
  const DeviceFunctions& vk = vulkan.functions;
  views.clear();
  for (uint32_t v = 0; v < layer.viewCount; ++v) {
    const XrCompositionLayerProjectionView& view = layer.views[v];
    const SwapchainObject* swapchain = find_object<SwapchainObject>(table, handle_value(view.subImage.swapchain));
    const VkImage image = swapchain->images[static_cast<size_t>(swapchain->last_released)].image;
    const XrRect2Di rect = view.subImage.imageRect;
    SubmittedView submitted;
    submitted.width = static_cast<uint32_t>(rect.extent.width);
    submitted.height = static_cast<uint32_t>(rect.extent.height);
    submitted.format = swapchain->info.format;
    submitted.pose = view.pose;
    submitted.fov = view.fov;
    const VkDeviceSize bytes = VkDeviceSize{submitted.width} * submitted.height * 4;  // the 8-bit RGBA/BGRA formats

    VkBufferCreateInfo buffer_info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    buffer_info.size = bytes;
    buffer_info.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    VkBuffer buffer = VK_NULL_HANDLE;
    if (vk.vkCreateBuffer(vulkan.device, &buffer_info, nullptr, &buffer) != VK_SUCCESS) return XR_ERROR_RUNTIME_FAILURE;
    VkMemoryRequirements requirements{};
    vk.vkGetBufferMemoryRequirements(vulkan.device, buffer, &requirements);
    VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    allocate.allocationSize = requirements.size;
    allocate.memoryTypeIndex = memory_type(vk.memory_properties, requirements.memoryTypeBits,
                                           VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    VkDeviceMemory memory = VK_NULL_HANDLE;
    bool done = allocate.memoryTypeIndex != UINT32_MAX &&
                vk.vkAllocateMemory(vulkan.device, &allocate, nullptr, &memory) == VK_SUCCESS &&
                vk.vkBindBufferMemory(vulkan.device, buffer, memory, 0) == VK_SUCCESS;
    done = done && submit_and_wait(vulkan, [&](VkCommandBuffer commands) {
             const VkImageMemoryBarrier to_source = layout_change(
                 image, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                 VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT);
             vk.vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0,
                                     nullptr, 0, nullptr, 1, &to_source);
             VkBufferImageCopy region{};
             region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, view.subImage.imageArrayIndex, 1};
             region.imageOffset = {rect.offset.x, rect.offset.y, 0};
             region.imageExtent = {submitted.width, submitted.height, 1};
             vk.vkCmdCopyImageToBuffer(commands, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer, 1, &region);
             const VkImageMemoryBarrier back =
                 layout_change(image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                               VK_ACCESS_TRANSFER_READ_BIT, 0);
             vk.vkCmdPipelineBarrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0,
                                     nullptr, 0, nullptr, 1, &back);
           });
    void* mapped = nullptr;
    done = done && vk.vkMapMemory(vulkan.device, memory, 0, bytes, 0, &mapped) == VK_SUCCESS;
    if (done) {
      submitted.bytes.assign(static_cast<const uint8_t*>(mapped), static_cast<const uint8_t*>(mapped) + bytes);
      vk.vkUnmapMemory(vulkan.device, memory);
    }
    vk.vkDestroyBuffer(vulkan.device, buffer, nullptr);
    if (memory != VK_NULL_HANDLE) vk.vkFreeMemory(vulkan.device, memory, nullptr);
    if (!done) return XR_ERROR_RUNTIME_FAILURE;
    views.push_back(std::move(submitted));
  }
  return XR_SUCCESS;
}

}  // namespace fovlab::test_xr
