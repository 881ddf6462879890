#pragma once
// Sphere tracing of an SDF scene: ground truth (GT, every sample traced from the camera), the
// inverted pyramid (IPR, Polychronakis et al. 2023 section 3.1/3.2.4: each level starts its rays at the min-filtered
// depth of the level below; only the top level shades) and its foveated form (FIPR, section 3.2:
// Sobel edges of the low level and the acuity model choose the pixels traced at the top level; the
// rest take the mid level's colour, or one traced ray, refreshed every 1st, 2nd or 4th frame;
// optional masked blur). docs/foveation.md. The sampling models of Ye et al. 2022 (RMFR, hyperbolic, linear,
// KFR: foveation/sampling_map.h) shade only their samples (renderer/foveated_sampling/).
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/render_choices.h"
#include "foveation/acuity_model.h"
#include "foveation/display_geometry.h"
#include "foveation/foveation_mask.h"
#include "foveation/sampling_map.h"
#include "renderer/present/device_frame.h"
#include "renderer/scene/eye_view.h"
#include "renderer/scene/scene_source.h"
#include "renderer/sphere_tracing/step_breakdown.h"
#include "renderer/vk/submission.h"

namespace fovlab {

namespace vk {
class Context;
class Buffer;
class ComputePipeline;
}  // namespace vk
namespace gpu {
struct TraceParams;
}  // namespace gpu
class Srgb8Encoder;
class SamplingPasses;

enum class TraceMethod { ground_truth, inverted_pyramid, foveated_pyramid, sampling_model };

const char* method_name(TraceMethod method);  // "gt", "ipr", "fipr" or "sampling"
std::optional<TraceMethod> parse_trace_method(const std::string& name);

// The names of core/render_choices.h's PeripheryReconstruction: "mid-footprint-bilinear", "bilinear",
// "catmull-rom" (the CLI's and the config's words).
const char* periphery_reconstruction_name(PeripheryReconstruction reconstruction);
std::optional<PeripheryReconstruction> parse_periphery_reconstruction(const std::string& name);

// The names of core/render_choices.h's NearMisses: "ignore", "promote" (the CLI's and the config's words).
const char* near_misses_name(NearMisses near_misses);
std::optional<NearMisses> parse_near_misses(const std::string& name);

// The names of core/render_choices.h's EdgeDepth: "level", "centre-ray" (the CLI's and the config's words).
const char* edge_depth_name(EdgeDepth edge_depth);
std::optional<EdgeDepth> parse_edge_depth(const std::string& name);

// FIPR's inputs beyond IPR's (docs/foveation.md). The display's pixel counts must equal the frame's.
struct FoveationSettings {
  DisplayGeometry display;
  double gaze_x_px = 0.0;  // gaze in frame pixels; non-finite: no gaze, every pixel traced in full
  double gaze_y_px = 0.0;
  AcuityModel acuity;  // fovea (eccentricity, degrees) and outer periphery
  MaskCombine combine = MaskCombine::max;
  float edge_threshold = 0.4f;  // Sobel magnitude of the low-level depth relative to the depth
  int periphery_refresh = 1;    // unmasked pixels get a new colour every 1st, 2nd or 4th frame
  int periphery_steps = 0;      // unmasked pixels: 0: the mid level's colour, interpolated as
      // `reconstruction` says (Polychronakis et al. 2023's reading); N > 0: traced (1 sample) from the mid depth with
      // a budget of min(N, max_steps) steps and shaded at full resolution
  PeripheryReconstruction reconstruction = PeripheryReconstruction::bilinear;  // periphery_steps 0
  NearMisses near_misses = NearMisses::promote;
  EdgeDepth edge_depth = EdgeDepth::centre_ray;  // the low level's depth its Sobel edges read (EdgeDepth)
  bool blur = false;         // pass 5: masked Gaussian blur
  uint32_t seed = 0;         // of the per-pixel thresholds
  uint32_t frame_index = 0;  // frame of a sequence; 0 starts one (every pixel refreshed)
};

// What render() gives besides the statistics and the pass times.
enum class TraceOutputs {
  all,      // the linear colour, steps per pixel and (FIPR) the mask, read back: render, bench, analysis
  colour,   // the linear colour alone, read back
  display,  // nothing read back: the colour sRGB8-encoded on the device (SphereTraceResult::display),
            // what a session shows, for a presenter on the same device or a read-back when needed
};

// The names of core/render_choices.h's CoarseTest.
const char* coarse_test_name(CoarseTest test);  // "ray" or "cone" (the CLI's and the config's words)

struct SphereTraceSettings {
  TraceMethod method = TraceMethod::ground_truth;
  int width = 640;
  int height = 360;
  int samples_per_pixel = 1;  // 1, 4 or 16 (docs/scenes.md: sample patterns)
  float time_s = 0.0f;
  int pyramid_levels = 3;                           // IPR: 2..5 levels, each with 1/4 the pixels of the one above
  int min_filter_size = 3;                          // IPR: 1, 3 or 5
  CoarseTest coarse_test = CoarseTest::centre_ray;  // IPR and FIPR: the depth levels' stopping rule
  bool full_resolution_depth = false;  // IPR: one depth ray per pixel (a level of the frame's size, started
                                       // from the level below and min-filtered like it) before the shaded
                                       // samples, which then start from it instead of from the half-size level
  int max_steps = 256;                 // step cap of one ray at one level
  float hit_threshold = 0.25f;         // hit when distance < t * pixel angle * level scale * hit_threshold
  // GT only, `fovlab bench`'s floor: an untimed GT pass records where each sample's trace stopped,
  // then every sample starts there and takes one step and its shading, the least a sphere tracer
  // can spend on this frame. The result's passes (and gpu_ms) are that second pass alone.
  bool one_step_floor = false;
  // GT and IPR, `fovlab bench --step-breakdown`: the top level traced by the tracer's step-breakdown
  // variant, which counts where its samples' steps go (SphereTraceResult::step_breakdown); the frame
  // is the same, bit for bit. Off, the plain tracer runs, with no counting compiled in.
  bool step_breakdown = false;
  // GT and IPR, a prototype of issue 41 (docs/benchmarks.md "Where the steps go"): the top level's
  // samples step up to this many times the distance bound (Keinert et al. 2014's over-relaxation,
  // 1 to 2), each step's factor the largest the spheres' overlap test would accept on a plane at the
  // slope the last step measured, by a variant of the tracer. 1: off, the plain tracer.
  float over_relaxation = 1.0f;
  FoveationSettings foveation;  // FIPR only
  // A headset eye's view (renderer/scene/eye_view.h): the scene's camera is the head, the frame the
  // eye's asymmetric frustum. None: the scene camera's symmetric frustum. FIPR and the sampling
  // models take their display from it (eye_display), which the caller sets.
  std::optional<EyeView> eye;
  // TraceMethod::sampling_model: the frame's map, whose screen is width x height. Each sample is
  // traced with samples_per_pixel rays spread over its footprint, from the camera (no pyramid).
  std::optional<SamplingMap> sampling;
  ResampleFilter sampling_filter = ResampleFilter::bilinear;  // how pass 2 reads the samples
  TraceOutputs outputs = TraceOutputs::all;
};

// Validates sizes and options; throws SettingError naming the field of the settings and what was
// expected (the CLI words it as its flag), or InputError for a display that is not the frame's.
void validate(const SphereTraceSettings& settings);

// The memory one render of these settings holds, in bytes: the tracer's frame buffers (counted in
// full: on a CPU device such as lavapipe they are host memory) and the images of its result.
// `fovlab render` and `fovlab bench` refuse sizes that would not fit (core/memory_budget.h).
uint64_t render_memory_bytes(const SphereTraceSettings& settings);

// At most this many samples a frame (pixels x samples per pixel): keeps buffers and one submit bounded.
constexpr uint64_t kMaxSphereTraceSamplesPerFrame = uint64_t{1} << 28;
// The field a SettingError names when width x height x samples_per_pixel is over that.
inline constexpr const char* kSamplesPerFrameField = "width x height x samples_per_pixel";

// The frame's colour must fit one storage buffer of the device: throws InputError
// "<size_name> = WxH: the frame needs N MiB in one buffer; expected at most M MiB on <device>".
// `size_name` says where the size came from: "--width x --height" for a command, a study config's
// fields for a study.
void check_sphere_trace_frame_bytes(const vk::Context& context, int width, int height, const std::string& size_name);

struct PyramidLevelStats {
  int width = 0;
  int height = 0;
  int scale = 1;               // full-resolution pixels per level pixel along each axis
  uint64_t steps = 0;          // all steps of all rays of this level
  uint64_t traced_pixels = 0;  // level pixels whose ray was traced this frame (all but in FIPR's mid and top)
  uint64_t shaded_pixels = 0;  // level pixels shaded this frame (the top level; FIPR's mid level too)

