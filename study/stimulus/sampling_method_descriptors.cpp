// The sampling models' descriptors (Ye et al. 2022): one row per source of samples
// (kSampleSourceDescriptors) times one row per model (kSamplingModelDescriptors), each pair one
// method (rmfr, pt-rmfr, img-rmfr, ...). render_method.cpp lists them among the other methods.
#include <deque>
#include <string>
#include <string_view>
#include <vector>

#include "study/stimulus/descriptor_builders.h"

namespace fovlab::descriptor_builders {
namespace {

// The ranges foveation/sampling_map.h checks (study/ uses core only; protocols/stimuli's tests keep
// the two in step).
constexpr double kMinSigma = 1.0, kMaxSigma = 8.0;
constexpr double kMinFocalShare = 1e-3, kMaxFocalShare = 1.0;
constexpr double kMinAlpha = 0.25, kMaxAlpha = 8.0;

// The sampling models' sources (Ye et al. 2022): on the sphere tracer, its parameters; on
// pre-rendered path-traced frames, the path tracer's; on a folder of images, none. The model's
// follow (the same keys on every source).
MethodDescriptor sphere_traced_samples(RenderMethod method, std::string_view name, std::string_view summary) {
  MethodDescriptor descriptor{method, name, summary, SceneKind::signed_distance};
  descriptor.depends_on_gaze = true;
  descriptor.max_samples_per_frame = kSphereTraceSamplesPerFrame;
  descriptor.parameters = sphere_trace_parameters<SphereTracedSamples>();
  descriptor.parameters[0].help = "rays a sample, spread over the sample's footprint on the screen";
  return descriptor;
}

MethodDescriptor path_traced_samples(RenderMethod method, std::string_view name, std::string_view summary) {
  MethodDescriptor descriptor{method, name, summary, SceneKind::path_traced};
  descriptor.depends_on_gaze = true;
  descriptor.parameters = path_trace_parameters<PathTracedSamples>();
  return descriptor;
}

// The lab's own images (protocols/stimuli/image_sequence.h): the images are what they are.
MethodDescriptor image_samples(RenderMethod method, std::string_view name, std::string_view summary) {
  MethodDescriptor descriptor{method, name, summary, SceneKind::image_sequence};
  descriptor.depends_on_gaze = true;
  return descriptor;
}

template <class Struct>
ParameterDescriptor sigma_parameter(std::string_view help) {
  return parameter<&Struct::sigma>("sigma", "", ParameterType::real, 2.6, kMinSigma, kMaxSigma, help);
}

template <class Struct>
void add_resample(std::vector<ParameterDescriptor>& list) {
  ParameterDescriptor resample =
      parameter<&Struct::resample>("resample", "", ParameterType::choice, 0, 0, 1,
                                   "how each pixel reads the samples around its place in the buffer: bilinear (2x2, "
                                   "the paper's) or lanczos (Lanczos-2, 4x4: sharper, with ringing)");
  resample.choices = {"bilinear", "lanczos"};
  list.push_back(resample);
}

template <class Struct>
void add_radii(std::vector<ParameterDescriptor>& list) {
  list.push_back(parameter<&Struct::inner_radius_deg>("inner_radius_deg", "deg", ParameterType::real, 10.0, 0, 90,
                                                      "r1: radius (eccentricity) of the full-resolution zone"));
  list.push_back(parameter<&Struct::outer_radius_deg>(
      "outer_radius_deg", "deg", ParameterType::real, 20.0, 0, 90,
      "r2: radius (eccentricity) where the fall-off ends; at least inner_radius_deg"));
}

// The sampling models' equalise (EqualiseChoice's order). "on" meant the theoretical density in logs
// before schema 8 and means samples since (docs/foveation.md, "Equal work"); a config of such a log
// keeps the choice "on", so its stimuli keep their canonical text.
template <class Struct>
ParameterDescriptor equalise_parameter(std::string_view solved) {
  ParameterDescriptor equalise = parameter<&Struct::equalise>("equalise", "", ParameterType::choice, 0, 0, 3, solved);
  equalise.choices = {"off", "on", "samples", "density"};
  equalise.choice_alias = ParameterDescriptor::ChoiceAlias{"on", "samples", 8};
  return equalise;
}

template <class Struct>
void add_equalise(std::vector<ParameterDescriptor>& list, std::string_view solved) {
  list.push_back(equalise_parameter<Struct>(solved));
  list.push_back(sigma_parameter<Struct>("equalise's target: RMFR at this sigma on the same display"));
}

MethodDescriptor rectangular_mapping(MethodDescriptor method) {
  using P = RectangularMappingModel;
  method.parameters.push_back(
      sigma_parameter<P>("screen over buffer size per axis: sigma^2 is the theoretical speed-up"));
  method.parameters.push_back(parameter<&P::focal_share_x>(
      "focal_share_x", "", ParameterType::real, 0.3, kMinFocalShare, kMaxFocalShare, "f_x as a share of the width"));
  method.parameters.push_back(parameter<&P::focal_share_y>(
      "focal_share_y", "", ParameterType::real, 0.3, kMinFocalShare, kMaxFocalShare, "f_y as a share of the height"));
  add_resample<P>(method.parameters);
  return method;
}

MethodDescriptor hyperbolic_layers(MethodDescriptor method) {
  using P = HyperbolicLayersModel;
  method.needs_display = true;
  auto& list = method.parameters;
  add_radii<P>(list);
  list.push_back(parameter<&P::middle_pixel_size_px>("middle_pixel_size_px", "px", ParameterType::real, 2.0, 1, 64,
                                                     "s2: the middle layer's pixel size in screen pixels"));
  list.push_back(parameter<&P::outer_pixel_size_px>("outer_pixel_size_px", "px", ParameterType::real, 12.35, 1, 256,
                                                    "s3: the outer layer's pixel size; at least middle_pixel_size_px"));
  list.push_back(parameter<&P::blend_band_deg>(
      "blend_band_deg", "deg", ParameterType::real, 1.0, 0, 90,
      "each layer fades out over this much eccentricity inside its radius; at most inner_radius_deg"));
  add_equalise<P>(
      list,
      "outer_pixel_size_px solved once, with the gaze at the centre: samples (\"on\"): as many shaded samples as "
      "RMFR's; density: mean density 1 / sigma^2 (what \"on\" meant in logs before schema 8)");
  add_resample<P>(list);
  add_display_parameters<P>(list);
  return method;
}

MethodDescriptor linear_falloff(MethodDescriptor method) {
  using P = LinearFalloffModel;
  method.needs_display = true;
  auto& list = method.parameters;
  add_radii<P>(list);
  list.push_back(parameter<&P::min_probability>("min_probability", "", ParameterType::real, 0.047, 0, 1,
                                                "p_min: the probability beyond outer_radius_deg"));
  list.push_back(parameter<&P::sample_seed>("sample_seed", "", ParameterType::integer, 0, 0, kSeedMax,
                                            "seed of the per-pixel thresholds"));
  add_equalise<P>(
      list,
      "min_probability solved once, with the gaze at the centre: samples (\"on\"): as many shaded samples as RMFR's; "
      "density: mean density 1 / sigma^2 (what \"on\" meant in logs before schema 8)");
  add_display_parameters<P>(list);
  return method;
}

MethodDescriptor kernel_log_polar(MethodDescriptor method) {
  using P = KernelLogPolarModel;
  method.parameters.push_back(
      sigma_parameter<P>("screen over buffer size per axis; with equalise samples: RMFR's, the target"));
  method.parameters.push_back(parameter<&P::alpha>("alpha", "", ParameterType::real, 4.0, kMinAlpha, kMaxAlpha,
                                                   "the kernel's exponent: u = w (ln r / L)^alpha"));
  method.parameters.push_back(omitted_at_default(equalise_parameter<P>(
      "samples (\"on\"): the buffer's sigma solved once, with the gaze at the centre, so that it shades as many "
      "samples as RMFR at sigma; density: as off (the buffer is RMFR's)")));
  add_resample<P>(method.parameters);
  return method;
}

// The sampling models, in SamplingModel's order: each one's summary and parameters.
struct SamplingModelDescriptor {
  std::string_view summary;
  MethodDescriptor (*add_parameters)(MethodDescriptor);
};
const SamplingModelDescriptor kSamplingModelDescriptors[] = {
    {"rectangular mapping-based foveated rendering (Ye et al. 2022, section 3)", &rectangular_mapping},
    {"three layers of falling resolution (Guenter et al.; Ye et al. 2022, section 5.1)", &hyperbolic_layers},
    {"linear fall-off of the sampling probability (Weier et al.; Ye et al. 2022, section 5.1)", &linear_falloff},
    {"kernel log-polar foveated rendering (Meng et al.; Ye et al. 2022, section 5.1)", &kernel_log_polar},
};
static_assert(std::size(kSamplingModelDescriptors) == kSamplingModelCount);

// The sources, in SampleSource's order: how a model's name and summary read on it, and its parameters.
struct SampleSourceDescriptor {
  std::string_view name_prefix;        // before the model's name: "rmfr", "pt-rmfr"
  std::string_view own_summary_after;  // empty: the model's own summary; else its name and this
  MethodDescriptor (*make)(RenderMethod, std::string_view, std::string_view);
};
const SampleSourceDescriptor kSampleSourceDescriptors[] = {
    {"", "", &sphere_traced_samples},
    {"pt-", " on pre-rendered path-traced frames (emulated)", &path_traced_samples},
    {"img-", " on a folder of images (PNG or EXR)", &image_samples},
};
static_assert(std::size(kSampleSourceDescriptors) == std::variant_size_v<SampleSource>);

}  // namespace

// Every (source, model) pair, source-major.
std::vector<MethodDescriptor> sampling_models() {
  // The names and summaries made here live as long as the descriptors (a deque keeps their places).
  static std::deque<std::string> texts;
  std::vector<MethodDescriptor> list;
  for (size_t source = 0; source < std::size(kSampleSourceDescriptors); ++source)
    for (size_t model = 0; model < kSamplingModelCount; ++model) {
      const SampleSourceDescriptor& on = kSampleSourceDescriptors[source];
      const SamplingModelDescriptor& entry = kSamplingModelDescriptors[model];
      const std::string_view name = texts.emplace_back(std::string(on.name_prefix) + kSamplingModelNames[model]);
      const std::string_view summary =
          on.own_summary_after.empty()
              ? entry.summary
              : std::string_view(texts.emplace_back(kSamplingModelNames[model] + std::string(on.own_summary_after)));
      list.push_back(
          entry.add_parameters(on.make(sampled_method(source, static_cast<SamplingModel>(model)), name, summary)));
    }
  return list;
}

}  // namespace fovlab::descriptor_builders
