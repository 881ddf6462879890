#include "renderer/foveated_sampling/sampling_passes.h"

#include <algorithm>
#include <cstddef>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "core/input_error.h"
#include "renderer/shaders/embedded_shaders.h"
#include "renderer/shaders/shared/list_dispatch_params.h"
#include "renderer/shaders/shared/sampling_params.h"
#include "renderer/vk/compute_pipeline.h"
#include "renderer/vk/context.h"
#include "renderer/vk/submission.h"

namespace fovlab {

namespace {

using GpuLayer = gpu::SamplingLayer;
using GpuSamplingParams = gpu::SamplingParams;
using gpu::PullPushParams;

constexpr uint32_t kHyperbolicGridWidth = 256;  // the positions pass's row length over the layers' samples

// The hyperbolic and linear models' zones: eccentricities r1 and r2 around the gaze on the display.
void set_zones(GpuSamplingParams& params, const DisplayGeometry& display, double gaze_x_px, double gaze_y_px,
               double inner_radius_deg, double outer_radius_deg) {
  params.gaze_px[0] = float(gaze_x_px);
  params.gaze_px[1] = float(gaze_y_px);
  params.pixel_pitch_mm[0] = float(display.pixel_pitch_x_mm());
  params.pixel_pitch_mm[1] = float(display.pixel_pitch_y_mm());
  params.principal_point_px[0] = float(display.principal_point_x_px());
  params.principal_point_px[1] = float(display.principal_point_y_px());
  params.viewing_distance_mm = float(display.viewing_distance_mm);
  params.inner_radius_deg = float(inner_radius_deg);
  params.outer_radius_deg = float(outer_radius_deg);
}

}  // namespace

SamplingPasses::SamplingPasses(vk::Context& context) : context_(context) {
  pull_push_pipeline_ =
      std::make_unique<vk::ComputePipeline>(context, shaders::pull_push_spirv, 2, sizeof(PullPushParams));
  list_dispatch_pipeline_ =
      std::make_unique<vk::ComputePipeline>(context, shaders::list_dispatch_spirv, 2, sizeof(gpu::ListParams));
  params_buffer_ = vk::Buffer(context, sizeof(GpuSamplingParams), vk::MemoryUse::device_local);
  dispatch_ = vk::Buffer(context, 3 * sizeof(uint32_t), vk::MemoryUse::device_local);
}

SamplingPasses::~SamplingPasses() = default;

// The buffers only grow: the hyperbolic layers' sample count changes with nearly every gaze sample,
// and a session's frames should not allocate.
void SamplingPasses::allocate(uint32_t capacity, uint64_t colour_entries) {
  capacity_ = capacity;
  if (capacity <= allocated_capacity_ && colour_entries <= colour_entries_ && list_.handle() != VK_NULL_HANDLE) return;
  allocated_capacity_ = std::max(capacity, allocated_capacity_);
  colour_entries_ = std::max(colour_entries, colour_entries_);
  const VkDeviceSize entries = std::max<VkDeviceSize>(1, allocated_capacity_);
  list_ = vk::Buffer(context_, entries * 4 * sizeof(uint32_t), vk::MemoryUse::device_local);
  list_readback_ = vk::Buffer(context_, entries * 4 * sizeof(uint32_t), vk::MemoryUse::host_readback);
  steps_ = vk::Buffer(context_, entries * sizeof(uint32_t), vk::MemoryUse::device_local);
  steps_readback_ = vk::Buffer(context_, entries * sizeof(uint32_t), vk::MemoryUse::host_readback);
  colours_view_ = vk::TexelView();  // (before the buffer it views)
  colours_ =
      vk::Buffer(context_, std::max<uint64_t>(1, colour_entries_) * 4 * sizeof(float), vk::MemoryUse::device_local);
}

void SamplingPasses::prepare(const SamplingMap& map, ResampleFilter filter) {
  GpuSamplingParams params{};
  params.resample_filter = uint32_t(filter);
  model_ = model_of(map);
  params.model = uint32_t(model_);
  screen_width_ = uint32_t(screen_width_px(map));
  screen_height_ = uint32_t(screen_height_px(map));
  params.screen_size[0] = screen_width_;
  params.screen_size[1] = screen_height_;
  uint32_t capacity = 0;
  uint64_t colour_entries = 0;
  pyramid_.clear();
  if (const auto* rmfr = std::get_if<RectangularMapping>(&map)) {
    grid_width_ = uint32_t(rmfr->buffer_width_px);
    grid_height_ = uint32_t(rmfr->buffer_height_px);
    params.gaze_share[0] = float(rmfr->x.gaze_share);
    params.gaze_share[1] = float(rmfr->y.gaze_share);
    params.focal_share[0] = float(rmfr->x.focal_share);
    params.focal_share[1] = float(rmfr->y.focal_share);
    params.gaze_px[0] = float(rmfr->x.gaze_share * screen_width_);
    params.gaze_px[1] = float(rmfr->y.gaze_share * screen_height_);
    capacity = grid_width_ * grid_height_;
  } else if (const auto* kfr = std::get_if<KernelLogPolarMapping>(&map)) {
    grid_width_ = uint32_t(kfr->buffer_width_px);
    grid_height_ = uint32_t(kfr->buffer_height_px);
    params.gaze_px[0] = float(kfr->gaze_x_px);
    params.gaze_px[1] = float(kfr->gaze_y_px);
    params.alpha = float(kfr->alpha);
    params.log_max_radius = float(kfr->log_max_radius);
    capacity = grid_width_ * grid_height_;
  } else if (const auto* layers = std::get_if<HyperbolicLayers>(&map)) {
    set_zones(params, layers->display, layers->gaze_x_px, layers->gaze_y_px, layers->inner_radius_deg,
              layers->middle_radius_deg);
    params.blend_band_deg = float(layers->blend_band_deg);
    for (size_t i = 0; i < 3; ++i) {
      const HyperbolicLayer& layer = layers->layers[i];
      GpuLayer& gpu = params.layers[i];
      gpu.origin_px[0] = float(layer.origin_x_px);
      gpu.origin_px[1] = float(layer.origin_y_px);
      gpu.pixel_size_px = float(layer.pixel_size_px);
      gpu.first_sample = capacity;
      gpu.grid_size[0] = uint32_t(layer.columns);
      gpu.grid_size[1] = uint32_t(layer.rows);
      gpu.weight_range_deg[0] = float(layer.from_deg);
      gpu.weight_range_deg[1] = float(layer.to_deg);
      capacity += uint32_t(layer.columns) * uint32_t(layer.rows);
    }
    grid_width_ = kHyperbolicGridWidth;
    grid_height_ = (capacity + kHyperbolicGridWidth - 1) / kHyperbolicGridWidth;
  } else if (const auto* linear = std::get_if<LinearFalloff>(&map)) {
    set_zones(params, linear->display, linear->gaze_x_px, linear->gaze_y_px, linear->inner_radius_deg,
              linear->outer_radius_deg);
    params.min_probability = float(linear->min_probability);
    params.seed = linear->seed;
    grid_width_ = screen_width_;
    grid_height_ = screen_height_;
    capacity = grid_width_ * grid_height_;
    // Pull-push levels, each half the one below (rounded up), down to one pixel.
    uint32_t width = screen_width_, height = screen_height_, offset = 0;
    while (true) {
      pyramid_.push_back({width, height, offset});
      offset += width * height;
      if (width == 1 && height == 1) break;
      width = (width + 1) / 2;
      height = (height + 1) / 2;
    }
    colour_entries = offset;
  }
  const uint32_t model_index = uint32_t(model_), filter_index = uint32_t(filter);
  if (model_index >= kModels || filter_index >= kFilters) throw std::logic_error("SamplingPasses: unknown model or filter");
  std::unique_ptr<vk::ComputePipeline>& positions = positions_pipelines_[model_index];
  if (!positions) {
    const uint32_t constants[] = {model_index};
    positions = std::make_unique<vk::ComputePipeline>(context_, shaders::sampling_positions_spirv, 3, 0,
                                                      sizeof(gpu::PositionParams), constants);
  }
  positions_pipeline_ = positions.get();
  reconstruct_pipeline_ = nullptr;
  if (model_ != SamplingModel::linear) {
    std::unique_ptr<vk::ComputePipeline>& reconstruct = reconstruct_pipelines_[model_index * kFilters + filter_index];
    if (!reconstruct) {
      const uint32_t constants[] = {model_index, filter_index};
      reconstruct = std::make_unique<vk::ComputePipeline>(context_, shaders::sampling_reconstruct_spirv, 2, 1,
                                                          sizeof(gpu::SamplingReconstructParams), constants);
    }
    reconstruct_pipeline_ = reconstruct.get();
  }
  params.buffer_size[0] = grid_width_;
  params.buffer_size[1] = grid_height_;
  params.sample_capacity = capacity;
  if (colour_entries == 0) colour_entries = capacity;
  allocate(capacity, colour_entries);
  if (model_ != SamplingModel::linear && colours_view_.handle() == VK_NULL_HANDLE) {
    const VkDeviceSize texels = colours_.size_bytes() / vk::kRgba32fTexelBytes;
    const VkDeviceSize most = vk::max_texel_view_texels(context_);
    if (texels > most)
      throw InputError("sampling buffer of " + std::to_string(texels) + " samples (" + sampling_model_name(model_) +
                       "): expected at most " + std::to_string(most) + " on " + context_.description.name +
                       " (maxTexelBufferElements; a smaller screen or a larger sigma fits)");
    colours_view_ = vk::TexelView(context_, colours_);
  }
  params_.resize(sizeof(params));
  std::memcpy(params_.data(), &params, sizeof(params));
}

void SamplingPasses::record_positions(VkCommandBuffer cmd, vk::PassTimer& timer, VkBuffer counters,
                                      uint32_t counter_index) {
  vkCmdUpdateBuffer(cmd, params_buffer_.handle(), 0, params_.size(), params_.data());
  vkCmdFillBuffer(cmd, colours_.handle(), 0, VK_WHOLE_SIZE, 0);
  vkCmdFillBuffer(cmd, steps_.handle(), 0, VK_WHOLE_SIZE, 0);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  const VkBuffer buffers[] = {params_buffer_.handle(), counters, list_.handle()};
  timer.begin(cmd, "sample_positions");
  const gpu::PositionParams positions{counter_index};
  positions_pipeline_->dispatch_2d(cmd, buffers, &positions, grid_width_, grid_height_);
  timer.end(cmd);
  vk::compute_to_compute_barrier(cmd);
  const VkBuffer dispatch_buffers[] = {counters, dispatch_.handle()};
  const gpu::ListParams lists{{counter_index, 0}, 1};
  list_dispatch_pipeline_->dispatch_2d(cmd, dispatch_buffers, &lists, 1, 1);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT);
}

