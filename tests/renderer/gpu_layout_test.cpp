// The structs C++ fills and the shaders read (renderer/shaders/shared/*_params.h, one text included
// by both): glslang's reflection of each struct in GLSL, laid out as the shaders read it (std430,
// in a push-constant block or a storage buffer), gives the same member offsets and size as the C++
// compiler. One table, one entry per struct; a member missing from the table fails too.
#include <gtest/gtest.h>

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>

#include <algorithm>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "renderer/scene/shader_includes.h"
#include "renderer/shaders/embedded_shaders.h"
#include "renderer/shaders/shared/fipr_params.h"
#include "renderer/shaders/shared/list_dispatch_params.h"
#include "renderer/shaders/shared/path_trace_params.h"
#include "renderer/shaders/shared/present_params.h"
#include "renderer/shaders/shared/sampling_params.h"
#include "renderer/shaders/shared/sphere_trace_params.h"
#include "renderer/shaders/shared/upsample_params.h"
#include "renderer/shaders/shared/volume_params.h"
#include "renderer/shaders/shared/zone_blend_params.h"

namespace fovlab {
namespace {

enum class Block { push_constant, storage_buffer };

struct MemberLayout {
  std::string name;
  size_t offset;
};

struct StructLayout {
  std::string header;  // as GLSL includes it
  std::string name;
  Block block;  // how the shaders read it (arrays of a struct: a storage buffer)
  size_t size;
  std::vector<MemberLayout> members;
};

#define MEMBER(type, member) \
  MemberLayout { #member, offsetof(gpu::type, member) }
#define STRUCT(header, type, block, ...)                                      \
  StructLayout {                                                              \
    "shared/" header, #type, Block::block, sizeof(gpu::type), { __VA_ARGS__ } \
  }

const std::vector<StructLayout>& shared_structs() {
  static const std::vector<StructLayout> table = {
      STRUCT("sphere_trace_params.h", TraceParams, push_constant, MEMBER(TraceParams, level_size),
             MEMBER(TraceParams, start_size), MEMBER(TraceParams, frame_size), MEMBER(TraceParams, time_s),
             MEMBER(TraceParams, hit_threshold), MEMBER(TraceParams, samples_per_pixel), MEMBER(TraceParams, max_steps),
             MEMBER(TraceParams, level_scale), MEMBER(TraceParams, flags), MEMBER(TraceParams, frame_index),
             MEMBER(TraceParams, periphery_steps), MEMBER(TraceParams, eye_tan_angles),
             MEMBER(TraceParams, eye_orientation), MEMBER(TraceParams, eye_position), MEMBER(TraceParams, eye_view)),
      STRUCT("fipr_params.h", MinFilterParams, push_constant, MEMBER(MinFilterParams, size),
             MEMBER(MinFilterParams, radius)),
      STRUCT("fipr_params.h", EdgeParams, push_constant, MEMBER(EdgeParams, size),
             MEMBER(EdgeParams, relative_threshold)),
      STRUCT("fipr_params.h", MaskParams, push_constant, MEMBER(MaskParams, frame_size), MEMBER(MaskParams, mid_size),
             MEMBER(MaskParams, low_size), MEMBER(MaskParams, low_scale), MEMBER(MaskParams, combine),
             MEMBER(MaskParams, gaze_px), MEMBER(MaskParams, pixel_pitch_mm), MEMBER(MaskParams, principal_point_px),
             MEMBER(MaskParams, viewing_distance_mm), MEMBER(MaskParams, fovea_radius_deg),
             MEMBER(MaskParams, outer_periphery_radius_deg), MEMBER(MaskParams, seed), MEMBER(MaskParams, frame_index),
             MEMBER(MaskParams, flags), MEMBER(MaskParams, refresh_period)),
      STRUCT("fipr_params.h", MidListParams, push_constant, MEMBER(MidListParams, mid_size),
             MEMBER(MidListParams, start_size), MEMBER(MidListParams, min_filter_radius),
             MEMBER(MidListParams, list_counter)),
      STRUCT("fipr_params.h", FiprReconstructParams, push_constant, MEMBER(FiprReconstructParams, frame_size),
             MEMBER(FiprReconstructParams, mid_size), MEMBER(FiprReconstructParams, refresh_period),
             MEMBER(FiprReconstructParams, frame_index), MEMBER(FiprReconstructParams, catmull_rom)),
      STRUCT("fipr_params.h", BlurParams, push_constant, MEMBER(BlurParams, size)),
      STRUCT("list_dispatch_params.h", ListParams, push_constant, MEMBER(ListParams, counter_index),
             MEMBER(ListParams, list_count)),
      STRUCT("zone_blend_params.h", BlendParams, push_constant, MEMBER(BlendParams, edge_tan2),
             MEMBER(BlendParams, gaze_direction), MEMBER(BlendParams, viewing_distance_mm),
             MEMBER(BlendParams, first_pixel_mm), MEMBER(BlendParams, pixel_pitch_mm), MEMBER(BlendParams, frame_size),
             MEMBER(BlendParams, band_end_deg), MEMBER(BlendParams, band_per_deg), MEMBER(BlendParams, has_middle)),
      STRUCT("zone_blend_params.h", CopyParams, push_constant, MEMBER(CopyParams, frame_size)),
      STRUCT("present_params.h", EncodeParams, push_constant, MEMBER(EncodeParams, image_size)),
      STRUCT("present_params.h", ComposeParams, push_constant, MEMBER(ComposeParams, frame_size),
             MEMBER(ComposeParams, image_size), MEMBER(ComposeParams, shown_min), MEMBER(ComposeParams, shown_max),
             MEMBER(ComposeParams, offset), MEMBER(ComposeParams, scale), MEMBER(ComposeParams, bgra)),
      STRUCT("sampling_params.h", SamplingLayer, storage_buffer, MEMBER(SamplingLayer, origin_px),
             MEMBER(SamplingLayer, pixel_size_px), MEMBER(SamplingLayer, first_sample),
             MEMBER(SamplingLayer, grid_size), MEMBER(SamplingLayer, weight_range_deg)),
      STRUCT("sampling_params.h", SamplingParams, storage_buffer, MEMBER(SamplingParams, screen_size),
             MEMBER(SamplingParams, buffer_size), MEMBER(SamplingParams, gaze_px), MEMBER(SamplingParams, gaze_share),
             MEMBER(SamplingParams, focal_share), MEMBER(SamplingParams, pixel_pitch_mm),
             MEMBER(SamplingParams, principal_point_px), MEMBER(SamplingParams, model), MEMBER(SamplingParams, seed),
             MEMBER(SamplingParams, alpha), MEMBER(SamplingParams, log_max_radius),
             MEMBER(SamplingParams, inner_radius_deg), MEMBER(SamplingParams, outer_radius_deg),
             MEMBER(SamplingParams, blend_band_deg), MEMBER(SamplingParams, min_probability),
             MEMBER(SamplingParams, viewing_distance_mm), MEMBER(SamplingParams, sample_capacity),
             MEMBER(SamplingParams, resample_filter), MEMBER(SamplingParams, pad0), MEMBER(SamplingParams, layers)),
      STRUCT("sampling_params.h", PositionParams, push_constant, MEMBER(PositionParams, counter_index)),
      STRUCT("sampling_params.h", SamplingReconstructParams, push_constant, MEMBER(SamplingReconstructParams, unused)),
      STRUCT("sampling_params.h", PullPushParams, push_constant, MEMBER(PullPushParams, fine_size),
             MEMBER(PullPushParams, coarse_size), MEMBER(PullPushParams, fine_offset),
             MEMBER(PullPushParams, coarse_offset), MEMBER(PullPushParams, mode)),
      STRUCT("sampling_params.h", FrameReadParams, push_constant, MEMBER(FrameReadParams, frame_size),
             MEMBER(FrameReadParams, counter_index)),
      STRUCT("path_trace_params.h", PathTraceParams, push_constant, MEMBER(PathTraceParams, eye),
             MEMBER(PathTraceParams, right), MEMBER(PathTraceParams, up), MEMBER(PathTraceParams, forward),
             MEMBER(PathTraceParams, sky_radiance), MEMBER(PathTraceParams, size),
             MEMBER(PathTraceParams, sample_begin), MEMBER(PathTraceParams, sample_count),
             MEMBER(PathTraceParams, max_bounces), MEMBER(PathTraceParams, seed),
             MEMBER(PathTraceParams, emitter_count), MEMBER(PathTraceParams, flags)),
      STRUCT("path_trace_params.h", BvhNode, storage_buffer, MEMBER(BvhNode, bounds_min),
             MEMBER(BvhNode, left_or_first), MEMBER(BvhNode, bounds_max), MEMBER(BvhNode, triangle_count)),
      STRUCT("path_trace_params.h", Triangle, storage_buffer, MEMBER(Triangle, v0), MEMBER(Triangle, material),
             MEMBER(Triangle, edge1), MEMBER(Triangle, light_pdf_per_area), MEMBER(Triangle, edge2),
             MEMBER(Triangle, scene_triangle)),
      STRUCT("path_trace_params.h", Material, storage_buffer, MEMBER(Material, colour), MEMBER(Material, kind),
             MEMBER(Material, index_of_refraction), MEMBER(Material, unused0), MEMBER(Material, unused1),
             MEMBER(Material, unused2)),
      STRUCT("path_trace_params.h", Emitter, storage_buffer, MEMBER(Emitter, slot), MEMBER(Emitter, cdf),
             MEMBER(Emitter, unused0), MEMBER(Emitter, unused1)),
      STRUCT("upsample_params.h", UpsampleParams, push_constant, MEMBER(UpsampleParams, source_size),
             MEMBER(UpsampleParams, target_size), MEMBER(UpsampleParams, factor), MEMBER(UpsampleParams, axis),
             MEMBER(UpsampleParams, target_offset)),
      STRUCT("volume_params.h", VolumeRayParams, storage_buffer, MEMBER(VolumeRayParams, eye),
             MEMBER(VolumeRayParams, forward), MEMBER(VolumeRayParams, right), MEMBER(VolumeRayParams, down),
             MEMBER(VolumeRayParams, box_half), MEMBER(VolumeRayParams, voxel_scale),
             MEMBER(VolumeRayParams, volume_size), MEMBER(VolumeRayParams, brick_count),
             MEMBER(VolumeRayParams, screen), MEMBER(VolumeRayParams, mask_offset), MEMBER(VolumeRayParams, gaze),
             MEMBER(VolumeRayParams, background), MEMBER(VolumeRayParams, shading),
             MEMBER(VolumeRayParams, sites_window)),
      STRUCT("volume_params.h", VoronoiReconstructParams, push_constant, MEMBER(VoronoiReconstructParams, screen_size),
             MEMBER(VoronoiReconstructParams, mask_size), MEMBER(VoronoiReconstructParams, mask_offset),
             MEMBER(VoronoiReconstructParams, history_count), MEMBER(VoronoiReconstructParams, store_slot)),
  };
  return table;
}

#undef STRUCT
#undef MEMBER

// GLSL's layout of one struct: the offsets of its members (an array or struct member: its first
// element's) and its size, read by reflection from a block holding just that struct.
struct GlslLayout {
  std::map<std::string, size_t> offsets;
  size_t size = 0;
  std::string log;  // compile errors
};

GlslLayout reflect(const StructLayout& layout) {
  static const bool initialised = glslang::InitializeProcess();
  (void)initialised;
  const std::string block = layout.block == Block::push_constant ? "layout(push_constant) uniform Probe"
                                                                 : "layout(std430, binding = 0) buffer Probe";
  const std::string source = "#version 460\n#extension GL_GOOGLE_include_directive : require\n#include \"" +
                             layout.header + "\"\nlayout(local_size_x = 1) in;\n" + block + " { " + layout.name +
                             " probe; };\nvoid main() { " + layout.name +
                             " copy = probe; }\n";  // the block in use: reflected
  const char* text = source.c_str();
  const char* name = "probe.comp.glsl";
  const int length = int(source.size());
  glslang::TShader shader(EShLangCompute);
  shader.setStringsWithLengthsAndNames(&text, &length, &name, 1);
  shader.setEnvInput(glslang::EShSourceGlsl, EShLangCompute, glslang::EShClientVulkan, 100);
  shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_1);
  shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_3);
  const auto messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules);
  SharedHeaderIncluder includer(shaders::shared_headers);
  GlslLayout result;
  if (!shader.parse(GetDefaultResources(), 460, ENoProfile, false, false, messages, includer)) {
    result.log = shader.getInfoLog();
    return result;
  }
  glslang::TProgram program;
  program.addShader(&shader);
  if (!program.link(messages) ||
      !program.buildReflection(EShReflectionAllBlockVariables | EShReflectionSeparateBuffers)) {
    result.log = program.getInfoLog();
    return result;
  }
  const std::string prefix = "probe.";
  const auto add = [&](const glslang::TObjectReflection& variable) {
    if (variable.name.rfind(prefix, 0) != 0) return;
    const std::string member =
        variable.name.substr(prefix.size(), variable.name.find_first_of(".[", prefix.size()) - prefix.size());
    const auto [entry, added] = result.offsets.emplace(member, size_t(variable.offset));
    if (!added) entry->second = std::min(entry->second, size_t(variable.offset));
  };
  if (layout.block == Block::push_constant) {
    for (int i = 0; i < program.getNumUniformVariables(); ++i) add(program.getUniform(i));
    if (program.getNumUniformBlocks() == 1) result.size = size_t(program.getUniformBlock(0).size);
  } else {
    for (int i = 0; i < program.getNumBufferVariables(); ++i) add(program.getBufferVariable(i));
    if (program.getNumBufferBlocks() == 1) result.size = size_t(program.getBufferBlock(0).size);
  }
  return result;
}

