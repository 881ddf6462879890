#pragma once
// The typed parameters of each rendering method: one plain struct per method, held in a variant
// whose alternative is the method, except the sampling models, each a (source, model) pair held in
// one alternative, SampledParameters (method_of). Their defaults, ranges, units and keys are in the method's
// descriptor (render_method.h): make a set with default_parameters(method), never by value
// initialisation alone (which zeroes everything).
//
// Angles say in their name whether they are a radius (an eccentricity from the gaze) or an
// aperture (the full angle across, twice the radius).
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <variant>

#include "core/render_choices.h"

namespace fovlab {

// How a method makes its frames. Ye et al. 2022's sampling models are one kind a source of samples
// (in SampleSource's order), the model itself RenderMethod::model: a new model is a SamplingModel
// (core/render_choices.h), never a new kind.
enum class MethodKind : uint8_t {
  ground_truth,
  inverted_pyramid,
  foveated_pyramid,
  path_traced,
  foveated_path_traced,
  sphere_traced_sampling,   // a sampling model on the sphere tracer (rmfr, hyperbolic, linear, kfr)
  path_traced_sampling,     // the same on pre-rendered path-traced frames (pt-rmfr, ...)
  volume_raycast,           // Bruder et al. 2019's volume raycaster: every pixel traced
  foveated_volume_raycast,  // the same, rays at the Voronoi mask's sites around the gaze
  image_sampling,           // a sampling model on a folder of the lab's own images (img-rmfr, ...)
};
inline constexpr MethodKind kSamplingKinds[] = {MethodKind::sphere_traced_sampling, MethodKind::path_traced_sampling,
                                                MethodKind::image_sampling};

// A rendering method: its kind and, for the sampling kinds, its model. The methods that are not
// sampling models are named constants (RenderMethod::foveated_pyramid); a sampling model is
// sampled_method(source, model).
struct RenderMethod {
  MethodKind kind = MethodKind::ground_truth;
  SamplingModel model = SamplingModel::rectangular;  // the sampling kinds' own; rectangular for the others
  auto operator<=>(const RenderMethod&) const = default;

