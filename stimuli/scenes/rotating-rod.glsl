// fovlab scene "rotating-rod": Ye et al. 2022's Figure 12 (a), the untextured rotating rod. A long, thin,
// bright capsule floats just above a plain dark ground plane and turns about the view axis, which
// passes through the rod's middle; the camera looks straight down at the plane, so the plane fills
// the whole frame and the rod crosses most of it.
//
// Rotation: the pattern's angle is ROTATING_ROD_DEG_PER_S * time_s degrees, counter-clockwise on
// screen (time 0..18 s gives 0..180 degrees; Ye et al. 2022 steps it by 10 degrees, one step a second).
// scene_map may not depend on time, so the camera rolls instead of the rod turning: the tracer
// takes the camera's right vector from world up, and a camera looking almost straight down
// (tilted by ROTATING_ROD_TILT_RAD) has its screen up along the horizontal part of its view
// direction, so turning that part turns the image. The view axis stays on the rod's centre; the
// tilt is far below a pixel at any frame size. The light falls straight down and the ambient term
// depends on normal.y only, so rolling the camera is the same image as rotating the rod, and at 180
// degrees the frame is (up to rounding) the one at 0.
//
// Frame: the visible part of the ground plane is 2 * ROTATING_ROD_VIEW_HALF_HEIGHT units high
// (16:9: 3.56 units wide); the rod is 3 units long, 0.1 thick, its axis 0.2 above the plane.
//
// Material ids: 0 ground plane (plain), 1 rod (plain).

const vec3 SCENE_BOUNDS_MIN = vec3(-8.0, -0.05, -8.0);
const vec3 SCENE_BOUNDS_MAX = vec3(8.0, 0.27, 8.0);  // the rod's top is at 0.25
const int SCENE_LIGHT_COUNT = 1;

const float ROTATING_ROD_DEG_PER_S = 10.0;         // pattern angle per second of scene time
const float ROTATING_ROD_EYE_HEIGHT = 4.0;         // camera above the ground plane
const float ROTATING_ROD_VIEW_HALF_HEIGHT = 1.0;   // half the frame height, measured on the plane
const float ROTATING_ROD_TILT_RAD = 1e-4;          // off-vertical tilt that fixes the camera's roll
const float ROTATING_ROD_HALF_LENGTH = 1.45;       // half the axis segment (the caps add the radius)
const float ROTATING_ROD_RADIUS = 0.05;
const float ROTATING_ROD_AXIS_HEIGHT = 0.2;        // the rod's axis above the plane

const vec3 ROTATING_ROD_GROUND_ALBEDO = vec3(0.05, 0.06, 0.08);
const vec3 ROTATING_ROD_ROD_ALBEDO = vec3(0.88, 0.84, 0.76);
const vec3 ROTATING_ROD_SUN_RADIANCE = vec3(0.75);  // straight down: the plane gets all of it
const vec3 ROTATING_ROD_SKY_AMBIENT = vec3(0.35);   // irradiance of a surface facing up
const vec3 ROTATING_ROD_DOWN_AMBIENT = vec3(0.2);   // of a surface facing down

// Capsule along x through (0, AXIS_HEIGHT, 0): an exact distance.
float rotating_rod_distance(vec3 p) {
  float axial = clamp(p.x, -ROTATING_ROD_HALF_LENGTH, ROTATING_ROD_HALF_LENGTH);
  return length(p - vec3(axial, ROTATING_ROD_AXIS_HEIGHT, 0.0)) - ROTATING_ROD_RADIUS;
}

vec2 scene_map(vec3 p) {
  float rod = rotating_rod_distance(p);
  float ground = p.y;
  return rod < ground ? vec2(rod, 1.0) : vec2(ground, 0.0);
}

vec3 scene_albedo(float material_id, vec3 p, vec3 normal, float footprint) {
  return int(material_id + 0.5) == 1 ? ROTATING_ROD_ROD_ALBEDO : ROTATING_ROD_GROUND_ALBEDO;
}

void scene_light(int index, float time_s, out vec4 position, out vec3 radiance) {
  position = vec4(0.0, 1.0, 0.0, 0.0);  // directional, straight down: symmetric under the roll
  radiance = ROTATING_ROD_SUN_RADIANCE;
}

vec3 scene_ambient(vec3 normal) {
  return mix(ROTATING_ROD_DOWN_AMBIENT, ROTATING_ROD_SKY_AMBIENT, 0.5 + 0.5 * normal.y);
}

// Rays that miss the bounds (only at frames far wider than 16:9) see the lit plane's colour.
vec3 scene_background(vec3 direction) {
  return ROTATING_ROD_GROUND_ALBEDO * (ROTATING_ROD_SKY_AMBIENT + ROTATING_ROD_SUN_RADIANCE);
}

vec3 scene_fog(vec3 colour, float distance, vec3 direction) { return colour; }

void scene_camera(float time_s, out vec3 eye, out vec3 target, out float vertical_fov_deg) {
  float angle_rad = radians(ROTATING_ROD_DEG_PER_S * time_s);
  // Screen up as a world (x, z) direction: -z at angle 0, turning towards +x (counter-clockwise
  // turning of the pattern on screen). The eye sits a tilt behind the straight-down line.
  vec2 screen_up = vec2(sin(angle_rad), -cos(angle_rad));
  vec2 eye_offset = -screen_up * ROTATING_ROD_TILT_RAD * ROTATING_ROD_EYE_HEIGHT;
  target = vec3(0.0);
  eye = vec3(eye_offset.x, ROTATING_ROD_EYE_HEIGHT, eye_offset.y);
  vertical_fov_deg = 2.0 * degrees(atan(ROTATING_ROD_VIEW_HALF_HEIGHT / ROTATING_ROD_EYE_HEIGHT));
}
