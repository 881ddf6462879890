#include "protocols/stimuli/stimulus_settings.h"

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "renderer/prerender/path_scene_source.h"
#include "renderer/scene/scene_source.h"

namespace fovlab {
namespace {

void set_pyramid(SphereTraceSettings& settings, int pyramid_levels, int min_filter_size) {
  settings.pyramid_levels = pyramid_levels;
  settings.min_filter_size = min_filter_size;
}

}  // namespace

SceneCatalog renderer_scene_catalog(bool check_files) {
  SceneCatalog catalog;
  catalog.signed_distance_names = builtin_scene_names();
  catalog.path_traced_names = {known_path_scenes()};
  catalog.path_traced_file_extension = ".obj";
  catalog.check_files = check_files;
  return catalog;
}

SphereTraceSettings sphere_trace_settings(const StimulusSpec& spec, int frame) {
  SphereTraceSettings settings;
  settings.width = spec.width_px;
  settings.height = spec.height_px;
  settings.time_s = static_cast<float>(spec.frame_time_s(frame));
  const auto set_trace = [&](const auto& p) {
    settings.samples_per_pixel = p.samples_per_pixel;
    settings.max_steps = p.max_steps;
    settings.hit_threshold = static_cast<float>(p.hit_threshold);
  };
  if (const auto* gt = std::get_if<GroundTruthParameters>(&spec.parameters)) {
    settings.method = TraceMethod::ground_truth;
    set_trace(*gt);
  } else if (const auto* ipr = std::get_if<InvertedPyramidParameters>(&spec.parameters)) {
    settings.method = TraceMethod::inverted_pyramid;
    set_trace(*ipr);
    set_pyramid(settings, ipr->pyramid_levels, ipr->min_filter_size);
  } else if (const auto* fipr = std::get_if<FoveatedPyramidParameters>(&spec.parameters)) {
    settings.method = TraceMethod::foveated_pyramid;
    set_trace(*fipr);
    set_pyramid(settings, fipr->pyramid_levels, fipr->min_filter_size);
    FoveationSettings& foveation = settings.foveation;
    foveation.display = stimulus_display(spec);
    foveation.gaze_x_px = std::numeric_limits<double>::quiet_NaN();
    foveation.gaze_y_px = std::numeric_limits<double>::quiet_NaN();
    foveation.acuity.fovea_radius_deg = fipr->fovea_radius_deg;
    foveation.acuity.outer_periphery_radius_deg = fipr->outer_periphery_radius_deg >= kNoOuterPeripheryRadiusDeg
                                               ? std::numeric_limits<double>::infinity()
                                               : fipr->outer_periphery_radius_deg;
    foveation.periphery_refresh = fipr->periphery_refresh;
    foveation.periphery_steps = fipr->periphery_steps;
    foveation.blur = fipr->blur;
    foveation.combine = static_cast<MaskCombine>(static_cast<uint32_t>(fipr->combine));
    foveation.edge_threshold = static_cast<float>(fipr->edge_threshold);
    foveation.seed = fipr->mask_seed;
    foveation.frame_index = 0;
  } else if (is_sampling_model(spec.method())) {
    settings.method = TraceMethod::sampling_model;
    std::visit(
        [&](const auto& p) {
          if constexpr (requires { p.max_steps; }) set_trace(p);
        },
        spec.parameters);
    settings.sampling = sampling_map(spec, std::nan(""), std::nan(""));
    std::visit(
        [&](const auto& p) {
          if constexpr (requires { p.resample; })
            settings.sampling_filter = static_cast<ResampleFilter>(static_cast<uint32_t>(p.resample));
        },
        spec.parameters);
  } else {
    throw std::logic_error("sphere_trace_settings: not a sphere-tracing method: " + std::string(spec.method_name()));
  }
  return settings;
}

SamplingMap sampling_map(const StimulusSpec& spec, double gaze_x_px, double gaze_y_px, const SamplingMap* centre) {
  SamplingSettings settings;
  DisplayGeometry display;
  display.width_px = spec.width_px;
  display.height_px = spec.height_px;
  if (const auto* rmfr = std::get_if<RectangularMappingParameters>(&spec.parameters)) {
    settings.model = SamplingModel::rectangular;
    settings.sigma = rmfr->sigma;
    settings.focal_share_x = rmfr->focal_share_x;
    settings.focal_share_y = rmfr->focal_share_y;
  } else if (const auto* kfr = std::get_if<KernelLogPolarParameters>(&spec.parameters)) {
    settings.model = SamplingModel::kernel_log_polar;
    settings.sigma = kfr->sigma;
    settings.alpha = kfr->alpha;
  } else if (const auto* layers = std::get_if<HyperbolicLayersParameters>(&spec.parameters)) {
    settings.model = SamplingModel::hyperbolic;
    settings.inner_radius_deg = layers->inner_radius_deg;
    settings.outer_radius_deg = layers->outer_radius_deg;
    settings.middle_pixel_size_px = layers->middle_pixel_size_px;
    settings.outer_pixel_size_px = layers->outer_pixel_size_px;
    settings.blend_band_deg = layers->blend_band_deg;
    settings.equalise = layers->equalise;
    settings.sigma = layers->sigma;
    display = stimulus_display(spec);
  } else if (const auto* linear = std::get_if<LinearFalloffParameters>(&spec.parameters)) {
    settings.model = SamplingModel::linear;
    settings.inner_radius_deg = linear->inner_radius_deg;
    settings.outer_radius_deg = linear->outer_radius_deg;
    settings.min_probability = linear->min_probability;
    settings.seed = linear->sample_seed;
    settings.equalise = linear->equalise;
    settings.sigma = linear->sigma;
    display = stimulus_display(spec);
  } else {
    throw std::logic_error("sampling_map: not a sampling model: " + std::string(spec.method_name()));
  }
  if (settings.equalise) {
    // Solved once for the stimulus, with the gaze at the centre; the map then follows each gaze
    // sample with that s3 or p_min. Every refresh samples alike (a re-solved s3 would re-pitch the
    // outer layer, a re-solved p_min flip peripheral pixels), and no gaze can make it unsolvable
    // mid-session: the centre's solution is checked before the first trial.
    const bool at_centre = std::isnan(gaze_x_px) || std::isnan(gaze_y_px);
    if (!centre && at_centre) return make_sampling_map(settings, display, gaze_x_px, gaze_y_px);  // the solution itself
    std::optional<SamplingMap> solved_here;
    if (!centre) solved_here = make_sampling_map(settings, display, std::nan(""), std::nan(""));
    const SamplingMap& solved = centre ? *centre : *solved_here;
    if (const auto* layers = std::get_if<HyperbolicLayers>(&solved)) settings.outer_pixel_size_px = layers->layers[2].pixel_size_px;
    if (const auto* linear = std::get_if<LinearFalloff>(&solved)) settings.min_probability = linear->min_probability;
    settings.equalise = false;
  }
  return make_sampling_map(settings, display, gaze_x_px, gaze_y_px);
}

DisplayGeometry stimulus_display(const StimulusSpec& spec) {
  const DisplaySize size = stimulus_display_size(spec);
  return display_from_size(spec.width_px, spec.height_px, size.width_mm, size.height_mm, size.viewing_distance_mm);
}

PathTracedFrames path_traced_frames(const StimulusSpec& spec) {
  PathTraceSequence frames;
  frames.scene = spec.scene;
  frames.width_px = spec.width_px;
  frames.height_px = spec.height_px;
  frames.frames_per_second = spec.frames_per_second;
  frames.camera_start_s = spec.camera_start_s;
  frames.frame_count = spec.frame_count;
  const auto set_paths = [&](const auto& p) {
    frames.samples_per_pixel = p.samples_per_pixel;
    frames.max_bounces = p.max_bounces;
    frames.seed = p.path_seed;
  };
  if (const auto* pt = std::get_if<PathTracedParameters>(&spec.parameters)) {
    set_paths(*pt);
    return {{frames}};
  }
  const auto* fpt = std::get_if<FoveatedPathTracedParameters>(&spec.parameters);
  if (!fpt) throw std::logic_error("path_traced_frames: not a path-traced method: " + std::string(spec.method_name()));
  set_paths(*fpt);
  PathTracedFrames result{{frames}};
  if (fpt->periphery_bounces >= 0 && fpt->periphery_bounces != frames.max_bounces) {
    PathTraceSequence periphery = frames;
    periphery.max_bounces = fpt->periphery_bounces;
    result.sequences.push_back(periphery);
  }
  return result;
}

ZoneBounds zone_bounds(const StimulusSpec& spec) {
  const auto* fpt = std::get_if<FoveatedPathTracedParameters>(&spec.parameters);
  if (!fpt) throw std::logic_error("zone_bounds: not an fpt stimulus: " + std::string(spec.method_name()));
  ZoneBounds bounds;
  bounds.foveal_deg = fpt->foveal_aperture_deg;
  bounds.middle_deg = fpt->foveal_aperture_deg + fpt->middle_minus_foveal_aperture_deg;
  bounds.band_deg = fpt->band_width_deg;
  return bounds;
}

}  // namespace fovlab