TEST(GpuLayout, EverySharedStructHasTheSameLayoutInGlslAndCpp) {
  for (const StructLayout& layout : shared_structs()) {
    SCOPED_TRACE(layout.header + ": " + layout.name);
    const GlslLayout glsl = reflect(layout);
    ASSERT_TRUE(glsl.log.empty()) << glsl.log;
    EXPECT_EQ(glsl.size, layout.size) << "size";
    std::string reflected;
    for (const auto& [name, offset] : glsl.offsets) reflected += " " + name + "@" + std::to_string(offset);
    EXPECT_EQ(glsl.offsets.size(), layout.members.size()) << "members in GLSL:" << reflected;
    for (const MemberLayout& member : layout.members) {
      const auto found = glsl.offsets.find(member.name);
      if (found == glsl.offsets.end()) {
        ADD_FAILURE() << member.name << ": not in the GLSL struct";
        continue;
      }
      EXPECT_EQ(found->second, member.offset) << member.name;
    }
  }
}

// Every header the run-time compile may include is one of those the table covers, and back.
TEST(GpuLayout, TheTableCoversEveryParamsHeader) {
  std::vector<std::string> covered;
  for (const StructLayout& layout : shared_structs()) covered.push_back(layout.header);
  for (const shaders::ShaderHeader& header : shaders::shared_headers) {
    if (header.name == "shared/gpu_types.h") continue;
    EXPECT_NE(std::find(covered.begin(), covered.end(), header.name), covered.end()) << header.name;
  }
}

}  // namespace
}  // namespace fovlab
