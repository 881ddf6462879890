#version 460
// Path tracing of a triangle scene (renderer/path_tracing/, docs/path-tracing.md): one invocation
// traces samples [sample_begin, sample_begin + sample_count) of one pixel and adds their sum to the
// pixel's accumulator. Unidirectional paths with next-event estimation on emissive triangles
// combined with BSDF sampling by the power heuristic; Lambertian, glass (exact Fresnel) and
// emissive materials; a uniform sky; Russian roulette after 3 bounces. Every random number is a
// hash of (seed, pixel, sample, dimension): no state carries from one sample to the next.
#extension GL_GOOGLE_include_directive : require
#include "lowbias32.glsl"
#include "shared/path_trace_params.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(std430, binding = 0) readonly buffer Nodes { BvhNode nodes[]; };
layout(std430, binding = 1) readonly buffer Triangles { Triangle triangles[]; };
layout(std430, binding = 2) readonly buffer Materials { Material materials[]; };
layout(std430, binding = 3) readonly buffer Emitters { Emitter emitters[]; };
layout(std430, binding = 4) buffer Accumulation { vec4 accumulation[]; };

layout(push_constant) uniform PathTraceParamsBlock { PathTraceParams params; };

const uint kLambertian = 0u;
const uint kGlass = 1u;
const uint kEmissive = 2u;
const float kPi = 3.14159265358979;
const float kInfinity = 1.0 / 0.0;
const int kStackSize = 48;  // kBvhMaxDepth
const uint kRouletteAfterBounce = 3u;
// Random dimensions per bounce: 0-1 direction, 2 glass choice / roulette, 3 emitter pick, 4-5 point on it.
const uint kDimensionsPerBounce = 8u;

// ---- random numbers: lowbias32 (Wellons' integer hash) of (seed, pixel, sample, dimension) ----
uint sample_key(uint pixel, uint sample_index) {
  return lowbias32(lowbias32(lowbias32(params.seed ^ 0x5bd1e995u) ^ pixel) ^ sample_index);
}

// Uniform in [0, 1): the top 24 bits of the hash.
float random_unit(uint key, uint dimension) {
  return float(lowbias32(key ^ lowbias32(dimension * 0x9e3779b9u + 0x632be5abu)) >> 8) * (1.0 / 16777216.0);
}

// ---- intersection ----
vec3 safe_inverse(vec3 d) {
  vec3 magnitude = max(abs(d), vec3(1e-20));
  return vec3(1.0) / (magnitude * mix(vec3(-1.0), vec3(1.0), greaterThanEqual(d, vec3(0.0))));
}

float box_entry(uint node, vec3 origin, vec3 inverse_direction, float max_distance) {
  vec3 t0 = (nodes[node].bounds_min - origin) * inverse_direction;
  vec3 t1 = (nodes[node].bounds_max - origin) * inverse_direction;
  vec3 near_t = min(t0, t1), far_t = max(t0, t1);
  float enter = max(max(near_t.x, near_t.y), max(near_t.z, 0.0));
  float leave = min(min(far_t.x, far_t.y), min(far_t.z, max_distance));
  return enter <= leave ? enter : kInfinity;
}

// Moller-Trumbore, both faces; the distance when it lies in (0, max_distance), else infinity.
float intersect_triangle(uint slot, vec3 origin, vec3 direction, float max_distance) {
  vec3 edge1 = triangles[slot].edge1, edge2 = triangles[slot].edge2;
  vec3 p = cross(direction, edge2);
  float determinant = dot(edge1, p);
  if (determinant == 0.0) return kInfinity;
  float inverse = 1.0 / determinant;
  vec3 s = origin - triangles[slot].v0;
  float u = dot(s, p) * inverse;
  if (u < 0.0 || u > 1.0) return kInfinity;
  vec3 q = cross(s, edge1);
  float v = dot(direction, q) * inverse;
  if (v < 0.0 || u + v > 1.0) return kInfinity;
  float t = dot(edge2, q) * inverse;
  return (t > 0.0 && t < max_distance) ? t : kInfinity;
}

