#include "renderer/zone_blend/zone_blender.h"

#include <cmath>
#include <cstring>
#include <string>

#include "core/input_error.h"
#include "renderer/shaders/embedded_shaders.h"
#include "renderer/upsampling/upsample_filter.h"
#include "renderer/upsampling/upsampler.h"
#include "renderer/vk/compute_pipeline.h"
#include "renderer/vk/context.h"
#include "renderer/vk/image_texels.h"
#include "renderer/vk/submission.h"

namespace fovlab {

namespace {

// Must match BlendParams in zone_blend.comp.glsl.
struct BlendParams {
  float edge_tan2[4];
  uint32_t frame_size[2];
  float gaze_px[2];
  float pixel_pitch_mm[2];
  float viewing_distance_mm;
  float foveal_radius_deg;
  float middle_radius_deg;
  float band_deg;
  uint32_t mode;
};
static_assert(sizeof(BlendParams) == 60, "BlendParams must match zone_blend.comp.glsl");
constexpr uint32_t kModeBlend = 0, kModeCopy = 1;

// tan^2 of an eccentricity bound in degrees: -1 below 0 (nothing is inside), huge from 90 on.
float tan2_of_bound(double bound_deg) {
  if (bound_deg < 0.0) return -1.0f;
  if (bound_deg >= 90.0) return 3.0e38f;
  const double t = std::tan(bound_deg * 3.14159265358979323846 / 180.0);
  return static_cast<float>(t * t);
}
constexpr VkDeviceSize kTexelBytes = 4 * sizeof(float);

vk::Buffer upload(const vk::Context& context, const Image& image) {
  vk::Buffer staging(context, VkDeviceSize(image.pixel_count()) * kTexelBytes, vk::MemoryUse::host_upload);
  vk::pack_rgba_texels(image, static_cast<float*>(staging.mapped()));
  staging.flush();
  return staging;
}

void copy_whole(VkCommandBuffer commands, const vk::Buffer& from, const vk::Buffer& to) {
  const VkBufferCopy region{0, 0, from.size_bytes()};
  vkCmdCopyBuffer(commands, from.handle(), to.handle(), 1, &region);
}

}  // namespace

ZoneBlender::ZoneBlender(vk::Context& context)
    : context_(context),
      pipeline_(std::make_unique<vk::ComputePipeline>(context, shaders::zone_blend_spirv, 4, sizeof(BlendParams))),
      upsampler_(std::make_unique<Upsampler>(context)) {}

ZoneBlender::~ZoneBlender() = default;

double ZoneBlender::set_frame(const Image& frame, const Image* periphery) {
  if (frame.channels < 1 || frame.channels > 4 || frame.width < 4 || frame.height < 4 || frame.width % 4 != 0 ||
      frame.height % 4 != 0)
    throw InputError("zone buffers of a " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                     " frame: expected a width and height that are multiples of 4 (the outer zone is 1/4 per axis) "
                     "and 1 to 4 channels");
  const Image& periphery_source = periphery ? *periphery : frame;
  if (periphery_source.width != frame.width || periphery_source.height != frame.height ||
      periphery_source.channels != frame.channels)
    throw InputError("periphery frame: expected the size and channels of the foveal frame");
  const VkDeviceSize frame_bytes = VkDeviceSize(frame.pixel_count()) * kTexelBytes;
  if (frame_bytes > context_.max_storage_buffer_bytes)
    throw InputError("zone buffers of " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                     " pixels: expected at most " + std::to_string(context_.max_storage_buffer_bytes >> 20) +
                     " MiB a buffer on " + context_.description.name);
  if (frame.width != width_ || frame.height != height_) {
    foveal_ = vk::Buffer(context_, frame_bytes, vk::MemoryUse::device_local);
    middle_ = vk::Buffer(context_, frame_bytes, vk::MemoryUse::device_local);
    outer_ = vk::Buffer(context_, frame_bytes, vk::MemoryUse::device_local);
    blended_ = vk::Buffer(context_, frame_bytes, vk::MemoryUse::device_local);
    width_ = frame.width;
    height_ = frame.height;
  }
  channels_ = frame.channels;

  const Image half = decimate_nearest(periphery_source, 2);
  const Image quarter = decimate_nearest(periphery_source, 4);
  const vk::Buffer foveal_staging = upload(context_, frame);
  const vk::Buffer half_staging = upload(context_, half);
  const vk::Buffer quarter_staging = upload(context_, quarter);
  const vk::Buffer scratch(context_, frame_bytes / 2, vk::MemoryUse::device_local);  // the x pass of factor 2
  const auto weights_for = [&](int factor) {
    const std::vector<float> table = upsample_cell_weights(UpsampleFilter::lanczos3, factor);
    vk::Buffer weights(context_, table.size() * sizeof(float), vk::MemoryUse::host_upload);
    std::memcpy(weights.mapped(), table.data(), table.size() * sizeof(float));
    weights.flush();
    return weights;
  };
  const vk::Buffer weights_2 = weights_for(2), weights_4 = weights_for(4);

  vk::OneTimeCommands commands(context_);
  VkCommandBuffer cmd = commands.handle();
  vk::PassTimer timer(context_, 4);
  timer.reset(cmd);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_WRITE_BIT,
                     VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_SHADER_READ_BIT);
  copy_whole(cmd, foveal_staging, foveal_);
  const auto w = uint32_t(frame.width), h = uint32_t(frame.height);
  upsampler_->record(cmd, half_staging.handle(), scratch.handle(), middle_.handle(), weights_2.handle(), w / 2, h / 2, 2,
                     &timer);
  vk::compute_to_compute_barrier(cmd);  // the scratch buffer is reused
  upsampler_->record(cmd, quarter_staging.handle(), scratch.handle(), outer_.handle(), weights_4.handle(), w / 4, h / 4,
                     4, &timer);
  commands.submit_and_wait();
  double gpu_ms = 0;
  for (const vk::PassTime& pass : timer.results()) gpu_ms += pass.gpu_ms;
  return gpu_ms;
}

