#include "renderer/vk/texel_view.h"

#include <stdexcept>
#include <string>
#include <utility>

#include "renderer/vk/buffer.h"
#include "renderer/vk/check.h"
#include "renderer/vk/context.h"

namespace fovlab::vk {

VkDeviceSize max_texel_view_texels(const Context& context) {
  VkPhysicalDeviceProperties properties;
  vkGetPhysicalDeviceProperties(context.physical_device, &properties);
  return properties.limits.maxTexelBufferElements;
}

TexelView::TexelView(const Context& context, const Buffer& buffer) {
  const VkDeviceSize texels = buffer.size_bytes() / kRgba32fTexelBytes;
  const VkDeviceSize most = max_texel_view_texels(context);
  if (texels == 0 || texels > most)
    throw std::invalid_argument("a texel view of " + std::to_string(texels) + " RGBA texels: expected 1 to " +
                                std::to_string(most) + " (maxTexelBufferElements)");
  VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
  info.buffer = buffer.handle();
  info.format = VK_FORMAT_R32G32B32A32_SFLOAT;
  info.offset = 0;
  info.range = texels * kRgba32fTexelBytes;
  VK_CHECK(vkCreateBufferView(context.device, &info, nullptr, &view_));
  device_ = context.device;
}

void TexelView::release() {
  if (view_) vkDestroyBufferView(device_, view_, nullptr);
  view_ = VK_NULL_HANDLE;
}

TexelView::~TexelView() { release(); }

TexelView::TexelView(TexelView&& other) noexcept { *this = std::move(other); }

TexelView& TexelView::operator=(TexelView&& other) noexcept {
  if (this != &other) {
    release();
    device_ = std::exchange(other.device_, VK_NULL_HANDLE);
    view_ = std::exchange(other.view_, VK_NULL_HANDLE);
  }
  return *this;
}

}  // namespace fovlab::vk
