// Sphere tracing of one pyramid level (or of the whole frame, for ground truth).
//
// Compiled at run time: the renderer prepends "#version 460" and the scene file (the scene
// interface of docs/scenes.md), then this text. One module serves every method:
//   - a pyramid level below the top traces one ray through each level pixel centre and writes the
//     distance it reached (depth) and its step count;
//   - the top level traces samples_per_pixel rays per pixel, shades them and writes colour and steps.
// A level with a start buffer begins each ray at the (min-filtered) depth of its parent pixel.
// FIPR (Polychronakis et al. 2023 section 3.2.4) adds two variants, both steered by the foveation mask:
//   - the mid level (FLAG_FOVEATED_MID) traces the pixels fipr_mid_list.comp.glsl listed: those
//     whose depth the top level needs (a masked pixel within the min filter's radius) or whose
//     unmasked children are due for a refresh, and shades them (one sample) in the second case; that
//     pass has already passed the other pixels' start depth on;
//   - the top level runs twice: over the list of masked pixels (FLAG_MASKED_LIST, an indirect
//     dispatch of 64 list entries a workgroup), tracing and shading them as IPR does; then, when
//     the periphery is traced (periphery_steps > 0), over the list of unmasked pixels due for a
//     refresh (FLAG_FOVEATED_TOP): each is traced from the mid depth with that step budget and
//     shaded. Pixels not listed keep the value they have (the colour buffer persists between
//     frames: the reduced periphery refresh). With periphery_steps 0, fipr_reconstruct.comp.glsl
//     fills the unmasked pixels from the mid level instead.
// Two switches of the pyramid (docs/scenes.md "Inverted pyramid"):
//   - FLAG_CONE: a depth level marches the cone of its whole pixel (corners and the top level's hit
//     band included) and stops where geometry may enter it, so no ray of a finer level, which lies
//     inside that cone, can meet a surface in front of the depth passed on (the conservative pyramid);
//     without it a depth level traces the ray through its pixel's centre (the paper's);
//   - FLAG_START_SAME_SIZE: the start buffer has this level's size (the full-resolution depth level
//     below the shaded samples), so each pixel starts from its own entry rather than its parent's.
// The sampling models of Ye et al. 2022 (FLAG_SAMPLE_LIST) trace and shade one list of screen positions
// (sampling_positions.comp.glsl) with spp samples each, spread and filtered over the samples'
// spacing (their footprint) as a pyramid level's scale does.

#extension GL_GOOGLE_include_directive : require
#include "shared/fipr_params.h"
#include "shared/sphere_trace_params.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer StartDepth { float start_depth[]; };
layout(std430, binding = 1) writeonly buffer LevelDepth { float level_depth[]; };
layout(std430, binding = 2) writeonly buffer LevelSteps { uint level_steps[]; };
layout(std430, binding = 3) writeonly buffer LevelColour { vec4 level_colour[]; };
layout(std430, binding = 4) buffer TraceCounters { uint counters[COUNTER_COUNT]; };  // COUNTER_*
layout(std430, binding = 5) readonly buffer FoveationMask { uint mask_values[]; };  // FIPR: a pixel list
// FIPR with FLAG_NEAR_MISS (fovlab_near_miss_depth): each depth level writes where its ray passed a
// surface (near_depth; NO_NEAR_MISS where none), read by the level above (parent_near_depth); the mid
// level adds the unmasked children of such a pixel to the full-resolution mask and the masked pixels'
// list, and the top level starts those from the mid level's near depth.
layout(std430, binding = 6) buffer PromotedMask { uint promoted_mask[]; };
layout(std430, binding = 7) writeonly buffer PromotedList { uint promoted_list[]; };
layout(std430, binding = 8) readonly buffer ParentNearDepth { float parent_near_depth[]; };
layout(std430, binding = 9) writeonly buffer NearDepth { float near_depth[]; };
// FLAG_EDGE_DEPTH (fovlab_edge_depth): FIPR's low level under the cone writes its centre ray's depth,
// which its Sobel edges read (depth_edges.comp.glsl).
layout(std430, binding = 10) writeonly buffer CentreRayDepth { float edge_depth[]; };
const float NO_NEAR_MISS = -1.0;

// An entry of the masked pixels' list that the mid level promoted (it starts from the mid level's
// near depth; the mask pass's entries start from the filtered depth, as IPR's pixels).
const uint fovlab_promoted_entry = 0x80000000u;

layout(push_constant) uniform TraceParamsBlock { TraceParams params; };
// The pass's FLAG_*, as a specialization constant: each pass runs a pipeline made for its own flags
// (SphereTracer::pipeline_for), so its code holds only its own paths. lavapipe runs the straight-line
// code of a branch that no invocation takes (docs/benchmarks.md, "The tracer specialised by its pass").
layout(constant_id = 0) const uint fovlab_trace_flags = 0u;

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

// The frame's camera: eye, basis and field of view, the same for every ray of the frame. main()
// makes it once per invocation (scene_camera may cost trigonometry), not once per ray or sample.
struct fovlab_camera_basis { vec3 eye; vec3 forward; vec3 right; vec3 up; float tan_half_fov; };
fovlab_camera_basis fovlab_camera;

