#include "renderer/zone_blend/zone_blender.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/glm.hpp>

#include "core/input_error.h"
#include "renderer/shaders/embedded_shaders.h"
#include "renderer/shaders/shared/list_dispatch_params.h"
#include "renderer/shaders/shared/zone_blend_params.h"
#include "renderer/upsampling/upsample_filter.h"
#include "renderer/upsampling/upsampler.h"
#include "renderer/vk/compute_pipeline.h"
#include "renderer/vk/context.h"
#include "renderer/vk/image_texels.h"
#include "renderer/vk/submission.h"

namespace fovlab {

namespace {

constexpr int kMaxFrameSide = 16384;  // zone_display.comp.glsl lists band pixels as x | y << 16

using gpu::BlendParams;
constexpr gpu::ListParams kBandList{{0, 0}, 1};  // one list, counted at word 0

// tan^2 of an eccentricity bound in degrees: -1 below 0 (nothing is inside), huge from 90 on.
float tan2_of_bound(double bound_deg) {
  if (bound_deg < 0.0) return -1.0f;
  if (bound_deg >= 90.0) return 3.0e38f;
  const double t = std::tan(bound_deg * 3.14159265358979323846 / 180.0);
  return static_cast<float>(t * t);
}

// The blend of a width x height frame for a gaze point, in the eye's millimetres
// (foveation/display_geometry.h); the unit ray to the gaze point is scaled by its largest
// component first, so that a gaze far off the screen neither overflows nor loses its direction. A
// gaze that is not a number: every pixel foveal (edges at 90 degrees, no band, no middle zone; the
// rays do not matter then).
BlendParams blend_params(int width, int height, const DisplayGeometry& display, double gaze_x_px, double gaze_y_px,
                         const ZoneBounds& bounds) {
  BlendParams params{};
  params.frame_size[0] = uint32_t(width);
  params.frame_size[1] = uint32_t(height);
  params.gaze_direction[2] = 1.0f;
  params.viewing_distance_mm = 1.0f;
  for (float& edge : params.edge_tan2) edge = tan2_of_bound(90.0);
  if (!std::isfinite(gaze_x_px) || !std::isfinite(gaze_y_px)) return params;
  const double pitch_x = display.pixel_pitch_x_mm(), pitch_y = display.pixel_pitch_y_mm();
  params.pixel_pitch_mm[0] = static_cast<float>(pitch_x);
  params.pixel_pitch_mm[1] = static_cast<float>(pitch_y);
  // Relative to the principal point (width / 2, height / 2 on a display viewed square-on).
  const double principal_x_px = 0.5 * width + display.principal_offset_x_px;
  const double principal_y_px = 0.5 * height + display.principal_offset_y_px;
  params.first_pixel_mm[0] = static_cast<float>((0.5 - principal_x_px) * pitch_x);
  params.first_pixel_mm[1] = static_cast<float>((0.5 - principal_y_px) * pitch_y);
  params.viewing_distance_mm = static_cast<float>(display.viewing_distance_mm);
  glm::dvec3 gaze{(gaze_x_px - principal_x_px) * pitch_x, (gaze_y_px - principal_y_px) * pitch_y,
                  display.viewing_distance_mm};
  gaze = glm::normalize(gaze / std::max({std::fabs(gaze.x), std::fabs(gaze.y), gaze.z}));
  for (int i = 0; i < 3; ++i) params.gaze_direction[i] = static_cast<float>(gaze[i]);
  const double half_band = 0.5 * bounds.band_deg;
  params.edge_tan2[0] = tan2_of_bound(0.5 * bounds.foveal_deg - half_band);
  params.edge_tan2[1] = tan2_of_bound(0.5 * bounds.foveal_deg + half_band);
  params.edge_tan2[2] = tan2_of_bound(0.5 * bounds.middle_deg - half_band);
  params.edge_tan2[3] = tan2_of_bound(0.5 * bounds.middle_deg + half_band);
  params.band_end_deg[0] = static_cast<float>(0.5 * bounds.foveal_deg + half_band);
  params.band_end_deg[1] = static_cast<float>(0.5 * bounds.middle_deg + half_band);
  params.band_per_deg = bounds.band_deg > 0.0 ? static_cast<float>(1.0 / bounds.band_deg) : 0.0f;
  params.has_middle = bounds.middle_deg > bounds.foveal_deg ? 1u : 0u;
  return params;
}

std::unique_ptr<vk::ComputePipeline> pipeline(const vk::Context& context, std::span<const uint32_t> spirv,
                                              uint32_t storage_buffers, uint32_t push_constant_bytes) {
  return std::make_unique<vk::ComputePipeline>(context, spirv, storage_buffers, push_constant_bytes);
}

uint32_t row_groups(int width) { return gpu::row_groups(uint32_t(width)); }

// `image` as RGBA float texels in the host-visible `staging`.
void stage(const Image& image, const vk::Buffer& staging) {
  vk::pack_rgba_texels(image, static_cast<float*>(staging.mapped()));
  staging.flush();
}

vk::Buffer upload(const vk::Context& context, const Image& image) {
  vk::Buffer staging(context, VkDeviceSize(image.pixel_count()) * vk::kRgba32fTexelBytes, vk::MemoryUse::host_upload);
  stage(image, staging);
  return staging;
}

void copy_whole(VkCommandBuffer commands, const vk::Buffer& from, const vk::Buffer& to) {
  const VkBufferCopy region{0, 0, from.size_bytes()};
  vkCmdCopyBuffer(commands, from.handle(), to.handle(), 1, &region);
}

// Copies `size_bytes` from `offset_bytes` of `from` (written by a shader or a copy) to the start of
// the host-readable `to`, with the barriers on either side.
void record_read_back(VkCommandBuffer commands, const vk::Buffer& from, VkDeviceSize offset_bytes,
                      VkDeviceSize size_bytes, const vk::Buffer& to) {
  vk::memory_barrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_ACCESS_TRANSFER_READ_BIT);
  const VkBufferCopy region{offset_bytes, 0, size_bytes};
  vkCmdCopyBuffer(commands, from.handle(), to.handle(), 1, &region);
  vk::memory_barrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                     VK_ACCESS_HOST_READ_BIT);
}

