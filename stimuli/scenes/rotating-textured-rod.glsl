// fovlab scene "rotating-textured-rod": Ye et al. 2022's Figure 12 (b), the textured rotating rod. The
// rod, plane, camera, light and rotation of "rotating-rod", with a fine checkerboard on the rod:
// cells ROTATING_TEXTURED_ROD_AXIAL_CELL long along the rod and 1/16 of its circumference around it
// (eight cells across the visible half), light cream against dark red-brown.
//
// Rotation: the pattern's angle is ROTATING_TEXTURED_ROD_DEG_PER_S * time_s degrees,
// counter-clockwise on screen (time 0..18 s gives 0..180 degrees; Ye et al. 2022 steps it by 10 degrees,
// one step a second). As in "rotating-rod" the camera rolls (scene_map may not depend on time):
// it looks down at the plane with a tilt of ROTATING_TEXTURED_ROD_TILT_RAD whose direction sets its
// screen up. The checkerboard is point-symmetric about the rod's centre (cell edges on the top line
// and at the middle of its length), so at 180 degrees the frame is (up to rounding) the one at 0.
//
// Frame: the visible part of the ground plane is 2 * ROTATING_TEXTURED_ROD_VIEW_HALF_HEIGHT units
// high (16:9: 3.56 units wide); the rod is 3 units long, 0.1 thick, its axis 0.2 above the plane.
// At 1920x1080 an axial cell is about 11 pixels, at 320x180 about 2.
//
// Material ids: 0 ground plane (plain), 1 rod (checkerboard, box-filtered over the footprint).

const vec3 SCENE_BOUNDS_MIN = vec3(-8.0, -0.05, -8.0);
const vec3 SCENE_BOUNDS_MAX = vec3(8.0, 0.27, 8.0);  // the rod's top is at 0.25
const int SCENE_LIGHT_COUNT = 1;

const float ROTATING_TEXTURED_ROD_DEG_PER_S = 10.0;        // pattern angle per second of scene time
const float ROTATING_TEXTURED_ROD_EYE_HEIGHT = 4.0;        // camera above the ground plane
const float ROTATING_TEXTURED_ROD_VIEW_HALF_HEIGHT = 1.0;  // half the frame height, on the plane
const float ROTATING_TEXTURED_ROD_TILT_RAD = 1e-4;         // off-vertical tilt that fixes the roll
const float ROTATING_TEXTURED_ROD_HALF_LENGTH = 1.45;      // half the axis segment (caps add the radius)
const float ROTATING_TEXTURED_ROD_RADIUS = 0.05;
const float ROTATING_TEXTURED_ROD_AXIS_HEIGHT = 0.2;       // the rod's axis above the plane
const float ROTATING_TEXTURED_ROD_AXIAL_CELL = 0.02;       // checker cell length along the rod
const float ROTATING_TEXTURED_ROD_CELLS_AROUND = 16.0;     // checker cells around the circumference

const vec3 ROTATING_TEXTURED_ROD_GROUND_ALBEDO = vec3(0.05, 0.06, 0.08);
const vec3 ROTATING_TEXTURED_ROD_LIGHT_ALBEDO = vec3(0.88, 0.84, 0.76);
const vec3 ROTATING_TEXTURED_ROD_DARK_ALBEDO = vec3(0.22, 0.08, 0.05);
const vec3 ROTATING_TEXTURED_ROD_SUN_RADIANCE = vec3(0.75);  // straight down: the plane gets all of it
const vec3 ROTATING_TEXTURED_ROD_SKY_AMBIENT = vec3(0.35);   // irradiance of a surface facing up
const vec3 ROTATING_TEXTURED_ROD_DOWN_AMBIENT = vec3(0.2);   // of a surface facing down

// Capsule along x through (0, AXIS_HEIGHT, 0): an exact distance.
float rotating_textured_rod_distance(vec3 p) {
  float axial = clamp(p.x, -ROTATING_TEXTURED_ROD_HALF_LENGTH, ROTATING_TEXTURED_ROD_HALF_LENGTH);
  return length(p - vec3(axial, ROTATING_TEXTURED_ROD_AXIS_HEIGHT, 0.0)) - ROTATING_TEXTURED_ROD_RADIUS;
}