  double traced_share() const { return double(traced_pixels) / (double(width) * double(height)); }
};

// FIPR's frame at a glance.
struct FoveationStats {
  uint64_t masked_pixels = 0;     // traced at the top level
  uint64_t refreshed_pixels = 0;  // unmasked pixels given a new colour this frame (mid level's, or traced)
  uint64_t kept_pixels = 0;       // unmasked pixels that kept last frame's colour (refresh 2 and 4)
};

struct SphereTraceResult {
  Image colour_linear;       // RGB, linear light (empty: TraceOutputs::display)
  Image steps_per_pixel;     // 1 channel: the pixel's own steps plus its share of the levels below (TraceOutputs::all)
  DeviceRgba8Frame display;  // TraceOutputs::display: the frame on the device, valid until the next render
  uint64_t total_steps = 0;
  uint64_t capped_rays = 0;               // rays stopped by max_steps before a hit or leaving the bounds
  uint64_t restarted_rays = 0;            // IPR rays whose start depth was inside geometry, restarted at the bounds
  std::vector<PyramidLevelStats> levels;  // bottom (coarsest) first; GT and the sampling models have one
  FoveationStats foveation;               // FIPR only
  Image mask;                             // FIPR, TraceOutputs::all: 1 channel, 1 where traced at the top level;
                                          // sampling models: the samples shaded in each pixel
  uint64_t shaded_samples = 0;            // sampling models: samples traced and shaded this frame
  std::optional<StepBreakdown> step_breakdown;  // SphereTraceSettings::step_breakdown: the top level's
  std::vector<vk::PassTime> passes;
  double gpu_ms = 0.0;  // sum of the passes

