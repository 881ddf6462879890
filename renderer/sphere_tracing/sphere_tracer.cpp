#include "renderer/sphere_tracing/sphere_tracer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "core/input_error.h"
#include "renderer/scene/scene_compiler.h"
#include "renderer/shaders/embedded_shaders.h"
#include "renderer/vk/buffer.h"
#include "renderer/vk/compute_pipeline.h"
#include "renderer/vk/context.h"
#include "renderer/vk/submission.h"

namespace fovlab {

namespace {

constexpr uint32_t kFlagShade = 1;
constexpr uint32_t kFlagHasStart = 2;
constexpr int kMaxFrameSide = 16384;
constexpr uint64_t kMaxSamplesPerFrame = uint64_t{1} << 28;  // keeps buffers and one submit bounded

// Must match TraceParams in sphere_trace.comp.glsl (std430 push constant layout).
struct TraceParams {
  uint32_t level_size[2];
  uint32_t start_size[2];
  float frame_size[2];
  float time_s;
  float hit_threshold;
  uint32_t samples_per_pixel;
  uint32_t max_steps;
  uint32_t level_scale;
  uint32_t flags;
};

// Must match MinFilterParams in min_filter.comp.glsl.
struct MinFilterParams {
  uint32_t size[2];
  int32_t radius;
};

struct LevelBuffers {
  PyramidLevelStats stats;    // size and scale; steps are counted per render
  vk::Buffer depth;           // distance each ray reached (not for the top level)
  vk::Buffer start_for_next;  // min-filtered depth (not for the top level, nor without a filter)
  vk::Buffer steps;
  vk::Buffer steps_readback;
};

uint32_t ceil_div(int value, int divisor) { return static_cast<uint32_t>((value + divisor - 1) / divisor); }

}  // namespace

// Every buffer of one frame layout; kept between renders of the same layout, so repeated frames
// (bench repeats, a session's frames) do not allocate.
struct SphereTracer::FrameBuffers {
  int width = 0;
  int height = 0;
  int level_count = 0;
  bool filtered = false;
  std::vector<LevelBuffers> levels;  // bottom (coarsest) first
  vk::Buffer colour;
  vk::Buffer colour_readback;
  vk::Buffer counters;
  vk::Buffer counters_readback;
  vk::Buffer unused;  // bound where a pass has no such buffer

  FrameBuffers(const vk::Context& context, int width_px, int height_px, int levels_count, bool with_filter)
      : width(width_px), height(height_px), level_count(levels_count), filtered(with_filter),
        levels(static_cast<size_t>(levels_count)) {
    for (int i = 0; i < level_count; ++i) {
      LevelBuffers& level = levels[static_cast<size_t>(i)];
      level.stats.scale = 1 << (level_count - 1 - i);
      level.stats.width = static_cast<int>(ceil_div(width, level.stats.scale));
      level.stats.height = static_cast<int>(ceil_div(height, level.stats.scale));
      const VkDeviceSize pixels = VkDeviceSize(level.stats.width) * VkDeviceSize(level.stats.height);
      level.steps = vk::Buffer(context, pixels * sizeof(uint32_t), vk::MemoryUse::device_local);
      level.steps_readback = vk::Buffer(context, pixels * sizeof(uint32_t), vk::MemoryUse::host_readback);
      if (i + 1 < level_count) {
        level.depth = vk::Buffer(context, pixels * sizeof(float), vk::MemoryUse::device_local);
        if (filtered) level.start_for_next = vk::Buffer(context, pixels * sizeof(float), vk::MemoryUse::device_local);
      }
    }
    const VkDeviceSize colour_bytes = VkDeviceSize(width) * VkDeviceSize(height) * 4 * sizeof(float);
    colour = vk::Buffer(context, colour_bytes, vk::MemoryUse::device_local);
    colour_readback = vk::Buffer(context, colour_bytes, vk::MemoryUse::host_readback);
    counters = vk::Buffer(context, 2 * sizeof(uint32_t), vk::MemoryUse::device_local);
    counters_readback = vk::Buffer(context, 2 * sizeof(uint32_t), vk::MemoryUse::host_readback);
    unused = vk::Buffer(context, 16, vk::MemoryUse::device_local);
  }

