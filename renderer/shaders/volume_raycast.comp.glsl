#version 460
// The volume raycaster (Bruder et al. 2019; docs/volume-rendering.md): one ray per pixel (the full frame) or
// per site of the Voronoi sampling mask (the foveated frame). Along the ray through the volume's box:
// trilinear samples of the 16-bit voxels, post-classified by the 1-D transfer function (a table,
// read linearly), Phong-shaded with a headlight from central-difference gradients, composited front
// to back until the opacity reaches 0.99 (early ray termination); bricks whose value range the
// transfer function makes fully transparent are stepped over (empty-space skipping); the first
// sample is jittered by a hash of (seed, frame, pixel). The foveated step grows with the distance to
// the gaze, step = base x (1 + 2 |s - c| / W), and the opacity is corrected for the step taken,
// alpha = 1 - (1 - alpha_ref)^(step / reference), the reference being half a voxel (switchable for
// the foveated step, to measure what the authors' uncorrected code loses). renderer/volume/volume_raycaster.cpp fills the parameters and is its reference.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#include "lowbias32.glsl"
#include "shared/volume_params.h"

const uint MODE_FULL = 0u;
const uint MODE_SITES = 1u;

layout(std430, binding = 0) readonly buffer VolumeRayParamsBuffer { VolumeRayParams params; };
layout(std430, binding = 1) readonly buffer Voxels { uint voxels[]; };         // two 16-bit voxels a word, x fastest
layout(std430, binding = 2) readonly buffer Transfer { vec4 transfer[]; };     // RGBA over 0..1
layout(std430, binding = 3) readonly buffer Bricks { uint brick_visible[]; };  // 1: some sample in it may be seen
// Mask positions (MODE_SITES), then per site its readers' box as two vec2 (lowest mask pixel, highest
// plus one): the mask pixels that read its colour, and its own pixel.
layout(std430, binding = 4) readonly buffer Sites { vec2 sites[]; };
layout(std430, binding = 5) writeonly buffer Colours { vec4 colours[]; };      // per pixel (MODE_FULL)
layout(std430, binding = 6) writeonly buffer SiteColours { uvec2 site_colours[]; };  // per site (MODE_SITES): RGB as half floats

float voxel(ivec3 p) {
  ivec3 size = ivec3(params.volume_size.xyz);
  p = clamp(p, ivec3(0), size - 1);
  uint index = (uint(p.z) * uint(size.y) + uint(p.y)) * uint(size.x) + uint(p.x);
  uint word = voxels[index >> 1u];
  return float((index & 1u) == 0u ? (word & 0xFFFFu) : (word >> 16u)) * (1.0 / 65535.0);
}

// Trilinear at a position in voxel units (voxel i's centre at i + 0.5), clamped to the edge.
float sample_volume(vec3 v) {
  vec3 q = v - 0.5;
  vec3 base = floor(q);
  vec3 f = q - base;
  ivec3 b = ivec3(base);
  float c000 = voxel(b), c100 = voxel(b + ivec3(1, 0, 0)), c010 = voxel(b + ivec3(0, 1, 0)), c110 = voxel(b + ivec3(1, 1, 0));
  float c001 = voxel(b + ivec3(0, 0, 1)), c101 = voxel(b + ivec3(1, 0, 1)), c011 = voxel(b + ivec3(0, 1, 1)), c111 = voxel(b + ivec3(1, 1, 1));
  float c00 = mix(c000, c100, f.x), c10 = mix(c010, c110, f.x), c01 = mix(c001, c101, f.x), c11 = mix(c011, c111, f.x);
  return mix(mix(c00, c10, f.y), mix(c01, c11, f.y), f.z);
}

vec4 classify(float value) {
  float position = clamp(value, 0.0, 1.0) * float(transfer.length() - 1);
  uint low = uint(floor(position));
  uint high = min(low + 1u, uint(transfer.length() - 1));
  return mix(transfer[low], transfer[high], position - float(low));
}

// The slab test of a ray against an axis-aligned box: the entry and exit distances.
vec2 box_hit(vec3 origin, vec3 direction, vec3 low, vec3 high) {
  vec3 inverse = 1.0 / direction;  // +-inf for an axis-parallel ray: the comparisons still hold
  vec3 t0 = (low - origin) * inverse, t1 = (high - origin) * inverse;
  vec3 near = min(t0, t1), far = max(t0, t1);
  return vec2(max(max(near.x, near.y), near.z), min(min(far.x, far.y), far.z));
}

