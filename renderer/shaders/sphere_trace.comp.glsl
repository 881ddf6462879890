// Sphere tracing of one pyramid level (or of the whole frame, for ground truth).
//
// Compiled at run time: the renderer prepends "#version 460" and the scene file (the scene
// interface of docs/scenes.md), then this text. One module serves every method:
//   - a pyramid level below the top traces one ray through each level pixel centre and writes the
//     distance it reached (depth) and its step count;
//   - the top level traces samples_per_pixel rays per pixel, shades them and writes colour and steps.
// A level with a start buffer begins each ray at the (min-filtered) depth of its parent pixel.

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer StartDepth { float start_depth[]; };
layout(std430, binding = 1) writeonly buffer LevelDepth { float level_depth[]; };
layout(std430, binding = 2) writeonly buffer LevelSteps { uint level_steps[]; };
layout(std430, binding = 3) writeonly buffer LevelColour { vec4 level_colour[]; };
layout(std430, binding = 4) buffer TraceCounters { uint capped_rays; uint restarted_rays; };

const uint FLAG_SHADE = 1u;       // top level: shade and write colour
const uint FLAG_HAS_START = 2u;   // start rays at start_depth of the parent pixel

layout(push_constant) uniform TraceParams {
  uvec2 level_size;          // pixels of this level
  uvec2 start_size;          // pixels of the start-depth buffer (the level below); unused without FLAG_HAS_START
  vec2 frame_size;           // pixels of the full-resolution frame
  float time_s;              // scene time
  float hit_threshold;       // a ray hits when distance < t * pixel_angle_rad * level_scale * hit_threshold
  uint samples_per_pixel;    // 1, 4 or 16 (top level only)
  uint max_steps;            // step cap of one ray at this level
  uint level_scale;          // full-resolution pixels per level pixel along each axis (1, 2, 4, ...)
  uint flags;
} params;

struct Ray { vec3 origin; vec3 direction; };

// Sub-pixel sample offsets in pixels from the pixel centre (docs/scenes.md "Anti-aliasing").
vec2 fovlab_sample_offset(uint sample_index, uint sample_count) {
  if (sample_count == 4u) {
    // Rotated grid: four samples, no two on a row or column.
    const vec2 rotated_grid[4] = vec2[4](vec2(-0.125, -0.375), vec2(0.375, -0.125),
                                         vec2(0.125, 0.375), vec2(-0.375, 0.125));
    return rotated_grid[sample_index];
  }
  if (sample_count == 16u) {
    // 4x4 regular grid of cell centres.
    return (vec2(float(sample_index % 4u), float(sample_index / 4u)) + 0.5) / 4.0 - 0.5;
  }
  return vec2(0.0);
}

// Camera ray through a point of the full-resolution frame, in pixels (y down). Also returns the
// angle one full-resolution pixel subtends at the image centre, in radians.
Ray fovlab_camera_ray(vec2 frame_point_px, out float pixel_angle_rad) {
  vec3 eye, target;
  float vertical_fov_deg;
  scene_camera(params.time_s, eye, target, vertical_fov_deg);
  vec3 forward = normalize(target - eye);
  vec3 right = normalize(cross(forward, vec3(0.0, 1.0, 0.0)));
  vec3 up = cross(right, forward);
  float tan_half_fov = tan(radians(vertical_fov_deg) * 0.5);
  vec2 ndc = (frame_point_px - 0.5 * params.frame_size) / (0.5 * params.frame_size.y);
  pixel_angle_rad = 2.0 * tan_half_fov / params.frame_size.y;
  Ray ray;
  ray.origin = eye;
  ray.direction = normalize(forward + tan_half_fov * (ndc.x * right - ndc.y * up));
  return ray;
}

// Parametric interval [t_enter, t_exit] of the ray inside the scene bounds; empty when t_exit < t_enter.
vec2 fovlab_bounds_interval(Ray ray) {
  vec3 inverse_direction = 1.0 / ray.direction;
  vec3 t0 = (SCENE_BOUNDS_MIN - ray.origin) * inverse_direction;
  vec3 t1 = (SCENE_BOUNDS_MAX - ray.origin) * inverse_direction;
  vec3 t_small = min(t0, t1);
  vec3 t_large = max(t0, t1);
  float t_enter = max(max(t_small.x, t_small.y), max(t_small.z, 0.0));
  float t_exit = min(min(t_large.x, t_large.y), t_large.z);
  return vec2(t_enter, t_exit);
}

const uint OUTCOME_HIT = 0u;
const uint OUTCOME_MISS = 1u;
const uint OUTCOME_CAPPED = 2u;

struct TraceResult { float t; uint steps; uint outcome; float distance; float material_id; };

