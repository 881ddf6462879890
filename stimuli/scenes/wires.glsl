// fovlab scene "wires": thin geometry in front of a wall, the case a coarse pyramid level can step
// over (Polychronakis et al. 2023 section 6 admits its min filter does not guarantee fine detail). A plain wall at
// z = 4 and a floor at y = 0; in front of the wall, left to right and near to far:
//   - six horizontal wires across the frame (radii 0.0015 to 0.024, about a twentieth of a pixel to
//     one pixel at 320x180, a fifth to four pixels at 1280x720) and two slanting ones;
//   - a fence of 49 vertical wires 0.25 apart (radius 0.002) before the wall;
//   - four slightly leaning thin rods (radii 0.006 to 0.03) standing on the floor;
//   - two thin rings (minor radii 0.004 and 0.008), one facing the camera, one turned 60 degrees;
//   - a plate 0.004 thick and 0.3 deep whose plane passes 0.02 beside the eye: seen almost
//     edge-on, a line.
// The camera is still (no time dependence), 40 degree vertical field of view; one sun, no fog.
//
// Material ids: 0 floor, 1 wall, 2 wires, 3 fence, 4 rods, 5 rings, 6 plate.
// Every distance below is exact (capsules, tori, boxes) or the minimum of exact ones.

const vec3 SCENE_BOUNDS_MIN = vec3(-7.0, -0.05, -5.9);
const vec3 SCENE_BOUNDS_MAX = vec3(7.0, 5.4, 4.05);
const int SCENE_LIGHT_COUNT = 1;

const vec3 WIRES_EYE = vec3(0.0, 1.5, -6.0);
const vec3 WIRES_SUN = vec3(-0.45, 0.8, -0.55);  // towards the sun (not normalised)
const float WIRES_WALL_Z = 4.0;

// Distance to the segment a-b thickened by radius.
float wires_capsule(vec3 p, vec3 a, vec3 b, float radius) {
  vec3 pa = p - a;
  vec3 ba = b - a;
  float h = clamp(dot(pa, ba) / dot(ba, ba), 0.0, 1.0);
  return length(pa - ba * h) - radius;
}

// Torus around the axis `normal` (unit) through `centre`.
float wires_ring(vec3 p, vec3 centre, vec3 normal, float major_radius, float minor_radius) {
  vec3 q = p - centre;
  float along = dot(q, normal);
  float across = length(q - along * normal);
  return length(vec2(across - major_radius, along)) - minor_radius;
}

float wires_box(vec3 p, vec3 half_size) {
  vec3 outside = abs(p) - half_size;
  return length(max(outside, 0.0)) + min(max(outside.x, max(outside.y, outside.z)), 0.0);
}

vec2 wires_closer(vec2 result, float distance, float material) {
  return distance < result.x ? vec2(distance, material) : result;
}