vec3 trace(vec2 screen_px, uint pixel_hash) {
  vec2 ndc = screen_px / vec2(params.screen.xy) * 2.0 - 1.0;
  float tan_half = params.forward.w;
  vec3 direction = normalize(params.forward.xyz + ndc.x * tan_half * params.right.w * params.right.xyz +
                             ndc.y * tan_half * params.down.xyz);
  vec3 background = params.background.rgb;
  vec2 hit = box_hit(params.eye.xyz, direction, -params.box_half.xyz, params.box_half.xyz);
  float t_enter = max(hit.x, 0.0);
  if (!(hit.y > t_enter)) return background;
  // Marching restarts at the entry point, so a camera far away (1e5 sides) keeps the precision of the
  // steps (a float t of 1e5 would not move by a step of 1e-3).
  vec3 entry = params.eye.xyz + t_enter * direction;
  float length_inside = hit.y - t_enter;
  float step_size = params.box_half.w;
  if (params.gaze.z > 0.5)
    step_size *= 1.0 + 2.0 * length(screen_px - params.gaze.xy) / float(params.screen.x);
  // The transfer function's opacity is for the reference step; corrected for the step taken (the
  // foveated step when gaze.w says so, else the base step, as the authors' code does).
  float exponent = (params.gaze.w > 0.5 ? step_size : params.box_half.w) / params.background.w;
  vec3 to_voxels = params.voxel_scale.xyz;
  vec3 v0 = (entry + params.box_half.xyz) * to_voxels;  // the entry in voxel units
  vec3 dv = direction * to_voxels;                      // voxels per world unit along the ray
  float jitter = float(lowbias32(pixel_hash) >> 8) * (1.0 / 16777216.0);
  float t = jitter * step_size;
  vec3 colour = vec3(0.0);
  float alpha = 0.0;
  uint brick_side = params.volume_size.w;
  ivec3 bricks = ivec3(params.brick_count.xyz);
  uint limit = uint(params.voxel_scale.w);
  for (uint iteration = 0u; iteration < limit && t < length_inside; ++iteration) {
    vec3 v = v0 + t * dv;
    ivec3 brick = clamp(ivec3(floor(v / float(brick_side))), ivec3(0), bricks - 1);
    if (brick_visible[(uint(brick.z) * uint(bricks.y) + uint(brick.y)) * uint(bricks.x) + uint(brick.x)] == 0u) {
      // Step over the brick: on to the first step of the jittered grid past its far side.
      vec3 low = vec3(brick) * float(brick_side), high = low + float(brick_side);
      float t_exit = box_hit(v0, dv, low, high).y;
      t = max(t + step_size, ceil((t_exit - t) / step_size + 1e-4) * step_size + t);
      continue;
    }
    vec4 sample_colour = classify(sample_volume(v));
    if (sample_colour.a > 0.0) {
      float sample_alpha = 1.0 - pow(max(1.0 - sample_colour.a, 0.0), exponent);
      vec3 gradient = vec3(sample_volume(v + vec3(1, 0, 0)) - sample_volume(v - vec3(1, 0, 0)),
                           sample_volume(v + vec3(0, 1, 0)) - sample_volume(v - vec3(0, 1, 0)),
                           sample_volume(v + vec3(0, 0, 1)) - sample_volume(v - vec3(0, 0, 1))) * to_voxels;
      float light = params.shading.x + params.shading.y;  // unshaded where the field is flat
      float gradient_length = length(gradient);
      if (gradient_length > 1e-6) {
        float facing = abs(dot(gradient / gradient_length, direction));  // a headlight, two-sided
        light = params.shading.x + params.shading.y * facing;
        sample_colour.rgb = sample_colour.rgb * light + params.shading.z * pow(facing, params.shading.w);
      } else {
        sample_colour.rgb *= light;
      }
      colour += (1.0 - alpha) * sample_alpha * sample_colour.rgb;
      alpha += (1.0 - alpha) * sample_alpha;
      if (alpha >= 0.99) break;
    }
    t += step_size;
  }
  return colour + (1.0 - alpha) * background;
}

void main() {
  if (params.screen.z == MODE_FULL) {
    uvec2 pixel = gl_GlobalInvocationID.xy;
    if (pixel.x >= params.screen.x || pixel.y >= params.screen.y) return;
    uint hash = pixel.x + lowbias32(pixel.y + lowbias32(uint(params.mask_offset.w) + lowbias32(uint(params.mask_offset.z))));
    colours[pixel.y * params.screen.x + pixel.x] = vec4(trace(vec2(pixel) + 0.5, hash), 1.0);
    return;
  }
  uint site = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationIndex;
  if (site >= params.screen.w) return;
  vec2 position = sites[site] - vec2(params.mask_offset.xy);
  // Sites beyond every screen pixel's neighbours are not traced (their colour is never read).
  if (any(lessThan(position, params.sites_window.xy)) || any(greaterThan(position, params.sites_window.zw))) return;
  if (params.brick_count.w == 1u) {  // only the sites some screen pixel reads, and those on the screen
    vec2 low = sites[params.screen.w + 2u * site] - vec2(params.mask_offset.xy);
    vec2 high = sites[params.screen.w + 2u * site + 1u] - vec2(params.mask_offset.xy);
    if (any(greaterThanEqual(low, vec2(params.screen.xy))) || any(lessThanEqual(high, vec2(0.0)))) return;
  }
  uvec2 pixel = uvec2(clamp(floor(position), vec2(0.0), vec2(params.screen.xy) - 1.0));
  uint hash = pixel.x + lowbias32(pixel.y + lowbias32(uint(params.mask_offset.w) + lowbias32(uint(params.mask_offset.z))));
  vec3 colour = trace(position, hash);
  site_colours[site] = uvec2(packHalf2x16(colour.rg), packHalf2x16(vec2(colour.b, 1.0)));
}
