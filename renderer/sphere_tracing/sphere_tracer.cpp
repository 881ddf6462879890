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
#include "renderer/sphere_tracing/sphere_tracer_frame.h"
#include "renderer/vk/buffer.h"
#include "renderer/vk/compute_pipeline.h"
#include "renderer/vk/context.h"
#include "renderer/vk/submission.h"

namespace fovlab {

namespace {

constexpr int kMaxFrameSide = 16384;

}  // namespace

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
    bytes += pixels * 2 * sizeof(uint32_t);                                         // steps, and read back
    if (i + 1 < level_count) bytes += pixels * sizeof(float) * (filtered ? 2 : 1);  // depth, start_for_next
  }
  bytes += frame_pixels * 4 * sizeof(float) * 2;  // colour, and read back
  bytes += frame_pixels * 4;                      // display_srgb8
  if (foveated && level_count >= 3) {
    bytes += level_pixels[0] * (sizeof(uint32_t) + sizeof(float));  // edges, edge depth
    bytes += frame_pixels * sizeof(uint32_t) * 4;  // mask, its readback, two lists
    bytes +=
        level_pixels[size_t(level_count - 2)] * (2 * sizeof(uint32_t) + 4 * sizeof(float));  // mid flags, list, colour
    bytes += frame_pixels * 4 * sizeof(float);                                               // blurred
  }
  if (settings.one_step_floor)
    bytes += frame_pixels * uint64_t(settings.samples_per_pixel) * sizeof(float);            // sample_depth
  if (settings.outputs != TraceOutputs::display) bytes += frame_pixels * 3 * sizeof(float);  // result: colour_linear
  if (settings.outputs == TraceOutputs::all)
    bytes += frame_pixels * sizeof(float) * (foveated ? 2 : 1);  // steps image, mask
  // Sampling models: the sample list and its read-back, colours, steps and their read-back, with
  // room for 1.3 samples a pixel (the hyperbolic layers' overlap, up to about 1.26; the linear
  // model's pull-push levels, 1.33 colours a pixel).
  if (settings.method == TraceMethod::sampling_model)
    bytes += frame_pixels * 13 / 10 * (4 * 4 * 2 + 4 * 4 + 4 * 2) + frame_pixels * 4 * 4 / 3;
  return bytes;
}

const char* method_name(TraceMethod method) {
  switch (method) {
    case TraceMethod::ground_truth:
      return "gt";
    case TraceMethod::inverted_pyramid:
      return "ipr";
    case TraceMethod::foveated_pyramid:
      return "fipr";
    case TraceMethod::sampling_model:
      return "sampling";
  }
  return "gt";
}

