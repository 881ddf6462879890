// The test runtime's swapchains: VkImages the runtime makes on the application's VkDevice (three a
// swapchain), handed out in order by acquire, wait and release with the specification's ordering
// rules (XR_ERROR_CALL_ORDER_INVALID when a call comes out of turn).
#include <array>

#include "tests/xr_runtime/test_runtime.h"

namespace fovlab::test_xr {
namespace {

constexpr uint32_t kImagesPerSwapchain = 3;

// The formats offered, the runtime's preference first: 8-bit sRGB (the compositor decodes it) and
// 8-bit UNORM, RGBA and BGRA.
constexpr std::array<VkFormat, 4> kFormats{VK_FORMAT_R8G8B8A8_SRGB, VK_FORMAT_B8G8R8A8_SRGB, VK_FORMAT_R8G8B8A8_UNORM,
                                           VK_FORMAT_B8G8R8A8_UNORM};

// Hold the table's mutex.
SwapchainObject* find_swapchain(HandleTable& table, XrSwapchain swapchain) {
  return find_object<SwapchainObject>(table, handle_value(swapchain));
}

}  // namespace

XrResult XRAPI_CALL enumerate_swapchain_formats(XrSession session, uint32_t capacity, uint32_t* count_output,
                                                int64_t* formats) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  if (find_object<SessionObject>(table, handle_value(session)) == nullptr) return XR_ERROR_HANDLE_INVALID;
  return enumerate(capacity, count_output, formats, static_cast<uint32_t>(kFormats.size()),
                   [](int64_t& format, uint32_t i) {
                     format = kFormats[i];
                     return XR_SUCCESS;
                   });
}

XrResult XRAPI_CALL create_swapchain(XrSession session, const XrSwapchainCreateInfo* create_info,
                                     XrSwapchain* swapchain) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  SessionObject* object = find_object<SessionObject>(table, handle_value(session));
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (create_info == nullptr || swapchain == nullptr || create_info->type != XR_TYPE_SWAPCHAIN_CREATE_INFO)
    return XR_ERROR_VALIDATION_FAILURE;
  const XrSwapchainCreateInfo& info = *create_info;
  if (info.createFlags & XR_SWAPCHAIN_CREATE_PROTECTED_CONTENT_BIT) return XR_ERROR_FEATURE_UNSUPPORTED;
  bool offered = false;
  for (const VkFormat format : kFormats) offered = offered || info.format == format;
  if (!offered) return XR_ERROR_SWAPCHAIN_FORMAT_UNSUPPORTED;
  // Colour formats only: a depth usage, storage (not on sRGB) or a mutable format is not offered.
  if (info.usageFlags & (XR_SWAPCHAIN_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_UNORDERED_ACCESS_BIT |
                         XR_SWAPCHAIN_USAGE_MUTABLE_FORMAT_BIT))
    return XR_ERROR_FEATURE_UNSUPPORTED;
  if (info.sampleCount != 1 || info.faceCount == 6) return XR_ERROR_FEATURE_UNSUPPORTED;
  const InstanceObject* instance = instance_of(table, handle_value(session));
  if (info.width == 0 || info.height == 0 || info.faceCount != 1 || info.arraySize == 0 || info.mipCount == 0 ||
      info.width > instance->headset.max_eye_width_px || info.height > instance->headset.max_eye_height_px)
    return XR_ERROR_VALIDATION_FAILURE;
  VkImageUsageFlags usage = 0;
  if (info.usageFlags & XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT) usage |= VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
  if (info.usageFlags & XR_SWAPCHAIN_USAGE_TRANSFER_SRC_BIT) usage |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  if (info.usageFlags & XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT) usage |= VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  if (info.usageFlags & XR_SWAPCHAIN_USAGE_SAMPLED_BIT) usage |= VK_IMAGE_USAGE_SAMPLED_BIT;

  SwapchainObject made;
  made.info = info;
  made.info.next = nullptr;
  made.format = static_cast<VkFormat>(info.format);
  const XrResult result = create_swapchain_images(object->vulkan, made, usage, kImagesPerSwapchain);
  const uint64_t handle = table.next_handle++;
  table.objects.emplace(handle, Object{handle_value(session), std::move(made)});
  if (XR_FAILED(result)) {
    destroy_with_children(table, handle);  // frees what was made
    return result;
  }
  *swapchain = reinterpret_cast<XrSwapchain>(handle);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL destroy_swapchain(XrSwapchain swapchain) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  if (find_swapchain(table, swapchain) == nullptr) return XR_ERROR_HANDLE_INVALID;
  destroy_with_children(table, handle_value(swapchain));
  return XR_SUCCESS;
}

