#version 460
// Pass 1b of the sampling models (Ye et al. 2022) on pre-rendered path-traced frames: each listed sample
// takes the frame's mean over its footprint, the square of side footprint_px centred on its
// position, every frame pixel weighted by the area it shares with the square (clipped to the
// screen). It is what a path tracer gives a sample whose paths are spread over that footprint, as
// the sphere tracer spreads a sample's rays (sphere_trace.comp.glsl's FLAG_SAMPLE_LIST); a
// footprint of one pixel is the bilinear read of the frame. renderer/foveated_sampling/
// frame_sampler.cpp's footprint_mean is the CPU reference.
#extension GL_GOOGLE_include_directive : require
#include "shared/sampling_params.h"

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Counters { uint counters[]; };
layout(std430, binding = 1) readonly buffer SampleList { uint sample_list[]; };  // x, y, footprint, entry
layout(std430, binding = 2) readonly buffer Frame { vec4 frame[]; };             // linear RGBA, row-major
layout(std430, binding = 3) writeonly buffer SampleColours { vec4 sample_colours[]; };

layout(push_constant) uniform FrameReadParamsBlock { FrameReadParams params; };

void main() {
  uint slot = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationIndex;
  if (slot >= counters[params.counter_index]) return;
  vec2 position = vec2(uintBitsToFloat(sample_list[4u * slot]), uintBitsToFloat(sample_list[4u * slot + 1u]));
  float footprint = uintBitsToFloat(sample_list[4u * slot + 2u]);
  // At least a pixel; a position that is not a number reads the first pixel (neither happens with
  // the maps' positions, but nothing here may turn into a NaN colour).
  if (!(footprint >= 1.0)) footprint = 1.0;
  if (isnan(position.x)) position.x = 0.5;
  if (isnan(position.y)) position.y = 0.5;
  uint entry = sample_list[4u * slot + 3u];
  vec2 size = vec2(params.frame_size);
  // The square, clipped to the screen; a sample just off the screen (KFR's, within reach of a
  // pixel at the edge) reads the nearest pixel-wide square on it.
  vec2 low = max(position - 0.5 * footprint, vec2(0.0));
  vec2 high = min(position + 0.5 * footprint, size);
  if (any(lessThanEqual(high, low))) {
    vec2 inside = clamp(position, vec2(0.5), size - 0.5);
    low = inside - 0.5;
    high = inside + 0.5;
  }
  ivec2 first = ivec2(floor(low));
  ivec2 last = min(ivec2(ceil(high)) - 1, ivec2(params.frame_size) - 1);
  vec4 sum = vec4(0.0);
  float weight_sum = 0.0;
  for (int y = first.y; y <= last.y; ++y) {
    float wy = min(high.y, float(y + 1)) - max(low.y, float(y));
    if (wy <= 0.0) continue;
    for (int x = first.x; x <= last.x; ++x) {
      float wx = min(high.x, float(x + 1)) - max(low.x, float(x));
      if (wx <= 0.0) continue;
      sum += (wx * wy) * frame[uint(y) * params.frame_size.x + uint(x)];
      weight_sum += wx * wy;
    }
  }
  sample_colours[entry] = vec4(weight_sum > 0.0 ? sum.rgb / weight_sum : vec3(0.0), 1.0);
}