void fovlab_set_camera() {
  vec3 target;
  float vertical_fov_deg;
  scene_camera(params.time_s, fovlab_camera.eye, target, vertical_fov_deg);
  fovlab_camera.forward = normalize(target - fovlab_camera.eye);
  fovlab_camera.right = normalize(cross(fovlab_camera.forward, vec3(0.0, 1.0, 0.0)));
  fovlab_camera.up = cross(fovlab_camera.right, fovlab_camera.forward);
  fovlab_camera.tan_half_fov = tan(radians(vertical_fov_deg) * 0.5);
#ifdef FOVLAB_EYE_VIEW
  if (params.eye_view != 0u) {
    // A headset eye (TraceParams::eye_view): the scene's camera is the head; the eye sits at
    // eye_position along the head's right, up and backward axes and looks along them turned by
    // eye_orientation (v' = v + 2 q.xyz x (q.xyz x v + q.w v)).
    mat3 head = mat3(fovlab_camera.right, fovlab_camera.up, -fovlab_camera.forward);
    fovlab_camera.eye += head * params.eye_position;
    vec4 q = params.eye_orientation;
    mat3 turn = mat3(1.0);
    for (int axis = 0; axis < 3; ++axis) turn[axis] += 2.0 * cross(q.xyz, cross(q.xyz, turn[axis]) + q.w * turn[axis]);
    fovlab_camera.right = head * turn[0];
    fovlab_camera.up = head * turn[1];
    fovlab_camera.forward = -(head * turn[2]);
  }
#endif
}

// fovlab_camera_basis ray through a point of the full-resolution frame, in pixels (y down). Also returns the
// angle one full-resolution pixel subtends at the image centre, in radians.
Ray fovlab_camera_ray(vec2 frame_point_px, out float pixel_angle_rad) {
#ifdef FOVLAB_EYE_VIEW
  if (params.eye_view != 0u) {
    // The eye's asymmetric frustum: tan-angles lerp(left, right) across and lerp(up, down) down the
    // frame; the pixel's angle is the one at the principal point (where the tan-angles are 0).
    vec4 tan_angles = params.eye_tan_angles;
    vec2 share = frame_point_px / params.frame_size;
    vec2 tan_point = vec2(mix(tan_angles.x, tan_angles.y, share.x), mix(tan_angles.z, tan_angles.w, share.y));
    pixel_angle_rad = (tan_angles.z - tan_angles.w) / params.frame_size.y;
    Ray eye_ray;
    eye_ray.origin = fovlab_camera.eye;
    eye_ray.direction =
        normalize(fovlab_camera.forward + tan_point.x * fovlab_camera.right + tan_point.y * fovlab_camera.up);
    return eye_ray;
  }
#endif
  vec2 ndc = (frame_point_px - 0.5 * params.frame_size) / (0.5 * params.frame_size.y);
  pixel_angle_rad = 2.0 * fovlab_camera.tan_half_fov / params.frame_size.y;
  Ray ray;
  ray.origin = fovlab_camera.eye;
  ray.direction =
      normalize(fovlab_camera.forward + fovlab_camera.tan_half_fov * (ndc.x * fovlab_camera.right - ndc.y * fovlab_camera.up));
  return ray;
}

// Parametric interval [t_enter, t_exit] of the ray inside a box; empty when t_exit < t_enter.
vec2 fovlab_box_interval(Ray ray, vec3 box_min, vec3 box_max) {
  vec3 inverse_direction = 1.0 / ray.direction;
  vec3 t0 = (box_min - ray.origin) * inverse_direction;
  vec3 t1 = (box_max - ray.origin) * inverse_direction;
  vec3 t_small = min(t0, t1);
  vec3 t_large = max(t0, t1);
  float t_enter = max(max(t_small.x, t_small.y), max(t_small.z, 0.0));
  float t_exit = min(min(t_large.x, t_large.y), t_large.z);
  return vec2(t_enter, t_exit);
}

vec2 fovlab_bounds_interval(Ray ray) { return fovlab_box_interval(ray, SCENE_BOUNDS_MIN, SCENE_BOUNDS_MAX); }

const uint OUTCOME_HIT = 0u;
const uint OUTCOME_MISS = 1u;
const uint OUTCOME_CAPPED = 2u;

// passed_surface: the march came within its near-miss cone of a surface and left it again (FLAG_NEAR_MISS;
// fovlab_trace); t_clear is then where the cone was last clear before it.
struct TraceResult {
  float t;
  uint steps;
  uint outcome;
  float distance;
  float material_id;
  bool passed_surface;
  float t_clear;
};

#ifdef FOVLAB_STEP_BREAKDOWN
// The step breakdown (sphere_trace_params.h STEP_*), compiled only into the tracer's step-breakdown
// variant, so the plain tracer's code is what it was. fovlab_shade_samples watches each shaded
// sample's march: fovlab_trace reports every step here while fovlab_watch_on is set.
bool fovlab_watch_on = false;
float fovlab_watch_near_per_unit_t;  // a step is near a surface below this distance per unit t
uint fovlab_watch_restart_steps;     // the step that found the start inside geometry (0 or 1)
uint fovlab_watch_first_near;        // steps before the first near step; fovlab_watch_none: none yet
uint fovlab_watch_run_start;         // steps before the current run of near steps began
bool fovlab_watch_in_run;
uint fovlab_watch_last_step;  // steps before the last step watched
const uint fovlab_watch_none = 0xffffffffu;

void fovlab_watch_begin(float epsilon_per_unit_t) {
  fovlab_watch_near_per_unit_t =
      max(epsilon_per_unit_t, epsilon_per_unit_t / params.hit_threshold * STEP_NEAR_FOOTPRINTS);
  fovlab_watch_restart_steps = 0u;
  fovlab_watch_first_near = fovlab_watch_none;
  fovlab_watch_run_start = 0u;
  fovlab_watch_in_run = false;
}

