// fovlab scene "rotating-texture": Ye et al. 2022's Figure 12 (c), the rotating texture. A flat plane with
// a fine, high-contrast texture fills the whole frame and turns about the view axis; the camera
// looks straight down at it. The texture is a plaid: a checkerboard of ROTATING_TEXTURE_CHECKER_CELL
// squares plus a sinusoidal grating of period ROTATING_TEXTURE_GRATING_PERIOD at
// ROTATING_TEXTURE_GRATING_ANGLE_DEG to the checker's rows. The oblique grating breaks the
// checkerboard's quarter-turn symmetry, so every rotation step gives a different frame; at 1920x1080
// a checker cell is about 16 pixels and the grating's period about 13, at 320x180 about 3 and 2.
//
// Rotation: the pattern's angle is ROTATING_TEXTURE_DEG_PER_S * time_s degrees, counter-clockwise
// on screen (time 0..18 s gives 0..180 degrees; Ye et al. 2022 steps it by 10 degrees, one step a
// second). scene_map may not depend on time, so the camera rolls instead of the plane turning: the
// tracer takes the camera's right vector from world up, and a camera looking almost straight down
// (tilted by ROTATING_TEXTURE_TILT_RAD) has its screen up along the horizontal part of its view
// direction, so turning that part turns the image. The view axis stays on the plane's origin, the
// centre of rotation. The light falls straight down, so the plane's shading is uniform. Both parts
// of the texture are point-symmetric about the origin, so at 180 degrees the frame is (up to
// rounding) the one at 0.
//
// Frame: the visible part of the plane is 2 * ROTATING_TEXTURE_VIEW_HALF_HEIGHT units high (16:9:
// 3.56 units wide); the plane reaches 8 units from the centre, beyond the frame at any angle.
//
// Material ids: 0 the textured plane (both parts box-filtered over the footprint).

const vec3 SCENE_BOUNDS_MIN = vec3(-8.0, -0.05, -8.0);
const vec3 SCENE_BOUNDS_MAX = vec3(8.0, 0.05, 8.0);
const int SCENE_LIGHT_COUNT = 1;

const float ROTATING_TEXTURE_DEG_PER_S = 10.0;           // pattern angle per second of scene time
const float ROTATING_TEXTURE_EYE_HEIGHT = 4.0;           // camera above the plane
const float ROTATING_TEXTURE_VIEW_HALF_HEIGHT = 1.0;     // half the frame height, on the plane
const float ROTATING_TEXTURE_TILT_RAD = 1e-4;            // off-vertical tilt that fixes the roll
const float ROTATING_TEXTURE_CHECKER_CELL = 0.03;        // side of a checker square
const float ROTATING_TEXTURE_GRATING_PERIOD = 0.025;     // wavelength of the grating
const float ROTATING_TEXTURE_GRATING_ANGLE_DEG = 30.0;   // grating's wave vector against world x
const float ROTATING_TEXTURE_CHECKER_WEIGHT = 0.55;      // the grating has the rest of the contrast

const vec3 ROTATING_TEXTURE_DARK_ALBEDO = vec3(0.03, 0.04, 0.07);
const vec3 ROTATING_TEXTURE_LIGHT_ALBEDO = vec3(0.8, 0.76, 0.66);
const vec3 ROTATING_TEXTURE_SUN_RADIANCE = vec3(0.7);    // straight down
const vec3 ROTATING_TEXTURE_SKY_AMBIENT = vec3(0.3);     // irradiance of a surface facing up
const vec3 ROTATING_TEXTURE_DOWN_AMBIENT = vec3(0.2);    // of a surface facing down

// Box average over [x - width/2, x + width/2] of the square wave that is +1 on [0, 1) and -1 on
// [1, 2) (period 2, in cells). Its antiderivative is the triangle wave 1 - |1 - mod(x, 2)|, so the
// average is a difference quotient of that; wide boxes fade to 0, the wave's mean.
float rotating_texture_filtered_wave(float x, float width) {
  float w = max(width, 1e-4);
  float high = 1.0 - abs(1.0 - mod(x + 0.5 * w, 2.0));
  float low = 1.0 - abs(1.0 - mod(x - 0.5 * w, 2.0));
  return (high - low) / w;
}