vec2 scene_map(vec3 p) {
  vec2 result = vec2(p.y, 0.0);
  result = wires_closer(result, WIRES_WALL_Z - p.z, 1.0);

  // Horizontal wires at z = 1.5, 6.5 to 8 units from the eye.
  float wires = 1e9;
  const float radii[6] = float[6](0.0015, 0.003, 0.006, 0.012, 0.018, 0.024);
  for (int i = 0; i < 6; ++i) {
    float y = 2.9 - 0.22 * float(i);
    wires = min(wires, wires_capsule(p, vec3(-6.5, y, 1.5), vec3(6.5, y, 1.5), radii[i]));
  }
  wires = min(wires, wires_capsule(p, vec3(-6.5, 0.4, 0.5), vec3(6.5, 3.2, 2.5), 0.003));
  wires = min(wires, wires_capsule(p, vec3(-6.5, 3.3, 3.0), vec3(6.5, 0.2, -0.5), 0.006));
  result = wires_closer(result, wires, 2.0);

  // The fence: vertical wires every 0.25 at z = 3.5, x in [-6, 6]. The nearest one is that of the
  // cell holding x (the cell index clamped to the fence), so one evaluation is exact.
  float cell = clamp(floor(p.x / 0.25 + 0.5), -24.0, 24.0);
  vec2 fence_offset = vec2(p.x - 0.25 * cell, p.z - 3.5);
  float fence = length(vec2(length(fence_offset), max(p.y - 3.0, 0.0) + max(-p.y, 0.0))) - 0.002;
  result = wires_closer(result, fence, 3.0);

  // Rods from the floor, leaning a little.
  float rods = wires_capsule(p, vec3(-4.2, 0.0, 0.0), vec3(-4.0, 2.6, 0.3), 0.03);
  rods = min(rods, wires_capsule(p, vec3(-2.7, 0.0, -0.5), vec3(-2.9, 2.2, -0.4), 0.012));
  rods = min(rods, wires_capsule(p, vec3(2.6, 0.0, 0.8), vec3(2.75, 2.4, 0.6), 0.006));
  rods = min(rods, wires_capsule(p, vec3(4.3, 0.0, -0.2), vec3(4.1, 2.8, 0.2), 0.02));
  result = wires_closer(result, rods, 4.0);

  // Thin rings: one facing the camera, one turned 60 degrees about the vertical.
  float rings = wires_ring(p, vec3(-1.6, 1.3, 0.0), vec3(0.0, 0.0, 1.0), 0.55, 0.004);
  rings = min(rings, wires_ring(p, vec3(1.4, 1.0, 1.0), vec3(0.866, 0.0, 0.5), 0.6, 0.008));
  result = wires_closer(result, rings, 5.0);

  // The edge-on plate: its plane passes 0.02 beside the eye, turned 7 degrees about the vertical
  // through it, so the camera sees its face at a grazing angle, a line under a pixel wide even at
  // 1280x720, 7 degrees off the frame's centre. It is 0.3 deep along the view: a ray passing its face
  // at a distance h (at least the hit band, else it hits) takes about 0.3 / h steps beside it, within
  // the step cap at 1280x720; a deeper plate makes that a step-cap test, not a thin-feature one.
  vec3 q = p - WIRES_EYE;
  const float c7 = 0.99254615, s7 = 0.12186934;
  vec3 plate_local = vec3(c7 * q.x - s7 * q.z, q.y, s7 * q.x + c7 * q.z);
  float plate = wires_box(plate_local - vec3(0.02, -0.6, 8.0), vec3(0.002, 0.55, 0.15));
  result = wires_closer(result, plate, 6.0);
  return result;
}

vec3 scene_albedo(float material_id, vec3 p, vec3 normal, float footprint) {
  int id = int(material_id + 0.5);
  if (id == 0) {  // floor: large two-tone squares (1 unit), not thin detail
    float check = mod(floor(p.x) + floor(p.z), 2.0);
    return mix(vec3(0.42, 0.4, 0.37), vec3(0.34, 0.33, 0.31), check);
  }
  if (id == 1) return vec3(0.82, 0.8, 0.74);   // wall: pale plaster, where dark lines show best
  if (id == 2) return vec3(0.05, 0.05, 0.06);  // wires: dark
  if (id == 3) return vec3(0.12, 0.1, 0.08);   // fence
  if (id == 4) return vec3(0.55, 0.2, 0.12);   // rods: red-brown
  if (id == 5) return vec3(0.1, 0.25, 0.6);    // rings: blue
  return vec3(0.08, 0.3, 0.1);                 // plate: green
}

void scene_light(int index, float time_s, out vec4 position, out vec3 radiance) {
  position = vec4(normalize(WIRES_SUN), 0.0);
  radiance = vec3(2.3, 2.2, 2.0);
}

vec3 scene_ambient(vec3 normal) { return vec3(0.18, 0.19, 0.21) * (0.75 + 0.25 * normal.y); }

vec3 scene_background(vec3 direction) { return vec3(0.55, 0.65, 0.8); }

vec3 scene_fog(vec3 colour, float distance, vec3 direction) { return colour; }

void scene_camera(float time_s, out vec3 eye, out vec3 target, out float vertical_fov_deg) {
  eye = WIRES_EYE;
  target = vec3(0.0, 1.5, 4.0);
  vertical_fov_deg = 40.0;
}