// Nearest hit (or, with any_hit, the first found) within (0, max_distance): its slot, or ~0u.
uint trace(vec3 origin, vec3 direction, float max_distance, bool any_hit, out float hit_distance) {
  hit_distance = max_distance;
  uint hit_slot = ~0u;
  vec3 inverse_direction = safe_inverse(direction);
  if (box_entry(0u, origin, inverse_direction, hit_distance) == kInfinity) return hit_slot;
  uint stack[kStackSize];
  int size = 0;
  uint node = 0u;
  for (;;) {
    uint count = nodes[node].triangle_count;
    uint first = nodes[node].left_or_first;
    bool descended = false;
    if (count > 0u) {
      for (uint slot = first; slot < first + count; ++slot) {
        float t = intersect_triangle(slot, origin, direction, hit_distance);
        if (t < hit_distance) {
          hit_distance = t;
          hit_slot = slot;
          if (any_hit) return hit_slot;
        }
      }
    } else {
      uint near_node = first, far_node = first + 1u;
      float near_t = box_entry(near_node, origin, inverse_direction, hit_distance);
      float far_t = box_entry(far_node, origin, inverse_direction, hit_distance);
      if (far_t < near_t) {
        float t = near_t; near_t = far_t; far_t = t;
        uint n = near_node; near_node = far_node; far_node = n;
      }
      if (near_t != kInfinity) {
        if (far_t != kInfinity && size < kStackSize) stack[size++] = far_node;
        node = near_node;
        descended = true;
      }
    }
    if (descended) continue;
    bool found = false;
    while (size > 0) {
      node = stack[--size];
      if (box_entry(node, origin, inverse_direction, hit_distance) != kInfinity) {
        found = true;
        break;
      }
    }
    if (!found) return hit_slot;
  }
}

// ---- sampling ----
// An orthonormal basis around unit n (Duff et al. 2017, branchless).
void basis(vec3 n, out vec3 tangent, out vec3 bitangent) {
  float s = n.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (s + n.z);
  float b = n.x * n.y * a;
  tangent = vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
  bitangent = vec3(b, s + n.y * n.y * a, -n.y);
}

vec3 cosine_direction(vec3 n, float u1, float u2) {
  float r = sqrt(u1), phi = 2.0 * kPi * u2;
  vec3 tangent, bitangent;
  basis(n, tangent, bitangent);
  return normalize(r * cos(phi) * tangent + r * sin(phi) * bitangent + sqrt(max(0.0, 1.0 - u1)) * n);
}

