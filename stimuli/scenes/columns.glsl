// fovlab scene "columns": a closed hall (floor, ceiling, side and end walls) with two rows of
// eleven fluted columns (plinth, base ring, fluted shaft, flared capital, abacus) under two
// ceiling beams, wall pilasters facing each column, five coloured point lights circling columns,
// and a camera walking slowly down the hall.
//
// Material ids: 0 floor (two-tone tiles), 1 walls, 2 ceiling (coffer pattern), 3 columns,
// 4 beams, 5 pilasters.
// Hall interior: x in [-6, 6], y in [0, 6], z in [-24, 24]. Columns at x = +-3.5, z = 4k, k = -5..5.
// Columns are found by domain repetition along z (one cell evaluated, neighbours bounded by the
// distance to the cell walls) and mirroring in x.

const vec3 SCENE_BOUNDS_MIN = vec3(-6.05, -0.05, -24.05);
const vec3 SCENE_BOUNDS_MAX = vec3(6.05, 6.05, 24.05);
const int SCENE_LIGHT_COUNT = 5;

const float COLUMNS_HALL_X = 6.0;      // half width
const float COLUMNS_HALL_Y = 6.0;      // height
const float COLUMNS_HALL_Z = 24.0;     // half length
const float COLUMNS_ROW_X = 3.5;       // |x| of the column rows
const float COLUMNS_SPACING = 4.0;     // distance between columns along z
const float COLUMNS_LAST = 5.0;        // cells k = -5..5
const float COLUMNS_EXTENT_Z = 0.66;   // largest |z| of a column or pilaster around its cell centre
const float COLUMNS_SHAFT_R = 0.42;

float columns_box(vec3 p, vec3 half_size) {
  vec3 outside = abs(p) - half_size;
  return length(max(outside, 0.0)) + min(max(outside.x, max(outside.y, outside.z)), 0.0);
}

// Extrudes a 2-D distance d2 (in xz) along y over [centre - half_height, centre + half_height].
float columns_extrude(float d2, float y, float centre, float half_height) {
  vec2 w = vec2(d2, abs(y - centre) - half_height);
  return min(max(w.x, w.y), 0.0) + length(max(w, 0.0));
}

// One column in its local frame: axis along y through the origin, floor at y = 0.
float columns_column(vec3 c) {
  float r = length(c.xz);
  // Cheap bounding cylinder (radius 0.94 covers the abacus corners): far away, it is the bound.
  float outer = columns_extrude(r - 0.94, c.y, 2.87, 2.87);
  if (outer > 0.25) return outer;

  // Shaft with sixteen flutes: polar repetition of one groove cylinder, carved over y in [0.7, 5.1].
  const float sector = 6.2831853 / 16.0;
  float angle = atan(c.z, c.x);
  float local_angle = mod(angle + 0.5 * sector, sector) - 0.5 * sector;
  vec2 g = r * vec2(cos(local_angle), sin(local_angle));
  float groove = length(g - vec2(COLUMNS_SHAFT_R + 0.03, 0.0)) - 0.08;
  groove = max(groove, abs(c.y - 2.9) - 2.2);
  float shaft = max(r - COLUMNS_SHAFT_R, -groove);

  float plinth = columns_box(c - vec3(0.0, 0.15, 0.0), vec3(0.62, 0.15, 0.62));
  float base_ring = columns_extrude(r - 0.54, c.y, 0.4, 0.1);
  // Flared capital (echinus): radius 0.42 at y = 5.2 growing to 0.6 at y = 5.52; the slope 0.55
  // makes the cone distance 1.14-Lipschitz, hence the division.
  float echinus = max((r - (0.42 + (c.y - 5.2) * 0.55)) / 1.14, abs(c.y - 5.36) - 0.16);
  float abacus = columns_box(c - vec3(0.0, 5.63, 0.0), vec3(0.66, 0.11, 0.66));
  return min(min(shaft, plinth), min(base_ring, min(echinus, abacus)));
}

