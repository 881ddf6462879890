#include "renderer/upsampling/upsampler.h"

#include <algorithm>
#include <stdexcept>
#include <utility>
#include <vector>
#include <string>

#include "core/input_error.h"
#include "renderer/shaders/embedded_shaders.h"
#include "renderer/shaders/shared/upsample_params.h"
#include "renderer/vk/buffer.h"
#include "renderer/vk/compute_pipeline.h"
#include "renderer/vk/context.h"
#include "renderer/vk/image_texels.h"
#include "renderer/vk/submission.h"

namespace fovlab {

using gpu::UpsampleParams;

Upsampler::Upsampler(vk::Context& context)
    : context_(context),
      pipeline_(std::make_unique<vk::ComputePipeline>(context, shaders::upsample_spirv, 3, sizeof(UpsampleParams))) {}

Upsampler::~Upsampler() = default;

UpsampleResult Upsampler::upsample(const Image& image, int factor, UpsampleFilter filter) {
  if (factor < 1 || factor > 8) throw std::invalid_argument("Upsampler: factor must be 1 to 8");
  if (image.channels < 1 || image.channels > 4 || image.width < 1 || image.height < 1)
    throw std::invalid_argument("Upsampler: expected a non-empty image of 1 to 4 channels");
  const uint32_t width = uint32_t(image.width), height = uint32_t(image.height), f = uint32_t(factor);
  const VkDeviceSize texel = 4 * sizeof(float);
  const VkDeviceSize source_bytes = VkDeviceSize(width) * height * texel;
  const VkDeviceSize middle_bytes = VkDeviceSize(width) * f * height * texel;
  const VkDeviceSize target_bytes = middle_bytes * f;
  if (target_bytes > context_.max_storage_buffer_bytes) {
    throw InputError("upsampled image of " + std::to_string(width * f) + "x" + std::to_string(height * f) +
                     " pixels: expected at most " + std::to_string(context_.max_storage_buffer_bytes >> 20) +
                     " MiB in one buffer on " + context_.description.name);
  }
  vk::Buffer source(context_, source_bytes, vk::MemoryUse::host_upload);
  vk::Buffer middle(context_, middle_bytes, vk::MemoryUse::device_local);
  vk::Buffer target(context_, target_bytes, vk::MemoryUse::device_local);
  vk::Buffer readback(context_, target_bytes, vk::MemoryUse::host_readback);

  vk::pack_rgba_texels(image, static_cast<float*>(source.mapped()));
  source.flush();

  vk::OneTimeCommands commands(context_);
  VkCommandBuffer cmd = commands.handle();
  vk::PassTimer timer(context_, 2);
  timer.reset(cmd);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VK_ACCESS_SHADER_READ_BIT);
  record(cmd, source.handle(), middle.handle(), target.handle(), width, height, f, filter, &timer);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
  const VkBufferCopy region{0, 0, target_bytes};
  vkCmdCopyBuffer(cmd, target.handle(), readback.handle(), 1, &region);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                     VK_ACCESS_HOST_READ_BIT);
  commands.submit_and_wait();

  UpsampleResult result;
  for (const vk::PassTime& pass : timer.results()) result.gpu_ms += pass.gpu_ms;
  readback.invalidate();
  result.image = vk::unpack_rgba_texels(static_cast<const float*>(readback.mapped()), int(width * f), int(height * f),
                                        image.channels);
  return result;
}

const vk::Buffer& Upsampler::weights(UpsampleFilter filter, uint32_t factor) {
  auto found = weights_.find({filter, factor});
  if (found != weights_.end()) return found->second;
  const std::vector<float> table = upsample_cell_weights(filter, int(factor));
  vk::Buffer weights(context_, table.size() * sizeof(float), vk::MemoryUse::host_upload);
  std::copy(table.begin(), table.end(), static_cast<float*>(weights.mapped()));
  weights.flush();
  return weights_.emplace(std::pair{filter, factor}, std::move(weights)).first->second;
}

void Upsampler::record(VkCommandBuffer commands, VkBuffer source, VkBuffer scratch, VkBuffer target, uint32_t width,
                       uint32_t height, uint32_t factor, UpsampleFilter filter, vk::PassTimer* timer,
                       uint32_t target_offset_texels, uint32_t target_width, uint32_t target_height) {
  if (target_width == 0) target_width = width * factor;
  if (target_height == 0) target_height = height * factor;
  if (target_width > width * factor || target_height > height * factor || target_width + factor <= width * factor ||
      target_height + factor <= height * factor)
    throw std::logic_error("Upsampler::record: a target side must lie in ((side - 1) * factor, side * factor]");
  const VkBuffer weight_table = weights(filter, factor).handle();
  const auto groups = [&](uint32_t lines, uint32_t cells) {
    return std::pair{gpu::row_groups(lines), (cells + gpu::CELLS_PER_INVOCATION - 1) / gpu::CELLS_PER_INVOCATION};
  };
  // Along x: one invocation a row and run of cells.
  const UpsampleParams along_x{{width, height}, {target_width, height}, factor, 0, 0};
  const VkBuffer x_buffers[] = {source, scratch, weight_table};
  if (timer) timer->begin(commands, "upsample_x");
  const auto [x_groups, x_runs] = groups(height, width);
  pipeline_->dispatch_groups(commands, x_buffers, &along_x, x_groups, x_runs);
  if (timer) timer->end(commands);
  vk::compute_to_compute_barrier(commands);
  // Along y: one invocation a column and run of cells.
  const UpsampleParams along_y{{target_width, height}, {target_width, target_height}, factor, 1, target_offset_texels};
  const VkBuffer y_buffers[] = {scratch, target, weight_table};
  if (timer) timer->begin(commands, "upsample_y");
  const auto [y_groups, y_runs] = groups(target_width, height);
  pipeline_->dispatch_groups(commands, y_buffers, &along_y, y_groups, y_runs);
  if (timer) timer->end(commands);
}

}  // namespace fovlab
