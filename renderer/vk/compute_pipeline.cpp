#include "renderer/vk/compute_pipeline.h"

#include <stdexcept>
#include <vector>

#include "renderer/vk/check.h"
#include "renderer/vk/context.h"

namespace fovlab::vk {

namespace {
constexpr uint32_t kWorkgroupSize = 8;  // local_size_x and local_size_y of every 2-D compute shader
}

ComputePipeline::ComputePipeline(const Context& context, std::span<const uint32_t> spirv, uint32_t storage_buffer_count,
                                 uint32_t push_constant_bytes)
    : ComputePipeline(context, spirv, storage_buffer_count, 0, push_constant_bytes) {}

ComputePipeline::ComputePipeline(const Context& context, std::span<const uint32_t> spirv, uint32_t storage_buffer_count,
                                 uint32_t texel_buffer_count, uint32_t push_constant_bytes,
                                 std::span<const uint32_t> specialization)
    : context_(context),
      storage_buffer_count_(storage_buffer_count),
      texel_buffer_count_(texel_buffer_count),
      push_constant_bytes_(push_constant_bytes) {
  VkDevice device = context.device;
  VkShaderModule module = VK_NULL_HANDLE;
  try {
    std::vector<VkDescriptorSetLayoutBinding> bindings(storage_buffer_count + texel_buffer_count);
    for (uint32_t i = 0; i < bindings.size(); ++i) {
      bindings[i].binding = i;
      bindings[i].descriptorType =
          i < storage_buffer_count ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER : VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
      bindings[i].descriptorCount = 1;
      bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    }
    VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    set_info.flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR;
    set_info.bindingCount = static_cast<uint32_t>(bindings.size());
    set_info.pBindings = bindings.data();
    VK_CHECK(vkCreateDescriptorSetLayout(device, &set_info, nullptr, &set_layout_));

    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_constant_bytes};
    VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layout_info.setLayoutCount = 1;
    layout_info.pSetLayouts = &set_layout_;
    layout_info.pushConstantRangeCount = push_constant_bytes ? 1 : 0;
    layout_info.pPushConstantRanges = &range;
    VK_CHECK(vkCreatePipelineLayout(device, &layout_info, nullptr, &layout_));

    VkShaderModuleCreateInfo module_info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    module_info.codeSize = spirv.size_bytes();
    module_info.pCode = spirv.data();
    VK_CHECK(vkCreateShaderModule(device, &module_info, nullptr, &module));

    VkComputePipelineCreateInfo pipeline_info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    pipeline_info.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    pipeline_info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    pipeline_info.stage.module = module;
    pipeline_info.stage.pName = "main";
    std::vector<VkSpecializationMapEntry> constants(specialization.size());
    for (uint32_t i = 0; i < constants.size(); ++i) constants[i] = {i, i * uint32_t(sizeof(uint32_t)), sizeof(uint32_t)};
    const VkSpecializationInfo specialization_info{static_cast<uint32_t>(constants.size()), constants.data(),
                                                   specialization.size_bytes(), specialization.data()};
    if (!specialization.empty()) pipeline_info.stage.pSpecializationInfo = &specialization_info;
    pipeline_info.layout = layout_;
    VK_CHECK(vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &pipeline_info, nullptr, &pipeline_));
    vkDestroyShaderModule(device, module, nullptr);
  } catch (...) {
    if (module) vkDestroyShaderModule(device, module, nullptr);
    release();
    throw;
  }
}

void ComputePipeline::release() {
  VkDevice device = context_.device;
  if (pipeline_) vkDestroyPipeline(device, pipeline_, nullptr);
  if (layout_) vkDestroyPipelineLayout(device, layout_, nullptr);
  if (set_layout_) vkDestroyDescriptorSetLayout(device, set_layout_, nullptr);
  pipeline_ = VK_NULL_HANDLE;
  layout_ = VK_NULL_HANDLE;
  set_layout_ = VK_NULL_HANDLE;
}

ComputePipeline::~ComputePipeline() { release(); }

void ComputePipeline::bind(VkCommandBuffer commands, std::span<const VkBuffer> buffers,
                           std::span<const VkBufferView> texel_buffers, const void* push_constants) const {
  if (buffers.size() != storage_buffer_count_) throw std::logic_error("dispatch: wrong number of buffers");
  if (texel_buffers.size() != texel_buffer_count_) throw std::logic_error("dispatch: wrong number of texel buffers");
  std::vector<VkDescriptorBufferInfo> infos(buffers.size());
  std::vector<VkWriteDescriptorSet> writes(buffers.size() + texel_buffers.size());
  for (uint32_t i = 0; i < writes.size(); ++i) {
    writes[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    writes[i].dstBinding = i;
    writes[i].descriptorCount = 1;
    if (i < buffers.size()) {
      infos[i] = {buffers[i], 0, VK_WHOLE_SIZE};
      writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      writes[i].pBufferInfo = &infos[i];
    } else {
      writes[i].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
      writes[i].pTexelBufferView = &texel_buffers[i - buffers.size()];
    }
  }
  vkCmdBindPipeline(commands, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
  context_.cmd_push_descriptor_set(commands, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0,
                                   static_cast<uint32_t>(writes.size()), writes.data());
  if (push_constant_bytes_) {
    vkCmdPushConstants(commands, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, push_constant_bytes_, push_constants);
  }
}

void ComputePipeline::dispatch_2d(VkCommandBuffer commands, std::span<const VkBuffer> buffers,
                                  const void* push_constants, uint32_t width, uint32_t height) const {
  dispatch_2d(commands, buffers, {}, push_constants, width, height);
}

void ComputePipeline::dispatch_2d(VkCommandBuffer commands, std::span<const VkBuffer> buffers,
                                  std::span<const VkBufferView> texel_buffers, const void* push_constants,
                                  uint32_t width, uint32_t height) const {
  bind(commands, buffers, texel_buffers, push_constants);
  vkCmdDispatch(commands, (width + kWorkgroupSize - 1) / kWorkgroupSize, (height + kWorkgroupSize - 1) / kWorkgroupSize,
                1);
}

void ComputePipeline::dispatch_groups(VkCommandBuffer commands, std::span<const VkBuffer> buffers,
                                      const void* push_constants, uint32_t group_count_x,
                                      uint32_t group_count_y) const {
  bind(commands, buffers, {}, push_constants);
  vkCmdDispatch(commands, group_count_x, group_count_y, 1);
}

void ComputePipeline::dispatch_indirect(VkCommandBuffer commands, std::span<const VkBuffer> buffers,
                                        const void* push_constants, VkBuffer arguments, VkDeviceSize offset) const {
  bind(commands, buffers, {}, push_constants);
  vkCmdDispatchIndirect(commands, arguments, offset);
}

}  // namespace fovlab::vk
