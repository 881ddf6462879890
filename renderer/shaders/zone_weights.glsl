// The blend's parameters and the zone weights of a pixel, shared by the zone blend's shaders
// (zone_blend, zone_display, zone_band). foveation/zone_layout.cpp is the reference
// (zone_weights, blend_zones_reference); ZoneBlender fills BlendParams (zone_blender.cpp).

#include "shared/zone_blend_params.h"

layout(push_constant) uniform BlendParamsBlock { BlendParams params; };

// The rays of a pixel: g x p, g . p and tan^2 of the angle between them (huge at or beyond 90 degrees).
struct PixelRays {
  vec3 normal;
  float cosine;
  float tan2;
};

PixelRays pixel_rays(uvec2 pixel) {
  vec3 point_ray = vec3(fma(vec2(pixel), params.pixel_pitch_mm, params.first_pixel_mm), params.viewing_distance_mm);
  PixelRays rays;
  rays.normal = cross(params.gaze_direction, point_ray);
  rays.cosine = dot(params.gaze_direction, point_ray);
  rays.tan2 = rays.cosine > 0.0 ? dot(rays.normal, rays.normal) / (rays.cosine * rays.cosine) : 3.0e38;
  return rays;
}

bool in_band(float tan2) {
  return (tan2 > params.edge_tan2.x && tan2 <= params.edge_tan2.y) ||
         (params.has_middle != 0u && tan2 > params.edge_tan2.z && tan2 <= params.edge_tan2.w);
}

// The zone of a pixel outside the bands: 0 foveal, 1 middle, 2 outer.
uint core_zone(float tan2) {
  return tan2 <= params.edge_tan2.x ? 0u : params.has_middle != 0u && tan2 <= params.edge_tan2.z ? 1u : 2u;
}

// The weights of the foveal, middle and outer zones; in a band from the exact angle.
vec3 zone_weights(PixelRays rays) {
  if (!in_band(rays.tan2)) {
    uint zone = core_zone(rays.tan2);
    return vec3(zone == 0u ? 1.0 : 0.0, zone == 1u ? 1.0 : 0.0, zone == 2u ? 1.0 : 0.0);
  }
  float eccentricity = degrees(atan(length(rays.normal), rays.cosine));
  vec2 inside = clamp((params.band_end_deg - eccentricity) * params.band_per_deg, 0.0, 1.0);
  float middle = params.has_middle != 0u ? (1.0 - inside.x) * inside.y : 0.0;
  return vec3(inside.x, middle, 1.0 - inside.x - middle);
}
