#pragma once
// The one sRGB encoder of what a participant sees (shaders/srgb8_encode.comp.glsl, srgb8.glsl):
// float RGBA texels, linear light, to packed sRGB8 (DeviceRgba8Frame's layout), NaN as black and
// values clipped to [0, 1]. The sphere-traced methods (SphereTracer's display output) and the path
// tracer's frames (ZoneBlender) both encode with it.
#include <memory>

#include <vulkan/vulkan.h>

namespace fovlab {

namespace vk {
class Buffer;
class ComputePipeline;
class Context;
}  // namespace vk

class Srgb8Encoder {
 public:
  explicit Srgb8Encoder(const vk::Context& context);
  ~Srgb8Encoder();
  Srgb8Encoder(const Srgb8Encoder&) = delete;
  Srgb8Encoder& operator=(const Srgb8Encoder&) = delete;

  // Records the encoding of width x height texels (16 bytes each) of `texels` into `encoded` (4 bytes
  // a texel). The caller orders it after the writes of `texels` and before the reads of `encoded`.
  void record(VkCommandBuffer commands, VkBuffer texels, VkBuffer encoded, int width, int height) const;

 private:
  std::unique_ptr<vk::ComputePipeline> pipeline_;
};

}  // namespace fovlab
