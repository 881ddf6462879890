#include "renderer/foveated_sampling/frame_sampler.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "core/input_error.h"
#include "renderer/present/srgb8_encoder.h"
#include "renderer/shaders/embedded_shaders.h"
#include "renderer/shaders/shared/sampling_params.h"
#include "renderer/vk/compute_pipeline.h"
#include "renderer/vk/context.h"
#include "renderer/vk/image_texels.h"

namespace fovlab {

namespace {

constexpr uint32_t kListCounter = 0;  // counters_[0] counts the sample list

using gpu::FrameReadParams;

}  // namespace

std::array<float, 3> footprint_mean(const Image& frame, const ListedSample& sample) {
  const float width = float(frame.width), height = float(frame.height);
  const float footprint = sample.footprint_px >= 1.0f ? sample.footprint_px : 1.0f;  // NaN too
  const float sample_x = std::isnan(sample.x_px) ? 0.5f : sample.x_px,
              sample_y = std::isnan(sample.y_px) ? 0.5f : sample.y_px;
  float low_x = std::max(sample_x - 0.5f * footprint, 0.0f), high_x = std::min(sample_x + 0.5f * footprint, width);
  float low_y = std::max(sample_y - 0.5f * footprint, 0.0f), high_y = std::min(sample_y + 0.5f * footprint, height);
  if (high_x <= low_x || high_y <= low_y) {
    const float x = std::clamp(sample_x, 0.5f, width - 0.5f), y = std::clamp(sample_y, 0.5f, height - 0.5f);
    low_x = x - 0.5f;
    high_x = x + 0.5f;
    low_y = y - 0.5f;
    high_y = y + 0.5f;
  }
  std::array<double, 3> sum{};
  double weight_sum = 0.0;
  const int last_x = std::min(int(std::ceil(high_x)) - 1, frame.width - 1);
  const int last_y = std::min(int(std::ceil(high_y)) - 1, frame.height - 1);
  for (int y = int(std::floor(low_y)); y <= last_y; ++y) {
    const double wy = std::min<double>(high_y, y + 1) - std::max<double>(low_y, y);
    if (wy <= 0.0) continue;
    for (int x = int(std::floor(low_x)); x <= last_x; ++x) {
      const double wx = std::min<double>(high_x, x + 1) - std::max<double>(low_x, x);
      if (wx <= 0.0) continue;
      for (int c = 0; c < std::min(frame.channels, 3); ++c) sum[size_t(c)] += wx * wy * frame.at(x, y, c);
      weight_sum += wx * wy;
    }
  }
  if (!(weight_sum > 0.0)) return {0.0f, 0.0f, 0.0f};
  return {float(sum[0] / weight_sum), float(sum[1] / weight_sum), float(sum[2] / weight_sum)};
}

FrameSampler::FrameSampler(vk::Context& context)
    : context_(context),
      passes_(std::make_unique<SamplingPasses>(context)),
      read_pipeline_(std::make_unique<vk::ComputePipeline>(context, shaders::sampling_frame_read_spirv, 4,
                                                           sizeof(FrameReadParams))),
      encoder_(std::make_unique<Srgb8Encoder>(context)),
      counters_(context, sizeof(uint32_t), vk::MemoryUse::device_local),
      counters_readback_(context, sizeof(uint32_t), vk::MemoryUse::host_readback) {}

FrameSampler::~FrameSampler() = default;

void FrameSampler::set_frame(const Image& frame) {
  if (frame.channels < 1 || frame.channels > 4 || frame.pixel_count() == 0)
    throw InputError("frame of " + std::to_string(frame.width) + "x" + std::to_string(frame.height) + "x" +
                     std::to_string(frame.channels) + " to sample: expected 1 to 4 channels and at least one pixel");
  const VkDeviceSize bytes = VkDeviceSize(frame.pixel_count()) * vk::kRgba32fTexelBytes;
  if (bytes > context_.max_storage_buffer_bytes)
    throw InputError("frame of " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                     " pixels to sample: expected at most " +
                     std::to_string(context_.max_storage_buffer_bytes / vk::kRgba32fTexelBytes) +
                     " pixels (16 bytes a pixel in one buffer) on " + context_.description.name);
  if (frame.width != width_ || frame.height != height_) {  // kept from one animation frame to the next
    frame_ = vk::Buffer(context_, bytes, vk::MemoryUse::device_local);
    colour_ = vk::Buffer(context_, bytes, vk::MemoryUse::device_local);
    colour_readback_ = vk::Buffer(context_, bytes, vk::MemoryUse::host_readback);
    display_srgb8_ = vk::Buffer(context_, VkDeviceSize(frame.pixel_count()) * 4, vk::MemoryUse::device_local);
    width_ = frame.width;
    height_ = frame.height;
  }
  vk::Buffer staging(context_, bytes, vk::MemoryUse::host_upload);
  vk::pack_rgba_texels(frame, static_cast<float*>(staging.mapped()));
  staging.flush();
  vk::OneTimeCommands commands(context_);
  const VkBufferCopy region{0, 0, bytes};
  vkCmdCopyBuffer(commands.handle(), staging.handle(), frame_.handle(), 1, &region);
  commands.submit_and_wait();
}

void FrameSampler::record_passes(VkCommandBuffer cmd, vk::PassTimer& timer, const SamplingMap& map,
                                 ResampleFilter filter) {
  if (width_ == 0) throw std::logic_error("FrameSampler: no frame set");
  if (screen_width_px(map) != width_ || screen_height_px(map) != height_)
    throw std::invalid_argument("FrameSampler: a map of a " + std::to_string(screen_width_px(map)) + "x" +
                                std::to_string(screen_height_px(map)) + " screen for a " + std::to_string(width_) +
                                "x" + std::to_string(height_) + " frame");
  passes_->prepare(map, filter);
  timer.reset(cmd);
  vkCmdFillBuffer(cmd, counters_.handle(), 0, VK_WHOLE_SIZE, 0);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  passes_->record_positions(cmd, timer, counters_.handle(), kListCounter);
  const FrameReadParams params{{uint32_t(width_), uint32_t(height_)}, kListCounter};
  const VkBuffer buffers[] = {counters_.handle(), passes_->sample_list(), frame_.handle(), passes_->sample_colours()};
  timer.begin(cmd, "read_frame_samples");
  read_pipeline_->dispatch_indirect(cmd, buffers, &params, passes_->dispatch_arguments(), 0);
  timer.end(cmd);
  vk::compute_to_compute_barrier(cmd);
  passes_->record_reconstruct(cmd, timer, colour_.handle());
}

FrameSamplingResult FrameSampler::resample(const SamplingMap& map, ResampleFilter filter, bool with_samples) {
  vk::OneTimeCommands commands(context_);
  VkCommandBuffer cmd = commands.handle();
  vk::PassTimer timer(context_, SamplingPasses::kMaxTimedPasses + 1);
  record_passes(cmd, timer, map, filter);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
  const VkBufferCopy colour_region{0, 0, colour_.size_bytes()};
  vkCmdCopyBuffer(cmd, colour_.handle(), colour_readback_.handle(), 1, &colour_region);
  const VkBufferCopy counter_region{0, 0, sizeof(uint32_t)};
  vkCmdCopyBuffer(cmd, counters_.handle(), counters_readback_.handle(), 1, &counter_region);
  if (with_samples) passes_->record_readback(cmd);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                     VK_ACCESS_HOST_READ_BIT);
  commands.submit_and_wait();

