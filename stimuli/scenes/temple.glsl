// fovlab scene "temple": an open coastal landscape. A value-noise heightfield of hills runs down
// to a flat sea; at the centre a rocky plateau with cliff sides (a noisy-rimmed mesa merged into
// the hills with a smooth maximum) carries a Greek temple: a three-step stylobate, a peristyle of
// 6 x 11 columns, a cella, an entablature with cornice and a gabled roof. Sun, sky, distance haze;
// the camera flies slowly around and towards the temple.
//
// Material ids: 0 sea, 1 terrain (grass / rock / sand by slope and height), 2 marble (steps,
// columns, entablature), 3 roof (terracotta), 4 cella walls (with a dark doorway).

const vec3 SCENE_BOUNDS_MIN = vec3(-90.0, -0.05, -90.0);
const vec3 SCENE_BOUNDS_MAX = vec3(90.0, 13.5, 90.0);
const int SCENE_LIGHT_COUNT = 1;

const vec3 TEMPLE_SUN = vec3(0.7, 0.5, -0.5);  // direction towards the sun (not normalised)

// ---- Noise: integer hash, value noise, fbm ----

uint temple_hash(ivec2 cell) {
  uint h = uint(cell.x) * 0x8da6b343u ^ uint(cell.y) * 0xd8163841u;
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return h;
}

float temple_cell_value(ivec2 cell) { return float(temple_hash(cell) >> 8) * (1.0 / 16777215.0); }

// Value noise in [0, 1] with cubic interpolation: each partial derivative is at most 1.5, so the
// gradient is at most 2.13 (per unit of the argument).
float temple_noise(vec2 x) {
  vec2 i = floor(x);
  vec2 f = x - i;
  vec2 u = f * f * (3.0 - 2.0 * f);
  ivec2 c = ivec2(i);
  float a = temple_cell_value(c);
  float b = temple_cell_value(c + ivec2(1, 0));
  float d = temple_cell_value(c + ivec2(0, 1));
  float e = temple_cell_value(c + ivec2(1, 1));
  return mix(mix(a, b, u.x), mix(d, e, u.x), u.y);
}

// Four octaves, gain 0.45, lacunarity 2 with a rotation between octaves; result in [0, 1].
// Gradient bound: 2.13 * (1 + 0.9 + 0.81 + 0.729) / 1.7443 = 4.19 per unit of the argument.
float temple_fbm(vec2 x) {
  const mat2 turn = mat2(1.6, 1.2, -1.2, 1.6);  // rotation by 36.9 degrees times 2
  float sum = 0.0;
  float amplitude = 1.0;
  for (int octave = 0; octave < 4; ++octave) {
    sum += amplitude * temple_noise(x);
    x = turn * x + vec2(17.3, -9.1);
    amplitude *= 0.45;
  }
  return sum * (1.0 / 1.7443);
}

// ---- Terrain ----

// Hills: about [-6, 4] (gradient <= 10 * 0.03 * 4.19 = 1.26) plus a gentle rise towards +x
// (0.03), so the land sinks into the sea towards -x.
float temple_hills(vec2 xz) { return -6.0 + 10.0 * temple_fbm(xz * 0.03 + vec2(3.7, 1.2)) + 0.03 * xz.x; }

