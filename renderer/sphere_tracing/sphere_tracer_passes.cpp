// SphereTracer's passes (render() in sphere_tracer.cpp records them in order): the trace of a level,
// the min filter between levels, and FIPR's passes (Polychronakis et al. 2023): Sobel edges of the
// low level's depth, the foveation mask, the mid level traced from its list, the masked pixels
// traced at the top level, the periphery traced or reconstructed from the mid level, the masked
// blur. GT's one-step floor is here too.
#include <algorithm>
#include <cmath>
#include <string>

#include "renderer/shaders/shared/fipr_params.h"
#include "renderer/shaders/shared/list_dispatch_params.h"
#include "renderer/shaders/shared/sphere_trace_params.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "renderer/sphere_tracing/sphere_tracer_frame.h"
#include "renderer/vk/compute_pipeline.h"

namespace fovlab {

namespace {

constexpr double kGazeLimitPx = 1e7;  // gaze further off the frame is clamped (its eccentricities are ~90 degrees)

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
  params.principal_point_px[0] = static_cast<float>(f.display.principal_point_x_px());
  params.principal_point_px[1] = static_cast<float>(f.display.principal_point_y_px());
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

std::array<VkBuffer, 11> with_binding(std::array<VkBuffer, 11> buffers, size_t binding, VkBuffer buffer) {
  buffers[binding] = buffer;
  return buffers;
}

}  // namespace

TraceParams SphereTracer::FrameRecording::trace_params(int level_index, const DepthStart& start) const {
  const LevelBuffers& level = frame.levels[size_t(level_index)];
  const FoveationSettings& fov = settings.foveation;
  const bool top = level_index + 1 == level_count;
  const bool foveated_mid = foveated && level_index == mid_index;
  const bool foveated_top = foveated && top;
  TraceParams params{};
  params.level_size[0] = static_cast<uint32_t>(level.stats.width);
  params.level_size[1] = static_cast<uint32_t>(level.stats.height);
  params.start_size[0] = static_cast<uint32_t>(start.stats.width);
  params.start_size[1] = static_cast<uint32_t>(start.stats.height);
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
  const bool has_start = start.depth != nullptr;
  params.flags = (top ? gpu::FLAG_SHADE : 0u) | (has_start ? gpu::FLAG_HAS_START : 0u) |
                 (foveated_mid ? gpu::FLAG_FOVEATED_MID : 0u) | (foveated_top ? gpu::FLAG_FOVEATED_TOP : 0u) |
                 (settings.coarse_test == CoarseTest::cone ? gpu::FLAG_CONE : 0u) |
                 (has_start && start.stats.scale == level.stats.scale ? gpu::FLAG_START_SAME_SIZE : 0u) |
                 (near_misses ? gpu::FLAG_NEAR_MISS : 0u) |
                 (edge_depth_of_centre_ray(level_index) ? gpu::FLAG_EDGE_DEPTH : 0u);
  params.frame_index = fov.frame_index;
  params.periphery_steps = static_cast<uint32_t>(std::min(fov.periphery_steps, settings.max_steps));
  set_eye_view(params, settings.eye);
  return params;
}

// FIPR's low level under the cone, with the edges read from its centre ray (EdgeDepth::centre_ray):
// it also marches that ray on from where the cone stopped, into frame.edge_depth (binding 10).
bool SphereTracer::FrameRecording::edge_depth_of_centre_ray(int level_index) const {
  return foveated && level_index == 0 && settings.coarse_test == CoarseTest::cone &&
         settings.foveation.edge_depth == EdgeDepth::centre_ray;
}

std::array<VkBuffer, 11> SphereTracer::FrameRecording::trace_bindings(int level_index, const DepthStart& start) const {
  const LevelBuffers& level = frame.levels[size_t(level_index)];
  const bool top = level_index + 1 == level_count;
  const bool foveated_mid = foveated && level_index == mid_index;
  const bool foveated_top = foveated && top;
  const VkBuffer unused = frame.unused.handle();
  const VkBuffer colour_target = top ? frame.colour.handle() : foveated_mid ? frame.mid_colour.handle() : unused;
  const VkBuffer mask_input = foveated_top ? frame.mask.handle() : foveated_mid ? frame.mid_list.handle() : unused;
  // Near misses: a depth level reads the near depths of the level below and writes its own; the mid
  // level adds the children it promotes to the mask and its list; the top level starts those from
  // the mid level's near depths.
  const bool promotes = foveated_mid && near_misses;
  return {start.depth ? start.depth->handle() : unused,
          top ? unused : level.depth.handle(),
          level.steps.handle(),
          colour_target,
          frame.counters.handle(),
          mask_input,
          promotes ? frame.mask.handle() : unused,
          promotes ? frame.masked_list.handle() : unused,
          near_misses && level_index > 0 ? frame.levels[size_t(level_index - 1)].near_depth.handle() : unused,
          near_misses && !top ? level.near_depth.handle() : unused,
          edge_depth_of_centre_ray(level_index) ? frame.edge_depth.handle() : unused};
}

void SphereTracer::clear_counters(FrameRecording& f) {
  f.timer.reset(f.cmd);
  vkCmdFillBuffer(f.cmd, f.frame.counters.handle(), 0, VK_WHOLE_SIZE, 0);
  if (f.foveated && f.all_due)
    vkCmdFillBuffer(f.cmd, f.frame.mid_colour.handle(), 0, VK_WHOLE_SIZE, 0);  // alpha 0: not shaded yet
  if (f.foveated)
    vkCmdFillBuffer(f.cmd, f.frame.levels.back().steps.handle(), 0, VK_WHOLE_SIZE, 0);  // pixels not traced: 0
  vk::memory_barrier(f.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

void SphereTracer::trace_level(FrameRecording& f, int level_index, const DepthStart& start) {
  const TraceParams params = f.trace_params(level_index, start);
  const auto buffers = f.trace_bindings(level_index, start);
  // The top level's samples may run a variant of the tracer (step breakdown, over-relaxation).
  const bool top = level_index + 1 == f.level_count;
  const vk::ComputePipeline& pipeline =
      top ? top_level_pipeline(f.settings, params) : trace_pipeline(f.settings, params);
  f.timer.begin(f.cmd, "trace_level" + std::to_string(level_index));
  pipeline.dispatch_2d(f.cmd, buffers, &params, params.level_size[0], params.level_size[1]);
  f.timer.end(f.cmd);
  vk::compute_to_compute_barrier(f.cmd);
}

SphereTracer::DepthStart SphereTracer::start_of_next_level(FrameRecording& f, int level_index) {
  LevelBuffers& level = f.frame.levels[size_t(level_index)];
  if (f.filter_radius == 0) return {&level.depth, level.stats};
  MinFilterParams filter{{uint32_t(level.stats.width), uint32_t(level.stats.height)}, f.filter_radius};
  const VkBuffer filter_buffers[] = {level.depth.handle(), level.start_for_next.handle()};
  f.timer.begin(f.cmd, "min_filter_level" + std::to_string(level_index));
  min_filter_pipeline_->dispatch_2d(f.cmd, filter_buffers, &filter, filter.size[0], filter.size[1]);
  f.timer.end(f.cmd);
  vk::compute_to_compute_barrier(f.cmd);
  return {&level.start_for_next, level.stats};
}

void SphereTracer::trace_ground_truth_floor(FrameRecording& f, const DepthStart& start) {
  // GT's trace, untimed, recording where each sample stopped; then the timed floor from there.
  const SphereTraceSettings& settings = f.settings;
  FrameBuffers& frame = f.frame;
  const int top = f.level_count - 1;
  const TraceParams params = f.trace_params(top, start);
  const auto buffers = f.trace_bindings(top, start);
  const VkDeviceSize sample_bytes = VkDeviceSize(settings.width) * VkDeviceSize(settings.height) *
                                    VkDeviceSize(settings.samples_per_pixel) * sizeof(float);
  if (frame.sample_depth.size_bytes() != sample_bytes)
    frame.sample_depth = vk::Buffer(context_, sample_bytes, vk::MemoryUse::device_local);
  TraceParams record = params;
  record.flags |= gpu::FLAG_SAMPLE_DEPTH_OUT;
  const auto record_buffers = with_binding(buffers, 1, frame.sample_depth.handle());
  trace_pipeline(f.settings, record)
      .dispatch_2d(f.cmd, record_buffers, &record, params.level_size[0], params.level_size[1]);
  vk::compute_to_compute_barrier(f.cmd);
  vkCmdFillBuffer(f.cmd, frame.counters.handle(), 0, VK_WHOLE_SIZE, 0);  // the floor's own capped and restarted rays
  vk::memory_barrier(f.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  TraceParams floor_params = params;
  floor_params.flags |= gpu::FLAG_SAMPLE_DEPTH_IN;
  floor_params.max_steps = 1;
  const auto floor_buffers = with_binding(buffers, 0, frame.sample_depth.handle());
  f.timer.begin(f.cmd, "one_step_floor");
  trace_pipeline(f.settings, floor_params)
      .dispatch_2d(f.cmd, floor_buffers, &floor_params, params.level_size[0], params.level_size[1]);
  f.timer.end(f.cmd);
  vk::compute_to_compute_barrier(f.cmd);
}

void SphereTracer::dispatch_list_sizes(FrameRecording& f, const char* pass, const vk::Buffer& counts,
                                       uint32_t first_counter, uint32_t second_counter, uint32_t list_count) {
  const ListParams lists{{first_counter, second_counter}, list_count};
  const VkBuffer dispatch_buffers[] = {f.frame.counters.handle(), counts.handle()};
  f.timer.begin(f.cmd, pass);
  list_dispatch_pipeline_->dispatch_2d(f.cmd, dispatch_buffers, &lists, 1, 1);
  f.timer.end(f.cmd);
  vk::memory_barrier(f.cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                     VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT);
}

void SphereTracer::fipr_edges(FrameRecording& f) {
  const LevelBuffers& low = f.frame.levels.front();
  EdgeParams edge_params{{uint32_t(low.stats.width), uint32_t(low.stats.height)}, f.settings.foveation.edge_threshold};
  const VkBuffer edge_depth = f.edge_depth_of_centre_ray(0) ? f.frame.edge_depth.handle() : low.depth.handle();
  const VkBuffer edge_buffers[] = {edge_depth, f.frame.edges.handle()};
  f.timer.begin(f.cmd, "sobel_edges");
  edges_pipeline_->dispatch_2d(f.cmd, edge_buffers, &edge_params, edge_params.size[0], edge_params.size[1]);
  f.timer.end(f.cmd);
  vk::compute_to_compute_barrier(f.cmd);
}

void SphereTracer::fipr_mask(FrameRecording& f) {
  FrameBuffers& frame = f.frame;
  const MaskParams params =
      mask_params(f.settings, frame.levels.front().stats, frame.levels[size_t(f.mid_index)].stats, f.all_due);
  const VkBuffer mask_buffers[] = {frame.edges.handle(),    frame.mask.handle(),        frame.mid_flags.handle(),
                                   frame.counters.handle(), frame.masked_list.handle(), frame.refresh_list.handle()};
  f.timer.begin(f.cmd, "foveation_mask");
  mask_pipeline_->dispatch_2d(f.cmd, mask_buffers, &params, params.mid_size[0], params.mid_size[1]);
  f.timer.end(f.cmd);
  vk::compute_to_compute_barrier(f.cmd);
}

void SphereTracer::fipr_trace_mid_level(FrameRecording& f, const DepthStart& start) {
  FrameBuffers& frame = f.frame;
  LevelBuffers& level = frame.levels[size_t(f.mid_index)];
  const TraceParams params = f.trace_params(f.mid_index, start);
  // The pixels to trace, listed (the others take their start depth there), then traced densely.
  const MidListParams list_params{{params.level_size[0], params.level_size[1]},
                                  {params.start_size[0], params.start_size[1]},
                                  f.filter_radius,
                                  gpu::COUNTER_MID_LIST_PIXELS};
  const VkBuffer list_buffers[] = {frame.mid_flags.handle(), start.depth->handle(),   level.depth.handle(),
                                   level.steps.handle(),     frame.counters.handle(), frame.mid_list.handle()};
  f.timer.begin(f.cmd, "mid_list");
  mid_list_pipeline_->dispatch_2d(f.cmd, list_buffers, &list_params, params.level_size[0], params.level_size[1]);
  f.timer.end(f.cmd);
  vk::compute_to_compute_barrier(f.cmd);
  dispatch_list_sizes(f, "mid_list_dispatch", frame.mid_list_dispatch, gpu::COUNTER_MID_LIST_PIXELS, 0, 1);
  f.timer.begin(f.cmd, "trace_level" + std::to_string(f.mid_index));
  trace_pipeline(f.settings, params)
      .dispatch_indirect(f.cmd, f.trace_bindings(f.mid_index, start), &params, frame.mid_list_dispatch.handle(), 0);
  f.timer.end(f.cmd);
  // The top level's lists are complete now: the mask pass's, and the children this level promoted.
  vk::compute_to_compute_barrier(f.cmd);
  dispatch_list_sizes(f, "list_dispatch", frame.list_dispatch, gpu::COUNTER_MASKED_PIXELS,
                      gpu::COUNTER_REFRESH_LIST_PIXELS, 2);
  vk::compute_to_compute_barrier(f.cmd);
}

// The masked pixels, densely from their list. The periphery's pass that follows writes the other
// pixels (mask 0), so neither waits for the other.
void SphereTracer::fipr_trace_masked(FrameRecording& f, const DepthStart& start) {
  const int top = f.level_count - 1;
  TraceParams list_params = f.trace_params(top, start);
  list_params.flags = (list_params.flags & ~gpu::FLAG_FOVEATED_TOP) | gpu::FLAG_MASKED_LIST;
  const auto list_buffers = with_binding(f.trace_bindings(top, start), 5, f.frame.masked_list.handle());
  f.timer.begin(f.cmd, "trace_level" + std::to_string(top));
  trace_pipeline(f.settings, list_params)
      .dispatch_indirect(f.cmd, list_buffers, &list_params, f.frame.list_dispatch.handle(), 0);
  f.timer.end(f.cmd);
}

// The unmasked pixels due for a refresh, one ray each from the mid level's depth (periphery_steps > 0).
void SphereTracer::fipr_trace_periphery(FrameRecording& f, const DepthStart& start) {
  const int top = f.level_count - 1;
  TraceParams periphery_params = f.trace_params(top, start);
  periphery_params.samples_per_pixel = 1;  // one ray per peripheral pixel (also its texture footprint)
  const auto refresh_buffers = with_binding(f.trace_bindings(top, start), 5, f.frame.refresh_list.handle());
  f.timer.begin(f.cmd, "periphery_trace");
  trace_pipeline(f.settings, periphery_params)
      .dispatch_indirect(f.cmd, refresh_buffers, &periphery_params, f.frame.list_dispatch.handle(),
                         3 * sizeof(uint32_t));
  f.timer.end(f.cmd);
}

// The unmasked pixels due for a refresh from the mid level's colours (periphery_steps 0).
void SphereTracer::fipr_reconstruct_periphery(FrameRecording& f) {
  FrameBuffers& frame = f.frame;
  const PyramidLevelStats& top = frame.levels.back().stats;
  const PyramidLevelStats& mid = frame.levels[size_t(f.mid_index)].stats;
  const FoveationSettings& fov = f.settings.foveation;
  FiprReconstructParams reconstruct{{uint32_t(top.width), uint32_t(top.height)},
                                    {uint32_t(mid.width), uint32_t(mid.height)},
                                    static_cast<uint32_t>(fov.periphery_refresh),
                                    fov.frame_index,
                                    fov.reconstruction == PeripheryReconstruction::catmull_rom ? 1u : 0u};
  const VkBuffer reconstruct_buffers[] = {frame.mask.handle(), frame.mid_flags.handle(), frame.mid_colour.handle(),
                                          frame.colour.handle()};
  f.timer.begin(f.cmd, "reconstruct");
  reconstruct_pipeline_->dispatch_2d(f.cmd, reconstruct_buffers, &reconstruct, reconstruct.frame_size[0],
                                     reconstruct.frame_size[1]);
  f.timer.end(f.cmd);
}

const vk::Buffer& SphereTracer::fipr_blur(FrameRecording& f) {
  FrameBuffers& frame = f.frame;
  BlurParams blur{{uint32_t(f.settings.width), uint32_t(f.settings.height)}};
  const VkBuffer blur_buffers[] = {frame.colour.handle(), frame.mask.handle(), frame.blurred.handle()};
  f.timer.begin(f.cmd, "masked_blur");
  blur_pipeline_->dispatch_2d(f.cmd, blur_buffers, &blur, blur.size[0], blur.size[1]);
  f.timer.end(f.cmd);
  vk::compute_to_compute_barrier(f.cmd);
  return frame.blurred;
}

}  // namespace fovlab
