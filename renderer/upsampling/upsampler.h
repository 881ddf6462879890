#pragma once
// The zone-buffer upsampling of renderer/upsampling/upsample_filter.h on the GPU: two compute
// passes (along x, then y) of renderer/shaders/upsample.comp.glsl, each timed.
#include <memory>

#include "core/image.h"
#include "renderer/upsampling/upsample_filter.h"

namespace fovlab {

namespace vk {
class Context;
class ComputePipeline;
}  // namespace vk

struct UpsampleResult {
  Image image;        // the input's channel count, width and height times the factor
  double gpu_ms = 0;  // both passes
};

class Upsampler {
 public:
  explicit Upsampler(vk::Context& context);
  ~Upsampler();
  Upsampler(const Upsampler&) = delete;
  Upsampler& operator=(const Upsampler&) = delete;

  // factor 1 to 8 per axis; 1 to 4 channels. InputError when the output would not fit a buffer.
  UpsampleResult upsample(const Image& image, int factor, UpsampleFilter filter);

 private:
  vk::Context& context_;
  std::unique_ptr<vk::ComputePipeline> pipeline_;
};

}  // namespace fovlab
