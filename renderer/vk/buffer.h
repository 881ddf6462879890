#pragma once
// A VkBuffer with its own memory, destroyed with it (move-only).
#include <vulkan/vulkan.h>

#include <cstddef>

namespace fovlab::vk {

// One texel of the float RGBA frames the passes hand each other (vec4 in std430).
inline constexpr VkDeviceSize kRgba32fTexelBytes = 4 * sizeof(float);

class Context;

enum class MemoryUse {
  device_local,   // storage the GPU reads and writes; not mapped
  host_readback,  // host-visible, mapped, cached where possible: the target of copies the CPU reads
  host_upload,    // host-visible, mapped: the CPU writes it, the GPU copies from it
};

class Buffer {
 public:
  Buffer() = default;
  Buffer(const Context& context, VkDeviceSize size_bytes, MemoryUse use);
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  VkDevice device() const { return device_; }  // VK_NULL_HANDLE for an empty buffer
  VkDeviceSize size_bytes() const { return size_bytes_; }
  // Mapped host pointer of a host-visible buffer (null for device_local). On memory that is not
  // host-coherent, call invalidate() before reading what the GPU wrote and flush() after writing.
  void* mapped() const { return mapped_; }
  void invalidate() const;
  void flush() const;

 private:
  void release();
  VkMappedMemoryRange whole_range() const;
  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_bytes_ = 0;
  void* mapped_ = nullptr;
  bool coherent_ = true;
};

}  // namespace fovlab::vk
