#pragma once
// A view of a whole Buffer as float RGBA texels, bound as a uniform texel buffer (a shader's
// samplerBuffer, read with texelFetch; ComputePipeline's texel bindings). Why: lavapipe fetches
// texels with vector gathers, where each load from a storage buffer runs lane by lane with a bounds
// check; the values read are the same floats. The buffer must outlive the view (move-only).
#include <vulkan/vulkan.h>

namespace fovlab::vk {

class Buffer;
class Context;

// maxTexelBufferElements: the most texels one view may hold on the context's device.
VkDeviceSize max_texel_view_texels(const Context& context);

class TexelView {
 public:
  TexelView() = default;
  // std::invalid_argument when the buffer holds more texels than max_texel_view_texels.
  TexelView(const Context& context, const Buffer& buffer);
  ~TexelView();
  TexelView(TexelView&& other) noexcept;
  TexelView& operator=(TexelView&& other) noexcept;
  TexelView(const TexelView&) = delete;
  TexelView& operator=(const TexelView&) = delete;

  VkBufferView handle() const { return view_; }

 private:
  void release();
  VkDevice device_ = VK_NULL_HANDLE;
  VkBufferView view_ = VK_NULL_HANDLE;
};

}  // namespace fovlab::vk