  bool fits(int width_px, int height_px, int levels_count, bool with_filter) const {
    return width == width_px && height == height_px && level_count == levels_count && filtered == with_filter;
  }
};

const char* method_name(TraceMethod method) {
  return method == TraceMethod::ground_truth ? "gt" : "ipr";
}

void validate(const SphereTraceSettings& settings) {
  auto check_side = [](int value, const char* flag) {
    if (value <= 0 || value > kMaxFrameSide) {
      throw InputError(std::string(flag) + " " + std::to_string(value) + ": expected 1 to " +
                       std::to_string(kMaxFrameSide) + " pixels");
    }
  };
  check_side(settings.width, "--width");
  check_side(settings.height, "--height");
  const int spp = settings.samples_per_pixel;
  if (spp != 1 && spp != 4 && spp != 16) {
    throw InputError("--spp " + std::to_string(spp) + ": expected 1, 4 or 16 samples per pixel");
  }
  const uint64_t samples = uint64_t(settings.width) * uint64_t(settings.height) * uint64_t(spp);
  if (samples > kMaxSamplesPerFrame) {
    throw InputError("--width x --height x --spp = " + std::to_string(samples) + " samples: expected at most " +
                     std::to_string(kMaxSamplesPerFrame));
  }
  if (settings.pyramid_levels < 2 || settings.pyramid_levels > 5) {
    throw InputError("--levels " + std::to_string(settings.pyramid_levels) + ": expected 2 to 5 pyramid levels");
  }
  const int filter = settings.min_filter_size;
  if (filter != 1 && filter != 3 && filter != 5) {
    throw InputError("--min-filter " + std::to_string(filter) + ": expected 1, 3 or 5");
  }
  if (settings.max_steps < 1 || settings.max_steps > 100000) {
    throw InputError("--max-steps " + std::to_string(settings.max_steps) + ": expected 1 to 100000");
  }
  if (!(settings.hit_threshold > 0.0f && settings.hit_threshold <= 8.0f)) {
    throw InputError("--hit-threshold: expected a value in (0, 8]");
  }
  if (!std::isfinite(settings.time_s)) throw InputError("--time: expected a finite number of seconds");
}

SphereTracer::SphereTracer(vk::Context& context, const SceneSource& scene) : context_(context) {
  CompiledShader trace = compile_scene_shader(scene, {"sphere_trace.comp.glsl", shaders::sphere_trace_source});
  shader_from_cache_ = trace.from_cache;
  trace_pipeline_ = std::make_unique<vk::ComputePipeline>(context, trace.spirv, 5, sizeof(TraceParams));
  min_filter_pipeline_ = std::make_unique<vk::ComputePipeline>(context, shaders::min_filter_spirv, 2,
                                                               sizeof(MinFilterParams));
}

SphereTracer::~SphereTracer() = default;

SphereTraceResult SphereTracer::render(const SphereTraceSettings& settings) {
  validate(settings);
  const VkDeviceSize colour_bytes = VkDeviceSize(settings.width) * VkDeviceSize(settings.height) * 4 * sizeof(float);
  if (colour_bytes > context_.max_storage_buffer_bytes) {
    throw InputError("--width x --height = " + std::to_string(settings.width) + "x" + std::to_string(settings.height) +
                     ": the frame needs " + std::to_string(colour_bytes >> 20) + " MiB in one buffer; expected at most " +
                     std::to_string(context_.max_storage_buffer_bytes >> 20) + " MiB on " + context_.description.name);
  }
  const int level_count = settings.method == TraceMethod::ground_truth ? 1 : settings.pyramid_levels;
  const int filter_radius = settings.min_filter_size / 2;
  const uint64_t frame_pixels = uint64_t(settings.width) * uint64_t(settings.height);

  if (!frame_ || !frame_->fits(settings.width, settings.height, level_count, filter_radius > 0)) {
    frame_.reset();  // free the old layout before allocating the new one
    frame_ = std::make_unique<FrameBuffers>(context_, settings.width, settings.height, level_count, filter_radius > 0);
  }
  std::vector<LevelBuffers>& levels = frame_->levels;
  const vk::Buffer& colour = frame_->colour;
  const vk::Buffer& colour_readback = frame_->colour_readback;
  const vk::Buffer& counters = frame_->counters;
  const vk::Buffer& counters_readback = frame_->counters_readback;
  const vk::Buffer& unused = frame_->unused;

  vk::OneTimeCommands commands(context_);
  VkCommandBuffer cmd = commands.handle();
  vk::PassTimer timer(context_, static_cast<uint32_t>(2 * level_count));
  timer.reset(cmd);
  vkCmdFillBuffer(cmd, counters.handle(), 0, VK_WHOLE_SIZE, 0);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);