  // All steps over the full-resolution pixel count (with spp samples the floor is about spp).
  double mean_steps_per_pixel() const { return double(total_steps) / double(colour_linear.pixel_count()); }
};

// One ray to the scene's first surface (issue 42: a headset's gaze resting on the rendered depth).
// The ray starts at origin_in_head and runs along direction_in_head in the head's frame, the frame
// of renderer/scene/eye_view.h (the scene camera at time_s is the head: x right, y up, z backwards;
// scene units).
struct SurfaceRay {
  float time_s = 0.0f;                                 // scene time, as SphereTraceSettings::time_s
  std::array<double, 3> origin_in_head{0.0, 0.0, 0.0};
  std::array<double, 3> direction_in_head{0.0, 0.0, -1.0};  // any length but 0
  // The march's hit band: it stops where the scene's distance is under hit_angle_rad x t. A GT frame
  // uses its pixel angle x SphereTraceSettings::hit_threshold; give the same to meet its surfaces.
  double hit_angle_rad = 1e-3;
  int max_steps = 256;  // as SphereTraceSettings::max_steps
};

// Compiles a scene's tracer once (or takes it from the shader cache) and renders frames of it.
class SphereTracer {
 public:
  SphereTracer(vk::Context& context, const SceneSource& scene);
  ~SphereTracer();
  SphereTracer(const SphereTracer&) = delete;
  SphereTracer& operator=(const SphereTracer&) = delete;

  bool shader_from_cache() const { return shader_from_cache_; }
  SphereTraceResult render(const SphereTraceSettings& settings);
  // The distance along the ray (unit direction, scene units) to where it meets the scene: GT's own
  // march (the shader's, through a one-pixel frame whose eye sits at the ray's origin and looks
  // along it, its pixel hit_angle_rad wide), read back. nullopt: the ray leaves the scene's bounds
  // without meeting a surface (the sky). A ray stopped by max_steps gives where it stopped, as a GT
  // frame shades that point as the surface. How exact: the march stops at the first point whose
  // distance bound is under hit_angle_rad x t, before GT's refining step, so with a scene whose
  // distance is exact (a true SDF) it is never beyond the surface and short of it by at most
  // hit_angle_rad x t / cos(incidence) (the angle between the ray and the surface's normal), plus
  // the shader's float rounding (about 1e-6 of t). SettingError for a direction that is not finite
  // and non-zero, an origin that is not finite, a hit_angle_rad not in (0, 1] or max_steps not in
  // 1..100000.
  std::optional<double> hit_distance(const SurfaceRay& ray);