// A start inside geometry: the march begins again at the bounds after `steps` steps.
void fovlab_watch_restart(uint steps) {
  fovlab_watch_restart_steps = steps;
  fovlab_watch_first_near = fovlab_watch_none;
  fovlab_watch_in_run = false;
}

// The step after `steps_before` steps found `distance` at t.
void fovlab_watch_step(uint steps_before, float distance, float t) {
  fovlab_watch_last_step = steps_before;
  if (distance < fovlab_watch_near_per_unit_t * t) {
    if (fovlab_watch_first_near == fovlab_watch_none) fovlab_watch_first_near = steps_before;
    if (!fovlab_watch_in_run) fovlab_watch_run_start = steps_before;
    fovlab_watch_in_run = true;
  } else {
    fovlab_watch_in_run = false;
  }
}
#endif

#ifdef FOVLAB_OVER_RELAX
// Prototype (issue 41), compiled only into a variant of the tracer (SphereTraceSettings::
// over_relaxation): the top level's samples step a factor times the distance bound, Keinert et al.
// 2014's over-relaxed sphere tracing. A step longer than the plain one is kept only where the spheres
// at its two ends overlap (no surface lies between them); else, or where it left the bounds, the
// march takes the plain step from the last point instead. The factor adapts: on a plane whose
// distance falls by `slope` per unit of t the overlap test accepts at most 2 / (1 + slope); each step
// takes fovlab_relax_margin of that for the slope the last accepted step measured (plain until
// one has), at most FOVLAB_OVER_RELAX.
bool fovlab_relax_on = false;
const float fovlab_relax_margin = 0.95;
#endif

// One step more onto the surface of a hit, within the step cap.
void fovlab_refine_hit(Ray ray, inout TraceResult result, uint step_cap) {
  if (result.outcome != OUTCOME_HIT || result.steps >= step_cap) return;
  result.t += result.distance;
  vec2 refined = scene_map(ray.origin + result.t * ray.direction);
  result.distance = refined.x;
  result.material_id = refined.y;
  result.steps += 1u;
}

// Sphere traces from t_start. A start inside geometry (a neighbour's depth behind a surface this ray
// meets earlier) shows as a negative distance at the first step; the ray then restarts where it
// enters the bounds. That first evaluation doubles as the first step of the march.
// step_cap: params.max_steps, or FIPR's budget for peripheral pixels; count_capped: whether a ray
// stopped by it counts in COUNTER_CAPPED_RAYS (not FIPR's peripheral rays: stopping early is their purpose).
// near_per_unit_t > 0 (FIPR's depth levels, FLAG_NEAR_MISS): the radius per unit t of a cone around
// the ray, the coarse pixel's; a step whose distance is below it has a surface within the cone, and a
// later step clear of it again means the ray passed that surface without hitting it (a wire between
// two centre rays, a silhouette it grazed). The first such surface is recorded: passed_surface, and
// t_clear, the last step before it whose cone was clear. 0: no watch (passed_surface stays false).
// The march ends (OUTCOME_MISS) beyond t_limit (fovlab_unlimited: where the ray leaves the bounds).
const float fovlab_unlimited = 3.0e38;
TraceResult fovlab_trace(Ray ray, float t_start, float epsilon_per_unit_t, bool refine_hit, uint step_cap,
                         bool count_capped, float near_per_unit_t, float t_limit) {
  TraceResult result;
  result.steps = 0u;
  result.distance = 0.0;
  result.material_id = 0.0;
  result.passed_surface = false;
  vec2 interval = fovlab_bounds_interval(ray);
  interval.y = min(interval.y, t_limit);
  float t = max(t_start, interval.x);
  result.t_clear = t;
  bool check_start = t > interval.x;
  bool near_surface = false;
#ifdef FOVLAB_OVER_RELAX
  float relax_cap = fovlab_relax_on ? float(FOVLAB_OVER_RELAX) : 1.0;
  float relax = 1.0;
  float relax_slope = 1.0;
  float relax_last_t = t;
  float relax_last_distance = 0.0;
  float relax_step = 0.0;
#endif
  while (result.steps < step_cap) {
    if (t > interval.y) {
#ifdef FOVLAB_OVER_RELAX
      if (relax_cap > 1.0 && relax_step > relax_last_distance) {  // a longer step left the bounds untested
        t = relax_last_t + relax_last_distance;
        relax_step = relax_last_distance;
        continue;
      }
#endif
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
        result.t_clear = t;
        atomicAdd(counters[COUNTER_RESTARTED_RAYS], 1u);
#ifdef FOVLAB_STEP_BREAKDOWN
        if (fovlab_watch_on) fovlab_watch_restart(result.steps);
#endif
        continue;
      }
    }
#ifdef FOVLAB_OVER_RELAX
    if (relax_cap > 1.0) {
      if (relax_step > relax_last_distance && relax_step > relax_last_distance + abs(sample_.x)) {
        // The plain step from the last point needs no test; the slope it measures sets the next factor.
        t = relax_last_t + relax_last_distance;
        relax_step = relax_last_distance;
        continue;
      }
      if (relax_step > 0.0) relax_slope = max((relax_last_distance - sample_.x) / relax_step, 0.0);
      relax_last_t = t;
      relax_last_distance = abs(sample_.x);
      relax = clamp(fovlab_relax_margin * 2.0 / (1.0 + relax_slope), 1.0, relax_cap);
    }
#endif
#ifdef FOVLAB_STEP_BREAKDOWN
    if (fovlab_watch_on) fovlab_watch_step(result.steps - 1u, sample_.x, t);
#endif
    if (near_per_unit_t > 0.0 && !result.passed_surface) {
      if (sample_.x < near_per_unit_t * t) {
        near_surface = true;
      } else if (near_surface) {
        result.passed_surface = true;
      } else {
        result.t_clear = t;
      }
    }
    if (sample_.x < epsilon_per_unit_t * t) {
      // Where the hit is shaded, one refining step onto the surface (within the cap): the shaded
      // point then depends far less on where the march started, so IPR and GT shade the same point
      // (thin detail such as flutes otherwise shades differently within the epsilon band). Depth
      // levels keep the unrefined, slightly conservative distance.
      result.t = t;
      result.outcome = OUTCOME_HIT;
      result.distance = sample_.x;
      result.material_id = sample_.y;
      if (refine_hit) fovlab_refine_hit(ray, result, step_cap);
      return result;
    }
#ifdef FOVLAB_OVER_RELAX
    relax_step = relax * sample_.x;
    t += relax_step;
    continue;
#endif
    t += sample_.x;
  }
  result.t = t;
  result.outcome = OUTCOME_CAPPED;
  vec2 final_sample = scene_map(ray.origin + t * ray.direction);
  result.distance = final_sample.x;
  result.material_id = final_sample.y;
  if (count_capped) atomicAdd(counters[COUNTER_CAPPED_RAYS], 1u);
  return result;
}