const char* coarse_test_name(CoarseTest test) { return test == CoarseTest::cone ? "cone" : "ray"; }
const char* periphery_reconstruction_name(PeripheryReconstruction reconstruction) {
  switch (reconstruction) {
    case PeripheryReconstruction::mid_footprint_bilinear:
      return "mid-footprint-bilinear";
    case PeripheryReconstruction::bilinear:
      return "bilinear";
    case PeripheryReconstruction::catmull_rom:
      return "catmull-rom";
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

const char* edge_depth_name(EdgeDepth edge_depth) {
  return edge_depth == EdgeDepth::centre_ray ? "centre-ray" : "level";
}

std::optional<EdgeDepth> parse_edge_depth(const std::string& name) {
  for (EdgeDepth edge_depth : kEdgeDepths)
    if (name == edge_depth_name(edge_depth)) return edge_depth;
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
    throw InputError("FIPR display of " + std::to_string(f.display.width_px) + "x" +
                     std::to_string(f.display.height_px) + " pixels: expected the frame's " +
                     std::to_string(settings.width) + "x" + std::to_string(settings.height));
  }
  const auto positive = [](double value) { return std::isfinite(value) && value > 0.0; };
  if (!positive(f.display.width_mm) || !positive(f.display.height_mm) || !positive(f.display.viewing_distance_mm)) {
    throw InputError("FIPR display: expected a positive finite width, height and viewing distance in mm");
  }
  if (!(std::isfinite(f.acuity.fovea_radius_deg) && f.acuity.fovea_radius_deg >= 0.0 &&
        f.acuity.fovea_radius_deg <= 180.0)) {
    throw SettingError("fovea_radius_deg", ": expected an eccentricity from 0 to 180 degrees");
  }
  if (std::isnan(f.acuity.outer_periphery_radius_deg) ||
      f.acuity.outer_periphery_radius_deg < f.acuity.fovea_radius_deg) {
    throw SettingError("outer_periphery_radius_deg", ": expected an eccentricity at least the fovea's");
  }
  if (f.periphery_refresh != 1 && f.periphery_refresh != 2 && f.periphery_refresh != 4) {
    throw SettingError("periphery_refresh", " " + std::to_string(f.periphery_refresh) +
                                                ": expected 1, 2 or 4 (frames between periphery updates)");
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
      throw SettingError(field,
                         " " + std::to_string(value) + ": expected 1 to " + std::to_string(kMaxFrameSide) + " pixels");
  };
  check_side(settings.width, "width");
  check_side(settings.height, "height");
  if (settings.eye) eye_view_shader_values(*settings.eye);  // InputError naming the view's field
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
    throw SettingError("pyramid_levels",
                       " " + std::to_string(settings.pyramid_levels) + ": expected 2 to 5 pyramid levels");
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
  if (settings.step_breakdown &&
      ((settings.method != TraceMethod::ground_truth && settings.method != TraceMethod::inverted_pyramid) ||
       settings.one_step_floor))
    throw SettingError("step_breakdown", ": expected the GT or IPR method, without the one-step floor");
  if (!(settings.over_relaxation >= 1.0f && settings.over_relaxation <= 2.0f))
    throw SettingError("over_relaxation", ": expected a factor from 1 to 2");
  if (settings.over_relaxation != 1.0f &&
      ((settings.method != TraceMethod::ground_truth && settings.method != TraceMethod::inverted_pyramid) ||
       settings.one_step_floor))
    throw SettingError("over_relaxation", ": expected the GT or IPR method (1: off), without the one-step floor");
  if (settings.method == TraceMethod::foveated_pyramid) validate_foveation(settings);
  if (settings.method == TraceMethod::sampling_model) {
    if (!settings.sampling) throw SettingError("sampling", ": expected a sampling model's map");
    if (screen_width_px(*settings.sampling) != settings.width ||
        screen_height_px(*settings.sampling) != settings.height)
      throw InputError("sampling map of " + std::to_string(screen_width_px(*settings.sampling)) + "x" +
                       std::to_string(screen_height_px(*settings.sampling)) + " pixels: expected the frame's " +
                       std::to_string(settings.width) + "x" + std::to_string(settings.height));
  }
}

SphereTracer::SphereTracer(vk::Context& context, const SceneSource& scene) : context_(context), scene_(scene) {
  CompiledShader trace =
      compile_scene_shader(scene, {"sphere_trace.comp.glsl", shaders::sphere_trace_source, shaders::shared_headers});
  shader_from_cache_ = trace.from_cache;
  variants_[""].spirv = std::move(trace.spirv);
  min_filter_pipeline_ =
      std::make_unique<vk::ComputePipeline>(context, shaders::min_filter_spirv, 2, sizeof(MinFilterParams));
  edges_pipeline_ = std::make_unique<vk::ComputePipeline>(context, shaders::depth_edges_spirv, 2, sizeof(EdgeParams));
  mask_pipeline_ = std::make_unique<vk::ComputePipeline>(context, shaders::foveation_mask_spirv, 6, sizeof(MaskParams));
  list_dispatch_pipeline_ =
      std::make_unique<vk::ComputePipeline>(context, shaders::list_dispatch_spirv, 2, sizeof(ListParams));
  mid_list_pipeline_ =
      std::make_unique<vk::ComputePipeline>(context, shaders::fipr_mid_list_spirv, 6, sizeof(MidListParams));
  reconstruct_pipeline_ =
      std::make_unique<vk::ComputePipeline>(context, shaders::fipr_reconstruct_spirv, 4, sizeof(FiprReconstructParams));
  blur_pipeline_ = std::make_unique<vk::ComputePipeline>(context, shaders::masked_blur_spirv, 3, sizeof(BlurParams));
  encoder_ = std::make_unique<Srgb8Encoder>(context);
}

// hit_distance's frame: one pixel's depth, steps and (unwritten) colour, the counters and a stand-in
// for the bindings it does not use, all host-visible so the pixel's depth is read where it lands.
struct SphereTracer::HitBuffers {
  vk::Buffer depth, steps, colour, counters, unused;
  explicit HitBuffers(const vk::Context& context)
      : depth(context, sizeof(float), vk::MemoryUse::host_readback),
        steps(context, sizeof(uint32_t), vk::MemoryUse::host_readback),
        colour(context, 4 * sizeof(float), vk::MemoryUse::host_readback),
        counters(context, gpu::COUNTER_COUNT * sizeof(uint32_t), vk::MemoryUse::host_readback),
        unused(context, 4 * sizeof(float), vk::MemoryUse::device_local) {}
};

SphereTracer::~SphereTracer() = default;

namespace {

// The eye turned so that its forward axis (-z) points along `direction` (unit): the shortest turn
// from -z, or half a turn about y when the direction is +z itself.
std::array<double, 4> orientation_looking_along(const std::array<double, 3>& direction) {
  const double w = 1.0 - direction[2];  // 1 + (-z . direction)
  if (w < 1e-12) return {0.0, 1.0, 0.0, 0.0};
  const std::array<double, 4> q{direction[1], -direction[0], 0.0, w};  // (-z x direction, w)
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[3] * q[3]);
  return {q[0] / norm, q[1] / norm, 0.0, q[3] / norm};
}

}  // namespace