void ZoneBlender::record_blend(VkCommandBuffer commands, const DisplayGeometry& display, double gaze_x_px,
                               double gaze_y_px, const ZoneBounds& bounds, uint32_t mode) {
  BlendParams params{};
  params.frame_size[0] = uint32_t(width_);
  params.frame_size[1] = uint32_t(height_);
  params.gaze_px[0] = static_cast<float>(gaze_x_px);
  params.gaze_px[1] = static_cast<float>(gaze_y_px);
  params.pixel_pitch_mm[0] = static_cast<float>(display.pixel_pitch_x_mm());
  params.pixel_pitch_mm[1] = static_cast<float>(display.pixel_pitch_y_mm());
  params.viewing_distance_mm = static_cast<float>(display.viewing_distance_mm);
  params.foveal_radius_deg = static_cast<float>(0.5 * bounds.foveal_deg);
  params.middle_radius_deg = bounds.middle_deg > bounds.foveal_deg ? static_cast<float>(0.5 * bounds.middle_deg) : -1.0f;
  params.band_deg = static_cast<float>(bounds.band_deg);
  const double half_band = 0.5 * bounds.band_deg;
  params.edge_tan2[0] = tan2_of_bound(0.5 * bounds.foveal_deg - half_band);
  params.edge_tan2[1] = tan2_of_bound(0.5 * bounds.foveal_deg + half_band);
  params.edge_tan2[2] = tan2_of_bound(0.5 * bounds.middle_deg - half_band);
  params.edge_tan2[3] = tan2_of_bound(0.5 * bounds.middle_deg + half_band);
  params.mode = mode;
  const VkBuffer buffers[] = {foveal_.handle(), middle_.handle(), outer_.handle(), blended_.handle()};
  constexpr uint32_t kGroupWidth = 64;  // local_size_x of zone_blend.comp.glsl; one row of groups per pixel row
  pipeline_->dispatch_groups(commands, buffers, &params, (uint32_t(width_) + kGroupWidth - 1) / kGroupWidth,
                             uint32_t(height_));
}

ZoneBlendResult ZoneBlender::blend(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px,
                                   const ZoneBounds& bounds) {
  if (width_ == 0) throw std::logic_error("ZoneBlender::blend before set_frame");
  check_zone_bounds(bounds);
  if (display.width_px != width_ || display.height_px != height_)
    throw InputError("zone blend: expected a display of the frame's " + std::to_string(width_) + "x" +
                     std::to_string(height_) + " pixels");
  if (!std::isfinite(gaze_x_px) || !std::isfinite(gaze_y_px))
    throw InputError("zone blend: expected a finite gaze point");
  vk::OneTimeCommands commands(context_);
  VkCommandBuffer cmd = commands.handle();
  vk::PassTimer timer(context_, 1);
  timer.reset(cmd);
  timer.begin(cmd, "zone_blend");
  record_blend(cmd, display, gaze_x_px, gaze_y_px, bounds, kModeBlend);
  timer.end(cmd);
  commands.submit_and_wait();
  ZoneBlendResult result;
  result.gpu_ms = timer.results().front().gpu_ms;
  result.image = read_back(blended_);
  return result;
}

Image ZoneBlender::zone_buffer(Zone zone) {
  if (width_ == 0) throw std::logic_error("ZoneBlender::zone_buffer before set_frame");
  return read_back(zone == Zone::foveal ? foveal_ : zone == Zone::middle ? middle_ : outer_);
}

std::vector<ZoneBlender::BlendCost> ZoneBlender::measure_cost(const DisplayGeometry& display, double gaze_x_px,
                                                              double gaze_y_px, const ZoneBounds& bounds, int repeats) {
  if (width_ == 0) throw std::logic_error("ZoneBlender::measure_cost before set_frame");
  std::vector<BlendCost> costs;
  for (int repeat = 0; repeat < repeats; ++repeat) {
    vk::OneTimeCommands commands(context_);
    VkCommandBuffer cmd = commands.handle();
    vk::PassTimer timer(context_, 3);
    timer.reset(cmd);
    timer.begin(cmd, "zone_blend");
    record_blend(cmd, display, gaze_x_px, gaze_y_px, bounds, kModeBlend);
    timer.end(cmd);
    vk::compute_to_compute_barrier(cmd);
    timer.begin(cmd, "copy_shader");
    record_blend(cmd, display, gaze_x_px, gaze_y_px, bounds, kModeCopy);
    timer.end(cmd);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    timer.begin(cmd, "copy_buffer");
    copy_whole(cmd, foveal_, blended_);
    timer.end(cmd);
    commands.submit_and_wait();
    const std::vector<vk::PassTime> times = timer.results();
    costs.push_back({times[0].gpu_ms, times[1].gpu_ms, times[2].gpu_ms});
  }
  return costs;
}

Image ZoneBlender::read_back(const vk::Buffer& buffer) {
  vk::Buffer readback(context_, buffer.size_bytes(), vk::MemoryUse::host_readback);
  vk::OneTimeCommands commands(context_);
  VkCommandBuffer cmd = commands.handle();
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_ACCESS_TRANSFER_READ_BIT);
  copy_whole(cmd, buffer, readback);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                     VK_ACCESS_HOST_READ_BIT);
  commands.submit_and_wait();
  readback.invalidate();
  return vk::unpack_rgba_texels(static_cast<const float*>(readback.mapped()), width_, height_, channels_);
}

}  // namespace fovlab
