#include "protocols/stimuli/stimulus_settings.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "core/input_error.h"
#include "core/number_text.h"
#include "renderer/prerender/path_scene_source.h"
#include "renderer/scene/scene_source.h"
#include "renderer/volume/volume_scene.h"

namespace fovlab {
namespace {

template <class Pyramid>
void set_pyramid(SphereTraceSettings& settings, const Pyramid& pyramid) {
  settings.pyramid_levels = pyramid.pyramid_levels;
  settings.min_filter_size = pyramid.min_filter_size;
  settings.coarse_test = pyramid.coarse_test;
}

}  // namespace

SceneCatalog renderer_scene_catalog(bool check_files) {
  SceneCatalog catalog;
  catalog.signed_distance_names = builtin_scene_names();
  catalog.path_traced_names = {known_path_scenes()};
  catalog.path_traced_file_extension = ".obj";
  catalog.volume_names = builtin_volume_names();
  catalog.volume_file_extension = ".toml";
  catalog.check_files = check_files;
  return catalog;
}

namespace {

// std::visit over one lambda per alternative.
template <class... Visitors>
struct Overloaded : Visitors... {
  using Visitors::operator()...;
};
template <class... Visitors>
Overloaded(Visitors...) -> Overloaded<Visitors...>;

template <class Trace>
void set_trace(SphereTraceSettings& settings, const Trace& trace) {
  settings.samples_per_pixel = trace.samples_per_pixel;
  settings.max_steps = trace.max_steps;
  settings.hit_threshold = static_cast<float>(trace.hit_threshold);
}

void set_foveation(SphereTraceSettings& settings, const FoveatedPyramidParameters& fipr, const StimulusSpec& spec,
                   const std::optional<EyeView>& eye) {
  FoveationSettings& foveation = settings.foveation;
  foveation.display = stimulus_display(spec, eye);
  foveation.gaze_x_px = std::numeric_limits<double>::quiet_NaN();
  foveation.gaze_y_px = std::numeric_limits<double>::quiet_NaN();
  foveation.acuity.fovea_radius_deg = fipr.fovea_radius_deg;
  foveation.acuity.outer_periphery_radius_deg = fipr.outer_periphery_radius_deg >= kNoOuterPeripheryRadiusDeg
                                                    ? std::numeric_limits<double>::infinity()
                                                    : fipr.outer_periphery_radius_deg;
  foveation.periphery_refresh = fipr.periphery_refresh;
  foveation.periphery_steps = fipr.periphery_steps;
  foveation.reconstruction = fipr.periphery_reconstruction;
  foveation.near_misses = fipr.near_misses;
  foveation.edge_depth = fipr.edge_depth;
  foveation.blur = fipr.blur;
  foveation.combine = fipr.combine;
  foveation.edge_threshold = static_cast<float>(fipr.edge_threshold);
  foveation.seed = fipr.mask_seed;
  foveation.frame_index = 0;
}

}  // namespace

SphereTraceSettings sphere_trace_settings(const StimulusSpec& spec, int frame, const std::optional<EyeView>& eye) {
  SphereTraceSettings settings;
  settings.width = spec.width_px;
  settings.height = spec.height_px;
  settings.time_s = static_cast<float>(spec.frame_time_s(frame));
  settings.eye = eye;
  const auto not_sphere_traced = [&] {
    throw std::logic_error("sphere_trace_settings: not a sphere-tracing method: " + std::string(spec.method_name()));
  };
  std::visit(Overloaded{
                 [&](const GroundTruthParameters& gt) {
                   settings.method = TraceMethod::ground_truth;
                   set_trace(settings, gt);
                 },
                 [&](const InvertedPyramidParameters& ipr) {
                   settings.method = TraceMethod::inverted_pyramid;
                   set_trace(settings, ipr);
                   set_pyramid(settings, ipr);
                   settings.full_resolution_depth = ipr.full_resolution_depth;
                 },
                 [&](const FoveatedPyramidParameters& fipr) {
                   settings.method = TraceMethod::foveated_pyramid;
                   set_trace(settings, fipr);
                   set_pyramid(settings, fipr);
                   set_foveation(settings, fipr, spec, eye);
                 },
                 [&](const SampledParameters& sampled) {
                   const auto* samples = std::get_if<SphereTracedSamples>(&sampled.source);
                   if (!samples) not_sphere_traced();
                   settings.method = TraceMethod::sampling_model;
                   set_trace(settings, *samples);
                   settings.sampling = sampling_map(spec, std::nan(""), std::nan(""), nullptr, eye);
                   settings.sampling_filter = sampling_filter(spec);
                 },
                 [&](const auto&) { not_sphere_traced(); },
             },
             spec.parameters);
  return settings;
}

namespace {

// A sampling model's settings from its parameters, the same on either source. Returns whether the
// model needs the spec's display.
// The equalisation a stimulus's choice asks for: "on" in a log before schema 8 the density.
Equalise equalise_of(EqualiseChoice choice) {
  switch (choice) {
    case EqualiseChoice::off:
      return Equalise::off;
    case EqualiseChoice::samples:
      return Equalise::samples;
    case EqualiseChoice::on_before_log_schema_8:
    case EqualiseChoice::density:
      return Equalise::density;
  }
  return Equalise::off;
}

bool read_model(const SamplingModelParameters& model, SamplingSettings& settings) {
  return std::visit(Overloaded{
                        [&](const RectangularMappingModel& p) {
                          settings.model = SamplingModel::rectangular;
                          settings.sigma = p.sigma;
                          settings.focal_share_x = p.focal_share_x;
                          settings.focal_share_y = p.focal_share_y;
                          return false;
                        },
                        [&](const KernelLogPolarModel& p) {
                          settings.model = SamplingModel::kernel_log_polar;
                          settings.sigma = p.sigma;
                          settings.alpha = p.alpha;
                          settings.equalise = equalise_of(p.equalise);
                          return false;
                        },
                        [&](const HyperbolicLayersModel& p) {
                          settings.model = SamplingModel::hyperbolic;
                          settings.inner_radius_deg = p.inner_radius_deg;
                          settings.outer_radius_deg = p.outer_radius_deg;
                          settings.middle_pixel_size_px = p.middle_pixel_size_px;
                          settings.outer_pixel_size_px = p.outer_pixel_size_px;
                          settings.blend_band_deg = p.blend_band_deg;
                          settings.equalise = equalise_of(p.equalise);
                          settings.sigma = p.sigma;
                          return true;
                        },
                        [&](const LinearFalloffModel& p) {
                          settings.model = SamplingModel::linear;
                          settings.inner_radius_deg = p.inner_radius_deg;
                          settings.outer_radius_deg = p.outer_radius_deg;
                          settings.min_probability = p.min_probability;
                          settings.seed = p.sample_seed;
                          settings.equalise = equalise_of(p.equalise);
                          settings.sigma = p.sigma;
                          return true;
                        },
                    },
                    model);
}

// The (source, model) pair of a sampling-model spec; std::logic_error for other methods.
const SampledParameters& sampled_parameters(const StimulusSpec& spec, const char* function) {
  const auto* sampled = std::get_if<SampledParameters>(&spec.parameters);
  if (!sampled)
    throw std::logic_error(std::string(function) + ": not a sampling model: " + std::string(spec.method_name()));
  return *sampled;
}

}  // namespace

SamplingMap sampling_map(const StimulusSpec& spec, double gaze_x_px, double gaze_y_px, const SamplingMap* centre,
                         const std::optional<EyeView>& eye) {
  const SampledParameters& sampled = sampled_parameters(spec, "sampling_map");
  SamplingSettings settings;
  DisplayGeometry display;
  display.width_px = spec.width_px;
  display.height_px = spec.height_px;
  const bool needs_display = read_model(sampled.model, settings);
  if (needs_display) display = stimulus_display(spec, eye);
  if (settings.equalise != Equalise::off) {
    // Solved once for the stimulus, with the gaze at the centre; the map then follows each gaze
    // sample with that s3 or p_min. Every refresh samples alike (a re-solved s3 would re-pitch the
    // outer layer, a re-solved p_min flip peripheral pixels), and no gaze can make it unsolvable
    // mid-session: the centre's solution is checked before the first trial.
    const bool at_centre = std::isnan(gaze_x_px) || std::isnan(gaze_y_px);
    if (!centre && at_centre) return make_sampling_map(settings, display, gaze_x_px, gaze_y_px);  // the solution itself
    std::optional<SamplingMap> solved_here;
    if (!centre) solved_here = make_sampling_map(settings, display, std::nan(""), std::nan(""));
    settings = with_solved_equalise(settings, centre ? *centre : *solved_here);
  }
  return make_sampling_map(settings, display, gaze_x_px, gaze_y_px);
}

void check_sampling_maps(const std::vector<PlannedStimulus>& stimuli, const std::string& source,
                         const std::optional<EyeView>& eye) {
  for (const PlannedStimulus& stimulus : stimuli) {
    if (!is_sampling_model(stimulus.spec.method())) continue;
    try {
      sampling_map(stimulus.spec, std::nan(""), std::nan(""), nullptr, eye);
    } catch (const InputError& error) {
      std::string where = source + ": " + (stimulus.is_reference ? "stimulus.reference" : "stimulus.test");
      if (!stimulus.variant.empty()) where += " variant " + stimulus.variant;
      if (stimulus.level) where += " at level " + format_number(*stimulus.level, 6);
      where.append(" (method \"").append(stimulus.spec.method_name()).append("\"): ");
      throw InputError(where + error.what());
    }
  }
}

ResampleFilter sampling_filter(const StimulusSpec& spec) {
  return std::visit(
      [](const auto& model) {
        if constexpr (requires { model.resample; }) return model.resample;
        return ResampleFilter::bilinear;  // the linear model fills by pull-push
      },
      sampled_parameters(spec, "sampling_filter").model);
}

VolumeRenderSettings volume_render_settings(const StimulusSpec& spec, int frame, const std::optional<EyeView>& eye) {
  VolumeRenderSettings settings;
  settings.eye = eye;
  settings.width_px = spec.width_px;
  settings.height_px = spec.height_px;
  settings.time_s = spec.frame_time_s(frame);
  if (const auto* full = std::get_if<VolumeRaycastParameters>(&spec.parameters)) {
    settings.step_voxels = full->step_voxels;
    settings.jitter_seed = full->jitter_seed;
  } else if (const auto* foveated = std::get_if<FoveatedVolumeRaycastParameters>(&spec.parameters)) {
    settings.step_voxels = foveated->step_voxels;
    settings.jitter_seed = foveated->jitter_seed;
    settings.correct_opacity = foveated->opacity_correction;
  } else {
    throw std::logic_error("volume_render_settings: not a volume method: " + std::string(spec.method_name()));
  }
  return settings;
}

VoronoiMaskSettings voronoi_mask_settings(const StimulusSpec& spec, const std::optional<EyeView>& eye) {
  const auto* foveated = std::get_if<FoveatedVolumeRaycastParameters>(&spec.parameters);
  if (!foveated) throw std::logic_error("voronoi_mask_settings: not fvolume: " + std::string(spec.method_name()));
  VoronoiMaskSettings settings =
      voronoi_mask_settings(spec.width_px, spec.height_px, stimulus_display(spec, eye), foveated->density_sigma_deg);
  settings.seed = foveated->mask_seed;
  return settings;
}

bool temporal_smoothing(const StimulusSpec& spec) {
  const auto* foveated = std::get_if<FoveatedVolumeRaycastParameters>(&spec.parameters);
  return foveated && foveated->temporal_smoothing;
}

DisplayGeometry stimulus_display(const StimulusSpec& spec, const std::optional<EyeView>& eye) {
  // The spec's display parameters are the flat stand-in a headset study is planned on; the eye's own
  // off-axis plane is what its pixels' eccentricities are on.
  if (eye) return eye_display(*eye, spec.width_px, spec.height_px);
  const DisplaySize size = stimulus_display_size(spec);
  return display_from_size(spec.width_px, spec.height_px, size.width_mm, size.height_mm, size.viewing_distance_mm);
}

std::vector<PathTraceFrameJob> path_traced_frame_jobs(const std::vector<StimulusSpec>& stimuli,
                                                      const std::vector<std::optional<EyeView>>& eyes) {
  std::vector<PathTraceSequence> sequences;
  for (const std::optional<EyeView>& eye : eyes)
    for (const StimulusSpec& spec : stimuli) {
      if (!is_path_traced(spec.method())) continue;
      for (const PathTraceSequence& sequence : path_traced_frames(spec, eye).sequences) {
        bool known = false;
        for (PathTraceSequence& other : sequences)
          if (other.description() == sequence.description()) {
            other.frame_count = std::max(other.frame_count, sequence.frame_count);
            known = true;
          }
        if (!known) sequences.push_back(sequence);
      }
    }
  std::vector<PathTraceFrameJob> jobs;
  for (const PathTraceSequence& sequence : sequences)
    for (int frame = 0; frame < sequence.frame_count; ++frame) jobs.push_back({sequence, frame});
  return jobs;
}

std::array<EyeView, 2> headset_eye_views(const HeadsetDisplayConfig& headset) {
  const double half_ipd_m = headset.ipd_mm / 2000.0;
  std::array<EyeView, 2> eyes;
  eyes[0].position_in_head = {-half_ipd_m, 0.0, 0.0};
  eyes[0].field_of_view = headset.left_eye_fov;
  eyes[1].position_in_head = {half_ipd_m, 0.0, 0.0};
  eyes[1].field_of_view = headset.right_eye_fov;
  return eyes;
}

std::vector<std::optional<EyeView>> study_frame_views(const DisplayConfig& display) {
  if (display.kind != DisplayKind::openxr) return {std::nullopt};
  const std::array<EyeView, 2> eyes = headset_eye_views(display.headset);
  return {eyes[0], eyes[1]};
}

PathTracedFrames path_traced_frames(const StimulusSpec& spec, const std::optional<EyeView>& eye) {
  PathTraceSequence frames;
  frames.eye = eye;
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
  if (!is_path_traced(spec.method()))
    throw std::logic_error("path_traced_frames: not a path-traced method: " + std::string(spec.method_name()));
  const auto* fpt = std::get_if<FoveatedPathTracedParameters>(&spec.parameters);
  if (!fpt) {  // pt and the sampling models: the frames alone
    if (const auto* pt = std::get_if<PathTracedParameters>(&spec.parameters)) set_paths(*pt);
    else set_paths(std::get<PathTracedSamples>(std::get<SampledParameters>(spec.parameters).source));
    return {{frames}};
  }
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

SphereTraceSettings with_method_pyramid_defaults(SphereTraceSettings settings, TraceMethod method,
                                                 const PyramidFlagsGiven& given) {
  if (method != TraceMethod::inverted_pyramid && method != TraceMethod::foveated_pyramid) return settings;
  const MethodDescriptor& descriptor = describe(
      method == TraceMethod::inverted_pyramid ? RenderMethod::inverted_pyramid : RenderMethod::foveated_pyramid);
  if (!given.min_filter) settings.min_filter_size = int(find_parameter(descriptor, "min_filter_size")->default_value);
  if (!given.coarse_test)
    settings.coarse_test = static_cast<CoarseTest>(int(find_parameter(descriptor, "coarse_test")->default_value));
  return settings;
}

}  // namespace fovlab
