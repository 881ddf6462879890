// fovlab scene "primitives": an open scene of fifteen primitive shapes in three rows of five on a
// large checkerboard ground plane, lit by the sun and a weak sky fill, seen by a slowly orbiting
// camera with ground, horizon and sky in view.
//
// Material ids: 0 ground (checkerboard), 1..15 the shapes (cell index + 1, one colour each).
// Grid: cell size 3, columns ix = -2..2 (x = -6..6), rows iz = -1..1 (z = -3..3). Every shape lies
// inside a vertical prism of half width PRIMITIVES_EXTENT around its cell centre, so scene_map
// evaluates only the shape of the cell holding p and bounds the others by the distance to the
// cell's walls (see primitives_shapes).

const vec3 SCENE_BOUNDS_MIN = vec3(-50.0, -0.05, -50.0);
const vec3 SCENE_BOUNDS_MAX = vec3(50.0, 2.45, 50.0);
const int SCENE_LIGHT_COUNT = 2;

const float PRIMITIVES_CELL = 3.0;
const float PRIMITIVES_EXTENT = 1.15;  // largest |x| or |z| of any shape around its cell centre
const vec3 PRIMITIVES_SUN = vec3(0.72, 0.58, -0.38);  // direction towards the sun (not normalised)

// ---- Distance functions (all exact or lower bounds, Lipschitz <= 1) ----

float primitives_box(vec3 p, vec3 half_size) {
  vec3 outside = abs(p) - half_size;
  return length(max(outside, 0.0)) + min(max(outside.x, max(outside.y, outside.z)), 0.0);
}

float primitives_round_box(vec3 p, vec3 half_size, float radius) {
  return primitives_box(p, half_size - radius) - radius;
}

// Solid of revolution around y from a 2-D profile distance: d = (radial, axial) excess.
float primitives_extrude(float d2, float half_height, float y) {
  vec2 w = vec2(d2, abs(y) - half_height);
  return min(max(w.x, w.y), 0.0) + length(max(w, 0.0));
}

// Torus in the xy plane (standing ring), major radius big_r, tube radius small_r.
float primitives_ring(vec3 p, float big_r, float small_r) {
  return length(vec2(length(p.xy) - big_r, p.z)) - small_r;
}

// Vertical capsule: segment from y = y0 to y = y1 on the axis, radius r.
float primitives_capsule(vec3 p, float y0, float y1, float r) {
  p.y -= clamp(p.y, y0, y1);
  return length(p) - r;
}

// Distance from 2-D point q to the segment a-b.
float primitives_segment(vec2 q, vec2 a, vec2 b) {
  vec2 ab = b - a;
  vec2 aq = q - a;
  float s = clamp(dot(aq, ab) / dot(ab, ab), 0.0, 1.0);
  return length(aq - s * ab);
}

// Solid cone standing on y = 0: base radius base_r, apex at height h. Exact: the 2-D distance of
// (radius, y) to the triangle (0,0)-(base_r,0)-(0,h), whose axis edge is not a surface.
float primitives_cone(vec3 p, float base_r, float h) {
  vec2 q = vec2(length(p.xz), p.y);
  float d = min(primitives_segment(q, vec2(0.0), vec2(base_r, 0.0)),
                primitives_segment(q, vec2(base_r, 0.0), vec2(0.0, h)));
  bool inside = q.y > 0.0 && q.x * h + q.y * base_r < base_r * h;
  return inside ? -d : d;
}

// Regular octahedron with vertices at distance s (lower bound: plane distance to the faces).
float primitives_octahedron(vec3 p, float s) {
  return (dot(abs(p), vec3(1.0)) - s) * 0.57735027;
}

// Vertical hexagonal prism: apothem a in xz, half height h (max of the face planes: a lower bound).
float primitives_hex_prism(vec3 p, float a, float h) {
  vec2 q = abs(p.xz);
  float d2 = max(q.x, 0.5 * q.x + 0.8660254 * q.y) - a;
  return primitives_extrude(d2, h, p.y);
}

// Ellipsoid lower bound: (|p / r| - 1) * min(r) has Lipschitz constant <= 1.
float primitives_ellipsoid(vec3 p, vec3 r) {
  return (length(p / r) - 1.0) * min(r.x, min(r.y, r.z));
}

// Chain link standing in the xy plane: a torus stretched by 2 * stretch along y.
float primitives_link(vec3 p, float stretch, float big_r, float small_r) {
  vec3 q = vec3(p.x, max(abs(p.y) - stretch, 0.0), p.z);
  return length(vec2(length(q.xy) - big_r, q.z)) - small_r;
}

