#include "renderer/sphere_tracing/sphere_tracer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <sstream>
#include <string>

#include "core/input_error.h"
#include "renderer/foveated_sampling/sampling_passes.h"
#include "renderer/present/srgb8_encoder.h"
#include "renderer/scene/scene_compiler.h"
#include "renderer/shaders/embedded_shaders.h"
#include "renderer/shaders/shared/fipr_params.h"
#include "renderer/shaders/shared/list_dispatch_params.h"
#include "renderer/shaders/shared/sphere_trace_params.h"
#include "renderer/vk/buffer.h"
#include "renderer/vk/compute_pipeline.h"
#include "renderer/vk/context.h"
#include "renderer/vk/submission.h"

namespace fovlab {

namespace {

using gpu::BlurParams;
using gpu::EdgeParams;
using gpu::FiprReconstructParams;
using gpu::ListParams;
using gpu::MaskParams;
using gpu::MidListParams;
using gpu::MinFilterParams;
using gpu::TraceParams;
constexpr double kGazeLimitPx = 1e7;  // gaze further off the frame is clamped (its eccentricities are ~90 degrees)

// Indices into the counters buffer (TraceCounters in sphere_trace.comp.glsl).
enum Counter : uint32_t {
  capped, restarted, masked, mid_traced, mid_shaded, refreshed, refresh_listed, mid_listed, counter_count
};
constexpr int kMaxFrameSide = 16384;

struct LevelBuffers {
  PyramidLevelStats stats;    // size and scale; steps are counted per render
  vk::Buffer depth;           // distance each ray reached (not for the top level)
  vk::Buffer start_for_next;  // min-filtered depth (not for the top level, nor without a filter)
  vk::Buffer near_depth;      // FIPR's depth levels: where the ray passed a surface within its cone, or -1
  vk::Buffer steps;
  vk::Buffer steps_readback;
};

uint32_t ceil_div(int value, int divisor) { return static_cast<uint32_t>((value + divisor - 1) / divisor); }

// The levels a frame traces, bottom first: the pyramid's (scales ..., 4, 2, 1), and with a
// full-resolution depth level one more of scale 1 below the top. GT and the sampling models: one.
struct LevelLayout {
  int pyramid_levels = 1;
  bool full_resolution_depth = false;

  int count() const { return pyramid_levels + (full_resolution_depth ? 1 : 0); }
  int scale(int index) const { return 1 << std::max(0, pyramid_levels - 1 - index); }
  bool operator==(const LevelLayout&) const = default;
};

LevelLayout level_layout(const SphereTraceSettings& settings) {
  if (settings.method == TraceMethod::ground_truth || settings.method == TraceMethod::sampling_model) return {};
  return {settings.pyramid_levels,
          settings.method == TraceMethod::inverted_pyramid && settings.full_resolution_depth};
}

}  // namespace

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
  vk::Buffer unused;  // bound where a pass has no such buffer
  vk::Buffer sample_depth;  // GT's one-step floor: where each sample's trace stopped (made when first needed)
  // FIPR only.
  vk::Buffer edges;           // low level: 0 or 1
  vk::Buffer mask;            // full resolution: 0 or 1
  vk::Buffer mask_readback;
  vk::Buffer masked_list;     // full-resolution pixel indices of the masked pixels (the first counters[masked])
  vk::Buffer refresh_list;    // and of the unmasked pixels due for a refresh, when the periphery is traced
  vk::Buffer list_dispatch;   // workgroup counts of the top level's passes over the two lists
  vk::Buffer mid_list;        // mid level: the pixels traced (fipr_mid_list.comp.glsl's entries)
  vk::Buffer mid_list_dispatch;  // workgroup counts of the mid level's pass over its list
  vk::Buffer mid_flags;       // mid level: masked children | children << 4
  vk::Buffer mid_colour;      // mid level: shaded colour of pixels due for a refresh
  vk::Buffer blurred;         // full resolution: pass 5's output

  FrameBuffers(const vk::Context& context, int width_px, int height_px, LevelLayout level_layout, bool with_filter,
               bool with_foveation)
      : width(width_px), height(height_px), layout(level_layout), filtered(with_filter), foveated(with_foveation),
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
    counters = vk::Buffer(context, counter_count * sizeof(uint32_t), vk::MemoryUse::device_local);
    counters_readback = vk::Buffer(context, counter_count * sizeof(uint32_t), vk::MemoryUse::host_readback);
    unused = vk::Buffer(context, 16, vk::MemoryUse::device_local);
    if (!foveated) return;
    const auto pixels_of = [](const PyramidLevelStats& level) { return VkDeviceSize(level.width) * VkDeviceSize(level.height); };
    const VkDeviceSize frame_pixels = VkDeviceSize(width) * VkDeviceSize(height);
    const VkDeviceSize mid_pixels = pixels_of(levels[size_t(level_count - 2)].stats);
    edges = vk::Buffer(context, pixels_of(levels[0].stats) * sizeof(uint32_t), vk::MemoryUse::device_local);
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
  std::array<uint32_t, counter_count> read_outputs(vk::Context& context, bool on_device, SphereTraceResult& result) const {
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
    std::array<uint32_t, counter_count> values;
    std::memcpy(values.data(), counters_readback.mapped(), sizeof(uint32_t) * counter_count);
    result.capped_rays = values[capped];
    result.restarted_rays = values[restarted];
    return values;
  }

