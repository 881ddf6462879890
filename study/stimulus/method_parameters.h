#pragma once
// The typed parameters of each rendering method: one plain struct per method, held in a variant
// whose alternative is the method. Their defaults, ranges, units and keys are in the method's
// descriptor (render_method.h): make a set with default_parameters(method), never by value
// initialisation alone (which zeroes everything).
//
// Angles say in their name whether they are a radius (an eccentricity from the gaze) or an
// aperture (the full angle across, twice the radius).
#include <cstdint>
#include <variant>

namespace fovlab {

enum class RenderMethod { ground_truth, inverted_pyramid, foveated_pyramid, path_traced, foveated_path_traced };

// How FIPR combines the acuity probability and the depth edges (docs/foveation.md); the order is
// that of foveation/foveation_mask.h's MaskCombine (protocols/stimuli checks it).
enum class FiprCombine : uint32_t { max, fovea_or_product, product, acuity };

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

// The inverted pyramid (IPR, seed 000 section 3.1).
struct InvertedPyramidParameters {
  int samples_per_pixel;
  int max_steps;
  double hit_threshold;
  int pyramid_levels;
  int min_filter_size;
};

// FIPR's outer periphery at this radius is none (eccentricities are below 180 degrees); the
// renderer's is then infinite (protocols/stimuli/stimulus_settings.cpp).
inline constexpr double kNoOuterPeripheryRadiusDeg = 180.0;

// The foveated inverted pyramid (FIPR, seed 000 section 3.2).
struct FoveatedPyramidParameters {
  int samples_per_pixel;
  int max_steps;
  double hit_threshold;
  int pyramid_levels;
  int min_filter_size;
  double fovea_radius_deg;            // eccentricity up to which every pixel is traced
  double outer_periphery_radius_deg;  // eccentricity beyond which none is (180: no outer periphery)
  int periphery_refresh;
  int periphery_steps;
  bool blur;
  FiprCombine combine;
  double edge_threshold;
  uint32_t mask_seed;
  StimulusDisplay display;
};

// Path tracing (seed 001's reference), shown from pre-rendered frames.
struct PathTracedParameters {
  int samples_per_pixel;
  int max_bounces;
  uint32_t path_seed;
};

// The emulated foveated path tracer (seed 001 section 3.2): three pre-rendered zone buffers blended
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

using MethodParameters = std::variant<GroundTruthParameters, InvertedPyramidParameters, FoveatedPyramidParameters,
                                      PathTracedParameters, FoveatedPathTracedParameters>;

inline RenderMethod method_of(const MethodParameters& parameters) {
  return static_cast<RenderMethod>(parameters.index());
}

// The display of a foveated method's parameters; nullptr for the others.
inline const StimulusDisplay* display_of(const MethodParameters& parameters) {
  if (const auto* fipr = std::get_if<FoveatedPyramidParameters>(&parameters)) return &fipr->display;
  if (const auto* fpt = std::get_if<FoveatedPathTracedParameters>(&parameters)) return &fpt->display;
  return nullptr;
}
inline StimulusDisplay* display_of(MethodParameters& parameters) {
  return const_cast<StimulusDisplay*>(display_of(static_cast<const MethodParameters&>(parameters)));
}

}  // namespace fovlab