std::optional<double> SphereTracer::hit_distance(const SurfaceRay& ray) {
  const auto& d = ray.direction_in_head;
  const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (!(std::isfinite(length) && length > 0.0))
    throw SettingError("direction_in_head", ": expected a finite direction that is not zero");
  for (double v : ray.origin_in_head)
    if (!std::isfinite(v)) throw SettingError("origin_in_head", ": expected a finite point");
  if (!(ray.hit_angle_rad > 0.0 && ray.hit_angle_rad <= 1.0))
    throw SettingError("hit_angle_rad", ": expected an angle in (0, 1] radians");
  if (ray.max_steps < 1 || ray.max_steps > 100000)
    throw SettingError("max_steps", " " + std::to_string(ray.max_steps) + ": expected 1 to 100000");
  if (!std::isfinite(ray.time_s)) throw SettingError("time_s", ": expected a finite number of seconds");

  // A one-pixel eye at the origin looking along the ray: its pixel centre's ray is the ray itself,
  // and its pixel angle (tan(up) - tan(down)) is the hit band asked for.
  EyeView eye;
  eye.position_in_head = ray.origin_in_head;
  eye.orientation_in_head = orientation_looking_along({d[0] / length, d[1] / length, d[2] / length});
  const double half_angle_rad = std::atan(0.5 * ray.hit_angle_rad);
  eye.field_of_view = {-half_angle_rad, half_angle_rad, half_angle_rad, -half_angle_rad};

  TraceParams params{};
  params.level_size[0] = params.level_size[1] = 1;
  params.start_size[0] = params.start_size[1] = 1;
  params.frame_size[0] = params.frame_size[1] = 1.0f;
  params.time_s = ray.time_s;
  params.hit_threshold = 1.0f;  // the band is all in the pixel angle
  params.samples_per_pixel = 1;
  params.max_steps = static_cast<uint32_t>(ray.max_steps);
  params.level_scale = 1;
  params.flags = 0;  // a depth level's ray: GT's march from the eye, unrefined, no cone
  set_eye_view(params, eye);

  if (!hit_) hit_ = std::make_unique<HitBuffers>(context_);
  HitBuffers& hit = *hit_;
  vk::OneTimeCommands commands(context_);
  const VkCommandBuffer cmd = commands.handle();
  vkCmdFillBuffer(cmd, hit.counters.handle(), 0, VK_WHOLE_SIZE, 0);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  const VkBuffer unused = hit.unused.handle();
  const VkBuffer buffers[] = {unused, hit.depth.handle(), hit.steps.handle(), hit.colour.handle(),
                              hit.counters.handle(), unused, unused, unused, unused, unused, unused};
  pipeline_for("#define FOVLAB_EYE_VIEW 1\n", params).dispatch_2d(cmd, buffers, &params, 1, 1);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                     VK_ACCESS_HOST_READ_BIT);
  commands.submit_and_wait();
  hit.depth.invalidate();
  float depth = 0.0f;
  std::memcpy(&depth, hit.depth.mapped(), sizeof depth);
  // The shader's MISS_DEPTH (1e18) marks a ray that left the bounds; any surface is far nearer.
  if (!std::isfinite(depth) || depth >= 1e17f) return std::nullopt;
  return double(depth);
}

