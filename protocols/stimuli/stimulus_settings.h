#pragma once
// From a typed stimulus spec (study/stimulus) to the settings of the renderer that draws it: the
// one place that knows both, one conversion a family (sphere_trace_settings, path_traced_frames,
// volume_render_settings), each a std::visit or a lookup of its own alternatives. A sampling model
// is converted once (sampling_map), whatever its source. Adding a rendering method adds its
// conversion here.
//
// A headset study (issue 42) renders each spec as one eye sees it: the functions taking an optional
// EyeView put it into the renderer's settings, and take the display geometry for eccentricity from
// the eye's off-axis image plane (eye_display) instead of the spec's display parameters, which
// describe the flat stand-in the study was planned on. stimulus_display is the one place that
// chooses; without an eye every result is the desktop's, unchanged.
#include <optional>
#include <array>
#include <optional>
#include <vector>

#include "foveation/display_geometry.h"
#include "foveation/sampling_map.h"
#include "foveation/voronoi_mask.h"
#include "foveation/zone_layout.h"
#include "renderer/prerender/frame_cache.h"
#include "renderer/scene/eye_view.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "renderer/volume/volume_raycaster.h"
#include "study/config/scene_catalog.h"
#include "study/schedule/study_plan.h"
#include "study/stimulus/stimulus_spec.h"

