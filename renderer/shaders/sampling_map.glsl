// The four sampling models of Ye et al. 2022 in the shaders: their parameters (one storage buffer at
// binding 0, filled by renderer/foveated_sampling/sampling_passes.cpp from the CPU model) and their
// maps. foveation/sampling_map.{h,cpp} and foveation/rectangular_mapping.cpp are the references;
// the equations are in docs/foveation.md ("Sampling models"). Needs eccentricity.glsl.

const float TWO_PI = 6.28318530718;

#include "shared/sampling_params.h"

layout(std430, binding = 0) readonly buffer SamplingParamsBuffer { SamplingParams sampling; };

float sampling_eccentricity_deg(vec2 point_px) {
  vec3 gaze_ray = ray_from_eye(sampling.gaze_px, sampling.principal_point_px, sampling.pixel_pitch_mm,
                               sampling.viewing_distance_mm);
  return eccentricity_between_deg(gaze_ray, ray_from_eye(point_px, sampling.principal_point_px, sampling.pixel_pitch_mm,
                                                         sampling.viewing_distance_mm));
}

// --- RMFR, per axis in shares of the screen and of the buffer (rectangular_mapping.cpp) ------------

float rmfr_g(float t, float phi) { return phi * t / (phi + t); }
float rmfr_g_inverse(float s, float phi) { return phi * s / (phi - s); }

float rmfr_to_buffer(float screen_share, float c, float phi) {
  float d = screen_share - c;
  if (d >= 0.0) return c + (1.0 - c) * rmfr_g(d, phi) / rmfr_g(1.0 - c, phi);
  return c - c * rmfr_g(-d, phi) / rmfr_g(c, phi);
}

float rmfr_to_screen(float buffer_share, float c, float phi) {
  if (buffer_share >= c) return c + rmfr_g_inverse((buffer_share - c) / (1.0 - c) * rmfr_g(1.0 - c, phi), phi);
  return c - rmfr_g_inverse((c - buffer_share) / c * rmfr_g(c, phi), phi);
}

float rmfr_axis_density(float screen_share, float c, float phi) {
  float d = screen_share - c;
  float side = d >= 0.0 ? 1.0 - c : c;
  return phi * (phi + side) / ((phi + abs(d)) * (phi + abs(d)));
}

// --- KFR (sampling_map.cpp KernelLogPolarMapping) --------------------------------------------------

vec2 kfr_to_buffer_px(vec2 point_px) {
  vec2 d = point_px - sampling.gaze_px;
  float radius = length(d);
  float log_share = clamp(log(max(radius, 1.0)) / sampling.log_max_radius, 0.0, 1.0);
  float angle = radius > 0.0 ? atan(d.y, d.x) : 0.0;  // atan(0, 0) is undefined in GLSL
  if (angle < 0.0) angle += TWO_PI;
  if (angle >= TWO_PI) angle = 0.0;
  return vec2(float(sampling.buffer_size.x) * pow(log_share, sampling.alpha),
              float(sampling.buffer_size.y) * angle / TWO_PI);
}

vec2 kfr_to_screen_px(vec2 buffer_px) {
  float share = clamp(buffer_px.x / float(sampling.buffer_size.x), 0.0, 1.0);
  float radius = exp(sampling.log_max_radius * pow(share, 1.0 / sampling.alpha));
  float angle = TWO_PI * buffer_px.y / float(sampling.buffer_size.y);
  return sampling.gaze_px + radius * vec2(cos(angle), sin(angle));
}

// KFR's sample spacings on the screen around a buffer column (sampling_map.cpp sample_spacings_px):
// radial dr/du = r L s^(1/alpha - 1) / (alpha w) (s = u / w) and tangential 2 pi r / h.
vec2 kfr_spacings_px(float buffer_u_px) {
  float share = clamp(buffer_u_px / float(sampling.buffer_size.x), 1e-6, 1.0);
  float radius = exp(sampling.log_max_radius * pow(share, 1.0 / sampling.alpha));
  float dr_du = radius * sampling.log_max_radius * pow(share, 1.0 / sampling.alpha - 1.0) /
                (sampling.alpha * float(sampling.buffer_size.x));
  return vec2(dr_du, TWO_PI * radius / float(sampling.buffer_size.y));
}

// --- Hyperbolic ------------------------------------------------------------------------------------

// The three layers' blend weights at a screen point (sampling_map.cpp HyperbolicLayers::weights).
vec3 hyperbolic_weights(vec2 point_px) {
  float e = sampling_eccentricity_deg(point_px);
  float inner, middle_fade;
  if (sampling.blend_band_deg > 0.0) {
    inner = clamp((sampling.inner_radius_deg - e) / sampling.blend_band_deg, 0.0, 1.0);
    middle_fade = clamp((sampling.outer_radius_deg - e) / sampling.blend_band_deg, 0.0, 1.0);
  } else {
    inner = e < sampling.inner_radius_deg ? 1.0 : 0.0;
    middle_fade = e < sampling.outer_radius_deg ? 1.0 : 0.0;
  }
  float middle = (1.0 - inner) * middle_fade;
  return vec3(inner, middle, 1.0 - inner - middle);
}

// --- Linear ----------------------------------------------------------------------------------------

float linear_probability(vec2 point_px) {
  float e = sampling_eccentricity_deg(point_px);
  if (e <= sampling.inner_radius_deg) return 1.0;
  if (e >= sampling.outer_radius_deg) return sampling.min_probability;
  return 1.0 - (1.0 - sampling.min_probability) * (e - sampling.inner_radius_deg) /
                   (sampling.outer_radius_deg - sampling.inner_radius_deg);
}
