#version 460
// The gaze-contingent three-zone blend of the emulated foveated path tracer (seed 001 section 3.2):
// each pixel mixes the full-resolution (foveal), upsampled 1/4 (middle) and upsampled 1/16 (outer)
// buffers by its exact eccentricity from the gaze. renderer/zone_blend/zone_layout.cpp is the
// reference (zone_weights, blend_zones_reference). Outside the bands a pixel reads one buffer and
// writes one, a copy's memory traffic, and needs no arctangent.
#extension GL_GOOGLE_include_directive : require
#include "eccentricity.glsl"

// One invocation a pixel in row-major order: a workgroup covers 64 consecutive pixels of a row,
// which lavapipe runs far faster than 8x8 tiles (contiguous SIMD loads and stores).
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Foveal { vec4 foveal[]; };
layout(std430, binding = 1) readonly buffer Middle { vec4 middle[]; };
layout(std430, binding = 2) readonly buffer Outer { vec4 outer[]; };
layout(std430, binding = 3) writeonly buffer Blended { vec4 blended[]; };

const uint MODE_BLEND = 0u;
const uint MODE_COPY = 1u;  // the baseline: the same dispatch copying the foveal buffer

layout(push_constant) uniform BlendParams {
  // Squared tangents of the band edges (radius -/+ band / 2): foveal inner, foveal outer, middle
  // inner, middle outer; -1 below 0 degrees, a huge value from 90 degrees. Outside the bands the
  // zone follows from tan^2 of the eccentricity, |a x b|^2 / (a . b)^2, without an arctangent.
  vec4 edge_tan2;           // first: a vec4 is 16-byte aligned
  uvec2 frame_size;
  vec2 gaze_px;
  vec2 pixel_pitch_mm;
  float viewing_distance_mm;
  float foveal_radius_deg;  // half the foveal zone's aperture
  float middle_radius_deg;  // half the middle zone's; < 0 when there is no middle zone
  float band_deg;
  uint mode;
} params;

float inside_weight(float eccentricity, float boundary, float band) {
  if (band <= 0.0) return eccentricity <= boundary ? 1.0 : 0.0;
  return clamp((boundary + 0.5 * band - eccentricity) / band, 0.0, 1.0);
}

void main() {
  uvec2 pixel = uvec2(gl_GlobalInvocationID.x, gl_GlobalInvocationID.y);
  if (pixel.x >= params.frame_size.x) return;
  uint index = pixel.y * params.frame_size.x + pixel.x;
  if (params.mode == MODE_COPY) {
    blended[index] = foveal[index];
    return;
  }
  vec3 gaze_ray = ray_from_eye(params.gaze_px, params.frame_size, params.pixel_pitch_mm, params.viewing_distance_mm);
  vec3 point_ray = ray_from_eye(vec2(pixel) + 0.5, params.frame_size, params.pixel_pitch_mm, params.viewing_distance_mm);
  vec3 normal = cross(gaze_ray, point_ray);
  float cosine = dot(gaze_ray, point_ray);
  float tan2 = cosine > 0.0 ? dot(normal, normal) / (cosine * cosine) : 3.0e38;
  bool has_middle = params.middle_radius_deg >= 0.0;
  vec4 colour;
  if (tan2 <= params.edge_tan2.x) {
    colour = foveal[index];
  } else if (tan2 > params.edge_tan2.y && has_middle && tan2 <= params.edge_tan2.z) {
    colour = middle[index];
  } else if (tan2 > params.edge_tan2.y && (!has_middle || tan2 > params.edge_tan2.w)) {
    colour = outer[index];
  } else {  // in a band: the exact angle
    float eccentricity = eccentricity_between_deg(gaze_ray, point_ray);
    float foveal_weight = inside_weight(eccentricity, params.foveal_radius_deg, params.band_deg);
    float middle_weight = has_middle ? (1.0 - foveal_weight) * inside_weight(eccentricity, params.middle_radius_deg, params.band_deg) : 0.0;
    float outer_weight = 1.0 - foveal_weight - middle_weight;
    colour = vec4(0.0);
    if (foveal_weight > 0.0) colour += foveal_weight * foveal[index];
    if (middle_weight > 0.0) colour += middle_weight * middle[index];
    if (outer_weight > 0.0) colour += outer_weight * outer[index];
  }
  blended[index] = colour;
}
