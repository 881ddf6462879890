#include "renderer/present/device_frame.h"

#include <cstring>
#include <stdexcept>

#include "renderer/vk/buffer.h"
#include "renderer/vk/context.h"
#include "renderer/vk/submission.h"

namespace fovlab {

void copy_device_frame(const DeviceRgba8Frame& frame, const vk::Buffer& to, bool for_host) {
  vk::OneTimeCommands commands(*frame.context);
  const VkCommandBuffer cmd = commands.handle();
  // The renderer's writes of the frame (compute or transfer) before the copy reads it.
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_ACCESS_TRANSFER_READ_BIT);
  const VkBufferCopy region{0, 0, VkDeviceSize(frame.width) * VkDeviceSize(frame.height) * 4};
  vkCmdCopyBuffer(cmd, frame.buffer, to.handle(), 1, &region);
  if (for_host)
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                       VK_ACCESS_HOST_READ_BIT);
  commands.submit_and_wait();
}

Rgba8Frame read_back(const DeviceRgba8Frame& frame) {
  vk::Buffer scratch;
  return read_back(frame, scratch);
}

Rgba8Frame read_back(const DeviceRgba8Frame& frame, vk::Buffer& readback) {
  if (!frame || !frame.context || frame.width <= 0 || frame.height <= 0)
    throw std::invalid_argument("read_back: no frame on a device");
  Rgba8Frame host(frame.width, frame.height);
  if (readback.size_bytes() < host.rgba.size() || readback.device() != frame.context->device) {
    readback = vk::Buffer();
    readback = vk::Buffer(*frame.context, host.rgba.size(), vk::MemoryUse::host_readback);
  }
  copy_device_frame(frame, readback, true);
  readback.invalidate();
  std::memcpy(host.rgba.data(), readback.mapped(), host.rgba.size());
  return host;
}

}  // namespace fovlab
