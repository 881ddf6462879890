#pragma once
// A compute pipeline whose bindings are N storage buffers (set 0, bindings 0..N-1), supplied at
// dispatch time with push descriptors, and whose parameters are push constants.
#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>

namespace fovlab::vk {

class Context;

class ComputePipeline {
 public:
  ComputePipeline(const Context& context, std::span<const uint32_t> spirv, uint32_t storage_buffer_count,
                  uint32_t push_constant_bytes);
  // With texel_buffer_count uniform texel buffers (samplerBuffer; TexelView) bound after the storage
  // buffers, at bindings storage_buffer_count and up, and the shader's specialization constants
  // constant_id 0, 1, ... set to `specialization` (32-bit each; those not given keep their defaults).
  ComputePipeline(const Context& context, std::span<const uint32_t> spirv, uint32_t storage_buffer_count,
                  uint32_t texel_buffer_count, uint32_t push_constant_bytes,
                  std::span<const uint32_t> specialization = {});
  ~ComputePipeline();
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;

  // Binds the pipeline, pushes the buffers (one per binding, whole range) and the push constants,
  // and dispatches enough 8x8 workgroups to cover width x height invocations.
  void dispatch_2d(VkCommandBuffer commands, std::span<const VkBuffer> buffers, const void* push_constants,
                   uint32_t width, uint32_t height) const;
  // The same for a pipeline with texel buffers: one view per texel binding, in binding order.
  void dispatch_2d(VkCommandBuffer commands, std::span<const VkBuffer> buffers,
                   std::span<const VkBufferView> texel_buffers, const void* push_constants, uint32_t width,
                   uint32_t height) const;
  // The same with the workgroup counts given (shaders of another local size).
  void dispatch_groups(VkCommandBuffer commands, std::span<const VkBuffer> buffers, const void* push_constants,
                       uint32_t group_count_x, uint32_t group_count_y) const;
  // The same, with the workgroup counts (three uint32) read by the device from `arguments` at
  // `offset` when the dispatch runs (written by an earlier pass; see memory_barrier for the wait).
  void dispatch_indirect(VkCommandBuffer commands, std::span<const VkBuffer> buffers, const void* push_constants,
                         VkBuffer arguments, VkDeviceSize offset) const;

 private:
  void bind(VkCommandBuffer commands, std::span<const VkBuffer> buffers, std::span<const VkBufferView> texel_buffers,
            const void* push_constants) const;
  void release();
  const Context& context_;
  uint32_t storage_buffer_count_;
  uint32_t texel_buffer_count_;
  uint32_t push_constant_bytes_;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
};

}  // namespace fovlab::vk