// The top level's variant: FOVLAB_STEP_BREAKDOWN (the counting of SphereTraceSettings::step_breakdown)
// and FOVLAB_OVER_RELAX (its over_relaxation) beside the eye's view.
const vk::ComputePipeline& SphereTracer::top_level_pipeline(const SphereTraceSettings& settings,
                                                            const TraceParams& params) {
  std::string defines = settings.eye ? "#define FOVLAB_EYE_VIEW 1\n" : "";
  if (settings.step_breakdown) defines += "#define FOVLAB_STEP_BREAKDOWN 1\n";
  if (settings.over_relaxation != 1.0f) {
    std::ostringstream factor;
    factor.precision(9);
    factor << std::showpoint << settings.over_relaxation;
    defines += "#define FOVLAB_OVER_RELAX " + factor.str() + "\n";
  }
  return pipeline_for(defines, params);
}

const vk::ComputePipeline& SphereTracer::trace_pipeline(const SphereTraceSettings& settings,
                                                        const TraceParams& params) {
  return pipeline_for(settings.eye ? "#define FOVLAB_EYE_VIEW 1\n" : "", params);
}

const vk::ComputePipeline& SphereTracer::pipeline_for(const std::string& defines, const TraceParams& params) {
  TracerVariant& variant = variants_[defines];
  if (variant.spirv.empty()) {
    const std::string source = defines + std::string(shaders::sphere_trace_source);
    variant.spirv =
        compile_scene_shader(scene_, {"sphere_trace.comp.glsl (variant)", source, shaders::shared_headers}).spirv;
  }
  std::unique_ptr<vk::ComputePipeline>& pipeline = variant.pipelines[params.flags];
  if (!pipeline) {
    const uint32_t specialization[] = {params.flags};  // constant_id 0: fovlab_trace_flags
    pipeline =
        std::make_unique<vk::ComputePipeline>(context_, variant.spirv, 11, 0, sizeof(TraceParams), specialization);
  }
  return *pipeline;
}