// sin(x) / x, 1 at 0.
float rotating_texture_sinc(float x) { return abs(x) < 1e-4 ? 1.0 : sin(x) / x; }

vec2 scene_map(vec3 p) { return vec2(p.y, 0.0); }

vec3 scene_albedo(float material_id, vec3 p, vec3 normal, float footprint) {
  // Checkerboard in [-1, 1]: the product of the two axes' square waves, each box-filtered over the
  // footprint (in cells).
  vec2 cells = p.xz / ROTATING_TEXTURE_CHECKER_CELL;
  float footprint_cells = footprint / ROTATING_TEXTURE_CHECKER_CELL;
  float checker = rotating_texture_filtered_wave(cells.x, footprint_cells) *
                  rotating_texture_filtered_wave(cells.y, footprint_cells);
  // Grating cos(k . p) in [-1, 1]; its average over a footprint-wide square is the same cosine
  // times sinc(k_x w / 2) sinc(k_z w / 2).
  float grating_angle_rad = radians(ROTATING_TEXTURE_GRATING_ANGLE_DEG);
  vec2 wave_vector = 6.2831853 / ROTATING_TEXTURE_GRATING_PERIOD * vec2(cos(grating_angle_rad), sin(grating_angle_rad));
  float grating = cos(dot(wave_vector, p.xz)) * rotating_texture_sinc(0.5 * wave_vector.x * footprint) *
                  rotating_texture_sinc(0.5 * wave_vector.y * footprint);
  float pattern = mix(grating, checker, ROTATING_TEXTURE_CHECKER_WEIGHT);
  return mix(ROTATING_TEXTURE_DARK_ALBEDO, ROTATING_TEXTURE_LIGHT_ALBEDO, 0.5 + 0.5 * pattern);
}

void scene_light(int index, float time_s, out vec4 position, out vec3 radiance) {
  position = vec4(0.0, 1.0, 0.0, 0.0);  // directional, straight down: uniform on the plane
  radiance = ROTATING_TEXTURE_SUN_RADIANCE;
}

vec3 scene_ambient(vec3 normal) {
  return mix(ROTATING_TEXTURE_DOWN_AMBIENT, ROTATING_TEXTURE_SKY_AMBIENT, 0.5 + 0.5 * normal.y);
}

// Rays that miss the bounds (only at frames far wider than 16:9) see the texture's mean colour.
vec3 scene_background(vec3 direction) {
  vec3 mean_albedo = 0.5 * (ROTATING_TEXTURE_DARK_ALBEDO + ROTATING_TEXTURE_LIGHT_ALBEDO);
  return mean_albedo * (ROTATING_TEXTURE_SKY_AMBIENT + ROTATING_TEXTURE_SUN_RADIANCE);
}

vec3 scene_fog(vec3 colour, float distance, vec3 direction) { return colour; }

void scene_camera(float time_s, out vec3 eye, out vec3 target, out float vertical_fov_deg) {
  float angle_rad = radians(ROTATING_TEXTURE_DEG_PER_S * time_s);
  // Screen up as a world (x, z) direction: -z at angle 0, turning towards +x (counter-clockwise
  // turning of the pattern on screen). The eye sits a tilt behind the straight-down line.
  vec2 screen_up = vec2(sin(angle_rad), -cos(angle_rad));
  vec2 eye_offset = -screen_up * ROTATING_TEXTURE_TILT_RAD * ROTATING_TEXTURE_EYE_HEIGHT;
  target = vec3(0.0);
  eye = vec3(eye_offset.x, ROTATING_TEXTURE_EYE_HEIGHT, eye_offset.y);
  vertical_fov_deg = 2.0 * degrees(atan(ROTATING_TEXTURE_VIEW_HALF_HEIGHT / ROTATING_TEXTURE_EYE_HEIGHT));
}
