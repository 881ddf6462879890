#pragma once
// The GPU passes of Ye et al. 2022's sampling models (RMFR, hyperbolic, linear, KFR; foveation/
// sampling_map.h), around whatever shades the samples:
//   1a. sampling_positions.comp.glsl lists this frame's samples (screen position, footprint, entry);
//   1b. (the caller) shades each listed sample into its entry of sample_colours(): the sphere
//       tracer traces them (SphereTracer, TraceMethod::sampling_model), or FrameSampler reads a
//       pre-rendered frame over their footprints (frame_sampler.h);
//   2.  sampling_reconstruct.comp.glsl (RMFR, KFR, hyperbolic) or pull_push.comp.glsl (linear) makes
//       every screen pixel from the shaded samples.
// Buffers are kept between frames of the same layout (a session's frames do not allocate).
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <vulkan/vulkan.h>

#include "foveation/sampling_map.h"
#include "renderer/vk/buffer.h"
#include "renderer/vk/texel_view.h"

namespace fovlab {

namespace vk {
class Context;
class ComputePipeline;
class PassTimer;
}  // namespace vk

// One listed sample, as the GPU writes it (readable with list_readback()).
struct ListedSample {
  float x_px, y_px, footprint_px;
  uint32_t entry;
};

class SamplingPasses {
 public:
  explicit SamplingPasses(vk::Context& context);
  ~SamplingPasses();
  SamplingPasses(const SamplingPasses&) = delete;
  SamplingPasses& operator=(const SamplingPasses&) = delete;

  // Sets the frame's map and pass 2's filter: their parameters for the shaders, and buffers large
  // enough for the map's samples.
  void prepare(const SamplingMap& map, ResampleFilter filter = ResampleFilter::bilinear);

  // Records pass 1a: clears the sample colours (alpha 0: not shaded), lists the samples, counting them
  // in counters[counter_index], and writes the workgroup counts of a pass over the list (64 a group)
  // into dispatch_arguments().
  void record_positions(VkCommandBuffer commands, vk::PassTimer& timer, VkBuffer counters, uint32_t counter_index);
  // Records pass 2 into `frame_colour` (RGBA float, one entry a screen pixel).
  void record_reconstruct(VkCommandBuffer commands, vk::PassTimer& timer, VkBuffer frame_colour);
  // Records the copy of the sample list and the per-entry steps to the host (list_readback()).
  void record_readback(VkCommandBuffer commands);

  VkBuffer sample_list() const { return list_.handle(); }
  VkBuffer sample_colours() const { return colours_.handle(); }
  VkBuffer sample_steps() const { return steps_.handle(); }
  VkBuffer dispatch_arguments() const { return dispatch_.handle(); }
  uint32_t sample_capacity() const { return capacity_; }
  // The first `count` listed samples and every entry's steps, after record_readback's submit.
  std::vector<ListedSample> listed_samples(uint32_t count) const;
  std::vector<uint32_t> entry_steps() const;
  // Passes record_positions and record_reconstruct time, for vk::PassTimer's size.
  static constexpr uint32_t kMaxTimedPasses = 40;

 private:
  struct PullPushLevel {
    uint32_t width, height, offset;
  };
  void allocate(uint32_t capacity, uint64_t colour_entries);
  vk::Context& context_;
  // Pass 1a's pipeline for each model and pass 2's for each model and filter, made on first use:
  // each is the shader specialised to it (its model and filter are constants there).
  static constexpr size_t kModels = 4, kFilters = 2;
  std::array<std::unique_ptr<vk::ComputePipeline>, kModels> positions_pipelines_;
  std::array<std::unique_ptr<vk::ComputePipeline>, kModels * kFilters> reconstruct_pipelines_;
  vk::ComputePipeline* positions_pipeline_ = nullptr;    // this frame's (prepare())
  vk::ComputePipeline* reconstruct_pipeline_ = nullptr;  // (none for the linear model)
  std::unique_ptr<vk::ComputePipeline> pull_push_pipeline_;
  std::unique_ptr<vk::ComputePipeline> list_dispatch_pipeline_;
  std::vector<uint8_t> params_;  // SamplingParams as the shaders read it
  SamplingModel model_ = SamplingModel::rectangular;
  uint32_t grid_width_ = 0, grid_height_ = 0;  // the positions pass's invocations
  uint32_t screen_width_ = 0, screen_height_ = 0;
  uint32_t capacity_ = 0;               // entries of this frame's sample buffer
  uint32_t allocated_capacity_ = 0;     // entries the buffers hold (they only grow)
  std::vector<PullPushLevel> pyramid_;  // linear: the pull-push levels, finest first
  vk::Buffer params_buffer_;
  vk::Buffer list_;
  vk::Buffer colours_;  // vec4 per entry (linear: and the coarser pull-push levels after them)
  vk::TexelView colours_view_;  // colours_ as pass 2 reads it (made for the models it serves)
  vk::Buffer steps_;
  vk::Buffer dispatch_;
  vk::Buffer list_readback_;
  vk::Buffer steps_readback_;
  uint64_t colour_entries_ = 0;  // allocated
};

}  // namespace fovlab
