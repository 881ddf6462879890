#include "study/stimulus/render_method.h"

#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <variant>

#include "core/number_text.h"
#include "study/stimulus/descriptor_builders.h"

namespace fovlab {
namespace {

// The builders (parameter<>, sphere_trace_parameters<>, ...) and the sampling models' descriptors.
using namespace descriptor_builders;

// The pyramid's depth levels. Since log schema 10 they stop by the cone (thin geometry kept,
// docs/scenes.md "Coarse test"), and the min filter, which the cone makes redundant, defaults to
// `min_filter_size` (1: IPR and FIPR alike, docs/benchmarks.md "Thin geometry with the new
// defaults"); logs of earlier schemas ran the paper's centre ray with a 3x3 filter (Polychronakis
// et al. 2023), which a config they carry reads where it names none.
template <class Struct>
void add_pyramid_parameters(std::vector<ParameterDescriptor>& parameters, int min_levels, int min_filter_size) {
  parameters.push_back(parameter<&Struct::pyramid_levels>(
      "pyramid_levels", "", ParameterType::integer, 3, min_levels, 5,
      "levels, each with 1/4 the pixels of the one above (FIPR: low, mid and top at least)"));
  ParameterDescriptor min_filter =
      with_allowed(parameter<&Struct::min_filter_size>("min_filter_size", "px", ParameterType::integer, min_filter_size,
                                                       1, 5, "side of the depth min filter"),
                   {1, 3, 5});
  parameters.push_back(min_filter_size == 3 ? min_filter : with_changed_default(min_filter, 10, 3));
  ParameterDescriptor coarse_test = parameter<&Struct::coarse_test>(
      "coarse_test", "", ParameterType::choice, 1, 0, 1,
      "how the depth levels stop: cone (the coarse pixel's whole cone: never starts a finer ray behind a surface it "
      "would hit) or ray (the paper's centre ray; may step over geometry thinner than a coarse pixel)");
  coarse_test.choices = {"ray", "cone"};
  parameters.push_back(omitted_at_default(with_changed_default(coarse_test, 10, 0)));
}

MethodDescriptor ground_truth() {
  MethodDescriptor method{RenderMethod::ground_truth, "gt", "sphere tracing, every sample from the camera",
                          SceneKind::signed_distance};
  method.max_samples_per_frame = kSphereTraceSamplesPerFrame;
  method.parameters = sphere_trace_parameters<GroundTruthParameters>();
  return method;
}

MethodDescriptor inverted_pyramid() {
  MethodDescriptor method{RenderMethod::inverted_pyramid, "ipr",
                          "the inverted pyramid (Polychronakis et al. 2023, section 3.1)", SceneKind::signed_distance};
  method.max_samples_per_frame = kSphereTraceSamplesPerFrame;
  method.parameters = sphere_trace_parameters<InvertedPyramidParameters>();
  add_pyramid_parameters<InvertedPyramidParameters>(method.parameters, 2, 1);
  ParameterDescriptor full_depth = parameter<&InvertedPyramidParameters::full_resolution_depth>(
      "full_resolution_depth", "", ParameterType::choice, 0, 0, 1,
      "on: one depth ray a pixel at full resolution before the shaded samples, which start from it");
  full_depth.choices = {"off", "on"};
  method.parameters.push_back(omitted_at_default(full_depth));
  return method;
}

MethodDescriptor foveated_pyramid() {
  using P = FoveatedPyramidParameters;
  MethodDescriptor method{RenderMethod::foveated_pyramid, "fipr",
                          "the foveated inverted pyramid (Polychronakis et al. 2023, section 3.2)",
                          SceneKind::signed_distance};
  method.depends_on_gaze = true;
  method.needs_display = true;
  method.max_samples_per_frame = kSphereTraceSamplesPerFrame;
  method.parameters = sphere_trace_parameters<P>();
  add_pyramid_parameters<P>(method.parameters, 3, 1);
  auto& list = method.parameters;
  list.push_back(with_legacy_key(
      parameter<&P::fovea_radius_deg>(
          "fovea_radius_deg", "deg", ParameterType::real, 7.5, 0, 180,
          "radius (eccentricity from the gaze, not an aperture) within which every pixel is traced at the top level"),
      "fovea_deg"));
  list.push_back(with_legacy_key(parameter<&P::outer_periphery_radius_deg>(
                                     "outer_periphery_radius_deg", "deg", ParameterType::real,
                                     kNoOuterPeripheryRadiusDeg, 0, kNoOuterPeripheryRadiusDeg,
                                     "radius (eccentricity) beyond which no pixel is traced at the top level for "
                                     "acuity (edges still are with combine max); 180: none; at least fovea_radius_deg"),
                                 "outer_periphery_deg"));
  list.push_back(with_allowed(
      parameter<&P::periphery_refresh>(
          "periphery_refresh", "frames", ParameterType::integer, 1, 1, 4,
          "pixels the mask leaves out get a new colour every 1st, 2nd or 4th image, else keep the previous image's"),
      {1, 2, 4}));
  list.push_back(parameter<&P::periphery_steps>(
      "periphery_steps", "steps", ParameterType::integer, 0, 0, 4096,
      "how a pixel the mask leaves out gets its new colour: 0 the mid level's colour, interpolated (the paper's "
      "reading); N traced at full resolution from the mid level's depth with at most N steps (and max_steps)"));
  // Added in log schema 5, defaulting to bilinear; every earlier log's FIPR was mid-footprint-bilinear.
  ParameterDescriptor reconstruction = parameter<&P::periphery_reconstruction>(
      "periphery_reconstruction", "", ParameterType::choice, 1, 0, 2,
      "with periphery_steps 0, how the mid level's colours fill the pixels: bilinear (each mid colour textured over "
      "one pixel's footprint, interpolated bilinearly), catmull-rom (so, interpolated by Catmull-Rom: sharper), or "
      "mid-footprint-bilinear (textured over its own 2-pixel footprint, bilinear: every FIPR stimulus of logs before "
      "schema 5); docs/foveation.md");
  reconstruction.choices = {"mid-footprint-bilinear", "bilinear", "catmull-rom"};
  list.push_back(omitted_at_default(with_changed_default(reconstruction, 5, 0)));
  // Added in log schema 6, defaulting to promote; every earlier log's FIPR ignored near misses.
  ParameterDescriptor near_misses = parameter<&P::near_misses>(
      "near_misses", "", ParameterType::choice, 1, 0, 1,
      "where a low- or mid-level ray passed a surface within its pixel's cone without hitting it (a wire between "
      "two rays, a grazed silhouette): promote (with periphery_steps 0, the periphery's pixels under such a mid pixel "
      "are traced in full at the top level, from in front of it) or ignore (the paper's: every FIPR stimulus of logs "
      "before schema 6); docs/foveation.md");
  near_misses.choices = {"ignore", "promote"};
  list.push_back(omitted_at_default(with_changed_default(near_misses, 6, 0)));
  ParameterDescriptor blur = parameter<&P::blur>("blur", "", ParameterType::choice, 0, 0, 1,
                                                 "pass 5, the masked Gaussian blur of the transition zones");
  blur.choices = {"off", "on"};
  list.push_back(blur);
  ParameterDescriptor combine = parameter<&P::combine>(
      "combine", "", ParameterType::choice, 0, 0, 3,
      "how acuity and edges make a pixel's probability: max (fovea, every peripheral edge, the rest by acuity), "
      "fovea-or-product, product (the paper's words), acuity (edges ignored); docs/foveation.md");
  combine.choices = {"max", "fovea-or-product", "product", "acuity"};
  list.push_back(combine);
  list.push_back(parameter<&P::edge_threshold>(
      "edge_threshold", "", ParameterType::real, 0.4, 1e-4, 1000,
      "Sobel magnitude of the low level's depth, relative to the depth, that makes an edge"));
  // Added in log schema 10, defaulting to centre-ray; every earlier log's FIPR read the level's depth.
  ParameterDescriptor edge_depth = parameter<&P::edge_depth>(
      "edge_depth", "", ParameterType::choice, 1, 0, 1,
      "which depth of the low level the edges are found in: centre-ray (where the ray through the pixel's centre "
      "hits, the paper's pyramid's; with coarse_test cone marched on from where the cone stopped) or level (the "
      "depth passed on: with the cone, where it stopped, in front of the surface; every FIPR stimulus of logs "
      "before schema 10); the same with coarse_test ray; docs/foveation.md");
  edge_depth.choices = {"level", "centre-ray"};
  list.push_back(omitted_at_default(with_changed_default(edge_depth, 10, 0)));
  list.push_back(parameter<&P::mask_seed>("mask_seed", "", ParameterType::integer, 0, 0, kSeedMax,
                                          "seed of the per-pixel thresholds of the mask"));
  add_display_parameters<P>(list);
  return method;
}

MethodDescriptor path_traced() {
  MethodDescriptor method{RenderMethod::path_traced, "pt",
                          "path tracing, pre-rendered (Polychronakis et al. 2021's reference)", SceneKind::path_traced};
  method.parameters = path_trace_parameters<PathTracedParameters>();
  return method;
}

MethodDescriptor foveated_path_traced() {
  using P = FoveatedPathTracedParameters;
  MethodDescriptor method{RenderMethod::foveated_path_traced, "fpt",
                          "the emulated foveated path tracer (Polychronakis et al. 2021, section 3.2)",
                          SceneKind::path_traced};
  method.depends_on_gaze = true;
  method.needs_display = true;
  method.parameters = path_trace_parameters<P>();
  auto& list = method.parameters;
  list.push_back(with_legacy_key(
      parameter<&P::foveal_aperture_deg>("foveal_aperture_deg", "deg", ParameterType::real, 10.0, 0, 360,
                                         "the foveal zone's full aperture (eccentricity up to half of it)"),
      "foveal_deg"));
  list.push_back(with_legacy_key(
      parameter<&P::middle_minus_foveal_aperture_deg>(
          "middle_minus_foveal_aperture_deg", "deg", ParameterType::real, 52.5, 0, 360,
          "how much wider the middle zone's aperture is than the foveal one's (Polychronakis et al. 2021's 5 to 30)"),
      "middle_over_foveal_deg"));
  list.push_back(
      with_legacy_key(parameter<&P::band_width_deg>(
                          "band_width_deg", "deg", ParameterType::real, 1.0, 0, 90,
                          "width, in degrees of eccentricity, of the linear band at each zone boundary; 0 a hard edge"),
                      "band_deg"));
  list.push_back(parameter<&P::periphery_bounces>(
      "periphery_bounces", "", ParameterType::integer, -1, -1, 1024,
      "-1: the middle and outer zones come from the same frames; else from frames path traced with this many bounces "
      "(the pilot of Polychronakis et al. 2021, section 4.2)"));
  add_display_parameters<P>(list);
  return method;
}

// Bruder et al. 2019's volume raycaster, full and Voronoi-foveated (docs/volume-rendering.md).
template <class P>
std::vector<ParameterDescriptor> volume_parameters() {
  return {
      parameter<&P::step_voxels>("step_voxels", "voxels", ParameterType::real, 0.5, 0.05, 16.0,
                                 "the base step along a ray (the foveated step grows from it away from the gaze)"),
      parameter<&P::jitter_seed>("jitter_seed", "", ParameterType::integer, 1, 0, kSeedMax,
                                 "seed of each ray's jittered first sample"),
  };
}

MethodDescriptor volume_raycast() {
  MethodDescriptor method{RenderMethod::volume_raycast, "volume",
                          "volume raycasting, every pixel traced (Bruder et al. 2019's reference)", SceneKind::volume};
  method.parameters = volume_parameters<VolumeRaycastParameters>();
  return method;
}

MethodDescriptor foveated_volume_raycast() {
  using P = FoveatedVolumeRaycastParameters;
  MethodDescriptor method{RenderMethod::foveated_volume_raycast, "fvolume",
                          "Voronoi-based foveated volume raycasting (Bruder et al. 2019)", SceneKind::volume};
  method.depends_on_gaze = true;
  method.needs_display = true;
  method.parameters = volume_parameters<P>();
  auto& list = method.parameters;
  list.push_back(parameter<&P::density_sigma_deg>(
      "density_sigma_deg", "deg", ParameterType::real, 2.5, 0.1, 90.0,
      "s: radius (eccentricity) of the sampling density's Gaussian, at the display's centre"));
  ParameterDescriptor correction = parameter<&P::opacity_correction>(
      "opacity_correction", "", ParameterType::choice, 1, 0, 1,
      "on: the opacity is corrected for the longer peripheral step; off: as the authors' code (too transparent)");
  correction.choices = {"off", "on"};
  list.push_back(correction);
  ParameterDescriptor smoothing = parameter<&P::temporal_smoothing>(
      "temporal_smoothing", "", ParameterType::choice, 1, 0, 1,
      "on: each image is the mean with up to 8 stored ones while the view stays and the gaze moves (section 4.4)");
  smoothing.choices = {"off", "on"};
  list.push_back(smoothing);
  list.push_back(parameter<&P::mask_seed>("mask_seed", "", ParameterType::integer, 1, 0, kSeedMax,
                                          "seed of the sampling mask's initial sites"));
  add_display_parameters<P>(list);
  return method;
}

const std::vector<MethodDescriptor>& methods() {
  static const std::vector<MethodDescriptor> all = [] {
    std::vector<MethodDescriptor> list = {ground_truth(), inverted_pyramid(), foveated_pyramid(), path_traced(),
                                          foveated_path_traced()};
    for (MethodDescriptor& model : sampling_models()) list.push_back(std::move(model));
    list.push_back(volume_raycast());
    list.push_back(foveated_volume_raycast());
    return list;
  }();
  return all;
}

std::string join(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "" : ", ") + item;
  return text;
}

}  // namespace

