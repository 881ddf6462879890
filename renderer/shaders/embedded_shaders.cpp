#include "renderer/shaders/embedded_shaders.h"

namespace fovlab::shaders {

namespace {
#include "buffer_copy.spv.h"
#include "depth_edges.spv.h"
#include "fipr_reconstruct.spv.h"
#include "list_dispatch.spv.h"
#include "fipr_mid_list.spv.h"
#include "foveation_mask.spv.h"
#include "frame_compose.spv.h"
#include "masked_blur.spv.h"
#include "min_filter.spv.h"
#include "path_trace.spv.h"
#include "pull_push.spv.h"
#include "volume_raycast.spv.h"
#include "voronoi_reconstruct.spv.h"
#include "sampling_positions.spv.h"
#include "sampling_reconstruct.spv.h"
#include "sampling_frame_read.spv.h"
#include "srgb8_encode.spv.h"
#include "upsample.spv.h"
#include "zone_band.spv.h"
#include "zone_blend.spv.h"
#include "zone_display.spv.h"
#include "sphere_trace.glsl.h"
#include "shared_gpu_types.h.h"
#include "shared_sphere_trace_params.h.h"
#include "shared_fipr_params.h.h"
#include "shared_list_dispatch_params.h.h"
#include "shared_zone_blend_params.h.h"
#include "shared_present_params.h.h"
#include "shared_sampling_params.h.h"
#include "shared_path_trace_params.h.h"
#include "shared_upsample_params.h.h"
#include "shared_volume_params.h.h"
}  // namespace

const std::span<const uint32_t> min_filter_spirv{min_filter_spirv_words};
const std::span<const uint32_t> depth_edges_spirv{depth_edges_spirv_words};
const std::span<const uint32_t> foveation_mask_spirv{foveation_mask_spirv_words};
const std::span<const uint32_t> masked_blur_spirv{masked_blur_spirv_words};
const std::span<const uint32_t> fipr_reconstruct_spirv{fipr_reconstruct_spirv_words};
const std::span<const uint32_t> upsample_spirv{upsample_spirv_words};
const std::span<const uint32_t> zone_blend_spirv{zone_blend_spirv_words};
const std::span<const uint32_t> zone_display_spirv{zone_display_spirv_words};
const std::span<const uint32_t> zone_band_spirv{zone_band_spirv_words};
const std::span<const uint32_t> srgb8_encode_spirv{srgb8_encode_spirv_words};
const std::span<const uint32_t> frame_compose_spirv{frame_compose_spirv_words};
const std::span<const uint32_t> buffer_copy_spirv{buffer_copy_spirv_words};
const std::span<const uint32_t> list_dispatch_spirv{list_dispatch_spirv_words};
const std::span<const uint32_t> fipr_mid_list_spirv{fipr_mid_list_spirv_words};
const std::span<const uint32_t> path_trace_spirv{path_trace_spirv_words};
const std::span<const uint32_t> sampling_positions_spirv{sampling_positions_spirv_words};
const std::span<const uint32_t> sampling_reconstruct_spirv{sampling_reconstruct_spirv_words};
const std::span<const uint32_t> sampling_frame_read_spirv{sampling_frame_read_spirv_words};
const std::span<const uint32_t> pull_push_spirv{pull_push_spirv_words};
const std::span<const uint32_t> volume_raycast_spirv{volume_raycast_spirv_words};
const std::span<const uint32_t> voronoi_reconstruct_spirv{voronoi_reconstruct_spirv_words};
const std::string_view sphere_trace_source{sphere_trace_text, sizeof(sphere_trace_text) - 1};

namespace {
template <size_t N>
constexpr std::string_view text_of(const char (&text)[N]) {
  return {text, N - 1};
}
const ShaderHeader kSharedHeaders[] = {
    {"shared/gpu_types.h", text_of(shared_gpu_types_text)},
    {"shared/sphere_trace_params.h", text_of(shared_sphere_trace_params_text)},
    {"shared/fipr_params.h", text_of(shared_fipr_params_text)},
    {"shared/list_dispatch_params.h", text_of(shared_list_dispatch_params_text)},
    {"shared/zone_blend_params.h", text_of(shared_zone_blend_params_text)},
    {"shared/present_params.h", text_of(shared_present_params_text)},
    {"shared/sampling_params.h", text_of(shared_sampling_params_text)},
    {"shared/path_trace_params.h", text_of(shared_path_trace_params_text)},
    {"shared/upsample_params.h", text_of(shared_upsample_params_text)},
    {"shared/volume_params.h", text_of(shared_volume_params_text)},
};
}  // namespace

const std::span<const ShaderHeader> shared_headers{kSharedHeaders};

}  // namespace fovlab::shaders
