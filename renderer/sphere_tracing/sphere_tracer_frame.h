#pragma once
// Internal to renderer/sphere_tracing/: the buffers of one frame layout (kept between renders) and
// what one render's passes share while it is recorded. sphere_tracer.cpp records render() as a
// sequence of passes; sphere_tracer_passes.cpp holds them.
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "renderer/present/srgb8_encoder.h"
#include "renderer/shaders/shared/sphere_trace_params.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "renderer/vk/buffer.h"
#include "renderer/vk/context.h"
#include "renderer/vk/submission.h"

namespace fovlab {

// The passes' push constants (renderer/shaders/shared/), named as both sphere_tracer files use them.
using gpu::BlurParams;
using gpu::EdgeParams;
using gpu::FiprReconstructParams;
using gpu::ListParams;
using gpu::MaskParams;
using gpu::MidListParams;
using gpu::MinFilterParams;
using gpu::TraceParams;

// The counters buffer read back: one word per gpu::COUNTER_* (sphere_trace_params.h).
using CounterValues = std::array<uint32_t, gpu::COUNTER_COUNT>;

struct LevelBuffers {
  PyramidLevelStats stats;    // size and scale; steps are counted per render
  vk::Buffer depth;           // distance each ray reached (not for the top level)
  vk::Buffer start_for_next;  // min-filtered depth (not for the top level, nor without a filter)
  vk::Buffer near_depth;      // FIPR's depth levels: where the ray passed a surface within its cone, or -1
  vk::Buffer steps;
  vk::Buffer steps_readback;
};

// A headset eye's view into the tracer's push constants (eye_view 0 without one).
inline void set_eye_view(TraceParams& params, const std::optional<EyeView>& eye) {
  if (!eye) return;
  const EyeViewShaderValues values = eye_view_shader_values(*eye);
  for (int i = 0; i < 4; ++i) params.eye_tan_angles[i] = values.tan_angles[size_t(i)];
  for (int i = 0; i < 4; ++i) params.eye_orientation[i] = values.orientation[size_t(i)];
  params.eye_position = {values.position[0], values.position[1], values.position[2]};
  params.eye_view = 1u;
}

inline uint32_t ceil_div(int value, int divisor) { return static_cast<uint32_t>((value + divisor - 1) / divisor); }

// The levels a frame traces, bottom first: the pyramid's (scales ..., 4, 2, 1), and with a
// full-resolution depth level one more of scale 1 below the top. GT and the sampling models: one.
struct LevelLayout {
  int pyramid_levels = 1;
  bool full_resolution_depth = false;

  int count() const { return pyramid_levels + (full_resolution_depth ? 1 : 0); }
  int scale(int index) const { return 1 << std::max(0, pyramid_levels - 1 - index); }
  bool operator==(const LevelLayout&) const = default;
};

inline LevelLayout level_layout(const SphereTraceSettings& settings) {
  if (settings.method == TraceMethod::ground_truth || settings.method == TraceMethod::sampling_model) return {};
  return {settings.pyramid_levels, settings.method == TraceMethod::inverted_pyramid && settings.full_resolution_depth};
}

// Every buffer of one frame layout; kept between renders of the same layout, so repeated frames
// (bench repeats, a session's frames) do not allocate.
struct SphereTracer::FrameBuffers {
  int width = 0;
  int height = 0;
  LevelLayout layout;
  bool filtered = false;
  bool foveated = false;
  // FIPR: `colour` and `mid_colour` hold the frame `history_index` of a sequence rendered with
  // `history_key`; the next frame may reuse them only if it continues that sequence.
  bool history_valid = false;
  uint32_t history_index = 0;
  std::string history_key;
  std::vector<LevelBuffers> levels;  // bottom (coarsest) first
  vk::Buffer colour;
  vk::Buffer colour_readback;
  vk::Buffer display_srgb8;  // TraceOutputs::display: the shown colour, packed sRGB8
  vk::Buffer counters;
  vk::Buffer counters_readback;
  vk::Buffer unused;        // bound where a pass has no such buffer
  vk::Buffer sample_depth;  // GT's one-step floor: where each sample's trace stopped (made when first needed)
  // FIPR only.
  vk::Buffer edges;  // low level: 0 or 1
  vk::Buffer edge_depth;  // low level: its centre ray's depth, which the edges read under the cone (EdgeDepth)
  vk::Buffer mask;   // full resolution: 0 or 1
  vk::Buffer mask_readback;
  vk::Buffer masked_list;        // full-resolution pixel indices of the masked pixels (COUNTER_MASKED_PIXELS of them)
  vk::Buffer refresh_list;       // and of the unmasked pixels due for a refresh, when the periphery is traced
  vk::Buffer list_dispatch;      // workgroup counts of the top level's passes over the two lists
  vk::Buffer mid_list;           // mid level: the pixels traced (fipr_mid_list.comp.glsl's entries)
  vk::Buffer mid_list_dispatch;  // workgroup counts of the mid level's pass over its list
  vk::Buffer mid_flags;          // mid level: masked children | children << 4
  vk::Buffer mid_colour;         // mid level: shaded colour of pixels due for a refresh
  vk::Buffer blurred;            // full resolution: pass 5's output