  FrameSamplingResult result;
  result.passes = timer.results();
  for (const vk::PassTime& pass : result.passes) result.gpu_ms += pass.gpu_ms;
  counters_readback_.invalidate();
  uint32_t listed = 0;
  std::memcpy(&listed, counters_readback_.mapped(), sizeof(listed));
  result.shaded_samples = listed;
  colour_readback_.invalidate();
  result.colour_linear =
      vk::unpack_rgba_texels(static_cast<const float*>(colour_readback_.mapped()), width_, height_, 3);
  if (with_samples) {
    result.samples_per_pixel = Image(width_, height_, 1);
    for (const ListedSample& sample : passes_->listed_samples(listed)) {
      const int x = int(std::floor(sample.x_px)), y = int(std::floor(sample.y_px));
      if (x < 0 || y < 0 || x >= width_ || y >= height_) continue;  // a tap just off the screen
      result.samples_per_pixel.at(x, y, 0) += 1.0f;
    }
  }
  return result;
}

DeviceRgba8Frame FrameSampler::display_frame_on_device(const SamplingMap& map, ResampleFilter filter) {
  vk::OneTimeCommands commands(context_);
  VkCommandBuffer cmd = commands.handle();
  vk::PassTimer timer(context_, SamplingPasses::kMaxTimedPasses + 1);
  record_passes(cmd, timer, map, filter);
  encoder_->record(cmd, colour_.handle(), display_srgb8_.handle(), width_, height_);
  commands.submit_and_wait();
  return DeviceRgba8Frame{&context_, display_srgb8_.handle(), width_, height_};
}

}  // namespace fovlab