std::span<const MethodDescriptor> all_methods() { return methods(); }

const MethodDescriptor& describe(RenderMethod method) {
  for (const MethodDescriptor& descriptor : methods())
    if (descriptor.method == method) return descriptor;
  throw std::logic_error("describe: a method without a descriptor");
}

std::optional<RenderMethod> find_method(std::string_view name) {
  for (const MethodDescriptor& method : methods())
    if (method.name == name) return method.method;
  return std::nullopt;
}

std::string known_methods() {
  std::vector<std::string> names;
  for (const MethodDescriptor& method : methods()) names.emplace_back(method.name);
  return join(names);
}

const ParameterDescriptor* find_parameter(const MethodDescriptor& method, std::string_view key, bool legacy) {
  for (const ParameterDescriptor& parameter : method.parameters)
    if (parameter.key == key || (legacy && !parameter.legacy_key.empty() && parameter.legacy_key == key))
      return &parameter;
  return nullptr;
}

std::string parameter_keys(const MethodDescriptor& method) {
  std::vector<std::string> keys;
  for (const ParameterDescriptor& parameter : method.parameters) keys.emplace_back(parameter.key);
  return join(keys);
}

std::optional<std::string> check_parameter_value(const ParameterDescriptor& parameter, double value) {
  if (parameter.type == ParameterType::choice) {
    std::vector<std::string> names;
    for (std::string_view name : parameter.choices) {
      std::string quoted(1, '"');  // (appended: GCC 12's -Wrestrict misfires on "\"" + std::string(name) + "\"" here)
      quoted.append(name).push_back('"');
      names.push_back(std::move(quoted));
    }
    const double index = std::floor(value);
    if (std::isfinite(value) && index == value && index >= 0 && index < double(parameter.choices.size()))
      return std::nullopt;
    return "one of " + join(names);
  }
  if (!parameter.allowed.empty()) {
    for (double allowed : parameter.allowed)
      if (value == allowed) return std::nullopt;
    std::string values = "one of";
    for (double allowed : parameter.allowed) values.append(" ").append(exact_number_text(allowed));
    return values;
  }
  if (!(value >= parameter.min_value && value <= parameter.max_value))
    return "a value in [" + exact_number_text(parameter.min_value) + ", " + exact_number_text(parameter.max_value) +
           "]";
  if (parameter.type == ParameterType::integer && std::floor(value) != value) return "a whole number";
  return std::nullopt;
}

