#version 460
// The gaze-contingent three-zone blend of the emulated foveated path tracer (seed 001 section 3.2):
// each pixel mixes the full-resolution (foveal), upsampled 1/4 (middle) and upsampled 1/16 (outer)
// buffers by its exact eccentricity from the gaze. renderer/zone_blend/zone_layout.cpp is the
// reference (zone_weights, blend_zones_reference).
//
// Two variants (specialization constant OUTPUT_SRGB8): the linear-light blend, all four channels as
// float (previews, tests), and the frame a participant sees, sRGB-encoded to 8 bits a channel and
// packed RGBA in one uint (alpha 255), which is a quarter of the writes and of the read-back.
//
// Outside the bands a pixel reads one zone texel and writes one, a copy's memory traffic, and needs
// no arctangent: the zone follows from tan^2 of the eccentricity. The three zones share one buffer,
// so one load instruction at a computed index reads them all. That matters on lavapipe, which runs
// both sides of every branch under a lane mask and spends as much on a load whose lanes are all
// masked as on one that reads: a load in each of three branches, one buffer a zone, cost three
// loads a pixel there. A loop, unlike a branch, runs only as often as its busiest lane needs.

// One invocation a pixel in row-major order: a workgroup covers 64 consecutive pixels of a row,
// which lavapipe runs far faster than 8x8 tiles (contiguous SIMD loads and stores).
layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(constant_id = 0) const uint OUTPUT_SRGB8 = 0u;

// The zone buffers one after the other, each frame_size.x * frame_size.y texels: foveal, middle, outer.
// Two views of it: RGBA texels, and the same texels' colour alone (a load of three channels).
struct ZoneColour { vec3 rgb; float unread; };  // 16 bytes in std430, as a vec4
layout(std430, binding = 0) readonly buffer Zones { vec4 zones[]; };
layout(std430, binding = 0) readonly buffer ZoneColours { ZoneColour zone_colours[]; };
layout(std430, binding = 1) writeonly buffer BlendedLinear { vec4 blended_linear[]; };  // OUTPUT_SRGB8 = 0
layout(std430, binding = 1) writeonly buffer BlendedSrgb8 { uint blended_srgb8[]; };    // OUTPUT_SRGB8 = 1

layout(push_constant) uniform BlendParams {
  // Squared tangents of the band edges (radius -/+ band / 2): foveal inner, foveal outer, middle
  // inner, middle outer; -1 below 0 degrees, a huge value from 90 degrees. Outside the bands the
  // zone follows from tan^2 of the eccentricity, |g x p|^2 / (g . p)^2 for the unit ray g to the
  // gaze and the ray p to the pixel, without an arctangent.
  vec4 edge_tan2;
  // In the eye's millimetres (renderer/foveation/display_geometry.h): g, made on the CPU in double
  // (ZoneBlender::record_blend), so that a gaze far off the screen stays exact; pixel (x, y)'s
  // centre at (first_pixel_mm + (x, y) * pixel_pitch_mm, viewing_distance_mm).
  vec3 gaze_direction;
  float viewing_distance_mm;
  vec2 first_pixel_mm;
  vec2 pixel_pitch_mm;
  uvec2 frame_size;
  // Inside a band the weight of the inner zone is clamp((band_end - e) / band, 0, 1) for the
  // eccentricity e in degrees: band_end = radius + band / 2 of the foveal and the middle boundary.
  vec2 band_end_deg;
  float band_per_deg;       // 1 / band (bands of 0 degrees have no pixels inside)
  uint has_middle;          // 0: no middle zone (its radius is not beyond the fovea's)
} params;

// core/colour.cpp's encode_srgb, then rounded to the nearest of 256 levels.
uint srgb8(float linear) {
  float value = clamp(isnan(linear) ? 0.0 : linear, 0.0, 1.0);
  float encoded = value <= 0.0031308 ? 12.92 * value : 1.055 * pow(value, 1.0 / 2.4) - 0.055;
  return uint(floor(encoded * 255.0 + 0.5));
}

// A zone buffer's texel as the variant needs it: the sRGB frame reads three channels, not four.
vec4 texel(uint i) { return OUTPUT_SRGB8 == 1u ? vec4(zone_colours[i].rgb, 1.0) : zones[i]; }

void main() {
  uvec2 pixel = uvec2(gl_GlobalInvocationID.x, gl_GlobalInvocationID.y);
  if (pixel.x >= params.frame_size.x) return;
  uint index = pixel.y * params.frame_size.x + pixel.x;

  vec3 point_ray = vec3(fma(vec2(pixel), params.pixel_pitch_mm, params.first_pixel_mm), params.viewing_distance_mm);
  vec3 normal = cross(params.gaze_direction, point_ray);
  float cosine = dot(params.gaze_direction, point_ray);
  float tan2 = cosine > 0.0 ? dot(normal, normal) / (cosine * cosine) : 3.0e38;
  bool has_middle = params.has_middle != 0u;
  float foveal_weight, middle_weight;
  if ((tan2 > params.edge_tan2.x && tan2 <= params.edge_tan2.y) ||
      (has_middle && tan2 > params.edge_tan2.z && tan2 <= params.edge_tan2.w)) {  // in a band: the exact angle
    float eccentricity = degrees(atan(length(normal), cosine));
    vec2 inside = clamp((params.band_end_deg - eccentricity) * params.band_per_deg, 0.0, 1.0);
    foveal_weight = inside.x;
    middle_weight = has_middle ? (1.0 - inside.x) * inside.y : 0.0;
  } else {
    foveal_weight = tan2 <= params.edge_tan2.x ? 1.0 : 0.0;
    middle_weight = foveal_weight == 0.0 && has_middle && tan2 <= params.edge_tan2.z ? 1.0 : 0.0;
  }
  float outer_weight = 1.0 - foveal_weight - middle_weight;

  // The zones with a weight, innermost to outermost, read by one load in a loop: outside the bands
  // it runs once. (A band between the fovea and the outer zone when there is no middle one skips
  // the middle with a weight of 0.)
  vec3 weights = vec3(foveal_weight, middle_weight, outer_weight);
  uint first_zone = foveal_weight > 0.0 ? 0u : middle_weight > 0.0 ? 1u : 2u;
  uint last_zone = outer_weight > 0.0 ? 2u : middle_weight > 0.0 ? 1u : 0u;
  uint zone_texels = params.frame_size.x * params.frame_size.y;
  vec4 colour = vec4(0.0);
  for (uint zone = first_zone; zone <= last_zone; ++zone) colour += weights[zone] * texel(zone * zone_texels + index);
  if (OUTPUT_SRGB8 == 1u) {
    blended_srgb8[index] = srgb8(colour.r) | (srgb8(colour.g) << 8) | (srgb8(colour.b) << 16) | (255u << 24);
  } else {
    blended_linear[index] = colour;
  }
}