  bool fits(int width_px, int height_px, LevelLayout level_layout, bool with_filter, bool with_foveation) const {
    return width == width_px && height == height_px && layout == level_layout && filtered == with_filter &&
           foveated == with_foveation;
  }
};

// FrameBuffers' allocations (keep the two in step) plus the result's images.
uint64_t render_memory_bytes(const SphereTraceSettings& settings) {
  const bool foveated = settings.method == TraceMethod::foveated_pyramid;
  const LevelLayout layout = level_layout(settings);
  const int level_count = layout.count();
  const bool filtered = settings.min_filter_size / 2 > 0;
  const uint64_t frame_pixels = uint64_t(settings.width) * uint64_t(settings.height);
  uint64_t bytes = 0;
  std::vector<uint64_t> level_pixels;
  for (int i = 0; i < level_count; ++i) {
    const int scale = layout.scale(i);
    const uint64_t pixels = uint64_t(ceil_div(settings.width, scale)) * uint64_t(ceil_div(settings.height, scale));
    level_pixels.push_back(pixels);
    bytes += pixels * 2 * sizeof(uint32_t);                                   // steps, and read back
    if (i + 1 < level_count) bytes += pixels * sizeof(float) * (filtered ? 2 : 1);  // depth, start_for_next
  }
  bytes += frame_pixels * 4 * sizeof(float) * 2;  // colour, and read back
  bytes += frame_pixels * 4;                      // display_srgb8
  if (foveated && level_count >= 3) {
    bytes += level_pixels[0] * sizeof(uint32_t);                                     // edges
    bytes += frame_pixels * sizeof(uint32_t) * 4;                                    // mask, its readback, two lists
    bytes += level_pixels[size_t(level_count - 2)] * (2 * sizeof(uint32_t) + 4 * sizeof(float));  // mid flags, list, colour
    bytes += frame_pixels * 4 * sizeof(float);                                       // blurred
  }
  if (settings.one_step_floor) bytes += frame_pixels * uint64_t(settings.samples_per_pixel) * sizeof(float);  // sample_depth
  if (settings.outputs != TraceOutputs::display) bytes += frame_pixels * 3 * sizeof(float);  // result: colour_linear
  if (settings.outputs == TraceOutputs::all) bytes += frame_pixels * sizeof(float) * (foveated ? 2 : 1);  // steps image, mask
  // Sampling models: the sample list and its read-back, colours, steps and their read-back, with
  // room for 1.3 samples a pixel (the hyperbolic layers' overlap, up to about 1.26; the linear
  // model's pull-push levels, 1.33 colours a pixel).
  if (settings.method == TraceMethod::sampling_model) bytes += frame_pixels * 13 / 10 * (4 * 4 * 2 + 4 * 4 + 4 * 2) + frame_pixels * 4 * 4 / 3;
  return bytes;
}

const char* method_name(TraceMethod method) {
  switch (method) {
    case TraceMethod::ground_truth: return "gt";
    case TraceMethod::inverted_pyramid: return "ipr";
    case TraceMethod::foveated_pyramid: return "fipr";
    case TraceMethod::sampling_model: return "sampling";
  }
  return "gt";
}

const char* coarse_test_name(CoarseTest test) { return test == CoarseTest::cone ? "cone" : "ray"; }
const char* periphery_reconstruction_name(PeripheryReconstruction reconstruction) {
  switch (reconstruction) {
    case PeripheryReconstruction::mid_footprint_bilinear: return "mid-footprint-bilinear";
    case PeripheryReconstruction::bilinear: return "bilinear";
    case PeripheryReconstruction::catmull_rom: return "catmull-rom";
  }
  return "?";
}

std::optional<PeripheryReconstruction> parse_periphery_reconstruction(const std::string& name) {
  for (PeripheryReconstruction reconstruction : kPeripheryReconstructions)
    if (name == periphery_reconstruction_name(reconstruction)) return reconstruction;
  return std::nullopt;
}

const char* near_misses_name(NearMisses near_misses) {
  return near_misses == NearMisses::promote ? "promote" : "ignore";
}

std::optional<NearMisses> parse_near_misses(const std::string& name) {
  for (NearMisses near_misses : kNearMisses)
    if (name == near_misses_name(near_misses)) return near_misses;
  return std::nullopt;
}

std::optional<TraceMethod> parse_trace_method(const std::string& name) {
  for (TraceMethod method : {TraceMethod::ground_truth, TraceMethod::inverted_pyramid, TraceMethod::foveated_pyramid})
    if (name == method_name(method)) return method;
  return std::nullopt;
}

