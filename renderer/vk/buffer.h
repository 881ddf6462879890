#pragma once
// A VkBuffer with its own memory, destroyed with it (move-only).
#include <vulkan/vulkan.h>

#include <cstddef>

namespace fovlab::vk {

class Context;

enum class MemoryUse {
  device_local,   // storage the GPU reads and writes; not mapped
  host_readback,  // host-visible, mapped: the target of copies the CPU reads
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
  VkDeviceSize size_bytes() const { return size_bytes_; }
  // Mapped host pointer of a host_readback buffer (null for device_local). Call
  // invalidate() before reading if the memory is not host-coherent.
  const void* mapped() const { return mapped_; }
  void invalidate() const;

 private:
  void release();
  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_bytes_ = 0;
  void* mapped_ = nullptr;
  bool coherent_ = true;
};

}  // namespace fovlab::vk
