#pragma once
// A frame onto a presentation image (a swapchain image's pixels) on the GPU: centred, scaled up by
// the largest integer factor that fits (1 when none does; a frame larger than the image is cropped
// to its centre), letterboxed with opaque black, and written in the image's byte order (RGBA or
// BGRA). shaders/frame_compose.comp.glsl does it; place_frame says where the frame lands, for the
// composer and for mapping the pointer back to frame pixels.
#include <memory>

#include <vulkan/vulkan.h>

namespace fovlab {

namespace vk {
class ComputePipeline;
class Context;
}  // namespace vk

struct FramePlacement {
  int scale = 1;
  int scaled_width = 0, scaled_height = 0;  // frame size times scale
  int src_x = 0, src_y = 0;                 // first scaled pixel shown (crop)
  int dst_x = 0, dst_y = 0;                 // where it lands in the image
  int shown_width = 0, shown_height = 0;    // the image rectangle that shows the frame
};

// Frame and image sizes in pixels, all positive.
FramePlacement place_frame(int frame_width, int frame_height, int image_width, int image_height);

class FrameComposer {
 public:
  explicit FrameComposer(const vk::Context& context);
  ~FrameComposer();
  FrameComposer(const FrameComposer&) = delete;
  FrameComposer& operator=(const FrameComposer&) = delete;

  // Records the composition of `frame` (packed RGBA8, frame_width x frame_height, read as a storage
  // buffer) into `image` (image_width x image_height uints, every pixel written), placed by
  // place_frame. The caller orders it after the frame's writes and before the image's reads.
  void record(VkCommandBuffer commands, VkBuffer frame, int frame_width, int frame_height, VkBuffer image,
              int image_width, int image_height, bool image_is_bgra) const;

 private:
  std::unique_ptr<vk::ComputePipeline> pipeline_;
};

}  // namespace fovlab