  FrameBuffers(const vk::Context& context, int width_px, int height_px, LevelLayout level_layout, bool with_filter,
               bool with_foveation)
      : width(width_px),
        height(height_px),
        layout(level_layout),
        filtered(with_filter),
        foveated(with_foveation),
        levels(static_cast<size_t>(level_layout.count())) {
    const int level_count = layout.count();
    for (int i = 0; i < level_count; ++i) {
      LevelBuffers& level = levels[static_cast<size_t>(i)];
      level.stats.scale = layout.scale(i);
      level.stats.width = static_cast<int>(ceil_div(width, level.stats.scale));
      level.stats.height = static_cast<int>(ceil_div(height, level.stats.scale));
      const VkDeviceSize pixels = VkDeviceSize(level.stats.width) * VkDeviceSize(level.stats.height);
      level.steps = vk::Buffer(context, pixels * sizeof(uint32_t), vk::MemoryUse::device_local);
      level.steps_readback = vk::Buffer(context, pixels * sizeof(uint32_t), vk::MemoryUse::host_readback);
      if (i + 1 < level_count) {
        level.depth = vk::Buffer(context, pixels * sizeof(float), vk::MemoryUse::device_local);
        if (filtered) level.start_for_next = vk::Buffer(context, pixels * sizeof(float), vk::MemoryUse::device_local);
        if (foveated) level.near_depth = vk::Buffer(context, pixels * sizeof(float), vk::MemoryUse::device_local);
      }
    }
    const VkDeviceSize colour_bytes = VkDeviceSize(width) * VkDeviceSize(height) * 4 * sizeof(float);
    colour = vk::Buffer(context, colour_bytes, vk::MemoryUse::device_local);
    colour_readback = vk::Buffer(context, colour_bytes, vk::MemoryUse::host_readback);
    display_srgb8 = vk::Buffer(context, VkDeviceSize(width) * VkDeviceSize(height) * 4, vk::MemoryUse::device_local);
    counters = vk::Buffer(context, gpu::COUNTER_COUNT * sizeof(uint32_t), vk::MemoryUse::device_local);
    counters_readback = vk::Buffer(context, gpu::COUNTER_COUNT * sizeof(uint32_t), vk::MemoryUse::host_readback);
    unused = vk::Buffer(context, 16, vk::MemoryUse::device_local);
    if (!foveated) return;
    const auto pixels_of = [](const PyramidLevelStats& level) {
      return VkDeviceSize(level.width) * VkDeviceSize(level.height);
    };
    const VkDeviceSize frame_pixels = VkDeviceSize(width) * VkDeviceSize(height);
    const VkDeviceSize mid_pixels = pixels_of(levels[size_t(level_count - 2)].stats);
    edges = vk::Buffer(context, pixels_of(levels[0].stats) * sizeof(uint32_t), vk::MemoryUse::device_local);
    edge_depth = vk::Buffer(context, pixels_of(levels[0].stats) * sizeof(float), vk::MemoryUse::device_local);
    mask = vk::Buffer(context, frame_pixels * sizeof(uint32_t), vk::MemoryUse::device_local);
    mask_readback = vk::Buffer(context, frame_pixels * sizeof(uint32_t), vk::MemoryUse::host_readback);
    masked_list = vk::Buffer(context, frame_pixels * sizeof(uint32_t), vk::MemoryUse::device_local);
    refresh_list = vk::Buffer(context, frame_pixels * sizeof(uint32_t), vk::MemoryUse::device_local);
    list_dispatch = vk::Buffer(context, 6 * sizeof(uint32_t), vk::MemoryUse::device_local);
    mid_list = vk::Buffer(context, mid_pixels * sizeof(uint32_t), vk::MemoryUse::device_local);
    mid_list_dispatch = vk::Buffer(context, 3 * sizeof(uint32_t), vk::MemoryUse::device_local);
    mid_flags = vk::Buffer(context, mid_pixels * sizeof(uint32_t), vk::MemoryUse::device_local);
    mid_colour = vk::Buffer(context, mid_pixels * 4 * sizeof(float), vk::MemoryUse::device_local);
    blurred = vk::Buffer(context, colour_bytes, vk::MemoryUse::device_local);
  }