std::string parameter_value_text(const ParameterDescriptor& parameter, double value) {
  if (parameter.type == ParameterType::choice && value >= 0 && value < double(parameter.choices.size()))
    return std::string(parameter.choices[static_cast<size_t>(value)]);
  return format_number(value, 17);
}

std::optional<double> parse_choice(const ParameterDescriptor& parameter, std::string_view name,
                                   int log_schema_version) {
  if (const auto& alias = parameter.choice_alias;
      alias && name == alias->name && (log_schema_version == 0 || log_schema_version >= alias->since_log_schema))
    name = alias->read_as;
  for (size_t i = 0; i < parameter.choices.size(); ++i)
    if (parameter.choices[i] == name) return double(i);
  return std::nullopt;
}

std::optional<double> parameter_value(const MethodParameters& parameters, std::string_view key) {
  const ParameterDescriptor* parameter = find_parameter(describe(method_of(parameters)), key);
  if (!parameter) return std::nullopt;
  return parameter->read(parameters);
}

bool default_changed_since(const ParameterDescriptor& parameter, int log_schema_version) {
  return log_schema_version > 0 && log_schema_version < parameter.default_since_log_schema;
}

double default_in_log_schema(const ParameterDescriptor& parameter, int log_schema_version) {
  return default_changed_since(parameter, log_schema_version) ? parameter.earlier_default : parameter.default_value;
}

