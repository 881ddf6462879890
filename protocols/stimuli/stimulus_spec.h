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
  std::string method;                         // "gt" or "ipr" (see method_parameters)
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

// The parameters of a method, or nullopt when the method is unknown.
std::optional<std::vector<MethodParameter>> method_parameters(const std::string& method);
// "gt, ipr": for messages.
std::string known_methods();
// Whether frames of this method depend on the gaze sample (then they cannot be prepared ahead).
bool method_depends_on_gaze(const std::string& method);

// The sphere-tracer settings of a gt/ipr spec (frame time of the given frame).
SphereTraceSettings sphere_trace_settings(const StimulusSpec& spec, int frame);

}  // namespace fovlab