  // Records how the shown colour leaves the frame, after the passes: sRGB8-encoded on the device
  // (TraceOutputs::display) or copied for the host, and the counters copied; `more_copies(copy)`
  // adds the method's own copies before the host may read them.
  template <class MoreCopies>
  void record_outputs(VkCommandBuffer cmd, vk::PassTimer& timer, Srgb8Encoder& encoder, const vk::Buffer& shown,
                      bool on_device, MoreCopies&& more_copies) {
    if (on_device) {
      timer.begin(cmd, "srgb8_encode");
      encoder.record(cmd, shown.handle(), display_srgb8.handle(), width, height);
      timer.end(cmd);
    }
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    const auto copy = [&](const vk::Buffer& from, const vk::Buffer& to) {
      VkBufferCopy region{0, 0, from.size_bytes()};
      vkCmdCopyBuffer(cmd, from.handle(), to.handle(), 1, &region);
    };
    if (!on_device) copy(shown, colour_readback);
    copy(counters, counters_readback);
    more_copies(copy);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                       VK_ACCESS_HOST_READ_BIT);
  }

  // After the submit: the frame (on the device, or its linear colour read back) into `result`, and
  // the counters' values.
  CounterValues read_outputs(vk::Context& context, bool on_device, SphereTraceResult& result) const {
    if (on_device) {
      result.display = DeviceRgba8Frame{&context, display_srgb8.handle(), width, height};
    } else {
      colour_readback.invalidate();
      const auto* rgba = static_cast<const float*>(colour_readback.mapped());
      result.colour_linear = Image(width, height, 3);
      const uint64_t pixels = uint64_t(width) * uint64_t(height);
      for (uint64_t p = 0; p < pixels; ++p)
        for (int c = 0; c < 3; ++c) result.colour_linear.pixels[p * 3 + uint64_t(c)] = rgba[p * 4 + uint64_t(c)];
    }
    counters_readback.invalidate();
    CounterValues values;
    std::memcpy(values.data(), counters_readback.mapped(), sizeof(uint32_t) * gpu::COUNTER_COUNT);
    result.capped_rays = values[gpu::COUNTER_CAPPED_RAYS];
    result.restarted_rays = values[gpu::COUNTER_RESTARTED_RAYS];
    return values;
  }

  bool fits(int width_px, int height_px, LevelLayout level_layout, bool with_filter, bool with_foveation) const {
    return width == width_px && height == height_px && layout == level_layout && filtered == with_filter &&
           foveated == with_foveation;
  }
};

// Where a level's rays start: the (min-filtered) depth of the level below; none for the bottom level.
struct SphereTracer::DepthStart {
  const vk::Buffer* depth = nullptr;
  PyramidLevelStats stats;  // the level below's size and scale
};

// One render being recorded: its settings and buffers, the command buffer and its timer, and what
// the passes derive from the settings.
struct SphereTracer::FrameRecording {
  const SphereTraceSettings& settings;
  FrameBuffers& frame;
  VkCommandBuffer cmd;
  vk::PassTimer& timer;
  bool foveated;  // FIPR
  int level_count;
  int mid_index;      // FIPR's mid level, the one below the top
  int filter_radius;  // the min filter's between levels; 0: none
  bool all_due;       // FIPR: the buffers hold no history this frame continues; every pixel is refreshed
  bool near_misses;   // FIPR's depth levels track where their rays pass a surface (near depths)

  // Level `level_index`'s trace: its push constants and its buffers (sphere_trace.comp.glsl's bindings).
  gpu::TraceParams trace_params(int level_index, const DepthStart& start) const;
  std::array<VkBuffer, 11> trace_bindings(int level_index, const DepthStart& start) const;
  bool edge_depth_of_centre_ray(int level_index) const;  // FIPR's low level marches its centre ray for the edges
  // After the submit, into `result`: FIPR's counts and mask, and every level's stats and steps.
  void read_fipr_outputs(const CounterValues& counters, SphereTraceResult& result) const;
  void read_level_stats(const CounterValues& counters, SphereTraceResult& result) const;
};

}  // namespace fovlab