static void validate_foveation(const SphereTraceSettings& settings) {
  const FoveationSettings& f = settings.foveation;
  if (settings.pyramid_levels < 3) {
    throw SettingError("pyramid_levels", " " + std::to_string(settings.pyramid_levels) +
                                             ": FIPR needs at least 3 pyramid levels (low, mid and top)");
  }
  if (f.display.width_px != settings.width || f.display.height_px != settings.height) {
    throw InputError("FIPR display of " + std::to_string(f.display.width_px) + "x" + std::to_string(f.display.height_px) +
                     " pixels: expected the frame's " + std::to_string(settings.width) + "x" +
                     std::to_string(settings.height));
  }
  const auto positive = [](double value) { return std::isfinite(value) && value > 0.0; };
  if (!positive(f.display.width_mm) || !positive(f.display.height_mm) || !positive(f.display.viewing_distance_mm)) {
    throw InputError("FIPR display: expected a positive finite width, height and viewing distance in mm");
  }
  if (!(std::isfinite(f.acuity.fovea_radius_deg) && f.acuity.fovea_radius_deg >= 0.0 && f.acuity.fovea_radius_deg <= 180.0)) {
    throw SettingError("fovea_radius_deg", ": expected an eccentricity from 0 to 180 degrees");
  }
  if (std::isnan(f.acuity.outer_periphery_radius_deg) || f.acuity.outer_periphery_radius_deg < f.acuity.fovea_radius_deg) {
    throw SettingError("outer_periphery_radius_deg", ": expected an eccentricity at least the fovea's");
  }
  if (f.periphery_refresh != 1 && f.periphery_refresh != 2 && f.periphery_refresh != 4) {
    throw SettingError("periphery_refresh",
                       " " + std::to_string(f.periphery_refresh) + ": expected 1, 2 or 4 (frames between periphery updates)");
  }
  if (f.periphery_steps < 0 || f.periphery_steps > 100000) {
    throw SettingError("periphery_steps", " " + std::to_string(f.periphery_steps) + ": expected 0 to 100000");
  }
  if (!(f.edge_threshold > 0.0f && std::isfinite(f.edge_threshold))) {
    throw SettingError("edge_threshold", ": expected a positive finite number");
  }
}

void validate(const SphereTraceSettings& settings) {
  auto check_side = [](int value, const char* field) {
    if (value <= 0 || value > kMaxFrameSide)
      throw SettingError(field, " " + std::to_string(value) + ": expected 1 to " + std::to_string(kMaxFrameSide) + " pixels");
  };
  check_side(settings.width, "width");
  check_side(settings.height, "height");
  const int spp = settings.samples_per_pixel;
  if (spp != 1 && spp != 4 && spp != 16) {
    throw SettingError("samples_per_pixel", " " + std::to_string(spp) + ": expected 1, 4 or 16 samples per pixel");
  }
  const uint64_t samples = uint64_t(settings.width) * uint64_t(settings.height) * uint64_t(spp);
  if (samples > kMaxSphereTraceSamplesPerFrame) {
    throw SettingError(kSamplesPerFrameField, " = " + std::to_string(samples) + " samples: expected at most " +
                                                  std::to_string(kMaxSphereTraceSamplesPerFrame));
  }
  if (settings.pyramid_levels < 2 || settings.pyramid_levels > 5) {
    throw SettingError("pyramid_levels", " " + std::to_string(settings.pyramid_levels) + ": expected 2 to 5 pyramid levels");
  }
  const int filter = settings.min_filter_size;
  if (filter != 1 && filter != 3 && filter != 5) {
    throw SettingError("min_filter_size", " " + std::to_string(filter) + ": expected 1, 3 or 5");
  }
  if (settings.max_steps < 1 || settings.max_steps > 100000) {
    throw SettingError("max_steps", " " + std::to_string(settings.max_steps) + ": expected 1 to 100000");
  }
  if (!(settings.hit_threshold > 0.0f && settings.hit_threshold <= 8.0f)) {
    throw SettingError("hit_threshold", ": expected a value in (0, 8]");
  }
  if (!std::isfinite(settings.time_s)) throw SettingError("time_s", ": expected a finite number of seconds");
  if (settings.one_step_floor && settings.method != TraceMethod::ground_truth)
    throw SettingError("one_step_floor", ": expected the GT method (the floor is measured on GT's frame)");
  if (settings.method == TraceMethod::foveated_pyramid) validate_foveation(settings);
  if (settings.method == TraceMethod::sampling_model) {
    if (!settings.sampling) throw SettingError("sampling", ": expected a sampling model's map");
    if (screen_width_px(*settings.sampling) != settings.width || screen_height_px(*settings.sampling) != settings.height)
      throw InputError("sampling map of " + std::to_string(screen_width_px(*settings.sampling)) + "x" +
                       std::to_string(screen_height_px(*settings.sampling)) + " pixels: expected the frame's " +
                       std::to_string(settings.width) + "x" + std::to_string(settings.height));
  }
}