// Sphere traces from t_start. A start inside geometry (a neighbour's depth behind a surface this ray
// meets earlier) shows as a negative distance at the first step; the ray then restarts where it
// enters the bounds. That first evaluation doubles as the first step of the march.
TraceResult fovlab_trace(Ray ray, float t_start, float epsilon_per_unit_t, bool refine_hit) {
  TraceResult result;
  result.steps = 0u;
  result.distance = 0.0;
  result.material_id = 0.0;
  vec2 interval = fovlab_bounds_interval(ray);
  float t = max(t_start, interval.x);
  bool check_start = t > interval.x;
  while (result.steps < params.max_steps) {
    if (t > interval.y) {
      result.t = interval.y;
      result.outcome = OUTCOME_MISS;
      return result;
    }
    vec2 sample_ = scene_map(ray.origin + t * ray.direction);
    result.steps += 1u;
    if (check_start) {
      check_start = false;
      if (sample_.x < 0.0) {
        t = interval.x;
        atomicAdd(restarted_rays, 1u);
        continue;
      }
    }
    if (sample_.x < epsilon_per_unit_t * t) {
      // Where the hit is shaded, one refining step onto the surface (within the cap): the shaded
      // point then depends far less on where the march started, so IPR and GT shade the same point
      // (thin detail such as flutes otherwise shades differently within the epsilon band). Depth
      // levels keep the unrefined, slightly conservative distance.
      if (refine_hit && result.steps < params.max_steps) {
        t += sample_.x;
        sample_ = scene_map(ray.origin + t * ray.direction);
        result.steps += 1u;
      }
      result.t = t;
      result.outcome = OUTCOME_HIT;
      result.distance = sample_.x;
      result.material_id = sample_.y;
      return result;
    }
    t += sample_.x;
  }
  result.t = t;
  result.outcome = OUTCOME_CAPPED;
  vec2 final_sample = scene_map(ray.origin + t * ray.direction);
  result.distance = final_sample.x;
  result.material_id = final_sample.y;
  atomicAdd(capped_rays, 1u);
  return result;
}

// Forward differences from the hit point, whose distance the trace already has: three evaluations.
vec3 fovlab_normal(vec3 p, float distance_at_p, float epsilon) {
  return normalize(vec3(scene_map(p + vec3(epsilon, 0.0, 0.0)).x, scene_map(p + vec3(0.0, epsilon, 0.0)).x,
                        scene_map(p + vec3(0.0, 0.0, epsilon)).x) - distance_at_p);
}

vec3 fovlab_shade(Ray ray, TraceResult hit, float epsilon_per_unit_t) {
  if (hit.outcome == OUTCOME_MISS) return scene_background(ray.direction);
  vec3 p = ray.origin + hit.t * ray.direction;
  vec3 normal = fovlab_normal(p, hit.distance, max(epsilon_per_unit_t * hit.t, 1e-6));
  // World-space width of this sample's share of the pixel on the surface, for texture filtering:
  // the footprint across the ray, stretched by the obliquity of the surface (clamped at grazing).
  float across_ray = epsilon_per_unit_t / params.hit_threshold * hit.t / sqrt(float(params.samples_per_pixel));
  float footprint = across_ray / max(abs(dot(normal, ray.direction)), 0.1);
  vec3 albedo = scene_albedo(hit.material_id, p, normal, footprint);
  vec3 irradiance = scene_ambient(normal);
  for (int i = 0; i < SCENE_LIGHT_COUNT; ++i) {
    vec4 position;
    vec3 radiance;
    scene_light(i, params.time_s, position, radiance);
    vec3 to_light = position.xyz;
    float falloff = 1.0;
    if (position.w != 0.0) {
      to_light = position.xyz - p;
      float distance_squared = max(dot(to_light, to_light), 1e-8);
      falloff = 1.0 / distance_squared;
    }
    irradiance += radiance * falloff * max(dot(normal, normalize(to_light)), 0.0);
  }
  return scene_fog(albedo * irradiance, hit.t, ray.direction);
}

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (any(greaterThanEqual(pixel, params.level_size))) return;
  uint index = pixel.y * params.level_size.x + pixel.x;

  float t_start = 0.0;
  if ((params.flags & FLAG_HAS_START) != 0u) {
    uvec2 parent = min(pixel / 2u, params.start_size - 1u);
    t_start = start_depth[parent.y * params.start_size.x + parent.x];
  }

  float scale = float(params.level_scale);
  vec2 centre_px = (vec2(pixel) + 0.5) * scale;
  if ((params.flags & FLAG_SHADE) == 0u) {
    float pixel_angle_rad;
    Ray ray = fovlab_camera_ray(centre_px, pixel_angle_rad);
    TraceResult result = fovlab_trace(ray, t_start, pixel_angle_rad * scale * params.hit_threshold, false);
    level_depth[index] = result.t;
    level_steps[index] = result.steps;
    return;
  }

  vec3 colour_sum = vec3(0.0);
  uint steps = 0u;
  for (uint s = 0u; s < params.samples_per_pixel; ++s) {
    float pixel_angle_rad;
    Ray ray = fovlab_camera_ray(centre_px + fovlab_sample_offset(s, params.samples_per_pixel) * scale,
                                pixel_angle_rad);
    float epsilon_per_unit_t = pixel_angle_rad * scale * params.hit_threshold;
    TraceResult result = fovlab_trace(ray, t_start, epsilon_per_unit_t, true);
    steps += result.steps;
    colour_sum += fovlab_shade(ray, result, epsilon_per_unit_t);
  }
  level_colour[index] = vec4(colour_sum / float(params.samples_per_pixel), 1.0);
  level_steps[index] = steps;
}
