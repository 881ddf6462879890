#pragma once
// The rendering methods a stimulus can use, each described once: its name, the scenes it renders,
// whether its frames follow the gaze, its rules on the frame size, and every parameter with its
// type, unit, range, default and help. The config reader, the canonical text, the log's JSON and
// docs/config.md's table (`fovlab methods`) are all made from these descriptors; the typed
// parameters themselves are in method_parameters.h. Adding a method: its parameter struct there,
// its descriptor in render_method.cpp, its renderer (protocols/stimuli/stimulus_settings.cpp).
#include <cstdint>
#include <initializer_list>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "study/stimulus/method_parameters.h"

namespace fovlab {

// The scenes a method renders: SDF scenes (GLSL) for the sphere tracers, path-traced scenes (the
// built-in courtyard or OBJ files) for the path tracer and its emulation, volume scenes (built-in or
// .toml files naming a volume) for the volume raycaster, a folder of PNG or EXR images for the
// sampling models on images (img-rmfr, ...).
enum class SceneKind { signed_distance, path_traced, volume, image_sequence };

enum class ParameterType { integer, real, choice };

// One parameter of a method. Its value travels as a double between the edges (TOML, JSON) and the
// typed struct; a choice is the index of its name in `choices`.
struct ParameterDescriptor {
  std::string_view key;   // TOML key, JSON key and canonical text: "fovea_radius_deg"
  std::string_view unit;  // "deg", "mm", "steps", "px", "" (a count or a name)
  std::string_view help;
  ParameterType type = ParameterType::real;
  double default_value = 0.0;
  double min_value = 0.0;  // inclusive range
  double max_value = 0.0;
  std::vector<double> allowed;            // integer: the only values allowed (empty: the whole range)
  std::vector<std::string_view> choices;  // choice: the names, in the order of their values
  // The key this parameter had in configs written before the typed model (log schema 2 and
  // earlier); read only from configs that a session log carries (parse_logged_study_config).
  std::string_view legacy_key;
  // Added after session logs had been written: at its default it is left out of a stimulus's
  // canonical text and JSON, so the stimuli of older logs keep theirs (and their frame caches).
  bool omitted_at_default = false;
  // A default changed in log schema `default_since_log_schema` (0: never changed): a config that a log
  // of an earlier schema carries reads a missing key as `earlier_default` (parse_logged_study_config),
  // so its stimuli render as they were recorded. With omitted_at_default, the value left out of the
  // canonical text is that earlier one, which the stimuli of those logs had. (One change a
  // parameter: a second would need the earlier defaults by schema.)
  int default_since_log_schema = 0;
  double earlier_default = 0.0;
  // A choice name whose meaning changed in log schema `since_log_schema` (equalise "on": the
  // theoretical density before schema 8, equal shaded samples since): a config read now, or one that
  // a log of that schema or later carries, reads `name` as the choice `read_as`; one that an earlier
  // log carries reads it as the choice of that name, so its stimuli (their canonical text, JSON and
  // frames) stay those it recorded.
  struct ChoiceAlias {
    std::string_view name, read_as;
    int since_log_schema = 0;
  };
  std::optional<ChoiceAlias> choice_alias;
  double (*read)(const MethodParameters&) = nullptr;
  void (*write)(MethodParameters&, double) = nullptr;
};

// Whether the parameter's default changed after logs of `log_schema_version` were written (0: a
// config read now, not from a log: never), and the value a stimulus whose config did not give it
// had in those logs.
bool default_changed_since(const ParameterDescriptor& parameter, int log_schema_version);
double default_in_log_schema(const ParameterDescriptor& parameter, int log_schema_version);

struct MethodDescriptor {
  RenderMethod method = RenderMethod::ground_truth;
  std::string_view name;  // "gt", "ipr", "fipr", "pt", "fpt": the config's `method`
  std::string_view summary;
  SceneKind scene_kind = SceneKind::signed_distance;
  bool depends_on_gaze = false;  // frames follow the gaze sample (cannot be prepared ahead)
  bool needs_display = false;    // reads display_width_mm, display_height_mm, viewing_distance_mm
  // Samples a frame may hold at most (width x height x samples_per_pixel); 0: no such limit.
  uint64_t max_samples_per_frame = 0;
  std::vector<ParameterDescriptor> parameters;
};

// Every method: gt, ipr, fipr, pt, fpt, the sampling models on the sphere tracer, on path-traced
// frames, then on images (each in SamplingModel's order), volume, fvolume (docs/config.md's order).
std::span<const MethodDescriptor> all_methods();
const MethodDescriptor& describe(RenderMethod method);
// A method's place in all_methods().
inline size_t method_index(RenderMethod method) {
  return static_cast<size_t>(&describe(method) - all_methods().data());
}
// The method of a config's `method` name; nullopt when no method has it.
std::optional<RenderMethod> find_method(std::string_view name);
// "gt, ipr, fipr, pt, fpt": for messages.
std::string known_methods();
// The parameter of a method with this key (or, with `legacy`, this legacy key); nullptr if none.
const ParameterDescriptor* find_parameter(const MethodDescriptor& method, std::string_view key, bool legacy = false);
// "a, b, c": the keys of a method's parameters, for messages.
std::string parameter_keys(const MethodDescriptor& method);

// Whether `value` is one the parameter takes; otherwise what was expected ("an integer in 1..16",
// "one of 1, 4, 16", ...), for the caller to word with the field it came from.
std::optional<std::string> check_parameter_value(const ParameterDescriptor& parameter, double value);
// A value as the edges show it: a choice by its name, a number as the shortest text that reads back.
std::string parameter_value_text(const ParameterDescriptor& parameter, double value);
// The index of a choice's name in a config that a log of `log_schema_version` carries (0: a config
// read now), choice_alias applied; nullopt when the parameter has no such choice.
std::optional<double> parse_choice(const ParameterDescriptor& parameter, std::string_view name,
                                   int log_schema_version = 0);

// The value of a parameter by key (a choice as its index); nullopt when the method has none.
std::optional<double> parameter_value(const MethodParameters& parameters, std::string_view key);

// Every parameter at its default.
MethodParameters default_parameters(RenderMethod method);
// The defaults with each layer on top, in order (later layers win). A layer maps keys to values as
// the edges carry them (a choice as its index), already checked by the reader; std::logic_error
// for a key the method does not have.
using ParameterLayer = std::map<std::string, double>;
MethodParameters parameters_with(RenderMethod method, std::initializer_list<const ParameterLayer*> layers);
// A rule between parameters of a method that no value breaks on its own (FIPR: the outer periphery
// lies at or beyond the fovea): the keys involved and what was expected, with the values.
struct ParameterConflict {
  std::vector<std::string_view> keys;
  std::string expected;
};
std::optional<ParameterConflict> parameter_conflict(const MethodParameters& parameters);

// docs/config.md's table of methods and parameters (Markdown), made from the descriptors.
std::string methods_markdown();

}  // namespace fovlab