void SamplingPasses::record_reconstruct(VkCommandBuffer cmd, vk::PassTimer& timer, VkBuffer frame_colour) {
  if (model_ != SamplingModel::linear) {
    const VkBuffer buffers[] = {params_buffer_.handle(), frame_colour};
    const VkBufferView texel_buffers[] = {colours_view_.handle()};
    const gpu::SamplingReconstructParams reconstruct{0};
    timer.begin(cmd, "sample_reconstruct");
    reconstruct_pipeline_->dispatch_2d(cmd, buffers, texel_buffers, &reconstruct, screen_width_, screen_height_);
    timer.end(cmd);
    vk::compute_to_compute_barrier(cmd);
    return;
  }
  const VkBuffer buffers[] = {colours_.handle(), frame_colour};
  timer.begin(cmd, "pull_push");
  for (size_t i = 0; i + 1 < pyramid_.size(); ++i) {
    const PullPushLevel& fine = pyramid_[i];
    const PullPushLevel& coarse = pyramid_[i + 1];
    PullPushParams pull{{fine.width, fine.height}, {coarse.width, coarse.height}, fine.offset, coarse.offset, 0};
    pull_push_pipeline_->dispatch_2d(cmd, buffers, &pull, coarse.width, coarse.height);
    vk::compute_to_compute_barrier(cmd);
  }
  for (size_t i = pyramid_.size() - 1; i-- > 0;) {
    const PullPushLevel& fine = pyramid_[i];
    const PullPushLevel& coarse = pyramid_[i + 1];
    PullPushParams push{
        {fine.width, fine.height}, {coarse.width, coarse.height}, fine.offset, coarse.offset, i == 0 ? 2u : 1u};
    pull_push_pipeline_->dispatch_2d(cmd, buffers, &push, fine.width, fine.height);
    vk::compute_to_compute_barrier(cmd);
  }
  if (pyramid_.size() == 1) {  // a one-pixel screen: the pixel is its own sample
    VkBufferCopy region{0, 0, 4 * sizeof(float)};
    vkCmdCopyBuffer(cmd, colours_.handle(), frame_colour, 1, &region);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  }
  timer.end(cmd);
}

void SamplingPasses::record_readback(VkCommandBuffer cmd) {
  VkBufferCopy list_region{0, 0, VkDeviceSize(std::max<uint32_t>(capacity_, 1)) * 4 * sizeof(uint32_t)};
  vkCmdCopyBuffer(cmd, list_.handle(), list_readback_.handle(), 1, &list_region);
  VkBufferCopy steps_region{0, 0, VkDeviceSize(std::max<uint32_t>(capacity_, 1)) * sizeof(uint32_t)};
  vkCmdCopyBuffer(cmd, steps_.handle(), steps_readback_.handle(), 1, &steps_region);
}

std::vector<ListedSample> SamplingPasses::listed_samples(uint32_t count) const {
  list_readback_.invalidate();
  std::vector<ListedSample> samples(std::min(count, capacity_));
  std::memcpy(samples.data(), list_readback_.mapped(), samples.size() * sizeof(ListedSample));
  return samples;
}

std::vector<uint32_t> SamplingPasses::entry_steps() const {
  steps_readback_.invalidate();
  std::vector<uint32_t> steps(capacity_);
  std::memcpy(steps.data(), steps_readback_.mapped(), steps.size() * sizeof(uint32_t));
  return steps;
}

}  // namespace fovlab