std::vector<uint8_t> mapped_bytes(const vk::Buffer& readback) {
  readback.invalidate();
  const auto* bytes = static_cast<const uint8_t*>(readback.mapped());
  return std::vector<uint8_t>(bytes, bytes + readback.size_bytes());
}

void require_colour(int channels, const char* what) {
  if (channels < 3)
    throw InputError(std::string(what) + ": expected a colour frame (3 or 4 channels), not " +
                     std::to_string(channels));
}

}  // namespace

void check_zone_frame_size(const vk::Context& context, int width_px, int height_px) {
  const VkDeviceSize pixels = VkDeviceSize(width_px) * VkDeviceSize(height_px);
  if (3 * vk::kRgba32fTexelBytes * pixels > context.max_storage_buffer_bytes)
    throw InputError("zone buffers of " + std::to_string(width_px) + "x" + std::to_string(height_px) +
                     " pixels: expected at most " +
                     std::to_string(context.max_storage_buffer_bytes / (3 * vk::kRgba32fTexelBytes)) +
                     " pixels (48 bytes a pixel in one buffer of at most " +
                     std::to_string(context.max_storage_buffer_bytes >> 20) + " MiB) on " + context.description.name);
}

ZoneBlender::ZoneBlender(vk::Context& context)
    : context_(context),
      linear_pipeline_(pipeline(context, shaders::zone_blend_spirv, 2, sizeof(BlendParams))),
      encoder_(std::make_unique<Srgb8Encoder>(context)),
      display_pipeline_(pipeline(context, shaders::zone_display_spirv, 3, sizeof(BlendParams))),
      band_pipeline_(pipeline(context, shaders::zone_band_spirv, 3, sizeof(BlendParams))),
      list_dispatch_pipeline_(pipeline(context, shaders::list_dispatch_spirv, 2, sizeof(kBandList))),
      upsampler_(std::make_unique<Upsampler>(context)) {}