namespace {

// The variant holding its alternative number `index`, value-initialised (zeroed: the descriptors
// write the defaults).
template <class Variant, size_t... Index>
Variant alternative_at(size_t index, std::index_sequence<Index...>) {
  Variant variant;
  ((index == Index ? void(variant.template emplace<Index>()) : void()), ...);
  return variant;
}
template <class Variant>
Variant alternative_at(size_t index) {
  return alternative_at<Variant>(index, std::make_index_sequence<std::variant_size_v<Variant>>());
}

}  // namespace

MethodParameters default_parameters(RenderMethod method) {
  MethodParameters parameters;
  switch (method.kind) {
    case MethodKind::ground_truth:
      parameters = GroundTruthParameters{};
      break;
    case MethodKind::inverted_pyramid:
      parameters = InvertedPyramidParameters{};
      break;
    case MethodKind::foveated_pyramid:
      parameters = FoveatedPyramidParameters{};
      break;
    case MethodKind::path_traced:
      parameters = PathTracedParameters{};
      break;
    case MethodKind::foveated_path_traced:
      parameters = FoveatedPathTracedParameters{};
      break;
    case MethodKind::sphere_traced_sampling:
    case MethodKind::path_traced_sampling:
    case MethodKind::image_sampling:
      parameters = SampledParameters{alternative_at<SampleSource>(sample_source_index(method)),
                                     alternative_at<SamplingModelParameters>(static_cast<size_t>(method.model))};
      break;
    case MethodKind::volume_raycast:
      parameters = VolumeRaycastParameters{};
      break;
    case MethodKind::foveated_volume_raycast:
      parameters = FoveatedVolumeRaycastParameters{};
      break;
  }
  for (const ParameterDescriptor& parameter : describe(method).parameters)
    parameter.write(parameters, parameter.default_value);
  return parameters;
}