XrResult XRAPI_CALL enumerate_swapchain_images(XrSwapchain swapchain, uint32_t capacity, uint32_t* count_output,
                                               XrSwapchainImageBaseHeader* images) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  const SwapchainObject* object = find_swapchain(table, swapchain);
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  auto* vulkan_images = reinterpret_cast<XrSwapchainImageVulkanKHR*>(images);
  const auto available = static_cast<uint32_t>(object->images.size());
  if (vulkan_images != nullptr && capacity >= available) {
    for (uint32_t i = 0; i < available; ++i) {
      if (vulkan_images[i].type != XR_TYPE_SWAPCHAIN_IMAGE_VULKAN2_KHR) return XR_ERROR_VALIDATION_FAILURE;
    }
  }
  return enumerate(capacity, count_output, vulkan_images, available, [&](XrSwapchainImageVulkanKHR& image, uint32_t i) {
    image.image = object->images[i].image;
    return XR_SUCCESS;
  });
}

XrResult XRAPI_CALL acquire_swapchain_image(XrSwapchain swapchain, const XrSwapchainImageAcquireInfo* acquire_info,
                                            uint32_t* index) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  SwapchainObject* object = find_swapchain(table, swapchain);
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if ((acquire_info != nullptr && acquire_info->type != XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO) || index == nullptr)
    return XR_ERROR_VALIDATION_FAILURE;
  // Every image already held by the application, or a static image acquired once already.
  if (object->acquired.size() + object->waited.size() == object->images.size()) return XR_ERROR_CALL_ORDER_INVALID;
  if ((object->info.createFlags & XR_SWAPCHAIN_CREATE_STATIC_IMAGE_BIT) &&
      (object->last_released >= 0 || !object->acquired.empty() || !object->waited.empty()))
    return XR_ERROR_CALL_ORDER_INVALID;
  *index = object->next_index;
  object->acquired.push_back(object->next_index);
  object->next_index = (object->next_index + 1) % static_cast<uint32_t>(object->images.size());
  return XR_SUCCESS;
}

// The images are ready at once: the compositor's read is finished before xrEndFrame returns.
XrResult XRAPI_CALL wait_swapchain_image(XrSwapchain swapchain, const XrSwapchainImageWaitInfo* wait_info) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  SwapchainObject* object = find_swapchain(table, swapchain);
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (wait_info == nullptr || wait_info->type != XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO) return XR_ERROR_VALIDATION_FAILURE;
  // The oldest acquired image is the one waited for; one waited image at a time.
  if (object->acquired.empty() || !object->waited.empty()) return XR_ERROR_CALL_ORDER_INVALID;
  object->waited.push_back(object->acquired.front());
  object->acquired.pop_front();
  return XR_SUCCESS;
}

XrResult XRAPI_CALL release_swapchain_image(XrSwapchain swapchain, const XrSwapchainImageReleaseInfo* release_info) {
  HandleTable& table = handle_table();
  std::lock_guard lock(table.mutex);
  SwapchainObject* object = find_swapchain(table, swapchain);
  if (object == nullptr) return XR_ERROR_HANDLE_INVALID;
  if (release_info != nullptr && release_info->type != XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO)
    return XR_ERROR_VALIDATION_FAILURE;
  if (object->waited.empty()) return XR_ERROR_CALL_ORDER_INVALID;  // no image waited for
  object->last_released = object->waited.front();
  object->waited.pop_front();
  return XR_SUCCESS;
}

}  // namespace fovlab::test_xr