// Plateau: flat at TOP inside a noisy rim, then cliff faces of slope CLIFF_SLOPE (eased over the
// first unit), floored at -10 (below the lowest hills, so beyond that it has no effect).
// The rim radius is r + three noise octaves of total amplitude RIM_NOISE; the gradient of the rim
// function is <= 1 + (3.5 * 0.07 + 1.5 * 0.2 + 0.8 * 0.55) * 2.13 = 3.10, so the cliff slope is
// <= 2.0 * 3.10 = 6.2.
const float TEMPLE_TOP = 7.0;          // height of the plateau top
const float TEMPLE_CLIFF_R = 13.0;     // mean plateau radius
const float TEMPLE_CLIFF_SLOPE = 2.0;  // rise per unit run of the cliff faces
const float TEMPLE_RIM_NOISE = 5.8;    // the rim radius varies by +- half this
// Horizontal annulus outside which the plateau term is flat: the rim varies within
// CLIFF_R +- RIM_NOISE / 2 and the cliff reaches the floor (-10) 17 / CLIFF_SLOPE + 0.5 further out.
const float TEMPLE_BAND_IN = TEMPLE_CLIFF_R - 0.5 * TEMPLE_RIM_NOISE;
const float TEMPLE_BAND_OUT = TEMPLE_CLIFF_R + 0.5 * TEMPLE_RIM_NOISE + 0.5 + 17.0 / TEMPLE_CLIFF_SLOPE;

float temple_plateau(vec2 xz) {
  float r = length(xz);
  if (r < TEMPLE_BAND_IN) return TEMPLE_TOP;  // inside the rim wherever the noise puts it
  if (r > TEMPLE_BAND_OUT) return -10.0;      // beyond the foot of the cliff
  float wobble = 3.5 * temple_noise(xz * 0.07) + 1.5 * temple_noise(xz * 0.2 + vec2(5.1, 2.3)) +
                 0.8 * temple_noise(xz * 0.55 + vec2(-3.3, 7.7));
  float rim = r + wobble - 0.5 * TEMPLE_RIM_NOISE - TEMPLE_CLIFF_R;
  float ramp = rim <= 0.0 ? 0.0 : (rim < 1.0 ? 0.5 * rim * rim : rim - 0.5);
  return max(TEMPLE_TOP - TEMPLE_CLIFF_SLOPE * ramp, -10.0);
}

float temple_height(vec2 xz) {
  float hills = temple_hills(xz);
  float plateau = temple_plateau(xz);
  // Polynomial smooth maximum (width 1.5): its gradient is a convex combination of the two.
  const float k = 1.5;
  float h = max(k - abs(hills - plateau), 0.0) / k;
  return max(hills, plateau) + h * h * k * 0.25;
}

// Heightfield distance bound. Over ground of slope <= G, a vertical gap g gives g / sqrt(1 + G^2).
// The cliff annulus has G_c = 6.2 (k_c = 0.159), the rest G_f = 1.29 (k_f = 0.613). Let b be the
// horizontal distance from p to the annulus. Following the horizontal path to the nearest surface
// point, the first b units have slope <= G_f, so the distance is at least
// min(k_f g, k_c (g + (G_c - G_f) b)) >= k_c g + min((k_f - k_c) g, k_c (G_c - G_f) b)
// (used with k_c = 0.155, k_f = 0.6, k_c (G_c - G_f) = 0.75).
// The second term is only used for g > 0.5: near the surface the bound is k_c g everywhere, so the
// normals (differences of this function) do not see the annulus edge.
float temple_terrain(vec3 p) {
  float gap = p.y - temple_height(p.xz);
  float r = length(p.xz);
  float band_distance = max(max(TEMPLE_BAND_IN - r, r - TEMPLE_BAND_OUT), 0.0);
  return 0.155 * gap + min(0.445 * max(gap - 0.5, 0.0), 0.75 * band_distance);
}

// ---- Temple ----

float temple_box(vec3 p, vec3 half_size) {
  vec3 outside = abs(p) - half_size;
  return length(max(outside, 0.0)) + min(max(outside.x, max(outside.y, outside.z)), 0.0);
}

const float TEMPLE_FLOOR = 8.05;   // top of the stylobate
const float TEMPLE_COL_TOP = 11.05;

