#version 460
// Pass 1a of the sampling models (Ye et al. 2022): where this frame's samples lie on the screen. One
// invocation per entry of the model's sample buffer (the reduced buffer of RMFR and KFR, the three
// layers of the hyperbolic model, the screen's pixels for the linear model); an entry that is
// shaded appends (x, y, footprint, entry) to the sample list, which the sphere tracer traces
// (FLAG_SAMPLE_LIST) or the pre-rendered frame is read at. Entries not listed are not shaded:
// KFR's that fall further off the screen than their bilinear reach, the hyperbolic layers' where the layer has no weight, the linear
// model's pixels whose threshold is at or above their probability.
// The footprint is the samples' spacing on the screen there, along the axis where they lie
// furthest apart (as a mip level is chosen), in pixels, at least 1: it widens the ray's hit threshold
// and texture filter the way a coarser pyramid level does, so a pattern finer than the samples is
// filtered rather than aliased.
// foveation/sampling_map.cpp is the CPU reference (shaded_samples counts the same entries).
#extension GL_GOOGLE_include_directive : require
#include "eccentricity.glsl"
#include "lowbias32.glsl"
#include "sampling_map.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = 1) buffer Counters { uint counters[]; };
// One sample a uvec4 (x, y, footprint as float bits, entry), written with one store: on lavapipe each
// store runs lane by lane, so four word stores cost four times one.
layout(std430, binding = 2) writeonly buffer SampleList { uvec4 sample_list[]; };

layout(push_constant) uniform PositionParamsBlock { PositionParams params; };

// The model this pipeline lists (MODEL_*, equal to the parameters' model), fixed when SamplingPasses
// makes it: lavapipe runs both sides of a branch under a mask, so with the model read at run time each
// entry paid for the other models' maps too.
layout(constant_id = 0) const uint POSITIONS_MODEL = MODEL_RECTANGULAR;

void write_sample(uint slot, vec2 position_px, float footprint_px, uint entry) {
  sample_list[slot] = uvec4(floatBitsToUint(position_px.x), floatBitsToUint(position_px.y),
                            floatBitsToUint(max(footprint_px, 1.0)), entry);
}

void append(vec2 position_px, float footprint_px, uint entry) {
  write_sample(atomicAdd(counters[params.counter_index], 1u), position_px, footprint_px, entry);
}

// Whether a sample serves a screen pixel: within `margin_px` of the screen (a pixel at the edge
// reads its bilinear taps from there).
bool serves_screen(vec2 point_px, float margin_px) {
  return all(greaterThanEqual(point_px, vec2(-margin_px))) &&
         all(lessThan(point_px, vec2(sampling.screen_size) + margin_px));
}

// The point `distance_px` along the line from the gaze through `point_px` (sampling_map.cpp).
vec2 along_gaze_line(vec2 point_px, float distance_px) {
  vec2 d = point_px - sampling.gaze_px;
  float length_px = length(d);
  if (length_px == 0.0) return point_px + vec2(max(distance_px, 0.0), 0.0);
  return sampling.gaze_px + d * (max(0.0, length_px + distance_px) / length_px);
}

void main() {
  uvec2 cell = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(cell, sampling.buffer_size))) return;
  uint entry = cell.y * sampling.buffer_size.x + cell.x;
  if (entry >= sampling.sample_capacity) return;
  vec2 screen = vec2(sampling.screen_size);
  vec2 buffer_centre = vec2(cell) + 0.5;

  if (POSITIONS_MODEL == MODEL_RECTANGULAR) {
    vec2 share = buffer_centre / vec2(sampling.buffer_size);
    vec2 screen_share = vec2(rmfr_to_screen(share.x, sampling.gaze_share.x, sampling.focal_share.x),
                             rmfr_to_screen(share.y, sampling.gaze_share.y, sampling.focal_share.y));
    // Buffer pixels per screen pixel along each axis; the spacing is its inverse.
    vec2 per_pixel = vec2(rmfr_axis_density(screen_share.x, sampling.gaze_share.x, sampling.focal_share.x),
                          rmfr_axis_density(screen_share.y, sampling.gaze_share.y, sampling.focal_share.y)) *
                     vec2(sampling.buffer_size) / screen;
    // Every entry of RMFR's buffer is a sample: each takes the slot of its entry, and one invocation
    // counts them all, instead of one atomic a sample (each of which lavapipe runs lane by lane).
    // The list's order does not reach a frame: the tracer writes each sample to its entry.
    write_sample(entry, screen_share * screen, 1.0 / min(per_pixel.x, per_pixel.y), entry);
    if (entry == 0u) atomicAdd(counters[params.counter_index], sampling.sample_capacity);
  } else if (POSITIONS_MODEL == MODEL_KERNEL_LOG_POLAR) {
    vec2 position = kfr_to_screen_px(buffer_centre);
    vec2 spacings = kfr_spacings_px(buffer_centre.x);
    if (serves_screen(position, spacings.x + spacings.y)) append(position, max(spacings.x, spacings.y), entry);
  } else if (POSITIONS_MODEL == MODEL_HYPERBOLIC) {
    for (int i = 0; i < 3; ++i) {
      SamplingLayer layer = sampling.layers[i];
      uint count = layer.grid_size.x * layer.grid_size.y;
      if (entry < layer.first_sample || entry >= layer.first_sample + count) continue;
      uint local = entry - layer.first_sample;
      vec2 centre = layer.origin_px + (vec2(local % layer.grid_size.x, local / layer.grid_size.x) + 0.5) * layer.pixel_size_px;
      float reach_px = 2.0 * layer.pixel_size_px;
      bool needed = sampling_eccentricity_deg(along_gaze_line(centre, -reach_px)) <= layer.weight_range_deg.y &&
                    sampling_eccentricity_deg(along_gaze_line(centre, reach_px)) >= layer.weight_range_deg.x;
      if (needed) append(centre, layer.pixel_size_px, entry);
      return;
    }
  } else if (POSITIONS_MODEL == MODEL_LINEAR) {
    if (pixel_threshold(sampling.seed, 0u, cell) < linear_probability(buffer_centre)) append(buffer_centre, 1.0, entry);
  }
}