namespace {

// Everything a FIPR frame's reusable pixels depend on, except gaze, scene time and frame index.
std::string history_key_of(const SphereTraceSettings& s) {
  const FoveationSettings& f = s.foveation;
  std::ostringstream key;
  key.precision(17);
  key << s.samples_per_pixel << ' ' << s.pyramid_levels << ' ' << s.min_filter_size << ' '
      << coarse_test_name(s.coarse_test) << ' ' << s.max_steps << ' ' << s.hit_threshold << ' ' << f.display.width_mm
      << ' ' << f.display.height_mm << ' ' << f.display.viewing_distance_mm << ' ' << f.acuity.fovea_radius_deg << ' '
      << f.acuity.outer_periphery_radius_deg << ' ' << static_cast<uint32_t>(f.combine) << ' ' << f.edge_threshold
      << ' ' << f.periphery_refresh << ' ' << f.periphery_steps << ' ' << f.seed << ' '
      << periphery_reconstruction_name(f.reconstruction) << ' ' << near_misses_name(f.near_misses) << ' '
      << edge_depth_name(f.edge_depth);
  if (s.eye) {  // each eye its own history
    key << " eye";
    for (double v : s.eye->position_in_head) key << ' ' << v;
    for (double v : s.eye->orientation_in_head) key << ' ' << v;
    const EyeFieldOfView& fov = s.eye->field_of_view;
    key << ' ' << fov.angle_left_rad << ' ' << fov.angle_right_rad << ' ' << fov.angle_up_rad << ' '
        << fov.angle_down_rad;
  }
  return key.str();
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
  if (settings.method == TraceMethod::sampling_model) return render_sampled(settings);
  prepare_frame(settings);
  FrameBuffers& frame = *frame_;
  const FoveationSettings& fov = settings.foveation;
  const bool foveated = settings.method == TraceMethod::foveated_pyramid;
  const int level_count = frame.layout.count();
  // A frame continues the sequence in the buffers only if it is the next one, with the same settings
  // (all but gaze, scene time and frame index); otherwise every pixel is refreshed.
  const std::string history_key = foveated ? history_key_of(settings) : std::string();
  const bool all_due = !frame.history_valid || fov.frame_index == 0 || fov.frame_index != frame.history_index + 1 ||
                       history_key != frame.history_key;
  // FIPR's depth levels track where their rays pass a surface (near depths), for the mid level's
  // promotion, which only a periphery from the mid level has, and the start of what it promoted.
  const bool near_misses = foveated && fov.near_misses == NearMisses::promote && fov.periphery_steps == 0;

  vk::OneTimeCommands commands(context_);
  vk::PassTimer timer(context_, static_cast<uint32_t>(2 * level_count + 10));
  FrameRecording f{settings, frame,       commands.handle(), timer,
                   foveated, level_count, level_count - 2,   settings.min_filter_size / 2,
                   all_due,  near_misses};
  clear_counters(f);

  // The depth levels, coarsest first, each starting from the one below (IPR, FIPR; GT has none).
  DepthStart start;
  for (int level = 0; level + 1 < level_count; ++level) {
    if (foveated && level == f.mid_index) {
      fipr_trace_mid_level(f, start);
    } else {
      trace_level(f, level, start);
    }
    if (foveated && level == 0) {
      fipr_edges(f);
      fipr_mask(f);
    }
    start = start_of_next_level(f, level);
  }
  // The top level: shaded.
  if (foveated) {
    fipr_trace_masked(f, start);
    if (fov.periphery_steps > 0) {
      fipr_trace_periphery(f, start);
    } else {
      fipr_reconstruct_periphery(f);
    }
    vk::compute_to_compute_barrier(commands.handle());
  } else if (settings.one_step_floor) {
    trace_ground_truth_floor(f, start);
  } else {
    trace_level(f, level_count - 1, start);
  }
  const vk::Buffer& shown = foveated && fov.blur ? fipr_blur(f) : frame.colour;

  const bool on_device = settings.outputs == TraceOutputs::display;
  frame.record_outputs(commands.handle(), timer, *encoder_, shown, on_device, [&](const auto& copy) {
    if (settings.outputs != TraceOutputs::all) return;
    if (foveated) copy(frame.mask, frame.mask_readback);
    for (const LevelBuffers& level : frame.levels) copy(level.steps, level.steps_readback);
  });
  commands.submit_and_wait();
  frame.history_valid = foveated;  // (a GT or IPR frame has its own layout: changing method resets history)
  frame.history_index = fov.frame_index;
  frame.history_key = history_key;

  SphereTraceResult result;
  result.passes = timer.results();
  for (const vk::PassTime& pass : result.passes) result.gpu_ms += pass.gpu_ms;
  const CounterValues counter_values = frame.read_outputs(context_, on_device, result);
  if (foveated) f.read_fipr_outputs(counter_values, result);
  f.read_level_stats(counter_values, result);
  if (settings.step_breakdown)
    result.step_breakdown = read_step_breakdown(counter_values, uint64_t(settings.width) * uint64_t(settings.height),
                                                uint64_t(settings.samples_per_pixel));
  return result;
}

void SphereTracer::FrameRecording::read_fipr_outputs(const CounterValues& counters, SphereTraceResult& result) const {
  const uint64_t frame_pixels = uint64_t(settings.width) * uint64_t(settings.height);
  result.foveation.masked_pixels = counters[gpu::COUNTER_MASKED_PIXELS];
  result.foveation.refreshed_pixels = counters[gpu::COUNTER_REFRESHED_PIXELS];
  result.foveation.kept_pixels =
      frame_pixels - counters[gpu::COUNTER_MASKED_PIXELS] - counters[gpu::COUNTER_REFRESHED_PIXELS];
  if (settings.outputs != TraceOutputs::all) return;
  frame.mask_readback.invalidate();
  const auto* mask = static_cast<const uint32_t*>(frame.mask_readback.mapped());
  result.mask = Image(settings.width, settings.height, 1);
  for (uint64_t p = 0; p < frame_pixels; ++p) result.mask.pixels[p] = mask[p] != 0 ? 1.0f : 0.0f;
}

// Every level pixel's steps are shared equally among the full-resolution pixels it covers, so the
// per-pixel image sums to total_steps.
void SphereTracer::FrameRecording::read_level_stats(const CounterValues& counters, SphereTraceResult& result) const {
  const FoveationSettings& fov = settings.foveation;
  if (settings.outputs == TraceOutputs::all) result.steps_per_pixel = Image(settings.width, settings.height, 1);
  for (int i = 0; i < level_count; ++i) {
    const LevelBuffers& level = frame.levels[size_t(i)];
    PyramidLevelStats stats = level.stats;
    stats.steps = 0;
    const uint64_t level_pixels = uint64_t(stats.width) * uint64_t(stats.height);
    const bool top = i + 1 == level_count;
    stats.traced_pixels = level_pixels;
    stats.shaded_pixels = top ? level_pixels : 0;
    if (foveated && top) {  // the masked pixels, and the periphery's refresh list when it is traced
      stats.traced_pixels = stats.shaded_pixels =
          counters[gpu::COUNTER_MASKED_PIXELS] +
          (fov.periphery_steps > 0 ? counters[gpu::COUNTER_REFRESH_LIST_PIXELS] : 0u);
    }
    if (foveated && i == mid_index) {
      stats.traced_pixels = counters[gpu::COUNTER_MID_TRACED_PIXELS];
      stats.shaded_pixels = counters[gpu::COUNTER_MID_SHADED_PIXELS];
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
  sampling.record_positions(cmd, timer, frame.counters.handle(), gpu::COUNTER_MASKED_PIXELS);

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
  set_eye_view(params, settings.eye);
  const VkBuffer unused = frame.unused.handle();
  const VkBuffer trace_buffers[] = {unused,
                                    unused,
                                    sampling.sample_steps(),
                                    sampling.sample_colours(),
                                    frame.counters.handle(),
                                    sampling.sample_list(),
                                    unused,
                                    unused,
                                    unused,
                                    unused,
                                    unused};
  timer.begin(cmd, "trace_samples");
  trace_pipeline(settings, params).dispatch_indirect(cmd, trace_buffers, &params, sampling.dispatch_arguments(), 0);
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
  const CounterValues counter_values = frame.read_outputs(context_, on_device, result);
  result.shaded_samples = counter_values[gpu::COUNTER_MASKED_PIXELS];

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
    for (const ListedSample& sample : sampling.listed_samples(counter_values[gpu::COUNTER_MASKED_PIXELS])) {
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