// One column standing on the stylobate, axis through the local origin (c.y is world height).
float temple_column(vec3 c) {
  float r = length(c.xz);
  // Slightly tapered shaft: radius 0.3 at the floor, 0.26 under the capital (1.0001-Lipschitz).
  float shaft = max(r - (0.3 - 0.0133 * (c.y - TEMPLE_FLOOR)), abs(c.y - 9.4) - 1.4);
  float echinus = max(r - (0.27 + 0.5 * (c.y - 10.8)), abs(c.y - 10.87) - 0.07) / 1.12;
  float abacus = temple_box(c - vec3(0.0, 10.99, 0.0), vec3(0.38, 0.06, 0.38));
  return min(shaft, min(echinus, abacus));
}

// Nearest column of a row along the local z axis: centres at z = offset + spacing * k, k in
// [k_min, k_max]; others lie beyond the cell walls by at least spacing / 2 - 0.38.
float temple_column_row(vec3 p, float spacing, float offset, float k_min, float k_max) {
  float k = clamp(floor((p.z - offset) / spacing + 0.5), k_min, k_max);
  float qz = p.z - offset - k * spacing;
  float half_cell = 0.5 * spacing;
  float wall = 1e9;
  if (k > k_min) wall = min(wall, qz + half_cell);
  if (k < k_max) wall = min(wall, half_cell - qz);
  return min(temple_column(vec3(p.x, p.y, qz)), wall + half_cell - 0.38);
}

vec2 temple_building(vec3 p) {
  // Bounding box early-out: x in [-5, 5], y in [6.5, 13.45], z in [-7.7, 7.7].
  float bound = temple_box(p - vec3(0.0, 9.975, 0.0), vec3(5.0, 3.475, 7.7));
  if (bound > 0.5) return vec2(bound, 2.0);

  // Three-step stylobate.
  float steps = temple_box(p - vec3(0.0, 6.925, 0.0), vec3(5.0, 0.425, 7.7));
  steps = min(steps, temple_box(p - vec3(0.0, 7.525, 0.0), vec3(4.6, 0.175, 7.3)));
  steps = min(steps, temple_box(p - vec3(0.0, 7.875, 0.0), vec3(4.2, 0.175, 6.9)));

  // Peristyle: 11 columns on each long side (x = +-3.6, z = -6.5..6.5), 6 on each short side
  // (z = +-6.5, x = -3.6..3.6); the corners belong to both.
  vec3 m = vec3(abs(p.x), p.y, abs(p.z));
  float columns = temple_column_row(vec3(m.x - 3.6, p.y, p.z), 1.3, 0.0, -5.0, 5.0);
  columns = min(columns, temple_column_row(vec3(m.z - 6.5, p.y, p.x), 1.44, 0.72, -3.0, 2.0));

  float entablature = temple_box(p - vec3(0.0, 11.45, 0.0), vec3(3.98, 0.4, 6.88));
  entablature = min(entablature, temple_box(p - vec3(0.0, 11.95, 0.0), vec3(4.2, 0.1, 7.1)));

  // Gabled roof: a triangular prism along z (base y = 12.05, half width 4.2, ridge at 13.45);
  // the maximum of its face-plane distances is a lower bound.
  float roof = max(max(12.05 - p.y, m.z - 7.1), (m.x * 1.4 + (p.y - 12.05) * 4.2 - 4.2 * 1.4) / 4.428);

  float cella = temple_box(p - vec3(0.0, 9.55, 0.0), vec3(2.3, 1.5, 4.6));

  vec2 result = vec2(steps, 2.0);
  if (columns < result.x) result = vec2(columns, 2.0);
  if (entablature < result.x) result = vec2(entablature, 2.0);
  if (roof < result.x) result = vec2(roof, 3.0);
  if (cella < result.x) result = vec2(cella, 4.0);
  return result;
}

vec2 scene_map(vec3 p) {
  vec2 result = vec2(p.y, 0.0);  // the sea at y = 0
  float terrain = temple_terrain(p);
  if (terrain < result.x) result = vec2(terrain, 1.0);
  vec2 building = temple_building(p);
  if (building.x < result.x) result = building;
  return result;
}