// Box average over [x - width/2, x + width/2] of the square wave that is +1 on [0, 1) and -1 on
// [1, 2) (period 2, in cells). Its antiderivative is the triangle wave 1 - |1 - mod(x, 2)|, so the
// average is a difference quotient of that; wide boxes fade to 0, the wave's mean.
float rotating_textured_rod_filtered_wave(float x, float width) {
  float w = max(width, 1e-4);
  float high = 1.0 - abs(1.0 - mod(x + 0.5 * w, 2.0));
  float low = 1.0 - abs(1.0 - mod(x - 0.5 * w, 2.0));
  return (high - low) / w;
}

vec2 scene_map(vec3 p) {
  float rod = rotating_textured_rod_distance(p);
  float ground = p.y;
  return rod < ground ? vec2(rod, 1.0) : vec2(ground, 0.0);
}

vec3 scene_albedo(float material_id, vec3 p, vec3 normal, float footprint) {
  if (int(material_id + 0.5) != 1) return ROTATING_TEXTURED_ROD_GROUND_ALBEDO;
  // Checker coordinates in cells: along the rod from its middle, and around it from its top line.
  float around_rad = atan(p.z, p.y - ROTATING_TEXTURED_ROD_AXIS_HEIGHT);
  float around_cell_length = 6.2831853 * ROTATING_TEXTURED_ROD_RADIUS / ROTATING_TEXTURED_ROD_CELLS_AROUND;
  float along = p.x / ROTATING_TEXTURED_ROD_AXIAL_CELL;
  float around = around_rad * ROTATING_TEXTURED_ROD_RADIUS / around_cell_length;
  float wave_along = rotating_textured_rod_filtered_wave(along, footprint / ROTATING_TEXTURED_ROD_AXIAL_CELL);
  float wave_around = rotating_textured_rod_filtered_wave(around, footprint / around_cell_length);
  float light_share = 0.5 + 0.5 * wave_along * wave_around;
  return mix(ROTATING_TEXTURED_ROD_DARK_ALBEDO, ROTATING_TEXTURED_ROD_LIGHT_ALBEDO, light_share);
}

void scene_light(int index, float time_s, out vec4 position, out vec3 radiance) {
  position = vec4(0.0, 1.0, 0.0, 0.0);  // directional, straight down: symmetric under the roll
  radiance = ROTATING_TEXTURED_ROD_SUN_RADIANCE;
}

vec3 scene_ambient(vec3 normal) {
  return mix(ROTATING_TEXTURED_ROD_DOWN_AMBIENT, ROTATING_TEXTURED_ROD_SKY_AMBIENT, 0.5 + 0.5 * normal.y);
}

// Rays that miss the bounds (only at frames far wider than 16:9) see the lit plane's colour.
vec3 scene_background(vec3 direction) {
  return ROTATING_TEXTURED_ROD_GROUND_ALBEDO * (ROTATING_TEXTURED_ROD_SKY_AMBIENT + ROTATING_TEXTURED_ROD_SUN_RADIANCE);
}

vec3 scene_fog(vec3 colour, float distance, vec3 direction) { return colour; }

void scene_camera(float time_s, out vec3 eye, out vec3 target, out float vertical_fov_deg) {
  float angle_rad = radians(ROTATING_TEXTURED_ROD_DEG_PER_S * time_s);
  // Screen up as a world (x, z) direction: -z at angle 0, turning towards +x (counter-clockwise
  // turning of the pattern on screen). The eye sits a tilt behind the straight-down line.
  vec2 screen_up = vec2(sin(angle_rad), -cos(angle_rad));
  vec2 eye_offset = -screen_up * ROTATING_TEXTURED_ROD_TILT_RAD * ROTATING_TEXTURED_ROD_EYE_HEIGHT;
  target = vec3(0.0);
  eye = vec3(eye_offset.x, ROTATING_TEXTURED_ROD_EYE_HEIGHT, eye_offset.y);
  vertical_fov_deg = 2.0 * degrees(atan(ROTATING_TEXTURED_ROD_VIEW_HALF_HEIGHT / ROTATING_TEXTURED_ROD_EYE_HEIGHT));
}
