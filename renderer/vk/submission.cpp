#include "renderer/vk/submission.h"

#include <stdexcept>

#include "renderer/vk/check.h"
#include "renderer/vk/context.h"

namespace fovlab::vk {

OneTimeCommands::OneTimeCommands(const Context& context) : context_(context) {
  VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  allocate.commandPool = context.command_pool;
  allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocate.commandBufferCount = 1;
  VK_CHECK(vkAllocateCommandBuffers(context.device, &allocate, &commands_));
  VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkResult result = vkCreateFence(context.device, &fence_info, nullptr, &fence_);
  if (result != VK_SUCCESS) {
    vkFreeCommandBuffers(context.device, context.command_pool, 1, &commands_);
    throw_vulkan_error("vkCreateFence", result);
  }
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_CHECK(vkBeginCommandBuffer(commands_, &begin));
}

OneTimeCommands::~OneTimeCommands() {
  vkDestroyFence(context_.device, fence_, nullptr);
  vkFreeCommandBuffers(context_.device, context_.command_pool, 1, &commands_);
}

void OneTimeCommands::submit_and_wait() {
  VK_CHECK(vkEndCommandBuffer(commands_));
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &commands_;
  VK_CHECK(vkQueueSubmit(context_.queue, 1, &submit, fence_));
  VK_CHECK(vkWaitForFences(context_.device, 1, &fence_, VK_TRUE, UINT64_MAX));
}

void memory_barrier(VkCommandBuffer commands, VkPipelineStageFlags src_stage, VkAccessFlags src_access,
                    VkPipelineStageFlags dst_stage, VkAccessFlags dst_access) {
  VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  barrier.srcAccessMask = src_access;
  barrier.dstAccessMask = dst_access;
  vkCmdPipelineBarrier(commands, src_stage, dst_stage, 0, 1, &barrier, 0, nullptr, 0, nullptr);
}

void image_layout_barrier(VkCommandBuffer commands, VkImage image, VkImageLayout from, VkImageLayout to,
                          VkPipelineStageFlags src_stage, VkAccessFlags src_access, VkPipelineStageFlags dst_stage,
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
  vkCmdPipelineBarrier(commands, src_stage, dst_stage, 0, 0, nullptr, 0, nullptr, 1, &barrier);
}

void compute_to_compute_barrier(VkCommandBuffer commands) {
  memory_barrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

PassTimer::PassTimer(const Context& context, uint32_t max_passes) : context_(context), max_passes_(max_passes) {
  if (context.timestamp_period_ns <= 0.0) return;
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = 2 * max_passes;
  VK_CHECK(vkCreateQueryPool(context.device, &info, nullptr, &pool_));
}

PassTimer::~PassTimer() {
  if (pool_) vkDestroyQueryPool(context_.device, pool_, nullptr);
}

void PassTimer::reset(VkCommandBuffer commands) {
  names_.clear();
  if (pool_) vkCmdResetQueryPool(commands, pool_, 0, 2 * max_passes_);
}

void PassTimer::begin(VkCommandBuffer commands, std::string name) {
  if (names_.size() >= max_passes_) throw std::logic_error("PassTimer: more passes than reserved");
  if (pool_) {
    // BOTTOM_OF_PIPE: written once earlier commands have finished, so a pass does not absorb the
    // tail of the one before it on a GPU that overlaps them.
    vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_,
                        2 * static_cast<uint32_t>(names_.size()));
  }
  names_.push_back(std::move(name));
}

void PassTimer::end(VkCommandBuffer commands) {
  if (names_.empty()) throw std::logic_error("PassTimer: end() without begin()");
  if (pool_) {
    vkCmdWriteTimestamp(commands, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, pool_,
                        2 * static_cast<uint32_t>(names_.size()) - 1);
  }
}

std::vector<PassTime> PassTimer::results() const {
  std::vector<PassTime> passes;
  std::vector<uint64_t> ticks(2 * names_.size());
  if (pool_ && !names_.empty()) {
    VK_CHECK(vkGetQueryPoolResults(context_.device, pool_, 0, static_cast<uint32_t>(ticks.size()),
                                   ticks.size() * sizeof(uint64_t), ticks.data(), sizeof(uint64_t),
                                   VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  }
  for (size_t i = 0; i < names_.size(); ++i) {
    const uint64_t mask =
        context_.timestamp_valid_bits >= 64 ? ~uint64_t{0} : (uint64_t{1} << context_.timestamp_valid_bits) - 1;
    const double elapsed_ticks =
        pool_ ? static_cast<double>(((ticks[2 * i + 1] & mask) - (ticks[2 * i] & mask)) & mask) : 0.0;
    passes.push_back({names_[i], elapsed_ticks * context_.timestamp_period_ns * 1e-6});
  }
  return passes;
}

}  // namespace fovlab::vk