  static const RenderMethod ground_truth, inverted_pyramid, foveated_pyramid, path_traced, foveated_path_traced,
      volume_raycast, foveated_volume_raycast;
};
inline constexpr RenderMethod RenderMethod::ground_truth{MethodKind::ground_truth};
inline constexpr RenderMethod RenderMethod::inverted_pyramid{MethodKind::inverted_pyramid};
inline constexpr RenderMethod RenderMethod::foveated_pyramid{MethodKind::foveated_pyramid};
inline constexpr RenderMethod RenderMethod::path_traced{MethodKind::path_traced};
inline constexpr RenderMethod RenderMethod::foveated_path_traced{MethodKind::foveated_path_traced};
inline constexpr RenderMethod RenderMethod::volume_raycast{MethodKind::volume_raycast};
inline constexpr RenderMethod RenderMethod::foveated_volume_raycast{MethodKind::foveated_volume_raycast};

// Whether a method is one of the sampling models, on any source.
constexpr bool is_sampling_model(RenderMethod method) {
  return method.kind == MethodKind::sphere_traced_sampling || method.kind == MethodKind::path_traced_sampling ||
         method.kind == MethodKind::image_sampling;
}
// A sampling model's source: its index in SampleSource (0 the sphere tracer, 1 path-traced frames,
// 2 a folder of images).
constexpr size_t sample_source_index(RenderMethod method) {
  return method.kind == MethodKind::path_traced_sampling ? 1 : method.kind == MethodKind::image_sampling ? 2 : 0;
}
// The method of a model on a source (SampleSource's index).
constexpr RenderMethod sampled_method(size_t source, SamplingModel model) {
  return RenderMethod{kSamplingKinds[source], model};
}

// The choices (MaskCombine, CoarseTest, PeripheryReconstruction, NearMisses, ResampleFilter) are
// core/render_choices.h's, the renderer's own: they reach it as they are.

// The physical display of the foveated methods: the stimulus image's size and the eye's distance.
// 0 means "not given": a study's schedule fills them from its [display].
struct StimulusDisplay {
  double display_width_mm = 0.0;
  double display_height_mm = 0.0;
  double viewing_distance_mm = 0.0;
};

// Sphere tracing of an SDF scene, every sample traced from the camera (GT).
struct GroundTruthParameters {
  int samples_per_pixel;
  int max_steps;
  double hit_threshold;
};

// The inverted pyramid (IPR, Polychronakis et al. 2023 section 3.1).
struct InvertedPyramidParameters {
  int samples_per_pixel;
  int max_steps;
  double hit_threshold;
  int pyramid_levels;
  int min_filter_size;
  CoarseTest coarse_test;
  bool full_resolution_depth;
};

// FIPR's outer periphery at this radius is none (eccentricities are below 180 degrees); the
// renderer's is then infinite (protocols/stimuli/stimulus_settings.cpp).
inline constexpr double kNoOuterPeripheryRadiusDeg = 180.0;

// The foveated inverted pyramid (FIPR, Polychronakis et al. 2023 section 3.2).
struct FoveatedPyramidParameters {
  int samples_per_pixel;
  int max_steps;
  double hit_threshold;
  int pyramid_levels;
  int min_filter_size;
  CoarseTest coarse_test;
  double fovea_radius_deg;            // eccentricity up to which every pixel is traced
  double outer_periphery_radius_deg;  // eccentricity beyond which none is (180: no outer periphery)
  int periphery_refresh;
  int periphery_steps;
  PeripheryReconstruction periphery_reconstruction;
  NearMisses near_misses;
  bool blur;
  MaskCombine combine;
  double edge_threshold;
  EdgeDepth edge_depth;
  uint32_t mask_seed;
  StimulusDisplay display;
};

// Path tracing (Polychronakis et al. 2021's reference), shown from pre-rendered frames.
struct PathTracedParameters {
  int samples_per_pixel;
  int max_bounces;
  uint32_t path_seed;
};

// The emulated foveated path tracer (Polychronakis et al. 2021 section 3.2): three pre-rendered zone buffers blended
// by the gaze of each refresh.
struct FoveatedPathTracedParameters {
  int samples_per_pixel;
  int max_bounces;
  uint32_t path_seed;
  double foveal_aperture_deg;               // full angle of the foveal zone
  double middle_minus_foveal_aperture_deg;  // the middle zone's aperture is the foveal one plus this
  double band_width_deg;                    // width of each blend band, in eccentricity
  int periphery_bounces;                    // bounces of the middle and outer zones; -1: max_bounces
  StimulusDisplay display;
};

// A sampling-model stimulus is a source of samples and a model of where they fall (Ye et al. 2022,
// section 5.1; foveation/sampling_map.h): only the model's samples are made, and the frame is made
// from them per gaze sample. Each method rmfr, hyperbolic, linear, kfr, pt-rmfr, ..., img-rmfr, ... is
// one pair (sampled_method). The source's parameters come first in the descriptor, then the
// model's, under the same keys on every source.

// The sphere tracer on the SDF scene: every sample traced from the camera.
struct SphereTracedSamples {
  int samples_per_pixel;  // rays a sample, spread over the sample's footprint
  int max_steps;
  double hit_threshold;
};

// Pre-rendered path-traced frames (as pt; Ye et al. 2022's demo does the same): the path tracer's
// parameters make the frames; each sample takes the frame's mean over its footprint.
struct PathTracedSamples {
  int samples_per_pixel;  // of the pre-rendered frames
  int max_bounces;
  uint32_t path_seed;
};

// A folder of the lab's own images (PNG or EXR, the block's scene), frame i of a presentation
// image i of the sorted folder (a folder of one image: a still); each sample takes the image's mean
// over its footprint, as on pre-rendered frames. No parameters: the images are what they are.
struct ImageSamples {};

// In the order of kSamplingKinds.
using SampleSource = std::variant<SphereTracedSamples, PathTracedSamples, ImageSamples>;
static_assert(std::variant_size_v<SampleSource> == std::size(kSamplingKinds));

// The sampling models' `equalise`, by its choice's index (render_method.cpp names them; Equalise in
// foveation/sampling_map.h says what each solves): off; on as logs before schema 8 recorded it, the
// theoretical density (a config read now, or from a log of schema 8 or later, reads "on" as
// samples); samples; density.
enum class EqualiseChoice : uint8_t { off, on_before_log_schema_8, samples, density };

// RMFR: a buffer sigma times smaller per axis, each axis warped towards the gaze.
struct RectangularMappingModel {
  double sigma;
  double focal_share_x;  // f_x / W
  double focal_share_y;  // f_y / H
  ResampleFilter resample;
};

// The hyperbolic model: layers of pixel size 1, 2 (middle_pixel_size_px) and s3 out to r1, r2 and
// the whole screen, blended over blend_band_deg at each border.
struct HyperbolicLayersModel {
  double inner_radius_deg;  // r1, an eccentricity (radius)
  double outer_radius_deg;  // r2
  double middle_pixel_size_px;
  double outer_pixel_size_px;
  double blend_band_deg;
  EqualiseChoice equalise;  // s3 solved (gaze at the centre) to match RMFR at sigma
  double sigma;             // the target of equalise
  ResampleFilter resample;
  StimulusDisplay display;
};

// The linear model: every pixel shaded with a probability 1 up to r1, falling linearly to p_min at r2.
struct LinearFalloffModel {
  double inner_radius_deg;
  double outer_radius_deg;
  double min_probability;
  uint32_t sample_seed;
  EqualiseChoice equalise;  // p_min solved (gaze at the centre) to match RMFR at sigma
  double sigma;
  StimulusDisplay display;
};

// KFR: a buffer sigma times smaller per axis in (log radius)^alpha and angle around the gaze.
struct KernelLogPolarModel {
  double sigma;
  double alpha;
  EqualiseChoice equalise;  // samples: the buffer's sigma solved (gaze at the centre) to match RMFR at sigma
  ResampleFilter resample;
};

// In SamplingModel's order (core/render_choices.h).
using SamplingModelParameters =
    std::variant<RectangularMappingModel, HyperbolicLayersModel, LinearFalloffModel, KernelLogPolarModel>;
static_assert(std::variant_size_v<SamplingModelParameters> == kSamplingModelCount);

struct SampledParameters {
  SampleSource source;
  SamplingModelParameters model;
};

// Bruder et al. 2019's volume raycaster (docs/volume-rendering.md) on a volume scene, every pixel traced.
struct VolumeRaycastParameters {
  double step_voxels;  // the base step along a ray
  uint32_t jitter_seed;
};

// Its Voronoi-foveated form: rays at the sites of the sampling mask shifted to each gaze sample, the
// frame rebuilt by natural-neighbour interpolation.
struct FoveatedVolumeRaycastParameters {
  double step_voxels;
  uint32_t jitter_seed;
  double density_sigma_deg;  // s: radius of the sampling density's Gaussian (an eccentricity)
  bool opacity_correction;   // the longer peripheral step's opacity corrected
  bool temporal_smoothing;   // the mean with up to 8 stored frames while the view stays
  uint32_t mask_seed;        // the weighted LBG's initial sites
  StimulusDisplay display;
};

using MethodParameters = std::variant<GroundTruthParameters, InvertedPyramidParameters, FoveatedPyramidParameters,
                                      PathTracedParameters, FoveatedPathTracedParameters, SampledParameters,
                                      VolumeRaycastParameters, FoveatedVolumeRaycastParameters>;

inline RenderMethod method_of(const MethodParameters& parameters) {
  if (const auto* sampled = std::get_if<SampledParameters>(&parameters))
    return sampled_method(sampled->source.index(), static_cast<SamplingModel>(sampled->model.index()));
  constexpr MethodKind kByAlternative[] = {MethodKind::ground_truth,           MethodKind::inverted_pyramid,
                                           MethodKind::foveated_pyramid,       MethodKind::path_traced,
                                           MethodKind::foveated_path_traced,   MethodKind::sphere_traced_sampling,
                                           MethodKind::volume_raycast,         MethodKind::foveated_volume_raycast};
  static_assert(std::size(kByAlternative) == std::variant_size_v<MethodParameters>);
  return RenderMethod{kByAlternative[parameters.index()]};
}

// The display of a foveated method's parameters; nullptr for the others.
inline const StimulusDisplay* display_of(const MethodParameters& parameters) {
  if (const auto* fipr = std::get_if<FoveatedPyramidParameters>(&parameters)) return &fipr->display;
  if (const auto* fpt = std::get_if<FoveatedPathTracedParameters>(&parameters)) return &fpt->display;
  if (const auto* sampled = std::get_if<SampledParameters>(&parameters)) {
    if (const auto* layers = std::get_if<HyperbolicLayersModel>(&sampled->model)) return &layers->display;
    if (const auto* linear = std::get_if<LinearFalloffModel>(&sampled->model)) return &linear->display;
  }
  if (const auto* volume = std::get_if<FoveatedVolumeRaycastParameters>(&parameters)) return &volume->display;
  return nullptr;
}
inline StimulusDisplay* display_of(MethodParameters& parameters) {
  return const_cast<StimulusDisplay*>(display_of(static_cast<const MethodParameters&>(parameters)));
}

}  // namespace fovlab