ZoneBlender::~ZoneBlender() = default;

double ZoneBlender::set_frame(const Image& frame, const Image* periphery) {
  if (frame.channels < 1 || frame.channels > 4 || frame.width < 1 || frame.height < 1 || frame.width > kMaxFrameSide ||
      frame.height > kMaxFrameSide)
    throw InputError("zone buffers of a " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                     " frame: expected a width and height from 1 to " + std::to_string(kMaxFrameSide) +
                     " and 1 to 4 channels");
  const Image& periphery_source = periphery ? *periphery : frame;
  if (periphery_source.width != frame.width || periphery_source.height != frame.height ||
      periphery_source.channels != frame.channels)
    throw InputError("periphery frame: expected the size and channels of the foveal frame");
  check_zone_frame_size(context_, frame.width, frame.height);  // the three zones share one buffer
  // The middle and outer zones are ceil(side / 2) and ceil(side / 4) per axis (decimate_nearest),
  // upsampled and cropped back to the frame's size: any size works, not only multiples of 4.
  const auto zone_side = [](int side, int factor) { return VkDeviceSize((side + factor - 1) / factor); };
  const VkDeviceSize frame_bytes = VkDeviceSize(frame.pixel_count()) * vk::kRgba32fTexelBytes;
  if (frame.width != width_ || frame.height != height_) {  // buffers kept from one animation frame to the next
    zones_ = vk::Buffer(context_, 3 * frame_bytes, vk::MemoryUse::device_local);
    foveal_staging_ = vk::Buffer(context_, frame_bytes, vk::MemoryUse::host_upload);
    half_staging_ =
        vk::Buffer(context_, zone_side(frame.width, 2) * zone_side(frame.height, 2) * vk::kRgba32fTexelBytes,
                   vk::MemoryUse::host_upload);
    quarter_staging_ =
        vk::Buffer(context_, zone_side(frame.width, 4) * zone_side(frame.height, 4) * vk::kRgba32fTexelBytes,
                   vk::MemoryUse::host_upload);
    // The x pass of factor 2 (the frame's width x half its height, rounded up): the larger of the two.
    upsample_scratch_ =
        vk::Buffer(context_, VkDeviceSize(frame.width) * zone_side(frame.height, 2) * vk::kRgba32fTexelBytes,
                   vk::MemoryUse::device_local);
    blended_linear_ = vk::Buffer(context_, frame_bytes, vk::MemoryUse::device_local);
    zones_srgb8_ = vk::Buffer(context_, 3 * VkDeviceSize(frame.pixel_count()) * 4, vk::MemoryUse::device_local);
    band_list_ = vk::Buffer(context_, (1 + VkDeviceSize(frame.pixel_count())) * 4, vk::MemoryUse::device_local);
    band_dispatch_ = vk::Buffer(context_, 3 * sizeof(uint32_t), vk::MemoryUse::device_local);
    blended_srgb8_ = vk::Buffer(context_, VkDeviceSize(frame.pixel_count()) * 4, vk::MemoryUse::device_local);
    blended_srgb8_readback_ = vk::Buffer(context_, blended_srgb8_.size_bytes(), vk::MemoryUse::host_readback);
    width_ = frame.width;
    height_ = frame.height;
  }
  channels_ = frame.channels;
  stage(frame, foveal_staging_);
  stage(decimate_nearest(periphery_source, 2), half_staging_);
  stage(decimate_nearest(periphery_source, 4), quarter_staging_);

  vk::OneTimeCommands commands(context_);
  VkCommandBuffer cmd = commands.handle();
  vk::PassTimer timer(context_, 5);
  timer.reset(cmd);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_WRITE_BIT,
                     VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_SHADER_READ_BIT);
  copy_whole(cmd, foveal_staging_, zones_);  // the foveal zone: the frame itself, first
  const auto w = uint32_t(frame.width), h = uint32_t(frame.height);
  const auto zone_texels = uint32_t(frame.pixel_count());
  upsampler_->record(cmd, half_staging_.handle(), upsample_scratch_.handle(), zones_.handle(), (w + 1) / 2, (h + 1) / 2,
                     2, UpsampleFilter::lanczos3, &timer, zone_texels, w, h);
  vk::compute_to_compute_barrier(cmd);  // the scratch buffer is reused
  upsampler_->record(cmd, quarter_staging_.handle(), upsample_scratch_.handle(), zones_.handle(), (w + 3) / 4,
                     (h + 3) / 4, 4, UpsampleFilter::lanczos3, &timer, 2 * zone_texels, w, h);
  if (channels_ >= 3) {  // the zones as a session shows them (display_frame copies most pixels from there)
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_ACCESS_SHADER_READ_BIT);
    timer.begin(cmd, "zones_to_srgb8");
    encoder_->record(cmd, zones_.handle(), zones_srgb8_.handle(), frame.width,
                     3 * frame.height);  // one image, three zones high
    timer.end(cmd);
  }
  commands.submit_and_wait();
  double gpu_ms = 0;
  for (const vk::PassTime& pass : timer.results()) gpu_ms += pass.gpu_ms;
  return gpu_ms;
}

