#include "bench/blend_cost.h"

#include <cstring>

#include "renderer/shaders/embedded_shaders.h"
#include "renderer/shaders/shared/zone_blend_params.h"
#include "renderer/vk/buffer.h"
#include "renderer/vk/compute_pipeline.h"
#include "renderer/vk/context.h"
#include "renderer/vk/submission.h"
#include "renderer/zone_blend/zone_blender.h"

namespace fovlab::bench {

namespace {

// The copy shader over the first width x height float RGBA texels of `from` into `to`.
void record_copy_shader(VkCommandBuffer commands, const vk::ComputePipeline& copy, const vk::Buffer& from,
                        const vk::Buffer& to, int width, int height) {
  const gpu::CopyParams params{{uint32_t(width), uint32_t(height)}};
  const VkBuffer buffers[] = {from.handle(), to.handle()};
  copy.dispatch_groups(commands, buffers, &params, gpu::row_groups(uint32_t(width)), uint32_t(height));
}

// The band list's count (word 0) into the host-readable `to`, with the barriers on either side.
void record_band_count_read_back(VkCommandBuffer commands, const vk::Buffer& band_list, const vk::Buffer& to) {
  vk::memory_barrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_ACCESS_TRANSFER_READ_BIT);
  const VkBufferCopy region{0, 0, sizeof(uint32_t)};
  vkCmdCopyBuffer(commands, band_list.handle(), to.handle(), 1, &region);
  vk::memory_barrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                     VK_ACCESS_HOST_READ_BIT);
}

}  // namespace

std::vector<BlendCost> measure_blend_cost(ZoneBlender& blender, const DisplayGeometry& display, double gaze_x_px,
                                          double gaze_y_px, const ZoneBounds& bounds, int repeats) {
  blender.check_display(display, bounds);
  vk::Context& context = blender.context();
  const vk::ComputePipeline copy(context, shaders::buffer_copy_spirv, 2, sizeof(gpu::CopyParams));
  const vk::Buffer& zones = blender.zone_buffers();
  const vk::Buffer& linear_blend = blender.linear_blend_buffer();
  const vk::Buffer band_count_readback(context, sizeof(uint32_t), vk::MemoryUse::host_readback);
  std::vector<BlendCost> costs;
  for (int repeat = 0; repeat < repeats; ++repeat) {
    vk::OneTimeCommands commands(context);
    VkCommandBuffer cmd = commands.handle();
    vk::PassTimer timer(context, 4);
    timer.reset(cmd);
    timer.begin(cmd, "display_blend");
    blender.record_display(cmd, display, gaze_x_px, gaze_y_px, bounds);
    timer.end(cmd);
    vk::compute_to_compute_barrier(cmd);  // each timed pass alone on the device
    timer.begin(cmd, "linear_blend");
    blender.record_blend(cmd, display, gaze_x_px, gaze_y_px, bounds);
    timer.end(cmd);
    vk::compute_to_compute_barrier(cmd);  // the copies overwrite the linear blend's output
    timer.begin(cmd, "copy_shader");
    record_copy_shader(cmd, copy, zones, linear_blend, blender.width(), blender.height());  // the foveal zone
    timer.end(cmd);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    timer.begin(cmd, "copy_buffer");
    const VkBufferCopy foveal_zone{0, 0, linear_blend.size_bytes()};  // the zones' first width x height texels
    vkCmdCopyBuffer(cmd, zones.handle(), linear_blend.handle(), 1, &foveal_zone);
    timer.end(cmd);
    record_band_count_read_back(cmd, blender.band_list_buffer(), band_count_readback);
    commands.submit_and_wait();
    const std::vector<vk::PassTime> times = timer.results();
    uint32_t band_pixels = 0;
    band_count_readback.invalidate();
    std::memcpy(&band_pixels, band_count_readback.mapped(), sizeof band_pixels);
    costs.push_back({times[0].gpu_ms, times[1].gpu_ms, times[2].gpu_ms, times[3].gpu_ms, band_pixels});
  }
  return costs;
}

}  // namespace fovlab::bench
