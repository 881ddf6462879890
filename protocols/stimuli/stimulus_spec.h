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

struct StimulusSpec {
  std::string scene;                          // built-in scene name or path to a .glsl scene
  std::string method;                         // "gt", "ipr" or "fipr" (see method_parameters)
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

// FIPR's display parameters: the physical size of the stimulus image and the eye's distance from
// it. Their default (0) means "not given": the schedule fills them from the config's [display]
// (protocols/schedule/study_plan.cpp), so a planned spec always holds them and they are part of its
// canonical text and id.
inline constexpr const char* kDisplayWidthParameter = "display_width_mm";
inline constexpr const char* kDisplayHeightParameter = "display_height_mm";
inline constexpr const char* kViewingDistanceParameter = "viewing_distance_mm";

// The parameters of a method, or nullopt when the method is unknown.
std::optional<std::vector<MethodParameter>> method_parameters(const std::string& method);
// "gt, ipr, fipr": for messages.
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

}  // namespace fovlab