 private:
  struct FrameBuffers;                                      // the buffers of one frame layout (sphere_tracer_frame.h)
  struct FrameRecording;                                    // one render being recorded
  struct DepthStart;                                        // where a level's rays start
  void prepare_frame(const SphereTraceSettings& settings);  // the buffers of its frame layout, kept if they fit
  // The tracer that runs a pass with these push constants, made on the first frame that asks for
  // it: sphere_trace.comp.glsl with the variant's #defines, specialised on the pass's flags
  // (params.flags, constant_id 0), so each pass's code has only its own paths. top_level_pipeline:
  // the top level's shaded samples, which may run a variant (step breakdown, over-relaxation);
  // trace_pipeline: every other pass, plain or, with a headset eye's view, with FOVLAB_EYE_VIEW (so
  // the plain tracer's code, and its frames, stay what they were). Each call site pushes the same
  // params it chose the pipeline by.
  const vk::ComputePipeline& top_level_pipeline(const SphereTraceSettings& settings, const gpu::TraceParams& params);
  const vk::ComputePipeline& trace_pipeline(const SphereTraceSettings& settings, const gpu::TraceParams& params);
  const vk::ComputePipeline& pipeline_for(const std::string& defines, const gpu::TraceParams& params);
  SphereTraceResult render_sampled(const SphereTraceSettings& settings);
  // render()'s passes (sphere_tracer_passes.cpp), in the order a frame records them.
  void clear_counters(FrameRecording& f);  // and FIPR's mid colours when it has no history
  void trace_level(FrameRecording& f, int level_index, const DepthStart& start);  // GT, IPR, FIPR's depth levels
  void fipr_edges(FrameRecording& f);                                         // Sobel edges of the low level's depth
  void fipr_mask(FrameRecording& f);                                          // the foveation mask and its lists
  void fipr_trace_mid_level(FrameRecording& f, const DepthStart& start);      // from its list; lists the top's
  DepthStart start_of_next_level(FrameRecording& f, int level_index);         // min-filtered depth
  void trace_ground_truth_floor(FrameRecording& f, const DepthStart& start);  // GT, then one step from there
  void fipr_trace_masked(FrameRecording& f, const DepthStart& start);         // the top level's masked pixels
  void fipr_trace_periphery(FrameRecording& f, const DepthStart& start);      // periphery_steps > 0
  void fipr_reconstruct_periphery(FrameRecording& f);                         // periphery_steps 0
  const vk::Buffer& fipr_blur(FrameRecording& f);                             // the masked blur: the shown frame
  void dispatch_list_sizes(FrameRecording& f, const char* pass, const vk::Buffer& counts, uint32_t first_counter,
                           uint32_t second_counter, uint32_t list_count);
  vk::Context& context_;
  SceneSource scene_;  // for the variants' compiles
  bool shader_from_cache_ = false;
  struct TracerVariant {  // sphere_trace.comp.glsl compiled with some #defines
    std::vector<uint32_t> spirv;
    std::map<uint32_t, std::unique_ptr<vk::ComputePipeline>> pipelines;  // by the flags they are specialised on
  };
  std::map<std::string, TracerVariant> variants_;  // by their #defines ("": the plain tracer, compiled first)
  std::unique_ptr<vk::ComputePipeline> min_filter_pipeline_;
  std::unique_ptr<vk::ComputePipeline> edges_pipeline_;
  std::unique_ptr<vk::ComputePipeline> mask_pipeline_;
  std::unique_ptr<vk::ComputePipeline> list_dispatch_pipeline_;
  std::unique_ptr<vk::ComputePipeline> mid_list_pipeline_;
  std::unique_ptr<vk::ComputePipeline> reconstruct_pipeline_;
  std::unique_ptr<vk::ComputePipeline> blur_pipeline_;
  std::unique_ptr<Srgb8Encoder> encoder_;
  std::unique_ptr<SamplingPasses> sampling_;  // made on the first sampled frame
  std::unique_ptr<FrameBuffers> frame_;       // buffers of the last frame layout rendered (FIPR: its history)
  struct HitBuffers;                          // hit_distance's one-pixel frame, made on its first call
  std::unique_ptr<HitBuffers> hit_;
};

}  // namespace fovlab