SphereTracer::SphereTracer(vk::Context& context, const SceneSource& scene) : context_(context) {
  CompiledShader trace = compile_scene_shader(scene, {"sphere_trace.comp.glsl", shaders::sphere_trace_source, shaders::shared_headers});
  shader_from_cache_ = trace.from_cache;
  trace_pipeline_ = std::make_unique<vk::ComputePipeline>(context, trace.spirv, 10, sizeof(TraceParams));
  min_filter_pipeline_ = std::make_unique<vk::ComputePipeline>(context, shaders::min_filter_spirv, 2,
                                                               sizeof(MinFilterParams));
  edges_pipeline_ = std::make_unique<vk::ComputePipeline>(context, shaders::depth_edges_spirv, 2, sizeof(EdgeParams));
  mask_pipeline_ = std::make_unique<vk::ComputePipeline>(context, shaders::foveation_mask_spirv, 6, sizeof(MaskParams));
  list_dispatch_pipeline_ = std::make_unique<vk::ComputePipeline>(context, shaders::list_dispatch_spirv, 2, sizeof(ListParams));
  mid_list_pipeline_ = std::make_unique<vk::ComputePipeline>(context, shaders::fipr_mid_list_spirv, 6, sizeof(MidListParams));
  reconstruct_pipeline_ = std::make_unique<vk::ComputePipeline>(context, shaders::fipr_reconstruct_spirv, 4,
                                                                sizeof(FiprReconstructParams));
  blur_pipeline_ = std::make_unique<vk::ComputePipeline>(context, shaders::masked_blur_spirv, 3, sizeof(BlurParams));
  encoder_ = std::make_unique<Srgb8Encoder>(context);
}

SphereTracer::~SphereTracer() = default;

namespace {

// Everything a FIPR frame's reusable pixels depend on, except gaze, scene time and frame index.
std::string history_key_of(const SphereTraceSettings& s) {
  const FoveationSettings& f = s.foveation;
  std::ostringstream key;
  key.precision(17);
  key << s.samples_per_pixel << ' ' << s.pyramid_levels << ' ' << s.min_filter_size << ' '
      << coarse_test_name(s.coarse_test) << ' ' << s.max_steps << ' '
      << s.hit_threshold << ' ' << f.display.width_mm << ' ' << f.display.height_mm << ' ' << f.display.viewing_distance_mm
      << ' ' << f.acuity.fovea_radius_deg << ' ' << f.acuity.outer_periphery_radius_deg << ' ' << static_cast<uint32_t>(f.combine)
      << ' ' << f.edge_threshold << ' ' << f.periphery_refresh << ' ' << f.periphery_steps << ' ' << f.seed << ' '
      << periphery_reconstruction_name(f.reconstruction) << ' ' << near_misses_name(f.near_misses);
  return key.str();
}

// The mask pass's constants: display, gaze and acuity model in the shader's float terms.
MaskParams mask_params(const SphereTraceSettings& settings, const PyramidLevelStats& low, const PyramidLevelStats& mid,
                       bool all_due) {
  const FoveationSettings& f = settings.foveation;
  MaskParams params{};
  params.frame_size[0] = static_cast<uint32_t>(settings.width);
  params.frame_size[1] = static_cast<uint32_t>(settings.height);
  params.mid_size[0] = static_cast<uint32_t>(mid.width);
  params.mid_size[1] = static_cast<uint32_t>(mid.height);
  params.low_size[0] = static_cast<uint32_t>(low.width);
  params.low_size[1] = static_cast<uint32_t>(low.height);
  params.low_scale = static_cast<uint32_t>(low.scale);
  params.combine = static_cast<uint32_t>(f.combine);
  const bool has_gaze = std::isfinite(f.gaze_x_px) && std::isfinite(f.gaze_y_px);
  params.flags = has_gaze ? 0u : gpu::FLAG_TRACE_ALL;
  if (has_gaze) {
    params.gaze_px[0] = static_cast<float>(std::clamp(f.gaze_x_px, -kGazeLimitPx, settings.width + kGazeLimitPx));
    params.gaze_px[1] = static_cast<float>(std::clamp(f.gaze_y_px, -kGazeLimitPx, settings.height + kGazeLimitPx));
  }
  params.pixel_pitch_mm[0] = static_cast<float>(f.display.pixel_pitch_x_mm());
  params.pixel_pitch_mm[1] = static_cast<float>(f.display.pixel_pitch_y_mm());
  params.viewing_distance_mm = static_cast<float>(f.display.viewing_distance_mm);
  params.fovea_radius_deg = static_cast<float>(f.acuity.fovea_radius_deg);
  params.outer_periphery_radius_deg = static_cast<float>(std::min(f.acuity.outer_periphery_radius_deg, 1e9));
  params.seed = f.seed;
  params.frame_index = f.frame_index;
  params.refresh_period = static_cast<uint32_t>(f.periphery_refresh);
  if (all_due) params.flags |= gpu::FLAG_ALL_DUE;
  if (f.periphery_steps > 0) params.flags |= gpu::FLAG_LIST_REFRESH;
  return params;
}

}  // namespace

void check_sphere_trace_frame_bytes(const vk::Context& context, int width, int height, const std::string& size_name) {
  const VkDeviceSize colour_bytes = VkDeviceSize(width) * VkDeviceSize(height) * 4 * sizeof(float);
  if (colour_bytes > context.max_storage_buffer_bytes) {
    throw InputError(size_name + " = " + std::to_string(width) + "x" + std::to_string(height) + ": the frame needs " +
                     std::to_string(colour_bytes >> 20) + " MiB in one buffer; expected at most " +
                     std::to_string(context.max_storage_buffer_bytes >> 20) + " MiB on " + context.description.name);
  }
}