// Unpolarised Fresnel reflectance; eta = n_incident / n_transmitted, cos_i > 0; 1 past the critical angle.
float fresnel_dielectric(float cos_i, float eta, out float cos_t) {
  float sin2_t = eta * eta * max(0.0, 1.0 - cos_i * cos_i);
  if (sin2_t >= 1.0) {
    cos_t = 0.0;
    return 1.0;
  }
  cos_t = sqrt(1.0 - sin2_t);
  float rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  float rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

// A ray start off the surface at p (scale-aware), on the side the direction leaves to.
vec3 offset_origin(vec3 p, vec3 geometric_normal, vec3 direction) {
  float epsilon = 1e-4 * (1.0 + max(max(abs(p.x), abs(p.y)), abs(p.z)));
  return p + geometric_normal * (dot(direction, geometric_normal) >= 0.0 ? epsilon : -epsilon);
}

uint pick_emitter(float u) {
  uint low = 0u, high = params.emitter_count - 1u;
  while (low < high) {
    uint middle = (low + high) / 2u;
    if (u < emitters[middle].cdf) high = middle; else low = middle + 1u;
  }
  return emitters[low].slot;
}

float power_heuristic(float pdf_a, float pdf_b) {
  float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  return a / (a + b);
}

// Next-event estimation at a Lambertian point: one emitter point, its shadow ray, weighted against
// BSDF sampling. Returns the radiance it brings, before the path throughput.
vec3 sample_emitter(vec3 p, vec3 normal, vec3 geometric_normal, vec3 albedo, uint key, uint dimension) {
  uint slot = pick_emitter(random_unit(key, dimension));
  float su = sqrt(random_unit(key, dimension + 1u));
  float v = random_unit(key, dimension + 2u);
  Triangle light = triangles[slot];
  vec3 y = light.v0 + su * (1.0 - v) * light.edge1 + su * v * light.edge2;
  vec3 to_light = y - p;
  float distance2 = dot(to_light, to_light);
  if (!(distance2 > 0.0)) return vec3(0.0);
  float distance = sqrt(distance2);
  vec3 direction = to_light / distance;
  float cos_surface = dot(normal, direction);
  if (cos_surface <= 0.0) return vec3(0.0);
  vec3 light_normal = cross(light.edge1, light.edge2);
  float cos_light = abs(dot(normalize(light_normal), direction));
  if (cos_light <= 0.0) return vec3(0.0);
  vec3 origin = offset_origin(p, geometric_normal, direction);
  vec3 to_target = y - origin;
  float shadow_distance = length(to_target) * (1.0 - 1e-4);
  float ignored;
  if (trace(origin, to_target / length(to_target), shadow_distance, true, ignored) != ~0u) return vec3(0.0);
  float pdf_light = light.light_pdf_per_area * distance2 / cos_light;
  float pdf_bsdf = cos_surface / kPi;
  vec3 radiance = materials[light.material].colour;
  return albedo / kPi * radiance * cos_surface / pdf_light * power_heuristic(pdf_light, pdf_bsdf);
}

vec3 trace_path(vec3 origin, vec3 direction, uint key) {
  vec3 radiance = vec3(0.0);
  vec3 throughput = vec3(1.0);
  bool nee = params.emitter_count > 0u;
  // The previous scattering: whether BSDF-sampled emission must be weighted against NEE, and its pdf.
  bool weigh_emission = false;
  float previous_bsdf_pdf = 1.0;
  for (uint bounce = 0u;; ++bounce) {
    float distance;
    uint slot = trace(origin, direction, kInfinity, false, distance);
    if (slot == ~0u) {
      radiance += throughput * params.sky_radiance.xyz;
      break;
    }
    Triangle triangle = triangles[slot];
    Material material = materials[triangle.material];
    vec3 geometric_normal = normalize(cross(triangle.edge1, triangle.edge2));
    if (material.kind == kEmissive) {
      float weight = 1.0;
      if (weigh_emission && triangle.light_pdf_per_area > 0.0) {
        float cos_light = abs(dot(geometric_normal, direction));
        float pdf_light = triangle.light_pdf_per_area * distance * distance / max(cos_light, 1e-20);
        weight = power_heuristic(previous_bsdf_pdf, pdf_light);
      }
      radiance += throughput * material.colour * weight;
      break;
    }
    if (bounce >= params.max_bounces) break;
    vec3 p = origin + direction * distance;
    uint dimension = 2u + bounce * kDimensionsPerBounce;  // 0-1: the pixel jitter
    if (bounce >= kRouletteAfterBounce) {
      float survive = min(1.0, max(max(throughput.x, throughput.y), throughput.z));
      if (random_unit(key, dimension + 6u) >= survive) break;
      throughput /= survive;
    }
    if (material.kind == kLambertian) {
      vec3 normal = dot(direction, geometric_normal) < 0.0 ? geometric_normal : -geometric_normal;
      if (nee) radiance += throughput * sample_emitter(p, normal, geometric_normal, material.colour, key, dimension + 3u);
      direction = cosine_direction(normal, random_unit(key, dimension), random_unit(key, dimension + 1u));
      previous_bsdf_pdf = max(dot(normal, direction), 0.0) / kPi;
      if (!(previous_bsdf_pdf > 0.0)) break;
      throughput *= material.colour;
      weigh_emission = nee;
    } else {  // glass
      bool entering = dot(direction, geometric_normal) < 0.0;
      vec3 normal = entering ? geometric_normal : -geometric_normal;
      float eta = entering ? 1.0 / material.index_of_refraction : material.index_of_refraction;
      float cos_i = -dot(direction, normal);
      float cos_t;
      float reflectance = fresnel_dielectric(cos_i, eta, cos_t);
      if (random_unit(key, dimension + 2u) < reflectance) {
        direction = direction + 2.0 * cos_i * normal;
      } else {
        direction = normalize(eta * direction + (eta * cos_i - cos_t) * normal);
        throughput *= material.colour;
      }
      weigh_emission = false;
    }
    origin = offset_origin(p, geometric_normal, direction);
  }
  return radiance;
}

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (pixel.x >= params.size.x || pixel.y >= params.size.y) return;
  uint pixel_index = pixel.y * params.size.x + pixel.x;
  vec3 sum = vec3(0.0);
  for (uint s = 0u; s < params.sample_count; ++s) {
    uint key = sample_key(pixel_index, params.sample_begin + s);
    vec2 film = (vec2(pixel) + vec2(random_unit(key, 0u), random_unit(key, 1u))) / vec2(params.size);
    vec2 ndc = vec2(2.0 * film.x - 1.0, 1.0 - 2.0 * film.y);  // top row first
    vec3 direction = normalize(params.forward.xyz + ndc.x * params.right.xyz + ndc.y * params.up.xyz);
    sum += trace_path(params.eye.xyz, direction, key);
  }
  accumulation[pixel_index] += vec4(sum, float(params.sample_count));
}
