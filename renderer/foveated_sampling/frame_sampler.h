#pragma once
// Ye et al. 2022's sampling models emulated on a pre-rendered frame (path-traced stimuli), as Polychronakis et al. 2021
// emulates its foveated path tracer and as the RMFR authors' demo resamples a full frame: the
// frame is uploaded once per animation frame; for each gaze sample, SamplingPasses lists the map's
// samples, sampling_frame_read.comp.glsl gives each the frame's mean over its footprint (what a
// path tracer spreading the sample's paths over that footprint returns), and pass 2 rebuilds every
// screen pixel from them exactly as it does for the sphere tracer's samples.
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/image.h"
#include "foveation/sampling_map.h"
#include "renderer/foveated_sampling/sampling_passes.h"
#include "renderer/present/device_frame.h"
#include "renderer/vk/buffer.h"
#include "renderer/vk/submission.h"

namespace fovlab {

namespace vk {
class Context;
class ComputePipeline;
}  // namespace vk
class Srgb8Encoder;

// The CPU reference of one sample's read (sampling_frame_read.comp.glsl): the mean of the frame's
// colour over the square of side footprint_px (at least 1) centred on the sample, each pixel
// weighted by the area it shares with the square clipped to the frame; a square wholly off the
// frame reads the pixel-wide square at the nearest point on it. The frame's first three channels
// (missing ones 0, as the GPU's texels hold them).
std::array<float, 3> footprint_mean(const Image& frame, const ListedSample& sample);

struct FrameSamplingResult {
  Image colour_linear;      // RGB, the frame's size (resample())
  Image samples_per_pixel;  // with_samples: how many listed samples lie in each pixel
  uint64_t shaded_samples = 0;
  double gpu_ms = 0.0;
  std::vector<vk::PassTime> passes;
};

class FrameSampler {
 public:
  explicit FrameSampler(vk::Context& context);
  ~FrameSampler();
  FrameSampler(const FrameSampler&) = delete;
  FrameSampler& operator=(const FrameSampler&) = delete;

  // The frame the samples read (linear light, 1 to 4 channels), kept on the device for every map
  // until the next set_frame. InputError when it does not fit the device's largest storage buffer.
  void set_frame(const Image& frame);
  int width() const { return width_; }
  int height() const { return height_; }

  // The frame through `map` (whose screen must be the frame's size, else std::invalid_argument),
  // read back in linear light with the count of shaded samples; with_samples also reads back where
  // the samples lie.
  FrameSamplingResult resample(const SamplingMap& map, ResampleFilter filter, bool with_samples = false);
  // What a participant sees, the session's path: the same frame sRGB-encoded on the device by the
  // one encoder (renderer/present/srgb8_encoder.h), nothing read back; valid until the next call.
  DeviceRgba8Frame display_frame_on_device(const SamplingMap& map, ResampleFilter filter);

  // The passes of the last call, whose sample list and colours stay until the next (tests read them).
  const SamplingPasses& passes() const { return *passes_; }

 private:
  // Records passes 1a, 1b and 2 into colour_.
  void record_passes(VkCommandBuffer commands, vk::PassTimer& timer, const SamplingMap& map, ResampleFilter filter);
  vk::Context& context_;
  std::unique_ptr<SamplingPasses> passes_;
  std::unique_ptr<vk::ComputePipeline> read_pipeline_;
  std::unique_ptr<Srgb8Encoder> encoder_;
  int width_ = 0, height_ = 0;
  vk::Buffer frame_;          // the pre-rendered frame, RGBA float texels
  vk::Buffer counters_;       // [0]: the listed samples
  vk::Buffer colour_;         // the rebuilt frame, RGBA float texels
  vk::Buffer display_srgb8_;  // one packed RGBA8 uint a pixel
  vk::Buffer colour_readback_, counters_readback_;
};

}  // namespace fovlab