void SphereTracer::prepare_frame(const SphereTraceSettings& settings) {
  const LevelLayout layout = level_layout(settings);
  const bool filtered = layout.count() > 1 && settings.min_filter_size / 2 > 0;
  const bool foveated = settings.method == TraceMethod::foveated_pyramid;
  if (frame_ && frame_->fits(settings.width, settings.height, layout, filtered, foveated)) return;
  frame_.reset();  // free the old layout before allocating the new one
  frame_ = std::make_unique<FrameBuffers>(context_, settings.width, settings.height, layout, filtered, foveated);
}

SphereTraceResult SphereTracer::render(const SphereTraceSettings& settings) {
  validate(settings);
  check_sphere_trace_frame_bytes(context_, settings.width, settings.height, "--width x --height");
  const bool foveated = settings.method == TraceMethod::foveated_pyramid;
  const LevelLayout layout = level_layout(settings);
  const int level_count = layout.count();
  const int filter_radius = settings.min_filter_size / 2;
  const uint64_t frame_pixels = uint64_t(settings.width) * uint64_t(settings.height);

  if (settings.method == TraceMethod::sampling_model) return render_sampled(settings);
  prepare_frame(settings);
  FrameBuffers& frame = *frame_;
  std::vector<LevelBuffers>& levels = frame.levels;
  const FoveationSettings& fov = settings.foveation;
  // A frame continues the sequence in the buffers only if it is the next one, with the same settings
  // (all but gaze, scene time and frame index); otherwise every pixel is refreshed.
  const std::string history_key = foveated ? history_key_of(settings) : std::string();
  const bool all_due = !frame.history_valid || fov.frame_index == 0 || fov.frame_index != frame.history_index + 1 ||
                       history_key != frame.history_key;
  const int mid_index = level_count - 2;

  vk::OneTimeCommands commands(context_);
  VkCommandBuffer cmd = commands.handle();
  vk::PassTimer timer(context_, static_cast<uint32_t>(2 * level_count + 10));
  timer.reset(cmd);
  vkCmdFillBuffer(cmd, frame.counters.handle(), 0, VK_WHOLE_SIZE, 0);
  if (foveated && all_due) vkCmdFillBuffer(cmd, frame.mid_colour.handle(), 0, VK_WHOLE_SIZE, 0);  // alpha 0: not shaded yet
  if (foveated) vkCmdFillBuffer(cmd, levels.back().steps.handle(), 0, VK_WHOLE_SIZE, 0);  // pixels not traced: 0
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);

  // The workgroup counts of indirect dispatches over one or two lists an earlier pass filled:
  const auto record_list_dispatch = [&](const char* pass, const ListParams& lists, const vk::Buffer& counts) {
    const VkBuffer dispatch_buffers[] = {frame.counters.handle(), counts.handle()};
    timer.begin(cmd, pass);
    list_dispatch_pipeline_->dispatch_2d(cmd, dispatch_buffers, &lists, 1, 1);
    timer.end(cmd);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT);
  };

  // FIPR passes 2 and 3, once the low level's depth exists.
  const auto edges_and_mask = [&] {
    const PyramidLevelStats& low = levels.front().stats;
    EdgeParams edge_params{{uint32_t(low.width), uint32_t(low.height)}, fov.edge_threshold};
    const VkBuffer edge_buffers[] = {levels.front().depth.handle(), frame.edges.handle()};
    timer.begin(cmd, "sobel_edges");
    edges_pipeline_->dispatch_2d(cmd, edge_buffers, &edge_params, edge_params.size[0], edge_params.size[1]);
    timer.end(cmd);
    vk::compute_to_compute_barrier(cmd);
    const MaskParams params = mask_params(settings, low, levels[size_t(mid_index)].stats, all_due);
    const VkBuffer mask_buffers[] = {frame.edges.handle(), frame.mask.handle(), frame.mid_flags.handle(),
                                     frame.counters.handle(), frame.masked_list.handle(), frame.refresh_list.handle()};
    timer.begin(cmd, "foveation_mask");
    mask_pipeline_->dispatch_2d(cmd, mask_buffers, &params, params.mid_size[0], params.mid_size[1]);
    timer.end(cmd);
    vk::compute_to_compute_barrier(cmd);
  };

  // FIPR's depth levels track where their rays pass a surface (near depths), for the mid level's
  // promotion, which only a periphery from the mid level has, and the start of what it promoted.
  const bool near_misses = foveated && fov.near_misses == NearMisses::promote && fov.periphery_steps == 0;
  const vk::Buffer* start = nullptr;  // start depth for the current level (the filtered level below)
  PyramidLevelStats start_stats;
  for (int i = 0; i < level_count; ++i) {
    LevelBuffers& level = levels[static_cast<size_t>(i)];
    const bool top = i + 1 == level_count;
    const bool foveated_mid = foveated && i == mid_index;
    const bool foveated_top = foveated && top;
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
    // The shader textures a shaded ray over level scale / sqrt(samples) pixels; a mid colour stands
    // for the frame's pixel at its position, so it takes one pixel's footprint (but as first built).
    if (foveated_mid && fov.periphery_steps == 0 && fov.reconstruction != PeripheryReconstruction::mid_footprint_bilinear)
      params.samples_per_pixel = static_cast<uint32_t>(level.stats.scale * level.stats.scale);
    params.max_steps = static_cast<uint32_t>(settings.max_steps);
    params.level_scale = static_cast<uint32_t>(level.stats.scale);
    params.flags = (top ? gpu::FLAG_SHADE : 0u) | (start ? gpu::FLAG_HAS_START : 0u) | (foveated_mid ? gpu::FLAG_FOVEATED_MID : 0u) |
                   (foveated_top ? gpu::FLAG_FOVEATED_TOP : 0u) |
                   (settings.coarse_test == CoarseTest::cone ? gpu::FLAG_CONE : 0u) |
                   (start && start_stats.scale == level.stats.scale ? gpu::FLAG_START_SAME_SIZE : 0u) |
                   (near_misses ? gpu::FLAG_NEAR_MISS : 0u);
    params.frame_index = fov.frame_index;
    params.periphery_steps = static_cast<uint32_t>(std::min(fov.periphery_steps, settings.max_steps));
    const VkBuffer colour_target = top ? frame.colour.handle() : foveated_mid ? frame.mid_colour.handle() : frame.unused.handle();
    const VkBuffer mask_input = foveated_top ? frame.mask.handle() : foveated_mid ? frame.mid_list.handle() : frame.unused.handle();
    // Near misses: a depth level reads the near depths of the level below and writes its own; the mid
    // level adds the children it promotes to the mask and its list; the top level starts those from
    // the mid level's near depths.
    const bool promotes = foveated_mid && near_misses;
    const VkBuffer unused = frame.unused.handle();
    const std::array<VkBuffer, 10> buffers = {start ? start->handle() : unused,
                                              top ? unused : level.depth.handle(),
                                              level.steps.handle(),
                                              colour_target,
                                              frame.counters.handle(),
                                              mask_input,
                                              promotes ? frame.mask.handle() : unused,
                                              promotes ? frame.masked_list.handle() : unused,
                                              near_misses && i > 0 ? levels[size_t(i - 1)].near_depth.handle() : unused,
                                              near_misses && !top ? level.near_depth.handle() : unused};
    const auto with_binding = [&](size_t binding, VkBuffer buffer) {
      std::array<VkBuffer, 10> changed = buffers;
      changed[binding] = buffer;
      return changed;
    };
    if (foveated_top) {
      // Masked pixels first, densely from their list; then the rest of the frame (reconstruction).
      // The two passes write disjoint pixels (mask 1, mask 0), so neither waits for the other.
      TraceParams list_params = params;
      list_params.flags = (params.flags & ~gpu::FLAG_FOVEATED_TOP) | gpu::FLAG_MASKED_LIST;
      const auto list_buffers = with_binding(5, frame.masked_list.handle());
      timer.begin(cmd, "trace_level" + std::to_string(i));
      trace_pipeline_->dispatch_indirect(cmd, list_buffers, &list_params, frame.list_dispatch.handle(), 0);
      timer.end(cmd);
      if (fov.periphery_steps > 0) {
        TraceParams periphery_params = params;
        periphery_params.samples_per_pixel = 1;  // one ray per peripheral pixel (also its texture footprint)
        const auto refresh_buffers = with_binding(5, frame.refresh_list.handle());
        timer.begin(cmd, "periphery_trace");
        trace_pipeline_->dispatch_indirect(cmd, refresh_buffers, &periphery_params, frame.list_dispatch.handle(),
                                           3 * sizeof(uint32_t));
        timer.end(cmd);
      } else {
        const PyramidLevelStats& mid = levels[size_t(mid_index)].stats;
        FiprReconstructParams reconstruct{{params.level_size[0], params.level_size[1]},
                                      {uint32_t(mid.width), uint32_t(mid.height)},
                                      static_cast<uint32_t>(fov.periphery_refresh), params.frame_index,
                                      fov.reconstruction == PeripheryReconstruction::catmull_rom ? 1u : 0u};
        const VkBuffer reconstruct_buffers[] = {frame.mask.handle(), frame.mid_flags.handle(), frame.mid_colour.handle(),
                                                frame.colour.handle()};
        timer.begin(cmd, "reconstruct");
        reconstruct_pipeline_->dispatch_2d(cmd, reconstruct_buffers, &reconstruct, params.level_size[0],
                                           params.level_size[1]);
        timer.end(cmd);
      }
      vk::compute_to_compute_barrier(cmd);
      break;
    }
    if (foveated_mid) {
      // The pixels to trace, listed (the others take their start depth there), then traced densely.
      const MidListParams list_params{{params.level_size[0], params.level_size[1]},
                                      {params.start_size[0], params.start_size[1]}, filter_radius, mid_listed};
      const VkBuffer list_buffers[] = {frame.mid_flags.handle(), start->handle(), level.depth.handle(),
                                       level.steps.handle(), frame.counters.handle(), frame.mid_list.handle()};
      timer.begin(cmd, "mid_list");
      mid_list_pipeline_->dispatch_2d(cmd, list_buffers, &list_params, params.level_size[0], params.level_size[1]);
      timer.end(cmd);
      vk::compute_to_compute_barrier(cmd);
      record_list_dispatch("mid_list_dispatch", {{mid_listed, 0}, 1}, frame.mid_list_dispatch);
      timer.begin(cmd, "trace_level" + std::to_string(i));
      trace_pipeline_->dispatch_indirect(cmd, buffers, &params, frame.mid_list_dispatch.handle(), 0);
      timer.end(cmd);
      // The top level's lists are complete now: the mask pass's, and the children this level promoted.
      vk::compute_to_compute_barrier(cmd);
      record_list_dispatch("list_dispatch", {{masked, refresh_listed}, 2}, frame.list_dispatch);
    } else if (settings.one_step_floor) {
      // GT's trace, untimed, recording where each sample stopped; then the timed floor from there.
      const VkDeviceSize sample_bytes = VkDeviceSize(frame_pixels) * VkDeviceSize(settings.samples_per_pixel) * sizeof(float);
      if (frame.sample_depth.size_bytes() != sample_bytes)
        frame.sample_depth = vk::Buffer(context_, sample_bytes, vk::MemoryUse::device_local);
      TraceParams record = params;
      record.flags |= gpu::FLAG_SAMPLE_DEPTH_OUT;
      const auto record_buffers = with_binding(1, frame.sample_depth.handle());
      trace_pipeline_->dispatch_2d(cmd, record_buffers, &record, params.level_size[0], params.level_size[1]);
      vk::compute_to_compute_barrier(cmd);
      vkCmdFillBuffer(cmd, frame.counters.handle(), 0, VK_WHOLE_SIZE, 0);  // the floor's own capped and restarted rays
      vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
      TraceParams floor_params = params;
      floor_params.flags |= gpu::FLAG_SAMPLE_DEPTH_IN;
      floor_params.max_steps = 1;
      const auto floor_buffers = with_binding(0, frame.sample_depth.handle());
      timer.begin(cmd, "one_step_floor");
      trace_pipeline_->dispatch_2d(cmd, floor_buffers, &floor_params, params.level_size[0], params.level_size[1]);
      timer.end(cmd);
    } else {
      timer.begin(cmd, "trace_level" + std::to_string(i));
      trace_pipeline_->dispatch_2d(cmd, buffers, &params, params.level_size[0], params.level_size[1]);
      timer.end(cmd);
    }
    vk::compute_to_compute_barrier(cmd);
    if (top) break;
    if (foveated && i == 0) edges_and_mask();

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

  const vk::Buffer* shown = &frame.colour;
  if (foveated && fov.blur) {
    BlurParams blur{{uint32_t(settings.width), uint32_t(settings.height)}};
    const VkBuffer blur_buffers[] = {frame.colour.handle(), frame.mask.handle(), frame.blurred.handle()};
    timer.begin(cmd, "masked_blur");
    blur_pipeline_->dispatch_2d(cmd, blur_buffers, &blur, blur.size[0], blur.size[1]);
    timer.end(cmd);
    vk::compute_to_compute_barrier(cmd);
    shown = &frame.blurred;
  }

  const bool on_device = settings.outputs == TraceOutputs::display;
  frame.record_outputs(cmd, timer, *encoder_, *shown, on_device, [&](const auto& copy) {
    if (settings.outputs != TraceOutputs::all) return;
    if (foveated) copy(frame.mask, frame.mask_readback);
    for (const LevelBuffers& level : levels) copy(level.steps, level.steps_readback);
  });
  commands.submit_and_wait();
  frame.history_valid = foveated;  // (a GT or IPR frame has its own layout: changing method resets history)
  frame.history_index = fov.frame_index;
  frame.history_key = history_key;

  SphereTraceResult result;
  result.passes = timer.results();
  for (const vk::PassTime& pass : result.passes) result.gpu_ms += pass.gpu_ms;

  const std::array<uint32_t, counter_count> counter_values = frame.read_outputs(context_, on_device, result);
  if (foveated) {
    result.foveation.masked_pixels = counter_values[masked];
    result.foveation.refreshed_pixels = counter_values[refreshed];
    result.foveation.kept_pixels = frame_pixels - counter_values[masked] - counter_values[refreshed];
  }
  if (foveated && settings.outputs == TraceOutputs::all) {
    frame.mask_readback.invalidate();
    const auto* mask = static_cast<const uint32_t*>(frame.mask_readback.mapped());
    result.mask = Image(settings.width, settings.height, 1);
    for (uint64_t p = 0; p < frame_pixels; ++p) result.mask.pixels[p] = mask[p] != 0 ? 1.0f : 0.0f;
  }

  // Every level pixel's steps are shared equally among the full-resolution pixels it covers, so the
  // per-pixel image sums to total_steps.
  if (settings.outputs == TraceOutputs::all) result.steps_per_pixel = Image(settings.width, settings.height, 1);
  for (int i = 0; i < level_count; ++i) {
    const LevelBuffers& level = levels[size_t(i)];
    PyramidLevelStats stats = level.stats;
    stats.steps = 0;
    const uint64_t level_pixels = uint64_t(stats.width) * uint64_t(stats.height);
    const bool top = i + 1 == level_count;
    stats.traced_pixels = level_pixels;
    stats.shaded_pixels = top ? level_pixels : 0;
    if (foveated && top) {  // the masked pixels, and the periphery's refresh list when it is traced
      stats.traced_pixels = stats.shaded_pixels =
          counter_values[masked] + (fov.periphery_steps > 0 ? counter_values[refresh_listed] : 0u);
    }
    if (foveated && i == mid_index) {
      stats.traced_pixels = counter_values[mid_traced];
      stats.shaded_pixels = counter_values[mid_shaded];
    }
    if (settings.outputs != TraceOutputs::all) {
      result.levels.push_back(stats);
      continue;
    }
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

// The sampling models: list the samples, trace and shade them, make every pixel from them.
SphereTraceResult SphereTracer::render_sampled(const SphereTraceSettings& settings) {
  prepare_frame(settings);
  FrameBuffers& frame = *frame_;
  frame.history_valid = false;
  if (!sampling_) sampling_ = std::make_unique<SamplingPasses>(context_);
  SamplingPasses& sampling = *sampling_;
  sampling.prepare(*settings.sampling, settings.sampling_filter);

  vk::OneTimeCommands commands(context_);
  VkCommandBuffer cmd = commands.handle();
  vk::PassTimer timer(context_, SamplingPasses::kMaxTimedPasses + 2);
  timer.reset(cmd);
  vkCmdFillBuffer(cmd, frame.counters.handle(), 0, VK_WHOLE_SIZE, 0);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  sampling.record_positions(cmd, timer, frame.counters.handle(), masked);

  TraceParams params{};
  params.level_size[0] = static_cast<uint32_t>(settings.width);
  params.level_size[1] = static_cast<uint32_t>(settings.height);
  params.frame_size[0] = static_cast<float>(settings.width);
  params.frame_size[1] = static_cast<float>(settings.height);
  params.time_s = settings.time_s;
  params.hit_threshold = settings.hit_threshold;
  params.samples_per_pixel = static_cast<uint32_t>(settings.samples_per_pixel);
  params.max_steps = static_cast<uint32_t>(settings.max_steps);
  params.level_scale = 1;
  params.flags = gpu::FLAG_SHADE | gpu::FLAG_SAMPLE_LIST;
  const VkBuffer unused = frame.unused.handle();
  const VkBuffer trace_buffers[] = {unused, unused, sampling.sample_steps(), sampling.sample_colours(), frame.counters.handle(),
                                    sampling.sample_list(), unused, unused, unused, unused};
  timer.begin(cmd, "trace_samples");
  trace_pipeline_->dispatch_indirect(cmd, trace_buffers, &params, sampling.dispatch_arguments(), 0);
  timer.end(cmd);
  vk::compute_to_compute_barrier(cmd);
  sampling.record_reconstruct(cmd, timer, frame.colour.handle());

  const bool on_device = settings.outputs == TraceOutputs::display;
  frame.record_outputs(cmd, timer, *encoder_, frame.colour, on_device, [&](const auto&) {
    if (settings.outputs == TraceOutputs::all) sampling.record_readback(cmd);  // steps and the sample list
  });
  commands.submit_and_wait();

  SphereTraceResult result;
  result.passes = timer.results();
  for (const vk::PassTime& pass : result.passes) result.gpu_ms += pass.gpu_ms;
  const std::array<uint32_t, counter_count> counter_values = frame.read_outputs(context_, on_device, result);
  result.shaded_samples = counter_values[masked];

  PyramidLevelStats stats;
  stats.width = settings.width;
  stats.height = settings.height;
  stats.traced_pixels = stats.shaded_pixels = result.shaded_samples;
  if (settings.outputs == TraceOutputs::all) {
    const std::vector<uint32_t> entry_steps = sampling.entry_steps();
    for (uint32_t steps : entry_steps) stats.steps += steps;
    result.total_steps = stats.steps;
    // Each sample's steps and count go to the pixel that holds its position.
    result.steps_per_pixel = Image(settings.width, settings.height, 1);
    result.mask = Image(settings.width, settings.height, 1);
    for (const ListedSample& sample : sampling.listed_samples(counter_values[masked])) {
      const int x = int(std::floor(sample.x_px)), y = int(std::floor(sample.y_px));
      if (x < 0 || y < 0 || x >= settings.width || y >= settings.height) continue;  // a tap just off the screen
      result.steps_per_pixel.at(x, y, 0) += float(entry_steps[sample.entry]);
      result.mask.at(x, y, 0) += 1.0f;
    }
  }
  result.levels.push_back(stats);  // (steps counted with TraceOutputs::all: a session's frames read nothing back)
  return result;
}

}  // namespace fovlab