MethodParameters parameters_with(RenderMethod method, std::initializer_list<const ParameterLayer*> layers) {
  MethodParameters parameters = default_parameters(method);
  const MethodDescriptor& descriptor = describe(method);
  for (const ParameterLayer* layer : layers)
    for (const auto& [key, value] : *layer) {
      const ParameterDescriptor* parameter = find_parameter(descriptor, key);
      if (!parameter)
        throw std::logic_error("parameters_with: " + std::string(descriptor.name) + " has no parameter " + key);
      parameter->write(parameters, value);
    }
  return parameters;
}

std::optional<ParameterConflict> parameter_conflict(const MethodParameters& parameters) {
  const auto at_least = [](std::string_view larger, double larger_value, std::string_view smaller,
                           double smaller_value) -> std::optional<ParameterConflict> {
    if (larger_value >= smaller_value) return std::nullopt;
    return ParameterConflict{{smaller, larger},
                             "expected " + std::string(larger) + " (" + format_number(larger_value, 6) +
                                 ") >= " + std::string(smaller) + " (" + format_number(smaller_value, 6) + ")"};
  };
  const auto hyperbolic = [&](const auto& layers) {
    if (auto conflict =
            at_least("outer_radius_deg", layers.outer_radius_deg, "inner_radius_deg", layers.inner_radius_deg))
      return conflict;
    if (auto conflict = at_least("outer_pixel_size_px", layers.outer_pixel_size_px, "middle_pixel_size_px",
                                 layers.middle_pixel_size_px))
      return conflict;
    return at_least("inner_radius_deg", layers.inner_radius_deg, "blend_band_deg", layers.blend_band_deg);
  };
  const auto linear = [&](const auto& falloff) {
    return at_least("outer_radius_deg", falloff.outer_radius_deg, "inner_radius_deg", falloff.inner_radius_deg);
  };
  if (const auto* sampled = std::get_if<SampledParameters>(&parameters)) {
    if (const auto* layers = std::get_if<HyperbolicLayersModel>(&sampled->model)) return hyperbolic(*layers);
    if (const auto* falloff = std::get_if<LinearFalloffModel>(&sampled->model)) return linear(*falloff);
    return std::nullopt;
  }
  const auto* fipr = std::get_if<FoveatedPyramidParameters>(&parameters);
  if (!fipr || fipr->outer_periphery_radius_deg >= fipr->fovea_radius_deg) return std::nullopt;
  return ParameterConflict{{"fovea_radius_deg", "outer_periphery_radius_deg"},
                           "expected outer_periphery_radius_deg (" +
                               format_number(fipr->outer_periphery_radius_deg, 6) + ") >= fovea_radius_deg (" +
                               format_number(fipr->fovea_radius_deg, 6) +
                               "): the outer periphery starts beyond the fovea"};
}

