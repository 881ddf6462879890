#pragma once
// What one stimulus is, independent of trials: a scene rendered by a method with its typed
// parameters, as an animation of frame_count frames sampled at frames_per_second from the scene's
// camera path. Specs are plain values, compared by their canonical text, and logged as JSON. How a
// spec becomes renderer settings is protocols/stimuli/stimulus_settings.h.
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "study/stimulus/render_method.h"

namespace fovlab {

struct StimulusSpec {
  std::string scene;            // built-in scene name or path to a scene file
  MethodParameters parameters;  // the method is the alternative held (method_of)
  int width_px = 0;
  int height_px = 0;
  int frame_count = 1;
  double frames_per_second = 1.0;
  double camera_start_s = 0.0;  // scene time of frame 0

  RenderMethod method() const { return method_of(parameters); }
  std::string_view method_name() const { return describe(method()).name; }
  double frame_time_s(int frame) const { return camera_start_s + frame / frames_per_second; }
  // Canonical text ("scene=...;method=...;key=value...;size=WxH;...", parameters sorted by key)
  // used for equality, frame-cache keys and messages.
  std::string canonical() const;
  bool operator==(const StimulusSpec& other) const { return canonical() == other.canonical(); }
};

// {"scene", "method", "parameters": {key: number, or a choice's name}, "width_px", ...}.
nlohmann::json to_json(const StimulusSpec& spec);

// The display a foveated spec's parameters describe; InputError naming the spec when a value is
// missing (a study's schedule fills them from [display]). std::logic_error for other methods.
struct DisplaySize {
  double width_mm = 0.0, height_mm = 0.0, viewing_distance_mm = 0.0;
};
DisplaySize stimulus_display_size(const StimulusSpec& spec);

}  // namespace fovlab