namespace fovlab {

// The scenes the renderer knows: built-in SDF scenes (stimuli/scenes), the built-in path-traced
// courtyard and OBJ files, built-in volume scenes (stimuli/volumes) and .toml volume scenes.
// check_files: scene files must exist.
SceneCatalog renderer_scene_catalog(bool check_files = true);

// Whether a method's frames come from the sphere tracer (gt, ipr, fipr) or from pre-rendered
// path-traced sequences (pt, fpt).
inline bool is_path_traced(RenderMethod method) { return describe(method).scene_kind == SceneKind::path_traced; }

// Whether a method is Bruder et al. 2019's volume raycaster (volume, fvolume).
inline bool is_volume(RenderMethod method) { return describe(method).scene_kind == SceneKind::volume; }

// The raycaster's settings of a volume or fvolume spec at an animation frame (the jitter's frame is
// left 0, for the caller to set), as `eye` sees it when given; std::logic_error for other methods.
VolumeRenderSettings volume_render_settings(const StimulusSpec& spec, int frame,
                                            const std::optional<EyeView>& eye = std::nullopt);
// The sampling mask of an fvolume spec: its frame size, display (stimulus_display: the eye's when
// given) and density_sigma_deg, mask_seed. InputError when the display parameters are missing;
// std::logic_error for other methods.
VoronoiMaskSettings voronoi_mask_settings(const StimulusSpec& spec, const std::optional<EyeView>& eye = std::nullopt);
// Whether an fvolume spec smooths over time (false for volume).
bool temporal_smoothing(const StimulusSpec& spec);

// The sphere-tracer settings of a gt, ipr, fipr or sampling-model spec (frame time of the given
// frame). FIPR: the display comes from the spec's display parameters and pixel size; the gaze is left
// non-finite (no gaze: every pixel traced in full) and frame_index 0, for the caller
// (StimulusLibrary) to set. Sampling models: the map of a gaze at the centre, for the caller to
// replace with each gaze sample's (sampling_map).
// With `eye`: the settings' eye, and FIPR's display and the sampling map the eye's (stimulus_display).
// Throws InputError when a FIPR spec lacks its display parameters (and no eye gives one);
// std::logic_error for the path-traced methods (pt, fpt, pt-rmfr, ...).
SphereTraceSettings sphere_trace_settings(const StimulusSpec& spec, int frame,
                                          const std::optional<EyeView>& eye = std::nullopt);

// The command line's --min-filter and --coarse-test (render, bench): a flag given sets IPR's and
// FIPR's depth levels alike; one not given leaves each method its own default.
struct PyramidFlagsGiven {
  bool min_filter = false;
  bool coarse_test = false;
};
// `settings` (the flags' values) for `method`: its min_filter_size and coarse_test where a flag did
// not give them are the method's descriptor defaults (log schema 10's: the cone, no min filter;
// study/stimulus/render_method.cpp). Other methods' settings are returned as given.
SphereTraceSettings with_method_pyramid_defaults(SphereTraceSettings settings, TraceMethod method,
                                                 const PyramidFlagsGiven& given);

// The display for the eccentricity of a foveated spec's pixels (fipr, fpt, fvolume, hyperbolic,
// linear): with `eye`, the eye's off-axis image plane of the spec's size (eye_display; InputError for
// a field of view that is not one), its display parameters ignored; without, the flat display they
// describe (InputError when missing).
DisplayGeometry stimulus_display(const StimulusSpec& spec, const std::optional<EyeView>& eye = std::nullopt);

// The sampling model of a sampling-model spec (is_sampling_model) for one gaze sample (NaN: the
// centre): the map SphereTraceSettings::sampling and FrameSampler take. rmfr and kfr need only the frame's pixels;
// hyperbolic and linear the spec's display (stimulus_display: the eye's when given). With equalise, s3, p_min or KFR's sigma is solved with
// the gaze at the centre and kept for every gaze (one stimulus samples alike); InputError when that
// cannot reach its target; std::logic_error for other methods.
// `centre`: this spec's map at the centre (sphere_trace_settings' settings.sampling), whose solved s3
// or p_min is taken instead of solving again: a session builds one map per refresh, not three.
SamplingMap sampling_map(const StimulusSpec& spec, double gaze_x_px, double gaze_y_px,
                         const SamplingMap* centre = nullptr, const std::optional<EyeView>& eye = std::nullopt);
// Refuses (InputError, one line) planned stimuli whose sampling model cannot make its map (equalise
// with no solution on this display), naming `source` (the config), the stimulus (stimulus.reference
// or stimulus.test, with its level), its method and why: `validate` says it, and a session before
// anything is written. With `eye`, the maps on that eye's display (a headset study checks each eye).
void check_sampling_maps(const std::vector<PlannedStimulus>& stimuli, const std::string& source,
                         const std::optional<EyeView>& eye = std::nullopt);
// How a sampling-model spec's pass 2 reads its samples (bilinear for the linear model, which fills
// by pull-push); std::logic_error for other methods.
ResampleFilter sampling_filter(const StimulusSpec& spec);

// The pre-rendered sequences a path-traced spec (pt, fpt, pt-rmfr, ...) shows: its frames, and for fpt with
// periphery_bounces >= 0 other than max_bounces (Polychronakis et al. 2021 section 4.2's pilot variant) a second
// sequence with that many bounces, the source of the middle and outer zones.
struct PathTracedFrames {
  std::vector<PathTraceSequence> sequences;  // [0]: the frames; [1]: the periphery's, if any
};
// With `eye`, each sequence is that headset eye's frames (PathTraceSequence::eye: a folder of its own).
PathTracedFrames path_traced_frames(const StimulusSpec& spec, const std::optional<EyeView>& eye = std::nullopt);

// Every frame of every path-traced sequence the stimuli need, each once: sequences in the order the
// stimuli first name them (a sequence named twice keeps the larger frame count), frames in order.
// The list fovlab prerender renders and --shard splits; validate counts what the cache lacks.
struct PathTraceFrameJob {
  PathTraceSequence sequence;
  int frame = 0;
};
// `eyes`: the views the frames are made for, each in turn (a headset study's two eyes:
// headset_eye_views); the default, one desktop view.
// The two views a headset study's stimuli are rendered from (left, right), from its config: head-
// locked, each eye ipd_mm / 2 to its side of the head's origin (metres: a scene unit is a metre),
// looking straight ahead, with the config's field of view. A session checks the runtime's views
// against them (protocols/session/session.h); `fovlab prerender` makes each eye's frames for them.
std::array<EyeView, 2> headset_eye_views(const HeadsetDisplayConfig& headset);
// The views a study's frames are made for: a headset study's two eyes, else the desktop's one.
std::vector<std::optional<EyeView>> study_frame_views(const DisplayConfig& display);
std::vector<PathTraceFrameJob> path_traced_frame_jobs(const std::vector<StimulusSpec>& stimuli,
                                                      const std::vector<std::optional<EyeView>>& eyes = {std::nullopt});

// The zones of an fpt spec: foveal aperture, middle = foveal + middle_minus_foveal, band width.
ZoneBounds zone_bounds(const StimulusSpec& spec);

}  // namespace fovlab
