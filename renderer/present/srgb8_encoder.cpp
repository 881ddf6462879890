#include "renderer/present/srgb8_encoder.h"

#include <cstdint>

#include "renderer/shaders/embedded_shaders.h"
#include "renderer/shaders/shared/present_params.h"
#include "renderer/vk/compute_pipeline.h"

namespace fovlab {

namespace {}

Srgb8Encoder::Srgb8Encoder(const vk::Context& context)
    : pipeline_(
          std::make_unique<vk::ComputePipeline>(context, shaders::srgb8_encode_spirv, 2, sizeof(gpu::EncodeParams))) {}

Srgb8Encoder::~Srgb8Encoder() = default;

void Srgb8Encoder::record(VkCommandBuffer commands, VkBuffer texels, VkBuffer encoded, int width, int height) const {
  const gpu::EncodeParams params{{uint32_t(width), uint32_t(height)}};
  const VkBuffer buffers[] = {texels, encoded};
  pipeline_->dispatch_groups(commands, buffers, &params, gpu::row_groups(uint32_t(width)), uint32_t(height));
}

}  // namespace fovlab
