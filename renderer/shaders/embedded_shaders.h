#pragma once
// Shaders built into the binary by the build (CMakeLists.txt):
// - scene-independent passes, compiled to SPIR-V by glslangValidator at build time;
// - GLSL that is compiled at run time together with a scene (the sphere tracer), kept as text;
// - the headers in shared/ that C++ and GLSL both include, kept as text for the run-time compile.
#include <cstdint>
#include <span>
#include <string_view>

namespace fovlab::shaders {

extern const std::span<const uint32_t> min_filter_spirv;
extern const std::span<const uint32_t> depth_edges_spirv;
extern const std::span<const uint32_t> foveation_mask_spirv;
extern const std::span<const uint32_t> masked_blur_spirv;
extern const std::span<const uint32_t> fipr_reconstruct_spirv;
extern const std::span<const uint32_t> upsample_spirv;
extern const std::span<const uint32_t> zone_blend_spirv;
extern const std::span<const uint32_t> zone_display_spirv;
extern const std::span<const uint32_t> zone_band_spirv;
extern const std::span<const uint32_t> srgb8_encode_spirv;
extern const std::span<const uint32_t> frame_compose_spirv;
extern const std::span<const uint32_t> buffer_copy_spirv;
extern const std::span<const uint32_t> list_dispatch_spirv;
extern const std::span<const uint32_t> fipr_mid_list_spirv;
extern const std::span<const uint32_t> path_trace_spirv;
extern const std::span<const uint32_t> sampling_positions_spirv;
extern const std::span<const uint32_t> sampling_reconstruct_spirv;
extern const std::span<const uint32_t> sampling_frame_read_spirv;
extern const std::span<const uint32_t> pull_push_spirv;
extern const std::span<const uint32_t> volume_raycast_spirv;
extern const std::span<const uint32_t> voronoi_reconstruct_spirv;
extern const std::string_view sphere_trace_source;

// A header as GLSL includes it ("shared/fipr_params.h") and its text.
struct ShaderHeader {
  std::string_view name;
  std::string_view text;
};
extern const std::span<const ShaderHeader> shared_headers;

}  // namespace fovlab::shaders