  const vk::Buffer* start = nullptr;  // start depth for the current level (the filtered level below)
  PyramidLevelStats start_stats;
  for (int i = 0; i < level_count; ++i) {
    LevelBuffers& level = levels[static_cast<size_t>(i)];
    const bool top = i + 1 == level_count;
    TraceParams params{};
    params.level_size[0] = static_cast<uint32_t>(level.stats.width);
    params.level_size[1] = static_cast<uint32_t>(level.stats.height);
    params.start_size[0] = static_cast<uint32_t>(start_stats.width);
    params.start_size[1] = static_cast<uint32_t>(start_stats.height);
    params.frame_size[0] = static_cast<float>(settings.width);
    params.frame_size[1] = static_cast<float>(settings.height);
    params.time_s = settings.time_s;
    params.hit_threshold = settings.hit_threshold;
    params.samples_per_pixel = top ? static_cast<uint32_t>(settings.samples_per_pixel) : 1u;
    params.max_steps = static_cast<uint32_t>(settings.max_steps);
    params.level_scale = static_cast<uint32_t>(level.stats.scale);
    params.flags = (top ? kFlagShade : 0u) | (start ? kFlagHasStart : 0u);
    const VkBuffer buffers[] = {start ? start->handle() : unused.handle(),
                                top ? unused.handle() : level.depth.handle(), level.steps.handle(),
                                top ? colour.handle() : unused.handle(), counters.handle()};
    timer.begin(cmd, "trace_level" + std::to_string(i));
    trace_pipeline_->dispatch_2d(cmd, buffers, &params, params.level_size[0], params.level_size[1]);
    timer.end(cmd);
    vk::compute_to_compute_barrier(cmd);
    if (top) break;

    start = &level.depth;
    if (filter_radius > 0) {
      MinFilterParams filter{{params.level_size[0], params.level_size[1]}, filter_radius};
      const VkBuffer filter_buffers[] = {level.depth.handle(), level.start_for_next.handle()};
      timer.begin(cmd, "min_filter_level" + std::to_string(i));
      min_filter_pipeline_->dispatch_2d(cmd, filter_buffers, &filter, filter.size[0], filter.size[1]);
      timer.end(cmd);
      vk::compute_to_compute_barrier(cmd);
      start = &level.start_for_next;
    }
    start_stats = level.stats;
  }

  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
  auto copy = [&](const vk::Buffer& from, const vk::Buffer& to) {
    VkBufferCopy region{0, 0, from.size_bytes()};
    vkCmdCopyBuffer(cmd, from.handle(), to.handle(), 1, &region);
  };
  copy(colour, colour_readback);
  copy(counters, counters_readback);
  for (const LevelBuffers& level : levels) copy(level.steps, level.steps_readback);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                     VK_ACCESS_HOST_READ_BIT);
  commands.submit_and_wait();

  SphereTraceResult result;
  result.passes = timer.results();
  for (const vk::PassTime& pass : result.passes) result.gpu_ms += pass.gpu_ms;

  colour_readback.invalidate();
  const auto* rgba = static_cast<const float*>(colour_readback.mapped());
  result.colour_linear = Image(settings.width, settings.height, 3);
  for (uint64_t p = 0; p < frame_pixels; ++p) {
    for (int c = 0; c < 3; ++c) result.colour_linear.pixels[p * 3 + uint64_t(c)] = rgba[p * 4 + uint64_t(c)];
  }

  counters_readback.invalidate();
  uint32_t counter_values[2];
  std::memcpy(counter_values, counters_readback.mapped(), sizeof(counter_values));
  result.capped_rays = counter_values[0];
  result.restarted_rays = counter_values[1];

  // Every level pixel's steps are shared equally among the full-resolution pixels it covers, so the
  // per-pixel image sums to total_steps.
  result.steps_per_pixel = Image(settings.width, settings.height, 1);
  for (const LevelBuffers& level : levels) {
    PyramidLevelStats stats = level.stats;
    stats.steps = 0;
    level.steps_readback.invalidate();
    const auto* steps = static_cast<const uint32_t*>(level.steps_readback.mapped());
    const int scale = level.stats.scale;
    for (int ly = 0; ly < level.stats.height; ++ly) {
      const int y0 = ly * scale;
      const int covered_rows = std::min(scale, settings.height - y0);
      for (int lx = 0; lx < level.stats.width; ++lx) {
        const uint32_t level_steps = steps[size_t(ly) * size_t(level.stats.width) + size_t(lx)];
        stats.steps += level_steps;
        const int x0 = lx * scale;
        const int covered_columns = std::min(scale, settings.width - x0);
        const float share = static_cast<float>(level_steps) / static_cast<float>(covered_rows * covered_columns);
        for (int y = y0; y < y0 + covered_rows; ++y) {
          for (int x = x0; x < x0 + covered_columns; ++x) result.steps_per_pixel.at(x, y, 0) += share;
        }
      }
    }
    result.total_steps += stats.steps;
    result.levels.push_back(stats);
  }
  return result;
}

}  // namespace fovlab
