// The blend's parameters and the zone weights of a pixel, shared by the zone blend's shaders
// (zone_blend, zone_display, zone_band). foveation/zone_layout.cpp is the reference
// (zone_weights, blend_zones_reference); ZoneBlender fills BlendParams (zone_blender.cpp).

layout(push_constant) uniform BlendParams {
  // Squared tangents of the band edges (radius -/+ band / 2): foveal inner, foveal outer, middle
  // inner, middle outer; -1 below 0 degrees, a huge value from 90 degrees. Outside the bands the
  // zone follows from tan^2 of the eccentricity, |g x p|^2 / (g . p)^2 for the unit ray g to the
  // gaze and the ray p to the pixel, without an arctangent.
  vec4 edge_tan2;
  // In the eye's millimetres (foveation/display_geometry.h): g, made on the CPU in double,
  // so that a gaze far off the screen stays exact; pixel (x, y)'s centre at
  // (first_pixel_mm + (x, y) * pixel_pitch_mm, viewing_distance_mm).
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
