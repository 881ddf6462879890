#pragma once
// What one stimulus is, independent of trials: a scene rendered by a method with its parameters,
// as an animation of frame_count frames sampled at frames_per_second from the scene's camera path.
// Specs are plain values, compared and hashed by their canonical text, and logged as JSON.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace fovlab {

struct SphereTraceSettings;
struct DisplayGeometry;
struct ZoneBounds;
struct PathTraceSequence;

struct StimulusSpec {
  std::string scene;                          // built-in scene name or path to a .glsl scene
  std::string method;                         // "gt", "ipr", "fipr", "pt" or "fpt" (see method_parameters)
  std::map<std::string, double> parameters;   // every parameter of the method, defaults filled in
  int width_px = 0;
  int height_px = 0;
  int frame_count = 1;
  double frames_per_second = 1.0;
  double camera_start_s = 0.0;                // scene time of frame 0

  double frame_time_s(int frame) const { return camera_start_s + frame / frames_per_second; }
  // Canonical text ("scene=...;method=...;...") used for equality, hashing and stimulus ids.
  std::string canonical() const;
  bool operator==(const StimulusSpec& other) const { return canonical() == other.canonical(); }
};

nlohmann::json to_json(const StimulusSpec& spec);

// One parameter a rendering method accepts: its default and its inclusive range; integral
// parameters must hold whole numbers, `choices` (when not empty) lists the only values allowed.
struct MethodParameter {
  std::string name;
  double default_value = 0.0;
  double min_value = 0.0;
  double max_value = 0.0;
  bool integral = false;
  std::vector<double> choices;
};

// The display parameters of FIPR and FPT: the physical size of the stimulus image and the eye's distance from
// it. Their default (0) means "not given": the schedule fills them from the config's [display]
// (protocols/schedule/study_plan.cpp), so a planned spec always holds them and they are part of its
// canonical text and id.
inline constexpr const char* kDisplayWidthParameter = "display_width_mm";
inline constexpr const char* kDisplayHeightParameter = "display_height_mm";
inline constexpr const char* kViewingDistanceParameter = "viewing_distance_mm";

// The parameters of a method, or nullopt when the method is unknown.
std::optional<std::vector<MethodParameter>> method_parameters(const std::string& method);
// "gt, ipr, fipr, pt, fpt": for messages.
std::string known_methods();
// Whether frames of this method depend on the gaze sample (then they cannot be prepared ahead).
bool method_depends_on_gaze(const std::string& method);

// A rule between parameters of a method that no value breaks on its own (FIPR: the outer periphery
// lies at or beyond the fovea). `parameters` are the ones involved; `expected` says what was
// expected, with the values, e.g. "expected outer_periphery_deg (5) >= fovea_deg (7.5)".
struct ParameterConflict {
  std::vector<std::string> parameters;
  std::string expected;
};
// Checks a full parameter set (defaults filled in) of a known method.
std::optional<ParameterConflict> parameter_conflict(const std::string& method,
                                                    const std::map<std::string, double>& parameters);

// The sphere-tracer settings of a gt, ipr or fipr spec (frame time of the given frame). FIPR: the
// display comes from the spec's display parameters and pixel size; the gaze is left non-finite (no
// gaze: every pixel traced in full) and frame_index 0, for the caller (StimulusLibrary) to set.
// Throws InputError when a FIPR spec lacks its display parameters.
SphereTraceSettings sphere_trace_settings(const StimulusSpec& spec, int frame);

// The display a spec's display parameters describe (fipr, fpt); InputError when they are missing.
DisplayGeometry stimulus_display(const StimulusSpec& spec);

// Path-traced methods (seed 001; docs/foveated-path-tracing.md): "pt" shows pre-rendered frames as
// they are (the non-foveated reference), "fpt" blends their three zone buffers by the gaze of each
// refresh (the emulated foveated path tracer). Their scenes are path-traced ones
// (renderer/prerender/path_scene_source.h).
bool is_path_traced_method(const std::string& method);

// The pre-rendered sequences a pt or fpt spec shows: its frames, and for fpt with
// periphery_bounces >= 0 other than max_bounces (seed 001 section 4.2's pilot variant) a second
// sequence with that many bounces, the source of the middle and outer zones.
struct PathTracedFrames {
  std::vector<PathTraceSequence> sequences;  // [0]: the frames; [1]: the periphery's, if any
};
PathTracedFrames path_traced_frames(const StimulusSpec& spec);

// The zones of an fpt spec: foveal_deg, middle = foveal_deg + middle_over_foveal_deg, band_deg.
ZoneBounds zone_bounds(const StimulusSpec& spec);

}  // namespace fovlab