vec2 scene_map(vec3 p) {
  // The room: the inside of a box, exact distance to its nearest face.
  float floor_d = p.y;
  float ceiling_d = COLUMNS_HALL_Y - p.y;
  float walls_d = min(COLUMNS_HALL_X - abs(p.x), COLUMNS_HALL_Z - abs(p.z));
  vec2 result = vec2(floor_d, 0.0);
  if (walls_d < result.x) result = vec2(walls_d, 1.0);
  if (ceiling_d < result.x) result = vec2(ceiling_d, 2.0);

  // Mirror in x: the row at x = +3.5 is the nearer one for x >= 0 (the columns lie in x > 0).
  vec3 m = vec3(abs(p.x), p.y, p.z);
  float beam = columns_box(m - vec3(COLUMNS_ROW_X, 5.87, 0.0), vec3(0.6, 0.13, COLUMNS_HALL_Z));
  if (beam < result.x) result = vec2(beam, 4.0);

  // Domain repetition along z: evaluate the nearest cell only. The other cells' columns and
  // pilasters lie beyond this cell's walls (open towards the ends of the hall) by at least
  // spacing / 2 - EXTENT_Z, so min(column, wall distance + that margin) never overestimates.
  float k = clamp(floor(p.z / COLUMNS_SPACING + 0.5), -COLUMNS_LAST, COLUMNS_LAST);
  float qz = p.z - k * COLUMNS_SPACING;
  float half_cell = 0.5 * COLUMNS_SPACING;
  float cell_wall = 1e9;
  if (k > -COLUMNS_LAST) cell_wall = min(cell_wall, qz + half_cell);
  if (k < COLUMNS_LAST) cell_wall = min(cell_wall, half_cell - qz);
  float neighbours = cell_wall + (half_cell - COLUMNS_EXTENT_Z);

  float column = min(columns_column(vec3(m.x - COLUMNS_ROW_X, m.y, qz)), neighbours);
  if (column < result.x) result = vec2(column, 3.0);
  float pilaster = columns_box(vec3(m.x - COLUMNS_HALL_X, m.y - 3.0, qz), vec3(0.22, 3.0, 0.45));
  pilaster = min(pilaster, neighbours);
  if (pilaster < result.x) result = vec2(pilaster, 5.0);
  return result;
}

vec3 scene_albedo(float material_id, vec3 p, vec3 normal, float footprint) {
  int id = int(material_id + 0.5);
  if (id == 0) {  // floor: 2 x 2 tiles in two tones, thin dark grout
    vec2 tile = p.xz * 0.5;
    float check = mod(floor(tile.x) + floor(tile.y), 2.0);
    vec2 edge = abs(fract(tile) - 0.5);
    float grout = step(0.485, max(edge.x, edge.y));
    vec3 colour = mix(vec3(0.62, 0.58, 0.52), vec3(0.22, 0.2, 0.19), check);
    return mix(colour, vec3(0.08), grout);
  }
  if (id == 1) {  // walls: plaster above a darker dado
    vec3 plaster = vec3(0.62, 0.52, 0.4);
    vec3 dado = vec3(0.32, 0.18, 0.14);
    return p.y < 1.0 ? dado : (p.y < 1.1 ? vec3(0.7, 0.66, 0.58) : plaster);
  }
  if (id == 2) {  // ceiling: coffers between the beams
    vec2 c = abs(fract(p.xz / vec2(1.5, 2.0)) - 0.5);
    return max(c.x, c.y) > 0.42 ? vec3(0.55, 0.5, 0.44) : vec3(0.28, 0.3, 0.38);
  }
  if (id == 3) return vec3(0.78, 0.75, 0.69);  // marble columns
  if (id == 4) return vec3(0.5, 0.44, 0.38);   // beams
  return vec3(0.7, 0.67, 0.6);                 // pilasters
}

void scene_light(int index, float time_s, out vec4 position, out vec3 radiance) {
  // Light i circles the column at x = +-3.5, z = -16, -8, 0, 8, 16 (sides alternate) on an ellipse
  // that keeps clear of the column, the wall and the neighbouring columns, bobbing up and down.
  float i = float(index);
  float side = (index % 2 == 0) ? 1.0 : -1.0;
  float angle = 0.55 * time_s * (index % 2 == 0 ? 1.0 : -1.0) + 1.3 * i;
  vec3 centre = vec3(side * COLUMNS_ROW_X, 2.9 + 0.5 * sin(0.8 * time_s + 2.1 * i), -16.0 + 8.0 * i);
  position = vec4(centre + vec3(1.45 * cos(angle), 0.0, 1.8 * sin(angle)), 1.0);
  const vec3 colours[5] = vec3[5](vec3(1.0, 0.62, 0.3), vec3(0.45, 0.65, 1.0), vec3(1.0, 0.92, 0.8),
                                  vec3(1.0, 0.45, 0.6), vec3(0.55, 1.0, 0.6));
  radiance = 3.2 * colours[index];
}

vec3 scene_ambient(vec3 normal) {
  return mix(vec3(0.035, 0.03, 0.028), vec3(0.06, 0.058, 0.055), 0.5 + 0.5 * normal.y);
}

vec3 scene_background(vec3 direction) { return vec3(0.0); }  // closed hall: never seen

vec3 scene_fog(vec3 colour, float distance, vec3 direction) {
  // A little dusty air deep down the hall.
  return mix(colour, vec3(0.03, 0.028, 0.025), 1.0 - exp(-0.012 * distance));
}

void scene_camera(float time_s, out vec3 eye, out vec3 target, out float vertical_fov_deg) {
  // Walks down the middle aisle at 1.1 units/s with a gentle sway and step bob.
  float z = -20.5 + 1.1 * time_s;
  eye = vec3(0.5 * sin(0.35 * time_s), 1.7 + 0.03 * sin(3.4 * time_s), z);
  target = vec3(0.8 * sin(0.35 * time_s + 0.9), 1.9, z + 6.0);
  vertical_fov_deg = 60.0;
}