// Hollow cube made of its twelve edges: the cube minus three axis-aligned square tubes.
float primitives_box_frame(vec3 p, float half_size, float edge) {
  float outer = primitives_box(p, vec3(half_size));
  float inner = half_size - edge;
  vec3 a = abs(p);
  float tube_x = max(a.y, a.z) - inner;
  float tube_y = max(a.x, a.z) - inner;
  float tube_z = max(a.x, a.y) - inner;
  return max(outer, -min(tube_x, min(tube_y, tube_z)));
}

// Polynomial smooth minimum (blend width k); the result is still 1-Lipschitz.
float primitives_smin(float a, float b, float k) {
  float h = max(k - abs(a - b), 0.0) / k;
  return min(a, b) - h * h * k * 0.25;
}

float primitives_smax(float a, float b, float k) { return -primitives_smin(-a, -b, k); }

vec3 primitives_rotate_y(vec3 p, float angle) {
  float c = cos(angle), s = sin(angle);
  return vec3(c * p.x - s * p.z, p.y, s * p.x + c * p.z);
}

// Shape number `index` (0..14) in its cell's local frame (origin on the ground at the cell centre).
float primitives_shape(int index, vec3 q) {
  switch (index) {
    // Back row (z = -3).
    case 0: return length(q - vec3(0.0, 1.0, 0.0)) - 1.0;                                   // sphere
    case 1: return primitives_box(primitives_rotate_y(q, 0.5) - vec3(0.0, 0.75, 0.0), vec3(0.75));  // box
    case 2: return primitives_round_box(q - vec3(0.0, 0.8, 0.0), vec3(0.6, 0.8, 0.9), 0.25); // rounded box
    case 3: return primitives_ring(primitives_rotate_y(q, -0.6) - vec3(0.0, 1.05, 0.0), 0.8, 0.25);  // torus
    case 4: return primitives_capsule(q, 0.55, 1.7, 0.55);                                  // capsule
    // Middle row (z = 0).
    case 5: return primitives_extrude(length(q.xz) - 0.75, 0.9, q.y - 0.9);                 // cylinder
    case 6: return primitives_cone(q, 0.95, 2.2);                                            // cone
    case 7: return primitives_octahedron(primitives_rotate_y(q, 0.4) - vec3(0.0, 1.1, 0.0), 1.1);  // octahedron
    case 8: return primitives_hex_prism(q - vec3(0.0, 0.65, 0.0), 0.85, 0.65);              // hexagonal prism
    case 9: return primitives_ellipsoid(q - vec3(0.0, 0.8, 0.0), vec3(1.1, 0.8, 0.6));      // ellipsoid
    // Front row (z = 3).
    case 10: return primitives_link(primitives_rotate_y(q, 0.7) - vec3(0.0, 1.15, 0.0), 0.45, 0.45, 0.2);  // link
    case 11: {  // smooth union of a box and a sphere
      float box = primitives_box(q - vec3(0.0, 0.5, 0.0), vec3(0.8, 0.5, 0.8));
      float ball = length(q - vec3(0.0, 1.3, 0.0)) - 0.6;
      return primitives_smin(box, ball, 0.5);
    }
    case 12: {  // rounded box with a sphere smoothly carved out of its top
      float block = primitives_round_box(q - vec3(0.0, 0.7, 0.0), vec3(0.8, 0.7, 0.8), 0.12);
      float ball = length(q - vec3(0.0, 1.55, 0.0)) - 0.85;
      return primitives_smax(block, -ball, 0.15);
    }
    case 13: return primitives_box_frame(primitives_rotate_y(q, 0.3) - vec3(0.0, 0.8, 0.0), 0.8, 0.12);  // box frame
    default: {  // three smoothly joined spheres
      float low = length(q - vec3(0.0, 0.7, 0.0)) - 0.7;
      float mid = length(q - vec3(0.0, 1.55, 0.0)) - 0.48;
      float top = length(q - vec3(0.0, 2.1, 0.0)) - 0.3;
      return primitives_smin(primitives_smin(low, mid, 0.3), top, 0.2);
    }
  }
}

