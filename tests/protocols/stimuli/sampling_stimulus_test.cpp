// Ye et al. 2022's sampling models as stimulus methods: their descriptors agree with the CPU models
// (foveation/sampling_map.h), and a spec becomes the map of each gaze sample.
#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/input_error.h"
#include "foveation/sampling_map.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "study/stimulus/stimulus_spec.h"

namespace fovlab {
namespace {

const ParameterDescriptor& parameter_named(RenderMethod method, const std::string& key) {
  const ParameterDescriptor* parameter = find_parameter(describe(method), key);
  if (!parameter) throw std::logic_error("no parameter " + key);
  return *parameter;
}

StimulusSpec spec_of(RenderMethod method) {
  StimulusSpec spec;
  spec.scene = "primitives";
  spec.parameters = default_parameters(method);
  spec.width_px = 96;
  spec.height_px = 54;
  if (StimulusDisplay* display = display_of(spec.parameters)) *display = StimulusDisplay{250.0, 140.625, 400.0};
  return spec;
}

// study/ may not include foveation/, so the descriptors repeat the models' ranges and defaults.
TEST(SamplingStimulus, DescriptorsAgreeWithTheModels) {
  const SamplingSettings defaults;
  for (size_t index = 0; index < kSamplingModelCount; ++index) {
    const RenderMethod method = sampled_method(0, static_cast<SamplingModel>(index));
    const ParameterDescriptor& sigma = parameter_named(method, "sigma");
    EXPECT_EQ(sigma.min_value, kRmfrMinSigma);
    EXPECT_EQ(sigma.max_value, kRmfrMaxSigma);
    EXPECT_EQ(sigma.default_value, defaults.sigma);
    EXPECT_TRUE(is_sampling_model(method));
    EXPECT_TRUE(describe(method).depends_on_gaze);
  }
  const RenderMethod rmfr = sampled_method(0, SamplingModel::rectangular);
  EXPECT_EQ(parameter_named(rmfr, "focal_share_x").min_value, kRmfrMinFocalShare);
  EXPECT_EQ(parameter_named(rmfr, "focal_share_x").max_value, kRmfrMaxFocalShare);
  EXPECT_EQ(parameter_named(rmfr, "focal_share_x").default_value, defaults.focal_share_x);
  EXPECT_EQ(parameter_named(rmfr, "focal_share_y").default_value, defaults.focal_share_y);
  const RenderMethod kfr = sampled_method(0, SamplingModel::kernel_log_polar);
  EXPECT_EQ(parameter_named(kfr, "alpha").min_value, kKfrMinAlpha);
  EXPECT_EQ(parameter_named(kfr, "alpha").max_value, kKfrMaxAlpha);
  EXPECT_EQ(parameter_named(kfr, "alpha").default_value, defaults.alpha);
  const RenderMethod layers = sampled_method(0, SamplingModel::hyperbolic);
  EXPECT_EQ(parameter_named(layers, "inner_radius_deg").default_value, defaults.inner_radius_deg);
  EXPECT_EQ(parameter_named(layers, "outer_radius_deg").default_value, defaults.outer_radius_deg);
  EXPECT_EQ(parameter_named(layers, "middle_pixel_size_px").default_value, defaults.middle_pixel_size_px);
  EXPECT_EQ(parameter_named(layers, "outer_pixel_size_px").default_value, defaults.outer_pixel_size_px);
  EXPECT_EQ(parameter_named(layers, "blend_band_deg").default_value, defaults.blend_band_deg);
  EXPECT_EQ(parameter_named(sampled_method(0, SamplingModel::linear), "min_probability").default_value, defaults.min_probability);
  for (RenderMethod method : {rmfr, kfr, layers}) {
    const ParameterDescriptor& resample = parameter_named(method, "resample");
    ASSERT_EQ(resample.choices.size(), 2u);
    EXPECT_EQ(resample.choices[0], resample_filter_name(ResampleFilter::bilinear));
    EXPECT_EQ(resample.choices[1], resample_filter_name(ResampleFilter::lanczos2));
  }
  EXPECT_EQ(find_parameter(describe(sampled_method(0, SamplingModel::linear)), "resample"), nullptr);  // pull-push
  EXPECT_TRUE(describe(layers).needs_display);
  EXPECT_TRUE(describe(sampled_method(0, SamplingModel::linear)).needs_display);
  EXPECT_FALSE(describe(rmfr).needs_display);
}

TEST(SamplingStimulus, SpecBecomesTheMapOfEachGazeSample) {
  for (size_t index = 0; index < kSamplingModelCount; ++index) {
    const auto model = static_cast<SamplingModel>(index);
    const StimulusSpec spec = spec_of(sampled_method(0, model));
    const SphereTraceSettings settings = sphere_trace_settings(spec, 0);
    ASSERT_EQ(settings.method, TraceMethod::sampling_model) << spec.method_name();
    ASSERT_TRUE(settings.sampling.has_value());
    EXPECT_EQ(model_of(*settings.sampling), model);
    EXPECT_NO_THROW(validate(settings)) << spec.method_name();
    EXPECT_EQ(settings.sampling_filter, ResampleFilter::bilinear);
    // Without a gaze the map is the centre's; with one it follows it.
    const SamplingMap centre = sampling_map(spec, std::nan(""), std::nan(""));
    const SamplingMap corner = sampling_map(spec, 5.0, 5.0);
    EXPECT_NE(density(centre, 5.5, 5.5), density(corner, 5.5, 5.5)) << spec.method_name();
    EXPECT_EQ(density(centre, 48, 27), density(sampling_map(spec, 48, 27), 48, 27)) << spec.method_name();
  }
}

// The models on pre-rendered path-traced frames take the path tracer's parameters, then exactly
// the model parameters of their sphere-traced twins (same keys, ranges, defaults, choices), and the
// same values make the same map for every gaze.
TEST(SamplingStimulus, PathTracedModelsMirrorTheirSphereTracedTwins) {
  for (size_t index = 0; index < kSamplingModelCount; ++index) {
    const auto model = static_cast<SamplingModel>(index);
    const struct {
      RenderMethod sphere_traced, path_traced;
    } twin = {sampled_method(0, model), sampled_method(1, model)};
    const MethodDescriptor& traced = describe(twin.sphere_traced);
    const MethodDescriptor& path = describe(twin.path_traced);
    EXPECT_EQ(path.name, "pt-" + std::string(traced.name));
    EXPECT_EQ(path.scene_kind, SceneKind::path_traced);
    EXPECT_TRUE(is_sampling_model(twin.path_traced) && is_path_traced(twin.path_traced));
    EXPECT_TRUE(path.depends_on_gaze);
    EXPECT_EQ(path.needs_display, traced.needs_display);
    // The path tracer's three, then the model's, in the twin's order.
    ASSERT_EQ(path.parameters.size(), traced.parameters.size());
    EXPECT_EQ(path.parameters[1].key, "max_bounces");
    for (size_t i = 3; i < path.parameters.size(); ++i) {
      const ParameterDescriptor& a = traced.parameters[i];
      const ParameterDescriptor& b = path.parameters[i];
      EXPECT_EQ(a.key, b.key);
      EXPECT_EQ(a.unit, b.unit);
      EXPECT_EQ(a.default_value, b.default_value) << a.key;
      EXPECT_EQ(a.min_value, b.min_value) << a.key;
      EXPECT_EQ(a.max_value, b.max_value) << a.key;
      EXPECT_EQ(a.choices, b.choices) << a.key;
    }
    // Non-default values through the edges' doubles: the same map from both.
    StimulusSpec traced_spec = spec_of(twin.sphere_traced), path_spec = spec_of(twin.path_traced);
    for (size_t i = 3; i < traced.parameters.size(); ++i) {
      const ParameterDescriptor& parameter = traced.parameters[i];
      double value = parameter.default_value;
      if (parameter.key == "sigma") value = 1.9;
      if (parameter.key == "focal_share_y" || parameter.key == "min_probability") value = 0.2;
      if (parameter.key == "alpha" || parameter.key == "outer_pixel_size_px") value = 5.0;
      if (parameter.key == "resample") value = 1;
      if (parameter.default_value < parameter.min_value) continue;  // the display, set by spec_of
      parameter.write(traced_spec.parameters, value);
      path.parameters[i].write(path_spec.parameters, value);
    }
    EXPECT_EQ(sampling_filter(traced_spec), sampling_filter(path_spec));
    for (const double gaze : {std::nan(""), 3.0, 40.0}) {
      const SamplingMap a = sampling_map(traced_spec, gaze, gaze), b = sampling_map(path_spec, gaze, gaze);
      EXPECT_EQ(model_of(a), model_of(b));
      EXPECT_EQ(shaded_samples(a), shaded_samples(b)) << path.name;
      EXPECT_EQ(density(a, 10.5, 20.5), density(b, 10.5, 20.5)) << path.name;
    }
  }
  // The path-traced models have no sphere-tracer settings; their frames are the pt sequence's.
  const StimulusSpec spec = spec_of(sampled_method(1, SamplingModel::kernel_log_polar));
  EXPECT_THROW(sphere_trace_settings(spec, 0), std::logic_error);
  const PathTracedFrames frames = path_traced_frames(spec);
  ASSERT_EQ(frames.sequences.size(), 1u);
  EXPECT_EQ(frames.sequences[0].samples_per_pixel, 128);
}

TEST(SamplingStimulus, ResampleChoiceReachesTheRenderer) {
  StimulusSpec spec = spec_of(sampled_method(0, SamplingModel::kernel_log_polar));
  std::get<KernelLogPolarModel>(std::get<SampledParameters>(spec.parameters).model).resample = ResampleFilter::lanczos2;
  EXPECT_EQ(sphere_trace_settings(spec, 0).sampling_filter, ResampleFilter::lanczos2);
}

TEST(SamplingStimulus, EqualiseAndItsFailureComeFromTheSpec) {
  StimulusSpec spec = spec_of(sampled_method(0, SamplingModel::linear));
  auto& linear = std::get<LinearFalloffModel>(std::get<SampledParameters>(spec.parameters).model);
  linear.equalise = EqualiseChoice::on_before_log_schema_8;  // a log's "on" before schema 8: the density
  linear.sigma = 1.05;  // this small display is mostly within 20 degrees: only a small sigma is reachable
  EXPECT_NEAR(mean_density(sampling_map(spec, 48, 27)), 1.0 / (1.05 * 1.05), 1e-9);
  // Solved at the centre and kept: a gaze in a corner samples with the same p_min (no flicker, and
  // no gaze can make it unsolvable mid-session).
  const double centre_p_min = std::get<LinearFalloff>(sampling_map(spec, 48, 27)).min_probability;
  EXPECT_EQ(std::get<LinearFalloff>(sampling_map(spec, 0, 0)).min_probability, centre_p_min);
  StimulusSpec layers_spec = spec_of(sampled_method(0, SamplingModel::hyperbolic));
  auto& layers = std::get<HyperbolicLayersModel>(std::get<SampledParameters>(layers_spec.parameters).model);
  layers.equalise = EqualiseChoice::density;
  layers.inner_radius_deg = 4;  // this small display lies within 20 degrees: smaller zones
  layers.outer_radius_deg = 8;
  layers.sigma = 2.2;
  const double centre_s3 =
      std::get<HyperbolicLayers>(sampling_map(layers_spec, std::nan(""), std::nan(""))).layers[2].pixel_size_px;
  EXPECT_EQ(std::get<HyperbolicLayers>(sampling_map(layers_spec, 96, 0)).layers[2].pixel_size_px, centre_s3);
  linear.sigma = 8.0;  // the full-resolution zone alone is denser than 1/64
  EXPECT_THROW(sampling_map(spec, 48, 27), InputError);
  StimulusSpec no_display = spec_of(sampled_method(0, SamplingModel::hyperbolic));
  *display_of(no_display.parameters) = StimulusDisplay{};
  EXPECT_THROW(sampling_map(no_display, 48, 27), InputError);
}

// equalise's names: "on" read now (or from a log of schema 8 or later) is "samples"; from a log of
// an earlier schema it is the choice "on", the density, whose name the stimuli keep; a name it
// does not have is refused with the names it has. KFR has equalise now, left out of its canonical
// text at "off" so its older stimuli keep theirs.
TEST(SamplingStimulus, EqualiseNamesByLogSchema) {
  for (SamplingModel model : {SamplingModel::hyperbolic, SamplingModel::linear, SamplingModel::kernel_log_polar})
    for (int source = 0; source < 2; ++source) {
      const ParameterDescriptor& equalise = parameter_named(sampled_method(source, model), "equalise");
      const std::string where = sampling_model_name(model);
      EXPECT_EQ(parse_choice(equalise, "off"), double(EqualiseChoice::off)) << where;
      EXPECT_EQ(parse_choice(equalise, "on"), double(EqualiseChoice::samples)) << where;
      EXPECT_EQ(parse_choice(equalise, "on", 8), double(EqualiseChoice::samples)) << where;
      EXPECT_EQ(parse_choice(equalise, "on", 7), double(EqualiseChoice::on_before_log_schema_8)) << where;
      EXPECT_EQ(parse_choice(equalise, "on", 1), double(EqualiseChoice::on_before_log_schema_8)) << where;
      EXPECT_EQ(parse_choice(equalise, "samples"), double(EqualiseChoice::samples)) << where;
      EXPECT_EQ(parse_choice(equalise, "density", 7), double(EqualiseChoice::density)) << where;
      EXPECT_FALSE(parse_choice(equalise, "bogus")) << where;
      EXPECT_EQ(check_parameter_value(equalise, -1), "one of \"off\", \"on\", \"samples\", \"density\"") << where;
      EXPECT_EQ(parameter_value_text(equalise, double(EqualiseChoice::on_before_log_schema_8)), "on") << where;
      EXPECT_EQ(parameter_value_text(equalise, double(EqualiseChoice::samples)), "samples") << where;
    }
  StimulusSpec kfr = spec_of(sampled_method(0, SamplingModel::kernel_log_polar));
  EXPECT_EQ(kfr.canonical().find("equalise"), std::string::npos) << kfr.canonical();
  std::get<KernelLogPolarModel>(std::get<SampledParameters>(kfr.parameters).model).equalise = EqualiseChoice::samples;
  EXPECT_NE(kfr.canonical().find(";equalise=samples;"), std::string::npos) << kfr.canonical();
  StimulusSpec layers = spec_of(sampled_method(0, SamplingModel::hyperbolic));
  auto& model = std::get<HyperbolicLayersModel>(std::get<SampledParameters>(layers.parameters).model);
  model.equalise = EqualiseChoice::on_before_log_schema_8;
  EXPECT_NE(layers.canonical().find(";equalise=on;"), std::string::npos) << layers.canonical();
  EXPECT_EQ(to_json(layers)["parameters"]["equalise"], "on");
}

// Each choice reaches the map: "on" of an earlier log and "density" solve the density, "samples"
// (today's "on") RMFR's shaded samples; KFR by its buffer's sigma.
TEST(SamplingStimulus, EqualiseChoicesReachTheMap) {
  StimulusSpec spec = spec_of(sampled_method(0, SamplingModel::hyperbolic));
  auto& layers = std::get<HyperbolicLayersModel>(std::get<SampledParameters>(spec.parameters).model);
  layers.inner_radius_deg = 4;  // this small display lies within 20 degrees: smaller zones
  layers.outer_radius_deg = 8;
  layers.sigma = 2.2;
  const auto s3 = [&](EqualiseChoice choice) {
    layers.equalise = choice;
    return std::get<HyperbolicLayers>(sampling_map(spec, std::nan(""), std::nan(""))).layers[2].pixel_size_px;
  };
  EXPECT_EQ(s3(EqualiseChoice::on_before_log_schema_8), s3(EqualiseChoice::density));
  EXPECT_NE(s3(EqualiseChoice::samples), s3(EqualiseChoice::density));
  layers.equalise = EqualiseChoice::samples;
  const double rmfr = double(rmfr_shaded_samples(spec.width_px, spec.height_px, 2.2));
  EXPECT_NEAR(double(shaded_samples(sampling_map(spec, std::nan(""), std::nan("")))) / rmfr, 1.0, 0.01);

  StimulusSpec kfr_spec = spec_of(sampled_method(1, SamplingModel::kernel_log_polar));
  auto& kfr = std::get<KernelLogPolarModel>(std::get<SampledParameters>(kfr_spec.parameters).model);
  kfr.equalise = EqualiseChoice::samples;
  const SamplingMap centre = sampling_map(kfr_spec, std::nan(""), std::nan(""));
  EXPECT_LT(std::get<KernelLogPolarMapping>(centre).sigma, kfr.sigma);
  // Kept for another gaze: the same buffer.
  const SamplingMap corner = sampling_map(kfr_spec, 0, 0);
  EXPECT_EQ(std::get<KernelLogPolarMapping>(corner).buffer_width_px,
            std::get<KernelLogPolarMapping>(centre).buffer_width_px);
  kfr.equalise = EqualiseChoice::density;  // KFR's buffer is RMFR's: as off
  EXPECT_EQ(std::get<KernelLogPolarMapping>(sampling_map(kfr_spec, 0, 0)).sigma, kfr.sigma);
}

}  // namespace
}  // namespace fovlab
