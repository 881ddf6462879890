#pragma once
// The emulated foveated path tracer's display-rate work on the GPU (seed 001 section 3.2): a
// full-resolution linear-light frame becomes three zone buffers once per animation frame (the frame
// itself; its nearest-neighbour decimations by 2 and 4, Lanczos-3 upsampled back to full size by
// renderer/upsampling), then every gaze sample blends them (renderer/shaders/zone_blend.comp.glsl;
// reference and definitions in zone_layout.h).
#include <vulkan/vulkan.h>

#include <memory>
#include <vector>

#include "core/image.h"
#include "renderer/foveation/display_geometry.h"
#include "renderer/vk/buffer.h"
#include "renderer/zone_blend/zone_layout.h"

namespace fovlab {

namespace vk {
class Context;
class ComputePipeline;
}  // namespace vk
class Upsampler;

enum class Zone { foveal, middle, outer };

struct ZoneBlendResult {
  Image image;        // linear light, the frame's channels
  double gpu_ms = 0;  // the blend pass alone
};

class ZoneBlender {
 public:
  explicit ZoneBlender(vk::Context& context);
  ~ZoneBlender();
  ZoneBlender(const ZoneBlender&) = delete;
  ZoneBlender& operator=(const ZoneBlender&) = delete;

  // Makes the three zone buffers of a frame (1 to 4 channels). `periphery` (same size), when
  // given, is the source of the middle and outer buffers instead of the frame: seed 001's pilot
  // variant (section 4.2) whose periphery is path traced with fewer bounces. Returns the GPU ms of
  // the upsampling passes.
  double set_frame(const Image& frame, const Image* periphery = nullptr);
  int width() const { return width_; }
  int height() const { return height_; }

  // The blend for one gaze point (pixel coordinates of the frame, finite; it may lie off the
  // screen). `display` must have the frame's pixel size. InputError on a bad bound or size.
  ZoneBlendResult blend(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px, const ZoneBounds& bounds);
  // One zone buffer as the blend reads it (full size; the middle and outer ones upsampled).
  Image zone_buffer(Zone zone);

  // The cost of the blend against the memory-bandwidth limit it is measured by: a plain copy of
  // one full-size buffer into the output (every pixel read once and written once, the least the
  // blend must do). Each repeat is one command buffer holding, between GPU timestamps, the blend for
  // the gaze, the same dispatch in copy mode (same shader, same workgroups), and vkCmdCopyBuffer.
  // One entry a repeat; zeros where the queue has no timestamps.
  struct BlendCost {
    double blend_ms = 0;
    double copy_shader_ms = 0;
    double copy_buffer_ms = 0;
  };
  std::vector<BlendCost> measure_cost(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px,
                                      const ZoneBounds& bounds, int repeats);

 private:
  void record_blend(VkCommandBuffer commands, const DisplayGeometry& display, double gaze_x_px, double gaze_y_px,
                    const ZoneBounds& bounds, uint32_t mode);
  Image read_back(const vk::Buffer& buffer);
  vk::Context& context_;
  std::unique_ptr<vk::ComputePipeline> pipeline_;
  std::unique_ptr<Upsampler> upsampler_;
  int width_ = 0;
  int height_ = 0;
  int channels_ = 0;
  vk::Buffer foveal_, middle_, outer_, blended_;
};

}  // namespace fovlab
