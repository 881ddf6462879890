#include "renderer/present/frame_compose.h"

#include <algorithm>
#include <cstdint>

#include "renderer/shaders/embedded_shaders.h"
#include "renderer/shaders/shared/present_params.h"
#include "renderer/vk/compute_pipeline.h"

namespace fovlab {

using gpu::ComposeParams;

FramePlacement place_frame(int frame_width, int frame_height, int image_width, int image_height) {
  FramePlacement placement;
  placement.scale = std::max(1, std::min(image_width / frame_width, image_height / frame_height));
  placement.scaled_width = frame_width * placement.scale;
  placement.scaled_height = frame_height * placement.scale;
  auto place = [](int scaled, int image, int& src, int& dst, int& size) {
    if (scaled <= image) {
      src = 0;
      dst = (image - scaled) / 2;
      size = scaled;
    } else {  // larger than the image: its centre
      src = (scaled - image) / 2;
      dst = 0;
      size = image;
    }
  };
  place(placement.scaled_width, image_width, placement.src_x, placement.dst_x, placement.shown_width);
  place(placement.scaled_height, image_height, placement.src_y, placement.dst_y, placement.shown_height);
  return placement;
}

FrameComposer::FrameComposer(const vk::Context& context)
    : pipeline_(
          std::make_unique<vk::ComputePipeline>(context, shaders::frame_compose_spirv, 2, sizeof(ComposeParams))) {}

FrameComposer::~FrameComposer() = default;

void FrameComposer::record(VkCommandBuffer commands, VkBuffer frame, int frame_width, int frame_height, VkBuffer image,
                           int image_width, int image_height, bool image_is_bgra) const {
  const FramePlacement placement = place_frame(frame_width, frame_height, image_width, image_height);
  ComposeParams params{};
  params.frame_size[0] = uint32_t(frame_width);
  params.frame_size[1] = uint32_t(frame_height);
  params.image_size[0] = uint32_t(image_width);
  params.image_size[1] = uint32_t(image_height);
  params.shown_min[0] = placement.dst_x;
  params.shown_min[1] = placement.dst_y;
  params.shown_max[0] = placement.dst_x + placement.shown_width;
  params.shown_max[1] = placement.dst_y + placement.shown_height;
  params.offset[0] = placement.dst_x - placement.src_x;
  params.offset[1] = placement.dst_y - placement.src_y;
  params.scale = uint32_t(placement.scale);
  params.bgra = image_is_bgra ? 1u : 0u;
  const VkBuffer buffers[] = {frame, image};
  pipeline_->dispatch_2d(commands, buffers, &params, uint32_t(image_width), uint32_t(image_height));
}

}  // namespace fovlab