// The conservative pyramid's march (FLAG_CONE): the cone around the ray whose radius at distance t
// is cone_per_unit_t * t (the level pixel's corners) holds no point within band_per_unit_t * t of a
// surface (the finest level's hit band) up to the distance returned. Every ray of a finer level, and
// every sample of the top level, lies inside the cone of its coarse pixel, so starting it there never
// skips a surface it would hit from the camera (where GT hits, the same rule says IPR can).
//   At a step from t with distance d, the cone's points up to t + s lie within sqrt(s^2 + (c (t + s))^2)
// of the ray's point at t (the chord between two rays through the eye is at most their angle times
// t), and the band there is at most b (t + d); so with clearance = d - b (t + d) the step s solves
// s^2 + c^2 (t + s)^2 = clearance^2. The march stops once clearance < fovlab_cone_stop * c * t: beyond that
// the steps shrink geometrically near a surface the cone grazes, and stopping early only hands the
// finer level a few more steps. The scene bounds are widened by the cone's largest radius plus band,
// so that entering and leaving them is decided for the whole cone, not just its axis.
const float fovlab_cone_stop = 1.5;
TraceResult fovlab_cone_trace(Ray ray, float t_start, float cone_per_unit_t, float band_per_unit_t, uint step_cap) {
  TraceResult result;
  result.steps = 0u;
  result.distance = 0.0;
  result.material_id = 0.0;
  result.passed_surface = false;  // (the cone stops at a surface it would pass)
  result.t_clear = t_start;
  // Beyond t_far (the farthest corner of the bounds from the eye) the cone lies outside the bounds,
  // where no march evaluates the scene; before it the widened box holds every point of the cone.
  vec3 far_corner = max(abs(SCENE_BOUNDS_MIN - ray.origin), abs(SCENE_BOUNDS_MAX - ray.origin));
  float t_far = length(far_corner);
  float margin = (cone_per_unit_t + band_per_unit_t) * t_far;
  vec2 interval = fovlab_box_interval(ray, SCENE_BOUNDS_MIN - margin, SCENE_BOUNDS_MAX + margin);
  float t = max(t_start, interval.x);
  bool check_start = t > interval.x;
  float c2 = cone_per_unit_t * cone_per_unit_t;
  while (result.steps < step_cap) {
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
        atomicAdd(counters[COUNTER_RESTARTED_RAYS], 1u);
        continue;
      }
    }
    float clearance = sample_.x - band_per_unit_t * (t + sample_.x);
    if (clearance < fovlab_cone_stop * cone_per_unit_t * t) {
      result.t = t;
      result.outcome = OUTCOME_HIT;
      result.distance = sample_.x;
      result.material_id = sample_.y;
      return result;
    }
    t += (sqrt(clearance * clearance * (1.0 + c2) - c2 * t * t) - c2 * t) / (1.0 + c2);
  }
  result.t = t;
  result.outcome = OUTCOME_CAPPED;
  atomicAdd(counters[COUNTER_CAPPED_RAYS], 1u);
  return result;
}

