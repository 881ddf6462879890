#ifndef FOVLAB_SAMPLING_PARAMS_H
#define FOVLAB_SAMPLING_PARAMS_H
// The sampling models' parameters (sampling_map.glsl's storage buffer) and the push constants of
// their passes (sampling_positions, sampling_reconstruct, pull_push, sampling_frame_read); filled
// by renderer/foveated_sampling/ from the CPU models.
#include "gpu_types.h"

FOVLAB_GPU_BEGIN

struct SamplingLayer {
  vec2 origin_px;  // top left of the layer's grid on the screen
  float pixel_size_px;
  uint first_sample;      // the layer's first entry in the sample buffer (row-major, `columns` a row)
  uvec2 grid_size;        // columns, rows
  vec2 weight_range_deg;  // eccentricities where the layer has weight
};

struct SamplingParams {
  uvec2 screen_size;       // W, H in pixels
  uvec2 buffer_size;       // RMFR, KFR: w, h; hyperbolic: the three layers' samples, 1 row; linear: W, H
  vec2 gaze_px;            // on the screen (clamped on the CPU)
  vec2 gaze_share;         // RMFR: c_x, c_y (clamped to [0.01, 0.99])
  vec2 focal_share;        // RMFR: phi_x, phi_y
  vec2 pixel_pitch_mm;     // hyperbolic and linear: the display, for eccentricities
  vec2 principal_point_px;  // where the eye's perpendicular meets the screen (eccentricity.glsl)
  uint model;              // MODEL_*
  uint seed;               // linear: the thresholds' seed
  float alpha;             // KFR
  float log_max_radius;    // KFR: L
  float inner_radius_deg;  // hyperbolic and linear: r1
  float outer_radius_deg;  // r2
  float blend_band_deg;    // hyperbolic
  float min_probability;   // linear: p_min
  float viewing_distance_mm;
  uint sample_capacity;  // entries of the sample buffer
  uint resample_filter;  // pass 2: FILTER_BILINEAR or FILTER_LANCZOS2 (ResampleFilter)
  uint pad0;
  SamplingLayer layers[3];  // hyperbolic: inner, middle, outer
};

// sampling_positions.comp.glsl
struct PositionParams {
  uint counter_index;  // counters[counter_index] counts the list
};

// sampling_reconstruct.comp.glsl (all it reads is in SamplingParams)
struct SamplingReconstructParams {
  uint unused;
};

// pull_push.comp.glsl
struct PullPushParams {
  uvec2 fine_size;
  uvec2 coarse_size;
  uint fine_offset;    // first entry of the finer level in `pyramid`
  uint coarse_offset;  // of the coarser one
  uint mode;           // 0: pull (writes coarse); 1: push (writes fine); 2: push into frame_colour
};

// sampling_frame_read.comp.glsl
struct FrameReadParams {
  uvec2 frame_size;
  uint counter_index;  // counters[counter_index] counts the list
};

// SamplingParams::model: foveation/sampling_map.h's SamplingModel; resample_filter: ResampleFilter.
const uint MODEL_RECTANGULAR = 0u;
const uint MODEL_HYPERBOLIC = 1u;
const uint MODEL_LINEAR = 2u;
const uint MODEL_KERNEL_LOG_POLAR = 3u;
const uint FILTER_BILINEAR = 0u;
const uint FILTER_LANCZOS2 = 1u;

FOVLAB_GPU_END

#ifdef __cplusplus
#include "core/render_choices.h"
#include "foveation/sampling_map.h"
static_assert(fovlab::gpu::MODEL_RECTANGULAR == uint32_t(fovlab::SamplingModel::rectangular) &&
              fovlab::gpu::MODEL_HYPERBOLIC == uint32_t(fovlab::SamplingModel::hyperbolic) &&
              fovlab::gpu::MODEL_LINEAR == uint32_t(fovlab::SamplingModel::linear) &&
              fovlab::gpu::MODEL_KERNEL_LOG_POLAR == uint32_t(fovlab::SamplingModel::kernel_log_polar));
static_assert(fovlab::gpu::FILTER_BILINEAR == uint32_t(fovlab::ResampleFilter::bilinear) &&
              fovlab::gpu::FILTER_LANCZOS2 == uint32_t(fovlab::ResampleFilter::lanczos2));
#endif

#endif