namespace {

// The shortest text that reads back as `value` (2.6, not printf's 17-digit 2.6000000000000001), for
// people reading the table; the canonical text keeps its 17 digits (logs compare it).
std::string shortest_number(double value) {
  char text[400];  // fixed notation of any double
  const auto result = std::to_chars(text, text + sizeof text, value, std::chars_format::fixed);
  return std::string(text, result.ptr);
}

}  // namespace

std::string methods_markdown() {
  std::string text;
  for (const MethodDescriptor& method : methods()) {
    text += "### `method = \"" + std::string(method.name) + "\"`: " + std::string(method.summary) + "\n\n";
    text += std::string("Scenes: ") +
            (method.scene_kind == SceneKind::signed_distance ? "SDF (built-in names or .glsl files)"
             : method.scene_kind == SceneKind::path_traced
                 ? "path-traced (courtyard or .obj files)"
             : method.scene_kind == SceneKind::volume
                 ? "volume scenes (built-in names or .toml files; docs/volume-rendering.md)"
                 : "a folder of .png or .exr images, each the display's size (frame i: image i; one image: a still)") +
            ". Frames " + (method.depends_on_gaze ? "follow the gaze of each refresh" : "do not depend on the gaze");
    if (method.max_samples_per_frame > 0)
      text += "; width_px x height_px x samples_per_pixel at most " + std::to_string(method.max_samples_per_frame);
    text += ".\n\n| key | unit | default | allowed | what |\n|---|---|---|---|---|\n";
    for (const ParameterDescriptor& parameter : method.parameters) {
      std::string allowed;
      if (parameter.type == ParameterType::choice) {
        std::vector<std::string> names;
        for (std::string_view name : parameter.choices) names.push_back("`\"" + std::string(name) + "\"`");
        allowed = join(names);
      } else if (!parameter.allowed.empty()) {
        std::vector<std::string> values;
        for (double value : parameter.allowed) values.push_back(format_number(value, 17));
        allowed = join(values);
      } else {
        allowed = (parameter.type == ParameterType::integer ? "integer " : "") + shortest_number(parameter.min_value) +
                  " to " + shortest_number(parameter.max_value);
      }
      // A default outside the range is "not given": the display's, filled in by the schedule.
      const auto value_text = [&](double value) {
        return parameter.type == ParameterType::choice ? "`\"" + parameter_value_text(parameter, value) + "\"`"
                                                       : shortest_number(value);
      };
      std::string default_text =
          parameter.type != ParameterType::choice && parameter.default_value < parameter.min_value
              ? "from `[display]`"
              : value_text(parameter.default_value);
      if (parameter.default_since_log_schema > 0)
        default_text += " (" + value_text(parameter.earlier_default) + " in logs before schema " +
                        std::to_string(parameter.default_since_log_schema) + ")";
      text += "| `" + std::string(parameter.key) + "` | " + std::string(parameter.unit) + " | " + default_text + " | " +
              allowed + " | " + std::string(parameter.help) +
              (parameter.legacy_key.empty() ? "" : " (was `" + std::string(parameter.legacy_key) + "`)") + " |\n";
    }
    text += "\n";
  }
  return text;
}

}  // namespace fovlab