// Distance to the shapes, and the index of the shape of the cell holding p. Only that shape is
// evaluated; every other shape lies beyond a wall of this cell (open towards the outside of the
// grid) by at least CELL / 2 - EXTENT, so min(shape, wall distance + that margin) is a lower bound.
vec2 primitives_shapes(vec3 p) {
  vec2 cell = clamp(floor(p.xz / PRIMITIVES_CELL + 0.5), vec2(-2.0, -1.0), vec2(2.0, 1.0));
  vec3 q = p - vec3(cell.x * PRIMITIVES_CELL, 0.0, cell.y * PRIMITIVES_CELL);
  float half_cell = 0.5 * PRIMITIVES_CELL;
  float wall = 1e9;
  if (cell.x > -2.0) wall = min(wall, q.x + half_cell);
  if (cell.x < 2.0) wall = min(wall, half_cell - q.x);
  if (cell.y > -1.0) wall = min(wall, q.z + half_cell);
  if (cell.y < 1.0) wall = min(wall, half_cell - q.z);
  int index = int(cell.x + 2.0) + 5 * int(cell.y + 1.0);
  float d = primitives_shape(index, q);
  return vec2(min(d, wall + (half_cell - PRIMITIVES_EXTENT)), float(index + 1));
}

vec2 scene_map(vec3 p) {
  vec2 shapes = primitives_shapes(p);
  float ground = p.y;
  return shapes.x < ground ? shapes : vec2(ground, 0.0);
}

vec3 scene_albedo(float material_id, vec3 p, vec3 normal, float footprint) {
  int id = int(material_id + 0.5);
  if (id == 0) {
    // Checkerboard of unit squares, box-filtered over the footprint so distant squares blend to
    // their mean instead of aliasing. The square wave s (+1/-1, period 2) has the triangle wave
    // g(x) = 1 - |1 - mod(x, 2)| as antiderivative; its box average is a difference of g, and the
    // 2-D checker is the product of the two axes' waves.
    float width = max(footprint, 1e-4);
    vec2 lo = p.xz - 0.5 * width;
    vec2 hi = p.xz + 0.5 * width;
    vec2 g_hi = 1.0 - abs(1.0 - mod(hi, 2.0));
    vec2 g_lo = 1.0 - abs(1.0 - mod(lo, 2.0));
    vec2 wave = (g_hi - g_lo) / width;
    float check = 0.5 - 0.5 * wave.x * wave.y;
    return mix(vec3(0.16, 0.17, 0.19), vec3(0.72, 0.71, 0.68), check);
  }
  // A cosine palette over the shape index: saturated but within [0.1, 0.85].
  float h = fract(float(id - 1) * 0.618034 + 0.05);
  return 0.475 + 0.375 * cos(6.2831853 * (h + vec3(0.0, 0.33, 0.67)));
}

void scene_light(int index, float time_s, out vec4 position, out vec3 radiance) {
  if (index == 0) {
    position = vec4(PRIMITIVES_SUN, 0.0);  // the sun
    radiance = vec3(1.0, 0.93, 0.8) * 0.95;
  } else {
    position = vec4(-0.55, 0.4, 0.75, 0.0);  // a cool fill from the opposite side
    radiance = vec3(0.14, 0.17, 0.24);
  }
}

vec3 scene_ambient(vec3 normal) {
  return mix(vec3(0.1, 0.09, 0.07), vec3(0.16, 0.2, 0.27), 0.5 + 0.5 * normal.y);
}

vec3 primitives_haze(vec3 direction) {
  return mix(vec3(0.6, 0.62, 0.64), vec3(0.72, 0.79, 0.88), smoothstep(-0.2, 0.02, direction.y));
}

vec3 scene_background(vec3 direction) {
  vec3 d = normalize(direction);
  vec3 zenith = vec3(0.18, 0.36, 0.72);
  vec3 sky = mix(vec3(0.72, 0.79, 0.88), zenith, pow(clamp(d.y, 0.0, 1.0), 0.55));
  float sun = max(dot(d, normalize(PRIMITIVES_SUN)), 0.0);
  sky += vec3(1.0, 0.85, 0.6) * (0.25 * pow(sun, 12.0) + 0.6 * pow(sun, 400.0));
  return d.y < 0.0 ? primitives_haze(d) : min(sky, vec3(1.0));
}

vec3 scene_fog(vec3 colour, float distance, vec3 direction) {
  float x = max(distance - 12.0, 0.0) / 26.0;
  return mix(colour, primitives_haze(normalize(direction)), 1.0 - exp(-x * x));
}

void scene_camera(float time_s, out vec3 eye, out vec3 target, out float vertical_fov_deg) {
  float angle = 0.45 + 0.07 * time_s;  // slow orbit, about 40 degrees over 10 s
  eye = vec3(14.5 * sin(angle), 4.0 + 0.25 * sin(0.3 * time_s), 14.5 * cos(angle));
  target = vec3(0.0, 1.0, 0.0);
  vertical_fov_deg = 50.0;
}
