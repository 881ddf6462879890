#pragma once
// Recording one command buffer, submitting it and waiting for it; barriers between compute passes;
// GPU timestamps around named passes.
#include <vulkan/vulkan.h>

#include <string>
#include <vector>

namespace fovlab::vk {

class Context;

// A primary command buffer in the recording state; submit_and_wait() ends, submits and blocks until
// the device has finished it. Freed on destruction.
class OneTimeCommands {
 public:
  explicit OneTimeCommands(const Context& context);
  ~OneTimeCommands();
  OneTimeCommands(const OneTimeCommands&) = delete;
  OneTimeCommands& operator=(const OneTimeCommands&) = delete;

  VkCommandBuffer handle() const { return commands_; }
  void submit_and_wait();

 private:
  const Context& context_;
  VkCommandBuffer commands_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
};

// Makes writes of earlier commands in `src_stage` visible to reads and writes in `dst_stage`.
void memory_barrier(VkCommandBuffer commands, VkPipelineStageFlags src_stage, VkAccessFlags src_access,
                    VkPipelineStageFlags dst_stage, VkAccessFlags dst_access);

// Moves a colour image (its one mip level and layer) from layout `from` to `to`, after `src_access`
// in `src_stage` and before `dst_access` in `dst_stage`.
void image_layout_barrier(VkCommandBuffer commands, VkImage image, VkImageLayout from, VkImageLayout to,
                          VkPipelineStageFlags src_stage, VkAccessFlags src_access, VkPipelineStageFlags dst_stage,
                          VkAccessFlags dst_access);

// Shorthand: compute pass -> next compute pass.
void compute_to_compute_barrier(VkCommandBuffer commands);

struct PassTime {
  std::string name;
  double gpu_ms = 0.0;
};

// Timestamps around each named pass of one command buffer. When the queue cannot write timestamps
// the passes are still listed, with gpu_ms = 0, and supported() is false.
class PassTimer {
 public:
  PassTimer(const Context& context, uint32_t max_passes);
  ~PassTimer();
  PassTimer(const PassTimer&) = delete;
  PassTimer& operator=(const PassTimer&) = delete;

  bool supported() const { return pool_ != VK_NULL_HANDLE; }
  void reset(VkCommandBuffer commands);  // record before the first begin()
  void begin(VkCommandBuffer commands, std::string name);
  void end(VkCommandBuffer commands);
  // After the command buffer has completed.
  std::vector<PassTime> results() const;

 private:
  const Context& context_;
  uint32_t max_passes_;
  VkQueryPool pool_ = VK_NULL_HANDLE;
  std::vector<std::string> names_;
};

}  // namespace fovlab::vk