void ZoneBlender::record_blend(VkCommandBuffer commands, const DisplayGeometry& display, double gaze_x_px,
                               double gaze_y_px, const ZoneBounds& bounds) const {
  const BlendParams params = blend_params(width_, height_, display, gaze_x_px, gaze_y_px, bounds);
  const VkBuffer buffers[] = {zones_.handle(), blended_linear_.handle()};
  linear_pipeline_->dispatch_groups(commands, buffers, &params, row_groups(width_), uint32_t(height_));
}

void ZoneBlender::record_display(VkCommandBuffer commands, const DisplayGeometry& display, double gaze_x_px,
                                 double gaze_y_px, const ZoneBounds& bounds) const {
  const BlendParams params = blend_params(width_, height_, display, gaze_x_px, gaze_y_px, bounds);
  // The count of an earlier display blend in this command buffer is read by its band pass and indirect dispatch.
  vk::memory_barrier(commands, VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_ACCESS_TRANSFER_WRITE_BIT);
  vkCmdFillBuffer(commands, band_list_.handle(), 0, sizeof(uint32_t), 0);  // no band pixels listed yet
  vk::memory_barrier(commands, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  const VkBuffer display_buffers[] = {zones_srgb8_.handle(), blended_srgb8_.handle(), band_list_.handle()};
  display_pipeline_->dispatch_groups(commands, display_buffers, &params, row_groups(width_), uint32_t(height_));
  vk::compute_to_compute_barrier(commands);
  const VkBuffer dispatch_buffers[] = {band_list_.handle(), band_dispatch_.handle()};
  list_dispatch_pipeline_->dispatch_2d(commands, dispatch_buffers, &kBandList, 1, 1);
  vk::memory_barrier(commands, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT);
  const VkBuffer band_buffers[] = {zones_.handle(), blended_srgb8_.handle(), band_list_.handle()};
  band_pipeline_->dispatch_indirect(commands, band_buffers, &params, band_dispatch_.handle(), 0);
}

void ZoneBlender::check_blend(const DisplayGeometry& display, const ZoneBounds& bounds) const {
  if (width_ == 0) throw std::logic_error("ZoneBlender: blend before set_frame");
  check_zone_bounds(bounds);
  if (display.width_px != width_ || display.height_px != height_)
    throw InputError("zone blend: expected a display of the frame's " + std::to_string(width_) + "x" +
                     std::to_string(height_) + " pixels");
}

ZoneBlendResult ZoneBlender::blend(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px,
                                   const ZoneBounds& bounds) {
  check_blend(display, bounds);
  if (!std::isfinite(gaze_x_px) || !std::isfinite(gaze_y_px))
    throw InputError("zone blend: expected a finite gaze point");
  vk::OneTimeCommands commands(context_);
  VkCommandBuffer cmd = commands.handle();
  vk::PassTimer timer(context_, 1);
  timer.reset(cmd);
  timer.begin(cmd, "zone_blend");
  record_blend(cmd, display, gaze_x_px, gaze_y_px, bounds);
  timer.end(cmd);
  commands.submit_and_wait();
  ZoneBlendResult result;
  result.gpu_ms = timer.results().front().gpu_ms;
  result.image = read_back(blended_linear_, 0, blended_linear_.size_bytes());
  return result;
}

std::vector<uint8_t> ZoneBlender::display_frame(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px,
                                                const ZoneBounds& bounds) {
  check_blend(display, bounds);
  require_colour(channels_, "zone blend to the display");
  vk::OneTimeCommands commands(context_);
  VkCommandBuffer cmd = commands.handle();
  record_display(cmd, display, gaze_x_px, gaze_y_px, bounds);
  record_read_back(cmd, blended_srgb8_, 0, blended_srgb8_.size_bytes(), blended_srgb8_readback_);
  commands.submit_and_wait();
  return mapped_bytes(blended_srgb8_readback_);
}

DeviceRgba8Frame ZoneBlender::display_frame_on_device(const DisplayGeometry& display, double gaze_x_px,
                                                      double gaze_y_px, const ZoneBounds& bounds) {
  check_blend(display, bounds);
  require_colour(channels_, "zone blend to the display");
  vk::OneTimeCommands commands(context_);
  record_display(commands.handle(), display, gaze_x_px, gaze_y_px, bounds);
  commands.submit_and_wait();
  return DeviceRgba8Frame{&context_, blended_srgb8_.handle(), width_, height_};
}

std::vector<uint8_t> ZoneBlender::encode_for_display(const Image& frame) {
  require_colour(frame.channels, "display encoding");
  if (VkDeviceSize(frame.pixel_count()) * vk::kRgba32fTexelBytes > context_.max_storage_buffer_bytes ||
      frame.pixel_count() == 0)
    throw InputError("display encoding of a " + std::to_string(frame.width) + "x" + std::to_string(frame.height) +
                     " frame: expected 1 to " +
                     std::to_string(context_.max_storage_buffer_bytes / vk::kRgba32fTexelBytes) + " pixels on " +
                     context_.description.name);
  const vk::Buffer texels = upload(context_, frame);  // read as the foveal zone, the only one read
  const VkDeviceSize bytes = VkDeviceSize(frame.pixel_count()) * 4;
  const vk::Buffer encoded(context_, bytes, vk::MemoryUse::device_local);
  const vk::Buffer readback(context_, bytes, vk::MemoryUse::host_readback);
  vk::OneTimeCommands commands(context_);
  VkCommandBuffer cmd = commands.handle();
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VK_ACCESS_SHADER_READ_BIT);
  encoder_->record(cmd, texels.handle(), encoded.handle(), frame.width, frame.height);
  record_read_back(cmd, encoded, 0, bytes, readback);
  commands.submit_and_wait();
  return mapped_bytes(readback);
}

Image ZoneBlender::zone_buffer(Zone zone) {
  if (width_ == 0) throw std::logic_error("ZoneBlender::zone_buffer before set_frame");
  const VkDeviceSize zone_bytes = zones_.size_bytes() / 3;
  return read_back(zones_, zone_bytes * (zone == Zone::foveal ? 0 : zone == Zone::middle ? 1 : 2), zone_bytes);
}

void ZoneBlender::check_display(const DisplayGeometry& display, const ZoneBounds& bounds) const {
  check_blend(display, bounds);
  require_colour(channels_, "zone blend to the display");
}

Image ZoneBlender::read_back(const vk::Buffer& buffer, VkDeviceSize offset_bytes, VkDeviceSize size_bytes) {
  vk::Buffer readback(context_, size_bytes, vk::MemoryUse::host_readback);
  vk::OneTimeCommands commands(context_);
  record_read_back(commands.handle(), buffer, offset_bytes, size_bytes, readback);
  commands.submit_and_wait();
  readback.invalidate();
  return vk::unpack_rgba_texels(static_cast<const float*>(readback.mapped()), width_, height_, channels_);
}

}  // namespace fovlab
