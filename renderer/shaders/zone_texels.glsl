// Reading and blending float RGBA texels (the zone buffers): shared by zone_blend, zone_band and
// srgb8_encode. The includer sets OUTPUT_SRGB8 before including this file (1: the output is sRGB8,
// so the texels' colour alone is read, a load of three channels).

// The zone buffers one after the other, `zone_texels` texels each: foveal, middle, outer (or any
// float RGBA image). Two views of it: RGBA texels, and the same texels' colour alone.
struct ZoneColour { vec3 rgb; float unread; };  // 16 bytes in std430, as a vec4
layout(std430, binding = 0) readonly buffer Zones { vec4 zones[]; };
layout(std430, binding = 0) readonly buffer ZoneColours { ZoneColour zone_colours[]; };

vec4 texel(uint i) { return OUTPUT_SRGB8 == 1u ? vec4(zone_colours[i].rgb, 1.0) : zones[i]; }

// The zones with a weight, innermost to outermost, read by one load in a loop: outside the bands it
// runs once. (A band between the fovea and the outer zone when there is no middle one skips the
// middle with a weight of 0.) `index` is the pixel's texel in each zone.
vec4 blend_texels(vec3 weights, uint index, uint zone_texels) {
  uint first_zone = weights.x > 0.0 ? 0u : weights.y > 0.0 ? 1u : 2u;
  uint last_zone = weights.z > 0.0 ? 2u : weights.y > 0.0 ? 1u : 0u;
  vec4 colour = vec4(0.0);
  for (uint zone = first_zone; zone <= last_zone; ++zone) colour += weights[zone] * texel(zone * zone_texels + index);
  return colour;
}