vec3 scene_albedo(float material_id, vec3 p, vec3 normal, float footprint) {
  int id = int(material_id + 0.5);
  if (id == 0) {  // sea: deep blue with faint long swells
    float swell = 0.5 + 0.5 * sin(0.35 * p.x + 0.2 * p.z + 2.0 * sin(0.05 * p.z));
    return mix(vec3(0.02, 0.09, 0.15), vec3(0.04, 0.15, 0.22), swell);
  }
  if (id == 1) {
    // Rock with horizontal strata on steep faces, dry grass on gentle ones, sand at the shore.
    float strata = temple_noise(vec2(p.y * 2.5, 0.15 * (p.x + p.z)));
    strata = 0.6 * strata + 0.4 * temple_noise(vec2(p.y * 9.0, 0.4 * (p.x - p.z)));
    vec3 rock = mix(vec3(0.3, 0.25, 0.21), vec3(0.56, 0.48, 0.39), strata);
    vec3 grass = mix(vec3(0.22, 0.27, 0.1), vec3(0.4, 0.38, 0.16), temple_noise(p.xz * 0.4));
    vec3 ground = mix(rock, grass, smoothstep(0.7, 0.85, normal.y));
    return mix(vec3(0.66, 0.6, 0.46), ground, smoothstep(0.3, 0.9, p.y));
  }
  if (id == 2) return vec3(0.8, 0.77, 0.7);   // marble
  if (id == 3) {                              // terracotta tiles in rows down the slopes
    float rows = step(0.85, fract(p.z * 2.5));
    return mix(vec3(0.6, 0.27, 0.16), vec3(0.38, 0.17, 0.1), rows);
  }
  // Cella walls, with a dark doorway in the middle of the -z front.
  bool door = abs(p.x) < 0.8 && p.y < 10.3 && p.z < -4.5;
  return door ? vec3(0.03, 0.025, 0.02) : vec3(0.72, 0.64, 0.52);
}

void scene_light(int index, float time_s, out vec4 position, out vec3 radiance) {
  position = vec4(TEMPLE_SUN, 0.0);
  radiance = vec3(1.15, 1.0, 0.82);
}

vec3 scene_ambient(vec3 normal) {
  return mix(vec3(0.05, 0.045, 0.04), vec3(0.14, 0.17, 0.22), 0.5 + 0.5 * normal.y);
}

vec3 temple_haze(vec3 direction) {
  float sun = max(dot(direction, normalize(TEMPLE_SUN)), 0.0);
  return mix(vec3(0.66, 0.72, 0.8), vec3(0.9, 0.8, 0.66), pow(sun, 6.0));
}

vec3 scene_background(vec3 direction) {
  vec3 d = normalize(direction);
  vec3 haze = temple_haze(d);
  vec3 sky = mix(haze, vec3(0.2, 0.38, 0.7), pow(clamp(d.y, 0.0, 1.0), 0.5));
  float sun = max(dot(d, normalize(TEMPLE_SUN)), 0.0);
  sky += vec3(1.0, 0.8, 0.55) * (0.2 * pow(sun, 16.0) + 0.8 * pow(sun, 600.0));
  return d.y < 0.0 ? haze : min(sky, vec3(1.0));
}

vec3 scene_fog(vec3 colour, float distance, vec3 direction) {
  float x = distance / 110.0;
  return mix(colour, temple_haze(normalize(direction)), 1.0 - exp(-x * x));
}

void scene_camera(float time_s, out vec3 eye, out vec3 target, out float vertical_fov_deg) {
  // Circles about 50 degrees around the temple while closing in from 38 to 26 units.
  float angle = 2.3 + 0.085 * time_s;
  float radius = 38.0 - 1.2 * time_s;
  eye = vec3(radius * sin(angle), 16.5 - 0.35 * time_s, radius * cos(angle));
  target = vec3(0.0, 9.0, 0.0);
  vertical_fov_deg = 45.0;
}
