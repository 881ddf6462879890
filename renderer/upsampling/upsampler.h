#pragma once
// The zone-buffer upsampling of renderer/upsampling/upsample_filter.h on the GPU: two compute
// passes (along x, then y) of renderer/shaders/upsample.comp.glsl, each timed.
#include <vulkan/vulkan.h>

#include <cstdint>
#include <map>
#include <memory>
#include <utility>

#include "core/image.h"
#include "renderer/vk/buffer.h"
#include "renderer/upsampling/upsample_filter.h"

namespace fovlab {

namespace vk {
class Context;
class ComputePipeline;
class PassTimer;
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

  // Records the two passes on device buffers of RGBA float texels: `source` (width x height) to
  // `target` (target_width x target_height; 0: the source's side times factor) through `scratch`
  // (target_width x height). A target side may be less than the source's times factor, down to
  // (side - 1) * factor + 1: the image is then cropped at its right or bottom edge, every kept pixel
  // as in the uncropped image (a zone buffer rounded up for a frame whose sides are not multiples of
  // the factor). The output starts `target_offset_texels` texels into `target`. Timed as
  // "upsample_x" and "upsample_y" when `timer` is given. The caller orders the source's writes
  // before and the target's reads after.
  void record(VkCommandBuffer commands, VkBuffer source, VkBuffer scratch, VkBuffer target, uint32_t width,
              uint32_t height, uint32_t factor, UpsampleFilter filter, vk::PassTimer* timer,
              uint32_t target_offset_texels = 0, uint32_t target_width = 0, uint32_t target_height = 0);

 private:
  // upsample_cell_weights(filter, factor) in a host-visible buffer, made once for the upsampler.
  const vk::Buffer& weights(UpsampleFilter filter, uint32_t factor);
  vk::Context& context_;
  std::unique_ptr<vk::ComputePipeline> pipeline_;
  std::map<std::pair<UpsampleFilter, uint32_t>, vk::Buffer> weights_;
};

}  // namespace fovlab