// A depth level's ray: the paper's centre ray with the level's hit threshold, or (FLAG_CONE) the
// level pixel's cone. The cone reaches from the centre to a corner, scale / sqrt(2) pixels, plus
// the top level's hit band; pixel_angle_rad is the centre pixel's, the largest of the frame. The
// same cone is the centre ray's near-miss cone (FLAG_NEAR_MISS).
const float fovlab_half_diagonal = 0.70711;
float fovlab_pixel_cone_per_unit_t(float pixel_angle_rad, float scale) {
  return pixel_angle_rad * (scale * fovlab_half_diagonal + params.hit_threshold);
}
float fovlab_near_per_unit_t(float pixel_angle_rad, float scale) {
  return (fovlab_trace_flags & FLAG_NEAR_MISS) != 0u ? fovlab_pixel_cone_per_unit_t(pixel_angle_rad, scale) : 0.0;
}
TraceResult fovlab_depth_trace(Ray ray, float t_start, float pixel_angle_rad, float scale) {
  if ((fovlab_trace_flags & FLAG_CONE) != 0u)
    return fovlab_cone_trace(ray, t_start, pixel_angle_rad * scale * fovlab_half_diagonal,
                             pixel_angle_rad * params.hit_threshold, params.max_steps);
  return fovlab_trace(ray, t_start, pixel_angle_rad * scale * params.hit_threshold, false, params.max_steps, true,
                      fovlab_near_per_unit_t(pixel_angle_rad, scale), fovlab_unlimited);
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

// A depth level's value for the level above: where the ray stopped, or MISS_DEPTH when it left the
// scene bounds (or never entered them), so that every miss reads the same and FIPR's Sobel pass sees
// the sky as flat and its silhouettes as steps. A ray starting beyond the bounds misses at once, as
// it would from the exit point; the min filter still starts rays next to a surface in front of it.
const float MISS_DEPTH = 1e18;  // its square still fits a float
float fovlab_depth_to_pass_on(TraceResult result) {
  return result.outcome == OUTCOME_MISS ? MISS_DEPTH : result.t;
}

// FLAG_EDGE_DEPTH: the depth at which the ray through the low pixel's centre meets the surface (the
// paper's pyramid's depth), for FIPR's Sobel edges. The cone stops up to 1.5 cone radii in front of
// whatever may enter it, so its depths move and smear the steps at silhouettes that the edges are
// found at, and the mask loses what those edges held. The centre ray lies inside the cone, so it
// marches on from where the cone stopped (its steps are added to `steps`); the depth passed on to
// the level above stays the cone's.
float fovlab_edge_depth(Ray ray, TraceResult cone, float pixel_angle_rad, float scale, inout uint steps) {
  if (cone.outcome != OUTCOME_HIT || cone.steps >= params.max_steps) return fovlab_depth_to_pass_on(cone);
  TraceResult centre = fovlab_trace(ray, cone.t, pixel_angle_rad * scale * params.hit_threshold, false,
                                    params.max_steps - cone.steps, false, 0.0, fovlab_unlimited);
  steps += centre.steps;
  return fovlab_depth_to_pass_on(centre);
}

// FLAG_NEAR_MISS: where this depth level's ray passed a surface within its pixel's cone, the depth
// before it (TraceResult.t_clear), else NO_NEAR_MISS. The level's own ray (`traced`, from the
// filtered depth t_start, exactly IPR's) shows a surface it passed; where the parent's ray passed one
// before t_start, this ray started behind it, so a probe from the parent's near depth looks again
// (its steps are added to `steps`): a surface it passes, or one it hits clearly in front of where
// `traced` stopped, is this pixel's near miss. Near depths go up their own chain: the depth chain,
// and with it every pixel of the mask pass, stays IPR's.
float fovlab_parent_near_depth(uvec2 pixel) {
  if ((fovlab_trace_flags & FLAG_HAS_START) == 0u) return NO_NEAR_MISS;
  uvec2 parent = min(pixel / 2u, params.start_size - 1u);
  return parent_near_depth[parent.y * params.start_size.x + parent.x];
}
float fovlab_near_miss_depth(Ray ray, float t_start, TraceResult traced, uvec2 pixel, float pixel_angle_rad, float scale,
                             inout uint steps) {
  float parent_near = fovlab_parent_near_depth(pixel);
  if (parent_near >= 0.0 && parent_near < t_start) {
    // It ends where `traced` started: beyond, that ray's own watch holds.
    float cone_per_unit_t = fovlab_pixel_cone_per_unit_t(pixel_angle_rad, scale);
    TraceResult probe = fovlab_trace(ray, parent_near, pixel_angle_rad * scale * params.hit_threshold, false,
                                     params.max_steps, false, cone_per_unit_t, t_start);
    steps += probe.steps;
    bool hit_in_front = probe.outcome == OUTCOME_HIT && probe.t < traced.t * (1.0 - cone_per_unit_t);
    if (probe.passed_surface || hit_in_front) return probe.t_clear;
  }
  return traced.passed_surface ? traced.t_clear : NO_NEAR_MISS;
}

// FLAG_NEAR_MISS: the unmasked children of a mid pixel whose ray passed a surface (a wire between its
// rays, a silhouette it grazed) join the mask and the masked pixels' list, so the top level traces
// and shades them in full instead of the periphery taking the colour behind that surface. The
// list's dispatch is counted after this pass. Returns how many children it promoted.
uint fovlab_promote_children(uint index) {
  if ((fovlab_trace_flags & FLAG_NEAR_MISS) == 0u) return 0u;
  uvec2 mid_pixel = uvec2(index % params.level_size.x, index / params.level_size.x);
  uvec2 frame_size = uvec2(params.frame_size);
  uint children[4];
  uint count = 0u;
  for (uint j = 0u; j < 2u; ++j) {
    for (uint i = 0u; i < 2u; ++i) {
      uvec2 child = mid_pixel * 2u + uvec2(i, j);
      if (any(greaterThanEqual(child, frame_size))) continue;
      uint child_index = child.y * frame_size.x + child.x;
      if (promoted_mask[child_index] != 0u) continue;
      promoted_mask[child_index] = 1u;
      children[count++] = child_index;
    }
  }
  if (count == 0u) return 0u;
  uint first = atomicAdd(counters[COUNTER_MASKED_PIXELS], count);
  for (uint i = 0u; i < count; ++i) promoted_list[first + i] = children[i] | fovlab_promoted_entry;
  return count;
}

// One listed pixel of FIPR's mid level (`entry`: fovlab_mid_entry_*).
void fovlab_foveated_mid(uint entry, uint index, float t_start, vec2 centre_px, float scale) {
  uint unmasked_children = (entry >> fovlab_mid_entry_unmasked_shift) & 7u;
  bool refresh_children = (entry & fovlab_mid_entry_refresh) != 0u;
  bool need_shade = refresh_children && params.periphery_steps == 0u;
  float pixel_angle_rad;
  Ray ray = fovlab_camera_ray(centre_px, pixel_angle_rad);
  float epsilon_per_unit_t = pixel_angle_rad * scale * params.hit_threshold;
  TraceResult result = fovlab_depth_trace(ray, t_start, pixel_angle_rad, scale);
  level_depth[index] = fovlab_depth_to_pass_on(result);
  atomicAdd(counters[COUNTER_MID_TRACED_PIXELS], 1u);
  uint promoted = 0u;
  uint probe_steps = 0u;
  if (need_shade) {
    // Its near depth, where the ray passed a surface (FLAG_NEAR_MISS): its children are promoted.
    float near = NO_NEAR_MISS;
    if ((fovlab_trace_flags & (FLAG_NEAR_MISS | FLAG_CONE)) == FLAG_NEAR_MISS) {
      near = fovlab_near_miss_depth(ray, t_start, result, uvec2(index % params.level_size.x, index / params.level_size.x),
                                    pixel_angle_rad, scale, probe_steps);
    }
    if ((fovlab_trace_flags & FLAG_CONE) != 0u && result.steps < params.max_steps) {
      // The cone stopped short of the surface: the shaded ray goes on from there with the level's
      // test, within what is left of the step cap (a capped cone was counted once already). If it
      // passes the surface the cone stopped at, the cone's depth is the near depth.
      uint cone_steps = result.steps;
      float cone_t = result.t;
      result = fovlab_trace(ray, result.t, epsilon_per_unit_t, false, params.max_steps - cone_steps, true,
                            fovlab_near_per_unit_t(pixel_angle_rad, scale), fovlab_unlimited);
      result.steps += cone_steps;
      if (result.passed_surface) near = cone_t;
    }
    if (near >= 0.0) {
      promoted = fovlab_promote_children(index);
      near_depth[index] = near;  // where the top level starts them
    }
    fovlab_refine_hit(ray, result, params.max_steps);
    // Alpha stamps the frame (+1; 0: never shaded), so the reconstruction can tell stale taps.
    level_colour[index] = vec4(fovlab_shade(ray, result, epsilon_per_unit_t), float(params.frame_index + 1u));
    atomicAdd(counters[COUNTER_MID_SHADED_PIXELS], 1u);
  }
  if (refresh_children) atomicAdd(counters[COUNTER_REFRESHED_PIXELS], unmasked_children - promoted);
  level_steps[index] = result.steps + probe_steps;
}

#ifdef FOVLAB_STEP_BREAKDOWN
// Adds to a 64-bit count of the counters buffer (two words, low then high).
void fovlab_add_64(uint index, uint value) {
  if (value == 0u) return;
  uint before = atomicAdd(counters[index], value);
  if (before + value < before) atomicAdd(counters[index + 1u], 1u);
}

// One pixel's step breakdown, summed over its samples and added to the counters once.
struct fovlab_pixel_breakdown {
  uint steps[STEP_CATEGORY_COUNT];
  uint samples[STEP_CATEGORY_COUNT];
  uint histogram[STEP_HISTOGRAM_BINS];
  bool one_surface;  // every sample so far hit, all with one material
  float material_id;
  float nearest_t;
  float farthest_t;
  uint all_steps;
  uint approach_steps;
  uint longest_approach;
};
fovlab_pixel_breakdown fovlab_breakdown;

void fovlab_breakdown_begin() {
  for (uint c = 0u; c < STEP_CATEGORY_COUNT; ++c) {
    fovlab_breakdown.steps[c] = 0u;
    fovlab_breakdown.samples[c] = 0u;
  }
  for (uint b = 0u; b < STEP_HISTOGRAM_BINS; ++b) fovlab_breakdown.histogram[b] = 0u;
  fovlab_breakdown.one_surface = true;
  fovlab_breakdown.material_id = 0.0;
  fovlab_breakdown.nearest_t = fovlab_unlimited;
  fovlab_breakdown.farthest_t = 0.0;
  fovlab_breakdown.all_steps = 0u;
  fovlab_breakdown.approach_steps = 0u;
  fovlab_breakdown.longest_approach = 0u;
}

// A watched sample's steps into the categories (sphere_trace_params.h STEP_CATEGORY_*), after its
// march (and refining step): `first` the sample of its pixel.
void fovlab_breakdown_sample(Ray ray, TraceResult result, float epsilon_per_unit_t, bool first) {
  uint steps[STEP_CATEGORY_COUNT];
  for (uint c = 0u; c < STEP_CATEGORY_COUNT; ++c) steps[c] = 0u;
  uint restart = fovlab_watch_restart_steps;
  steps[STEP_CATEGORY_OTHER] = restart;
  if (result.outcome == OUTCOME_MISS) {
    steps[STEP_CATEGORY_MISS] = result.steps - restart;
  } else if (result.outcome == OUTCOME_CAPPED) {
    steps[STEP_CATEGORY_OTHER] = result.steps;
  } else {
    // The hit step is the last step watched, and near: it ends the final near run. After it only
    // the refining step (fovlab_refine_hit), if any.
    uint hit_step = fovlab_watch_last_step;
    uint run = hit_step + 1u - fovlab_watch_run_start;
    steps[STEP_CATEGORY_APPROACH] = fovlab_watch_first_near - restart;
    steps[STEP_CATEGORY_SILHOUETTE] = fovlab_watch_run_start - fovlab_watch_first_near;
    uint final_category = STEP_CATEGORY_FINAL;
    if (run >= STEP_LONG_RUN) {
      // The angle of the surface to the ray, from the normal fovlab_shade takes there.
      vec3 p = ray.origin + result.t * ray.direction;
      vec3 normal = fovlab_normal(p, result.distance, max(epsilon_per_unit_t * result.t, 1e-6));
      bool grazing = abs(dot(normal, ray.direction)) < STEP_GRAZING_SINE;
      final_category = grazing ? STEP_CATEGORY_GRAZING : STEP_CATEGORY_SLOW_BOUND;
    }
    steps[final_category] = run;
    steps[STEP_CATEGORY_FINAL] += result.steps - hit_step - 1u;
  }
  for (uint c = 0u; c < STEP_CATEGORY_COUNT; ++c) {
    fovlab_breakdown.steps[c] += steps[c];
    if (steps[c] > 0u) fovlab_breakdown.samples[c] += 1u;
  }
  uint bin = result.steps <= 1u ? 0u : min(uint(findMSB(result.steps - 1u)) + 1u, STEP_HISTOGRAM_BINS - 1u);
  fovlab_breakdown.histogram[bin] += 1u;
  fovlab_breakdown.all_steps += result.steps;
  uint approach = steps[STEP_CATEGORY_APPROACH];
  fovlab_breakdown.approach_steps += approach;
  fovlab_breakdown.longest_approach = max(fovlab_breakdown.longest_approach, approach);
  bool same_surface = result.outcome == OUTCOME_HIT && (first || result.material_id == fovlab_breakdown.material_id);
  fovlab_breakdown.one_surface = fovlab_breakdown.one_surface && same_surface;
  fovlab_breakdown.material_id = result.material_id;
  fovlab_breakdown.nearest_t = min(fovlab_breakdown.nearest_t, result.t);
  fovlab_breakdown.farthest_t = max(fovlab_breakdown.farthest_t, result.t);
}

// The pixel's breakdown into the counters. One surface: its samples all hit the same material within
// STEP_ONE_SURFACE_DEPTH of the nearest one's depth (one surface, no silhouette across the pixel).
void fovlab_breakdown_end() {
  for (uint c = 0u; c < STEP_CATEGORY_COUNT; ++c) {
    fovlab_add_64(COUNTER_STEP_CATEGORY_STEPS + 2u * c, fovlab_breakdown.steps[c]);
    if (fovlab_breakdown.samples[c] > 0u)
      atomicAdd(counters[COUNTER_STEP_CATEGORY_SAMPLES + c], fovlab_breakdown.samples[c]);
  }
  for (uint b = 0u; b < STEP_HISTOGRAM_BINS; ++b)
    if (fovlab_breakdown.histogram[b] > 0u) atomicAdd(counters[COUNTER_STEP_HISTOGRAM + b], fovlab_breakdown.histogram[b]);
  bool one_surface = fovlab_breakdown.one_surface &&
                  fovlab_breakdown.farthest_t - fovlab_breakdown.nearest_t <= STEP_ONE_SURFACE_DEPTH * fovlab_breakdown.nearest_t;
  if (!one_surface) return;
  atomicAdd(counters[COUNTER_STEP_ONE_SURFACE_PIXELS], 1u);
  fovlab_add_64(COUNTER_STEP_ONE_SURFACE_STEPS, fovlab_breakdown.all_steps);
  fovlab_add_64(COUNTER_STEP_ONE_SURFACE_APPROACH, fovlab_breakdown.approach_steps);
  fovlab_add_64(COUNTER_STEP_ONE_SURFACE_LONGEST, fovlab_breakdown.longest_approach);
}
#endif

// Shades a pixel's (or a sample's) spp rays around centre_px, spread over `scale` pixels.
// The one-step floor (`fovlab bench`): GT records where each sample stopped (FLAG_SAMPLE_DEPTH_OUT,
// before the refining step, so the distance there is not negative), then each sample starts there
// with a step cap of 1 (FLAG_SAMPLE_DEPTH_IN): one evaluation, which is its hit test, and shading.
void fovlab_shade_samples(uint index, float t_start, vec2 centre_px, float scale) {
  vec3 colour_sum = vec3(0.0);
  uint steps = 0u;
  bool record_depth = (fovlab_trace_flags & FLAG_SAMPLE_DEPTH_OUT) != 0u;
#ifdef FOVLAB_STEP_BREAKDOWN
  fovlab_breakdown_begin();
#endif
  for (uint s = 0u; s < params.samples_per_pixel; ++s) {
    float pixel_angle_rad;
    Ray ray = fovlab_camera_ray(centre_px + fovlab_sample_offset(s, params.samples_per_pixel) * scale,
                                pixel_angle_rad);
    float epsilon_per_unit_t = pixel_angle_rad * scale * params.hit_threshold;
    uint sample_entry = index * params.samples_per_pixel + s;
    float t_sample = (fovlab_trace_flags & FLAG_SAMPLE_DEPTH_IN) != 0u ? start_depth[sample_entry] : t_start;
#ifdef FOVLAB_STEP_BREAKDOWN
    fovlab_watch_begin(epsilon_per_unit_t);
    fovlab_watch_on = true;
#endif
#ifdef FOVLAB_OVER_RELAX
    fovlab_relax_on = true;
#endif
    TraceResult result =
        fovlab_trace(ray, t_sample, epsilon_per_unit_t, !record_depth, params.max_steps, true, 0.0, fovlab_unlimited);
#ifdef FOVLAB_STEP_BREAKDOWN
    fovlab_watch_on = false;
#endif
#ifdef FOVLAB_OVER_RELAX
    fovlab_relax_on = false;
#endif
    if (record_depth) {
      level_depth[sample_entry] = fovlab_depth_to_pass_on(result);
      fovlab_refine_hit(ray, result, params.max_steps);
    }
#ifdef FOVLAB_STEP_BREAKDOWN
    fovlab_breakdown_sample(ray, result, epsilon_per_unit_t, s == 0u);
#endif
    steps += result.steps;
    colour_sum += fovlab_shade(ray, result, epsilon_per_unit_t);
  }
  level_colour[index] = vec4(colour_sum / float(params.samples_per_pixel), 1.0);
  level_steps[index] = steps;
#ifdef FOVLAB_STEP_BREAKDOWN
  fovlab_breakdown_end();
#endif
}

void main() {
  fovlab_set_camera();
  uvec2 pixel = gl_GlobalInvocationID.xy;
  uint index;
  uint list_slot = (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u + gl_LocalInvocationIndex;
  if ((fovlab_trace_flags & FLAG_SAMPLE_LIST) != 0u) {
    if (list_slot >= counters[COUNTER_MASKED_PIXELS]) return;
    uvec4 entry = uvec4(mask_values[4u * list_slot], mask_values[4u * list_slot + 1u], mask_values[4u * list_slot + 2u],
                        mask_values[4u * list_slot + 3u]);
    fovlab_shade_samples(entry.w, 0.0, uintBitsToFloat(entry.xy), uintBitsToFloat(entry.z));
    return;
  }
  uint mid_entry = 0u;
  if ((fovlab_trace_flags & (FLAG_MASKED_LIST | FLAG_FOVEATED_TOP | FLAG_FOVEATED_MID)) != 0u) {
    uint list_length = (fovlab_trace_flags & FLAG_MASKED_LIST) != 0u   ? counters[COUNTER_MASKED_PIXELS]
                       : (fovlab_trace_flags & FLAG_FOVEATED_TOP) != 0u ? counters[COUNTER_REFRESH_LIST_PIXELS]
                                                                  : counters[COUNTER_MID_LIST_PIXELS];
    if (list_slot >= list_length) return;
    mid_entry = mask_values[list_slot];
    index = mid_entry & fovlab_mid_entry_index_mask;  // (the pixel lists hold bare indices, under 2^28)
    pixel = uvec2(index % params.level_size.x, index / params.level_size.x);
  } else {
    if (any(greaterThanEqual(pixel, params.level_size))) return;
    index = pixel.y * params.level_size.x + pixel.x;
  }

  if ((fovlab_trace_flags & FLAG_FOVEATED_TOP) != 0u) {
    uvec2 parent = min(pixel / 2u, params.start_size - 1u);
    float pixel_angle_rad;
    Ray ray = fovlab_camera_ray(vec2(pixel) + 0.5, pixel_angle_rad);
    float epsilon_per_unit_t = pixel_angle_rad * params.hit_threshold;
    TraceResult result = fovlab_trace(ray, start_depth[parent.y * params.start_size.x + parent.x], epsilon_per_unit_t,
                                      true, params.periphery_steps, false, 0.0, fovlab_unlimited);
    level_colour[index] = vec4(fovlab_shade(ray, result, epsilon_per_unit_t), 1.0);
    level_steps[index] = result.steps;
    return;
  }

  float t_start = 0.0;
  if ((fovlab_trace_flags & FLAG_HAS_START) != 0u) {
    uvec2 parent = min((fovlab_trace_flags & FLAG_START_SAME_SIZE) != 0u ? pixel : pixel / 2u, params.start_size - 1u);
    t_start = start_depth[parent.y * params.start_size.x + parent.x];
    // A pixel the mid level promoted starts in front of the surface its parent's ray passed.
    if ((fovlab_trace_flags & FLAG_MASKED_LIST) != 0u && (mid_entry & fovlab_promoted_entry) != 0u)
      t_start = min(t_start, fovlab_parent_near_depth(pixel));
  }

  float scale = float(params.level_scale);
  vec2 centre_px = (vec2(pixel) + 0.5) * scale;
  if ((fovlab_trace_flags & FLAG_FOVEATED_MID) != 0u) {
    fovlab_foveated_mid(mid_entry, index, t_start, centre_px, scale);
    return;
  }
  if ((fovlab_trace_flags & FLAG_SHADE) == 0u) {
    float pixel_angle_rad;
    Ray ray = fovlab_camera_ray(centre_px, pixel_angle_rad);
    TraceResult result = fovlab_depth_trace(ray, t_start, pixel_angle_rad, scale);
    level_depth[index] = fovlab_depth_to_pass_on(result);
    uint steps = result.steps;
    if ((fovlab_trace_flags & (FLAG_NEAR_MISS | FLAG_CONE)) == FLAG_NEAR_MISS)
      near_depth[index] = fovlab_near_miss_depth(ray, t_start, result, pixel, pixel_angle_rad, scale, steps);
    if ((fovlab_trace_flags & FLAG_EDGE_DEPTH) != 0u)
      edge_depth[index] = fovlab_edge_depth(ray, result, pixel_angle_rad, scale, steps);
    level_steps[index] = steps;
    return;
  }

  fovlab_shade_samples(index, t_start, centre_px, scale);
}
