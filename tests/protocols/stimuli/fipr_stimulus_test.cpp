// FIPR as a study stimulus (study/stimulus/stimulus_spec.h, study/schedule/study_plan.cpp):
// its parameters (defaults, ranges, choices), their one-line config errors, the rule between fovea
// and outer periphery, the display the schedule fills in from [display], the settings handed to the
// renderer, and the shipped FIPR main study (experiments/fipr_main.toml).
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <regex>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "protocols/stimuli/stimulus_settings.h"
#include "core/input_error.h"
#include "study/config/study_config.h"
#include "tests/study/config/config_error_test_support.h"
#include "study/schedule/study_plan.h"
#include "study/stimulus/stimulus_spec.h"
#include "renderer/path_tracing/path_tracer.h"
#include "renderer/sphere_tracing/sphere_tracer.h"

namespace fovlab {
namespace {

const std::string kPath = "studies/fipr.toml";

// A small FIPR study; `test` and `variants` and `levels` are the parts the tests change.
struct FiprText {
  std::string display = R"([display]
width_px = 64
height_px = 48
refresh_hz = 60
width_mm = 400
height_mm = 300
viewing_distance_mm = 600
)";
  std::string test = "[stimulus.test]\nmethod = \"fipr\"\n";
  std::string variants;
  std::string levels = "[levels]\nparameter = \"fovea_radius_deg\"\nvalues = [2.5, 5, 7.5]\n";

  std::string text() const {
    return R"([study]
name = "fipr_unit"
seed = 3

)" + display +
           R"(
[stimulus]
duration_s = 0.1
frames_per_second = 20

[stimulus.reference]
method = "gt"

)" + test + "\n" +
           variants + "\n" + levels + R"(
[protocol]
kind = "2afc"
question = "same"
repeats = 2

[[block]]
scene = "primitives"
)";
  }
};

StudyConfig parse(const std::string& text) { return parse_study_config_text(text, kPath, renderer_scene_catalog()); }

using test::line_of;

// The error must be one line "studies/fipr.toml:LINE: KEY: ..." containing `fragment`.
void expect_error(const std::string& text, int line, const std::string& key, const std::string& fragment) {
  test::expect_config_error(text, kPath, line, key, fragment);
}

const ParameterDescriptor& parameter_named(const MethodDescriptor& method, const std::string& key) {
  const ParameterDescriptor* parameter = find_parameter(method, key);
  if (!parameter) throw std::logic_error("no parameter " + key);
  return *parameter;
}

// A FIPR spec of 64 x 48 pixels at every default.
StimulusSpec default_fipr_spec() {
  StimulusSpec spec;
  spec.scene = "primitives";
  spec.parameters = default_parameters(RenderMethod::foveated_pyramid);
  spec.width_px = 64;
  spec.height_px = 48;
  return spec;
}

// --- the method -------------------------------------------------------------------------------------

TEST(FiprStimulus, IsAKnownGazeDependentMethod) {
  EXPECT_NE(known_methods().find("fipr"), std::string::npos);
  ASSERT_EQ(find_method("fipr"), RenderMethod::foveated_pyramid);
  EXPECT_TRUE(describe(RenderMethod::foveated_pyramid).depends_on_gaze);
  EXPECT_TRUE(describe(RenderMethod::foveated_pyramid).needs_display);
  EXPECT_FALSE(describe(RenderMethod::ground_truth).depends_on_gaze);
  EXPECT_FALSE(describe(RenderMethod::inverted_pyramid).depends_on_gaze);
  EXPECT_FALSE(find_method("FIPR"));
}

TEST(FiprStimulus, ParametersDefaultsRangesAndChoices) {
  const MethodDescriptor& parameters = describe(RenderMethod::foveated_pyramid);
  std::set<std::string> names;
  for (const ParameterDescriptor& parameter : parameters.parameters) names.insert(std::string(parameter.key));
  EXPECT_EQ(names, (std::set<std::string>{"samples_per_pixel",
                                          "max_steps",
                                          "hit_threshold",
                                          "pyramid_levels",
                                          "min_filter_size",
                                          "coarse_test",
                                          "fovea_radius_deg",
                                          "outer_periphery_radius_deg",
                                          "periphery_refresh",
                                          "periphery_steps",
                                          "periphery_reconstruction",
                                          "near_misses",
                                          "blur",
                                          "combine",
                                          "edge_threshold",
                                          "edge_depth",
                                          "mask_seed",
                                          "display_width_mm",
                                          "display_height_mm",
                                          "viewing_distance_mm"}));
  const auto& levels = parameter_named(parameters, "pyramid_levels");
  EXPECT_EQ(levels.default_value, 3);
  EXPECT_EQ(levels.min_value, 3);  // low, mid and top
  EXPECT_EQ(levels.max_value, 5);
  EXPECT_EQ(parameter_named(parameters, "samples_per_pixel").allowed, (std::vector<double>{1, 4, 16}));
  EXPECT_EQ(parameter_named(parameters, "min_filter_size").allowed, (std::vector<double>{1, 3, 5}));
  EXPECT_EQ(parameter_named(parameters, "fovea_radius_deg").default_value, 7.5);
  EXPECT_EQ(parameter_named(parameters, "fovea_radius_deg").max_value, 180);
  EXPECT_EQ(parameter_named(parameters, "fovea_radius_deg").unit, "deg");
  EXPECT_EQ(parameter_named(parameters, "fovea_radius_deg").legacy_key, "fovea_deg");
  EXPECT_EQ(parameter_named(parameters, "outer_periphery_radius_deg").default_value, 180);
  EXPECT_EQ(parameter_named(parameters, "periphery_refresh").allowed, (std::vector<double>{1, 2, 4}));
  EXPECT_EQ(parameter_named(parameters, "periphery_steps").default_value, FoveationSettings{}.periphery_steps);
  EXPECT_EQ(parameter_named(parameters, "periphery_steps").min_value, 0);  // 0: the mid level's colour
  const auto& reconstruction = parameter_named(parameters, "periphery_reconstruction");
  EXPECT_EQ(reconstruction.choices,
            (std::vector<std::string_view>{"mid-footprint-bilinear", "bilinear", "catmull-rom"}));
  EXPECT_EQ(reconstruction.default_value, 1);  // bilinear, the renderer's default too
  EXPECT_EQ(FoveationSettings{}.reconstruction, PeripheryReconstruction::bilinear);
  EXPECT_EQ(reconstruction.default_since_log_schema, 5);
  EXPECT_EQ(reconstruction.earlier_default, 0);  // mid-footprint-bilinear in logs of schema 1-4
  // The config's words are the renderer's, in the same order.
  for (size_t i = 0; i < reconstruction.choices.size(); ++i)
    EXPECT_EQ(parse_periphery_reconstruction(std::string(reconstruction.choices[i])),
              static_cast<PeripheryReconstruction>(i));
  EXPECT_TRUE(reconstruction.omitted_at_default);
  const auto& near_misses = parameter_named(parameters, "near_misses");
  EXPECT_EQ(near_misses.choices, (std::vector<std::string_view>{"ignore", "promote"}));
  EXPECT_EQ(near_misses.default_value, 1);  // promote, the renderer's default too
  EXPECT_EQ(FoveationSettings{}.near_misses, NearMisses::promote);
  EXPECT_EQ(near_misses.default_since_log_schema, 6);
  EXPECT_EQ(near_misses.earlier_default, 0);  // ignore in logs of schema 1-5
  for (size_t i = 0; i < near_misses.choices.size(); ++i)
    EXPECT_EQ(parse_near_misses(std::string(near_misses.choices[i])), static_cast<NearMisses>(i));
  EXPECT_TRUE(near_misses.omitted_at_default);
  EXPECT_EQ(parameter_named(parameters, "blur").choices, (std::vector<std::string_view>{"off", "on"}));
  EXPECT_EQ(parameter_named(parameters, "combine").choices,
            (std::vector<std::string_view>{"max", "fovea-or-product", "product", "acuity"}));
  EXPECT_EQ(parameter_named(parameters, "edge_threshold").default_value, 0.4);
  EXPECT_GT(parameter_named(parameters, "edge_threshold").min_value, 0.0);
  EXPECT_EQ(parameter_named(parameters, "mask_seed").type, ParameterType::integer);
  EXPECT_EQ(parameter_named(parameters, "mask_seed").max_value, 4294967295.0);
  for (const char* display : {"display_width_mm", "display_height_mm", "viewing_distance_mm"})
    EXPECT_EQ(parameter_named(parameters, display).default_value, 0) << display << ": 0 means from [display]";
  EXPECT_EQ(parameter_named(parameters, "coarse_test").choices, (std::vector<std::string_view>{"ray", "cone"}));
  EXPECT_TRUE(parameter_named(parameters, "coarse_test").omitted_at_default);
  // The cone since log schema 10 (IPR's and FIPR's), ray in logs of schema 1-9; the min filter 1
  // since (the cone makes it redundant), 3 before.
  for (const RenderMethod method : {RenderMethod::inverted_pyramid, RenderMethod::foveated_pyramid}) {
    const ParameterDescriptor& coarse_test = parameter_named(describe(method), "coarse_test");
    EXPECT_EQ(coarse_test.default_value, 1);
    EXPECT_EQ(coarse_test.default_since_log_schema, 10);
    EXPECT_EQ(coarse_test.earlier_default, 0);
    const ParameterDescriptor& min_filter = parameter_named(describe(method), "min_filter_size");
    EXPECT_EQ(min_filter.default_value, 1);
    EXPECT_EQ(min_filter.default_since_log_schema, 10);
    EXPECT_EQ(min_filter.earlier_default, 3);
  }
  const auto& edge_depth = parameter_named(parameters, "edge_depth");
  EXPECT_EQ(edge_depth.choices, (std::vector<std::string_view>{"level", "centre-ray"}));
  EXPECT_EQ(edge_depth.default_value, 1);  // centre-ray, the renderer's default too
  EXPECT_EQ(FoveationSettings{}.edge_depth, EdgeDepth::centre_ray);
  EXPECT_EQ(edge_depth.default_since_log_schema, 10);
  EXPECT_EQ(edge_depth.earlier_default, 0);  // level in logs of schema 1-9
  for (size_t i = 0; i < edge_depth.choices.size(); ++i)
    EXPECT_EQ(parse_edge_depth(std::string(edge_depth.choices[i])), static_cast<EdgeDepth>(i));
  EXPECT_TRUE(edge_depth.omitted_at_default);
  // IPR's parameters are FIPR's first six, and the full-resolution depth level (IPR's alone).
  for (const ParameterDescriptor& parameter : describe(RenderMethod::inverted_pyramid).parameters)
    EXPECT_EQ(names.count(std::string(parameter.key)), parameter.key == "full_resolution_depth" ? 0u : 1u);
  EXPECT_EQ(describe(RenderMethod::inverted_pyramid).parameters.size(), 7u);
}

// One default per setting: a FIPR spec at its descriptor's defaults gives the renderer's own
// defaults (SphereTraceSettings{}), which the command line's flags start from too, but for the
// pyramid's min filter and coarse test (below).
TEST(FiprStimulus, DescriptorDefaultsAreTheRenderersDefaults) {
  StimulusSpec spec = default_fipr_spec();
  std::get<FoveatedPyramidParameters>(spec.parameters).display = {400, 300, 600};
  const SphereTraceSettings from_spec = sphere_trace_settings(spec, 0);
  const SphereTraceSettings renderer;
  EXPECT_EQ(from_spec.samples_per_pixel, renderer.samples_per_pixel);
  EXPECT_EQ(from_spec.max_steps, renderer.max_steps);
  EXPECT_EQ(from_spec.hit_threshold, renderer.hit_threshold);
  EXPECT_EQ(from_spec.pyramid_levels, renderer.pyramid_levels);
  // The pyramid is the method's (the cone without the min filter since log schema 10); the
  // renderer's own settings stay the paper's pyramid, and the command line applies the method's
  // defaults to them (app/cli_support.h with_method_pyramid_defaults).
  EXPECT_EQ(from_spec.min_filter_size, 1);
  EXPECT_EQ(from_spec.coarse_test, CoarseTest::cone);
  const FoveationSettings& f = from_spec.foveation;
  const FoveationSettings& r = renderer.foveation;
  EXPECT_EQ(f.acuity.fovea_radius_deg, r.acuity.fovea_radius_deg);
  EXPECT_EQ(f.acuity.outer_periphery_radius_deg, r.acuity.outer_periphery_radius_deg);
  EXPECT_EQ(f.combine, r.combine);
  EXPECT_EQ(f.edge_threshold, r.edge_threshold);
  EXPECT_EQ(f.periphery_refresh, r.periphery_refresh);
  EXPECT_EQ(f.periphery_steps, r.periphery_steps);
  EXPECT_EQ(f.blur, r.blur);
  EXPECT_EQ(f.seed, r.seed);
  EXPECT_EQ(f.reconstruction, r.reconstruction);
  // Each of the config's choices reaches the renderer as the same-named reconstruction.
  auto& fipr = std::get<FoveatedPyramidParameters>(spec.parameters);
  for (const PeripheryReconstruction choice :
       {PeripheryReconstruction::mid_footprint_bilinear, PeripheryReconstruction::bilinear,
        PeripheryReconstruction::catmull_rom}) {
    fipr.periphery_reconstruction = choice;
    const std::string name = to_json(spec)["parameters"].value("periphery_reconstruction", "mid-footprint-bilinear");
    EXPECT_EQ(periphery_reconstruction_name(sphere_trace_settings(spec, 0).foveation.reconstruction), name);
  }
  EXPECT_EQ(f.near_misses, r.near_misses);
  for (const NearMisses choice : {NearMisses::ignore, NearMisses::promote}) {
    fipr.near_misses = choice;
    const std::string name = to_json(spec)["parameters"].value("near_misses", "ignore");
    EXPECT_EQ(near_misses_name(sphere_trace_settings(spec, 0).foveation.near_misses), name);
  }
  EXPECT_EQ(f.edge_depth, r.edge_depth);
  for (const EdgeDepth choice : kEdgeDepths) {
    fipr.edge_depth = choice;
    const std::string name = to_json(spec)["parameters"].value("edge_depth", "level");
    EXPECT_EQ(edge_depth_name(sphere_trace_settings(spec, 0).foveation.edge_depth), name);
  }
}

TEST(FiprStimulus, SettingsForTheRenderer) {
  StimulusSpec spec = default_fipr_spec();
  spec.frame_count = 3;
  spec.frames_per_second = 20;
  spec.camera_start_s = 1.0;
  // Without its display a FIPR spec cannot be rendered (the schedule always fills it in).
  EXPECT_THROW(sphere_trace_settings(spec, 0), InputError);

  auto& fipr = std::get<FoveatedPyramidParameters>(spec.parameters);
  fipr.display = {400, 300, 600};
  SphereTraceSettings settings = sphere_trace_settings(spec, 2);
  EXPECT_EQ(settings.method, TraceMethod::foveated_pyramid);
  EXPECT_EQ(settings.width, 64);
  EXPECT_EQ(settings.height, 48);
  EXPECT_FLOAT_EQ(settings.time_s, 1.1f);
  EXPECT_EQ(settings.pyramid_levels, 3);
  const FoveationSettings& f = settings.foveation;
  EXPECT_EQ(f.display.width_px, 64);
  EXPECT_EQ(f.display.height_px, 48);
  EXPECT_EQ(f.display.width_mm, 400);
  EXPECT_EQ(f.display.height_mm, 300);
  EXPECT_EQ(f.display.viewing_distance_mm, 600);
  EXPECT_FALSE(std::isfinite(f.gaze_x_px));  // the library sets the gaze
  EXPECT_EQ(f.frame_index, 0u);
  EXPECT_EQ(f.acuity.fovea_radius_deg, 7.5);
  EXPECT_EQ(f.acuity.outer_periphery_radius_deg, std::numeric_limits<double>::infinity());  // 180: none
  EXPECT_EQ(f.periphery_refresh, 1);
  EXPECT_EQ(f.periphery_steps, FoveationSettings{}.periphery_steps);
  EXPECT_FALSE(f.blur);
  EXPECT_EQ(f.combine, MaskCombine::max);
  EXPECT_FLOAT_EQ(f.edge_threshold, 0.4f);
  EXPECT_EQ(f.seed, 0u);
  EXPECT_EQ(settings.coarse_test, CoarseTest::cone);
  EXPECT_NO_THROW(validate(settings));

  fipr.coarse_test = CoarseTest::centre_ray;
  fipr.fovea_radius_deg = 12.5;
  fipr.outer_periphery_radius_deg = 40;
  fipr.periphery_refresh = 4;
  fipr.periphery_steps = 0;
  fipr.blur = true;
  fipr.combine = MaskCombine::product;
  fipr.edge_threshold = 0.1;
  fipr.mask_seed = 4294967295u;
  settings = sphere_trace_settings(spec, 0);
  EXPECT_EQ(settings.foveation.acuity.fovea_radius_deg, 12.5);
  EXPECT_EQ(settings.foveation.acuity.outer_periphery_radius_deg, 40);
  EXPECT_EQ(settings.foveation.periphery_refresh, 4);
  EXPECT_EQ(settings.foveation.periphery_steps, 0);
  EXPECT_TRUE(settings.foveation.blur);
  EXPECT_EQ(settings.foveation.combine, MaskCombine::product);
  EXPECT_FLOAT_EQ(settings.foveation.edge_threshold, 0.1f);
  EXPECT_EQ(settings.foveation.seed, 4294967295u);
  EXPECT_EQ(settings.coarse_test, CoarseTest::centre_ray);
  EXPECT_NO_THROW(validate(settings));
}

TEST(FiprStimulus, OuterPeripheryRule) {
  MethodParameters parameters = default_parameters(RenderMethod::foveated_pyramid);
  EXPECT_FALSE(parameter_conflict(parameters));
  std::get<FoveatedPyramidParameters>(parameters).outer_periphery_radius_deg = 7.5;  // equal: allowed
  EXPECT_FALSE(parameter_conflict(parameters));
  std::get<FoveatedPyramidParameters>(parameters).outer_periphery_radius_deg = 5;
  const auto conflict = parameter_conflict(parameters);
  ASSERT_TRUE(conflict);
  EXPECT_NE(conflict->expected.find("outer_periphery_radius_deg (5) >= fovea_radius_deg (7.5)"), std::string::npos)
      << conflict->expected;
  EXPECT_FALSE(parameter_conflict(default_parameters(RenderMethod::ground_truth)));
}

// The renderer's enumeration and frame rules are the descriptors': a change on one side fails here.
TEST(FiprStimulus, DescriptorsAgreeWithTheRenderer) {
  const ParameterDescriptor& combine = parameter_named(describe(RenderMethod::foveated_pyramid), "combine");
  for (size_t i = 0; i < combine.choices.size(); ++i)
    EXPECT_EQ(combine.choices[i], mask_combine_name(static_cast<MaskCombine>(i)));
  for (RenderMethod method :
       {RenderMethod::ground_truth, RenderMethod::inverted_pyramid, RenderMethod::foveated_pyramid})
    EXPECT_EQ(describe(method).max_samples_per_frame, kMaxSphereTraceSamplesPerFrame);
  // The defaults the renderer's own settings start from are the descriptors' (the CLI's render
  // command and the benchmarks construct those settings directly).
  const SphereTraceSettings trace;
  const MethodDescriptor& fipr = describe(RenderMethod::foveated_pyramid);
  EXPECT_EQ(parameter_named(fipr, "max_steps").default_value, trace.max_steps);
  EXPECT_EQ(parameter_named(fipr, "samples_per_pixel").default_value, trace.samples_per_pixel);
  EXPECT_FLOAT_EQ(float(parameter_named(fipr, "hit_threshold").default_value), trace.hit_threshold);
  EXPECT_EQ(parameter_named(fipr, "pyramid_levels").default_value, trace.pyramid_levels);
  // The pyramid's min filter and coarse test: the renderer's own settings are the paper's pyramid (3x3,
  // ray); a method's defaults (the cone, 1x1 since log schema 10) reach it through its spec
  // (sphere_trace_settings) and the command line's with_method_pyramid_defaults.
  EXPECT_EQ(parameter_named(fipr, "min_filter_size").earlier_default, trace.min_filter_size);
  EXPECT_EQ(parameter_named(fipr, "coarse_test").earlier_default, double(static_cast<uint32_t>(trace.coarse_test)));
  EXPECT_FLOAT_EQ(float(parameter_named(fipr, "edge_threshold").default_value), trace.foveation.edge_threshold);
  const PathTraceSettings paths;
  const MethodDescriptor& fpt = describe(RenderMethod::foveated_path_traced);
  EXPECT_EQ(parameter_named(fpt, "samples_per_pixel").default_value, paths.samples_per_pixel);
  EXPECT_EQ(parameter_named(fpt, "max_bounces").default_value, paths.max_bounces);
  EXPECT_EQ(parameter_named(fpt, "path_seed").default_value, paths.seed);
  const ZoneBounds zones;
  EXPECT_EQ(parameter_named(fpt, "foveal_aperture_deg").default_value, zones.foveal_deg);
  EXPECT_EQ(parameter_named(fpt, "middle_minus_foveal_aperture_deg").default_value,
            zones.middle_deg - zones.foveal_deg);
  EXPECT_EQ(parameter_named(fpt, "band_width_deg").default_value, zones.band_deg);
}

// --- configs ----------------------------------------------------------------------------------------

TEST(FiprStimulus, ConfigWithEveryParameter) {
  FiprText base;
  base.test = R"([stimulus.test]
method = "fipr"
samples_per_pixel = 4
max_steps = 128
hit_threshold = 0.5
pyramid_levels = 4
min_filter_size = 5
outer_periphery_radius_deg = 40
periphery_refresh = 2
periphery_steps = 16
blur = "on"
combine = "acuity"
edge_threshold = 0.25
mask_seed = 77
display_width_mm = 200
display_height_mm = 150
viewing_distance_mm = 300
)";
  const StudyConfig config = parse(base.text());
  EXPECT_EQ(describe(config.stimulus.test.method).name, "fipr");
  EXPECT_EQ(config.stimulus.test.parameters.size(), 15u);
  EXPECT_EQ(config.stimulus.test.parameters.at("mask_seed"), 77);
  EXPECT_EQ(config.stimulus.test.parameters.at("combine"), 3);  // its index
  const auto typed = std::get<FoveatedPyramidParameters>(
      parameters_with(config.stimulus.test.method, {&config.stimulus.test.parameters}));
  EXPECT_EQ(typed.combine, MaskCombine::acuity);
  EXPECT_TRUE(typed.blur);
  EXPECT_EQ(typed.outer_periphery_radius_deg, 40);
}

TEST(FiprStimulus, BadValuesAreOneLineErrorsNamingTheField) {
  const struct {
    std::string line;
    std::string fragment;
  } cases[] = {
      {"fovea_radius_deg = 200", "expected a value in [0, 180], got 200"},
      {"fovea_radius_deg = -1", "expected a value in [0, 180]"},
      {"outer_periphery_radius_deg = 181", "expected a value in [0, 180]"},
      {"pyramid_levels = 2", "expected a value in [3, 5], got 2"},
      {"min_filter_size = 2", "expected one of 1 3 5, got 2"},
      {"samples_per_pixel = 2", "expected one of 1 4 16, got 2"},
      {"periphery_refresh = 3", "expected one of 1 2 4, got 3"},
      {"periphery_steps = -1", "expected a value in [0, 4096], got -1"},
      {"periphery_steps = 2.5", "whole number"},
      {"blur = 1", "expected one of \"off\", \"on\" (a name), got 1"},
      {"blur = \"yes\"", "expected one of \"off\", \"on\", got \"yes\""},
      {"combine = 3", "(a name), got 3"},
      {"combine = \"min\"", "expected one of \"max\", \"fovea-or-product\", \"product\", \"acuity\", got \"min\""},
      {"fovea_deg = 5", "not a parameter of method \"fipr\""},
      {"edge_threshold = 0", "expected a value in"},
      {"mask_seed = 1.5", "whole number"},
      {"mask_seed = 4294967296", "expected a value in"},
      {"display_width_mm = 0", "expected a value in [1, "},
      {"viewing_distance_mm = -500", "expected a value in [1, "},
      {"hit_threshold = 9", "expected a value in [0.0001, 8]"},
      {"fovea = 5", "not a parameter of method \"fipr\""},
  };
  for (const auto& c : cases) {
    FiprText base;
    base.test += c.line + "\n";
    const std::string text = base.text();
    const std::string key = c.line.substr(0, c.line.find(' '));
    expect_error(text, line_of(text, c.line), "stimulus.test." + key, c.fragment);
  }
  // Levels are checked against the parameter's range too.
  FiprText base;
  base.levels = "[levels]\nparameter = \"fovea_radius_deg\"\nvalues = [2.5, 190]\n";
  std::string text = base.text();
  expect_error(text, line_of(text, "values = [2.5, 190]"), "levels.values", "got 190");
  // A FIPR parameter on an IPR test is not a parameter of that method.
  base = FiprText{};
  base.test = "[stimulus.test]\nmethod = \"ipr\"\nfovea_radius_deg = 5\n";
  base.levels.clear();
  text = base.text();
  expect_error(text, line_of(text, "fovea_radius_deg = 5"), "stimulus.test.fovea_radius_deg",
               "not a parameter of method \"ipr\"");
  // A choice parameter cannot be the levels' (levels are ordered numbers).
  base = FiprText{};
  base.levels = "[levels]\nparameter = \"combine\"\nvalues = [0, 1]\n";
  text = base.text();
  expect_error(text, line_of(text, "parameter = \"combine\""), "levels.parameter", "not a numeric parameter");
}

TEST(FiprStimulus, OuterPeripheryInsideTheFoveaNamesTheFieldThatSetIt) {
  // In the test table, against the default fovea.
  FiprText base;
  base.levels.clear();
  base.test += "outer_periphery_radius_deg = 5\n";
  std::string text = base.text();
  expect_error(text, line_of(text, "outer_periphery_radius_deg = 5"), "stimulus.test.outer_periphery_radius_deg",
               "expected outer_periphery_radius_deg (5) >= fovea_radius_deg (7.5)");

  // A level value beyond the test's outer periphery: the levels are named.
  base = FiprText{};
  base.test += "outer_periphery_radius_deg = 6\n";
  text = base.text();
  expect_error(text, line_of(text, "values = [2.5, 5, 7.5]"), "levels.values",
               "value 7.5: expected outer_periphery_radius_deg (6)");

  // A variant's outer periphery inside a level's fovea: the level is what moved last.
  base = FiprText{};
  base.variants = "[[stimulus.variant]]\nname = \"near\"\nouter_periphery_radius_deg = 3\n";
  text = base.text();
  expect_error(text, line_of(text, "values = [2.5, 5, 7.5]"), "levels.values", "value 5:");

  // Without levels, the variant that set it.
  base = FiprText{};
  base.levels.clear();
  base.variants =
      "[[stimulus.variant]]\nname = \"wide\"\n\n[[stimulus.variant]]\nname = \"near\"\nouter_periphery_radius_deg = "
      "3\n";
  text = base.text();
  expect_error(text, line_of(text, "outer_periphery_radius_deg = 3"), "stimulus.variant[2].outer_periphery_radius_deg",
               "expected outer_periphery_radius_deg (3) >= fovea_radius_deg (7.5)");

  // The reference may be FIPR too.
  text = FiprText{}.text();
  const std::string gt_reference = "[stimulus.reference]\nmethod = \"gt\"\n";
  text.replace(text.find(gt_reference), gt_reference.size(),
               "[stimulus.reference]\nmethod = \"fipr\"\nouter_periphery_radius_deg = 10\nfovea_radius_deg = 20\n");
  expect_error(text, line_of(text, "fovea_radius_deg = 20"), "stimulus.reference.fovea_radius_deg",
               "outer_periphery_radius_deg (10)");
}

// --- the schedule -----------------------------------------------------------------------------------

TEST(FiprStimulus, TheScheduleFillsTheDisplayFromTheConfig) {
  const StudyPlan plan = make_study_plan(parse(FiprText{}.text()), "P1");
  int fipr = 0;
  for (const PlannedStimulus& stimulus : plan.stimuli) {
    if (stimulus.spec.method() != RenderMethod::foveated_pyramid) {
      EXPECT_FALSE(parameter_value(stimulus.spec.parameters, "display_width_mm"));  // GT has no display parameters
      continue;
    }
    ++fipr;
    EXPECT_EQ(*parameter_value(stimulus.spec.parameters, "display_width_mm"), 400);
    EXPECT_EQ(*parameter_value(stimulus.spec.parameters, "display_height_mm"), 300);
    EXPECT_EQ(*parameter_value(stimulus.spec.parameters, "viewing_distance_mm"), 600);
    EXPECT_NE(stimulus.spec.canonical().find("display_width_mm=400"), std::string::npos);
    EXPECT_EQ(*parameter_value(stimulus.spec.parameters, "fovea_radius_deg"), *stimulus.level);
    const SphereTraceSettings settings = sphere_trace_settings(stimulus.spec, 0);
    EXPECT_NO_THROW(validate(settings));
    EXPECT_EQ(settings.foveation.display.width_mm, 400);
  }
  EXPECT_EQ(fipr, 3);

  // A display given as a diagonal: its computed size.
  FiprText diagonal;
  diagonal.display = "[display]\nwidth_px = 64\nheight_px = 48\ndiagonal_in = 20\nviewing_distance_mm = 700\n";
  const StudyConfig config = parse(diagonal.text());
  const StudyPlan from_diagonal = make_study_plan(config, "P1");
  const StimulusSpec& spec = from_diagonal.stimuli.at(1).spec;
  ASSERT_EQ(spec.method(), RenderMethod::foveated_pyramid);
  const StimulusDisplay& shown = std::get<FoveatedPyramidParameters>(spec.parameters).display;
  EXPECT_DOUBLE_EQ(shown.display_width_mm, 20 * 25.4 * 0.8);  // 4:3
  EXPECT_DOUBLE_EQ(shown.display_height_mm, 20 * 25.4 * 0.6);
  EXPECT_EQ(shown.viewing_distance_mm, 700);
  EXPECT_DOUBLE_EQ(shown.display_width_mm, config.display.width_mm);
}

TEST(FiprStimulus, ADisplayTheConfigSetsIsKeptAndMakesAnotherStimulus) {
  FiprText base;
  base.test += "viewing_distance_mm = 450\n";
  base.variants =
      "[[stimulus.variant]]\nname = \"here\"\n\n[[stimulus.variant]]\nname = \"small\"\n"
      "display_width_mm = 200\ndisplay_height_mm = 150\n";
  const StudyPlan plan = make_study_plan(parse(base.text()), "P1");
  std::set<std::string> canonical;
  int fipr = 0;
  for (const PlannedStimulus& stimulus : plan.stimuli) {
    canonical.insert(stimulus.spec.canonical());
    if (stimulus.spec.method() != RenderMethod::foveated_pyramid) continue;
    ++fipr;
    EXPECT_EQ(*parameter_value(stimulus.spec.parameters, "viewing_distance_mm"), 450);
    const bool small = stimulus.variant == "small";
    EXPECT_EQ(*parameter_value(stimulus.spec.parameters, "display_width_mm"), small ? 200 : 400) << stimulus.variant;
    EXPECT_EQ(*parameter_value(stimulus.spec.parameters, "display_height_mm"), small ? 150 : 300) << stimulus.variant;
  }
  EXPECT_EQ(fipr, 6);                                // 2 variants x 3 levels
  EXPECT_EQ(canonical.size(), plan.stimuli.size());  // the display tells them apart

  // Levels may set a display parameter too (e.g. a viewing distance as the study's variable).
  base = FiprText{};
  base.levels = "[levels]\nparameter = \"viewing_distance_mm\"\nvalues = [300, 900]\n";
  const StudyPlan by_distance = make_study_plan(parse(base.text()), "P1");
  std::set<double> distances;
  for (const PlannedStimulus& stimulus : by_distance.stimuli)
    if (stimulus.spec.method() == RenderMethod::foveated_pyramid)
      distances.insert(*parameter_value(stimulus.spec.parameters, "viewing_distance_mm"));
  EXPECT_EQ(distances, (std::set<double>{300, 900}));
}

TEST(FiprStimulus, TheShippedMainStudy) {
  const std::string path = std::string(FOVLAB_SOURCE_DIR) + "/experiments/fipr_main.toml";
  const StudyConfig config = parse_study_config_file(path, renderer_scene_catalog());
  EXPECT_EQ(config.name, "fipr_main");
  EXPECT_EQ(config.protocol.kind, ProtocolKind::two_afc);
  EXPECT_EQ(config.protocol.two_afc_question, TwoAfcQuestion::same);
  EXPECT_EQ(describe(config.stimulus.reference.method).name, "gt");
  EXPECT_EQ(describe(config.stimulus.test.method).name, "fipr");
  EXPECT_EQ(config.levels.parameter, "fovea_radius_deg");
  EXPECT_EQ(config.levels.values, (std::vector<double>{2.5, 5, 7.5, 10, 12.5, 15}));
  EXPECT_EQ(config.attention.share, 0.0);
  const StudyPlan plan = make_study_plan(config, "P01");
  ASSERT_EQ(plan.blocks.size(), 3u);
  std::set<std::string> scenes;
  for (const PlannedBlock& block : plan.blocks) {
    scenes.insert(block.scene);
    EXPECT_EQ(block.trial_count, 72) << block.name;  // 6 levels x 2 variants x 6 repeats
  }
  EXPECT_EQ(scenes, (std::set<std::string>{"primitives", "columns", "temple"}));
  EXPECT_EQ(plan.trials.size(), 216u);
  std::map<std::string, int> per_condition, reference_first;
  std::set<double> blur;
  for (const Trial& trial : plan.trials) {
    ++per_condition[plan.blocks[size_t(trial.block)].name + "/" + trial.condition];
    reference_first[plan.blocks[size_t(trial.block)].name + "/" + trial.condition] += trial.reference_first ? 1 : 0;
    for (int id : trial.sequence) {
      const StimulusSpec& spec = plan.stimuli[size_t(id)].spec;
      if (spec.method() == RenderMethod::foveated_pyramid) blur.insert(*parameter_value(spec.parameters, "blur"));
    }
  }
  EXPECT_EQ(per_condition.size(), 36u);  // 3 scenes x 2 variants x 6 levels
  for (const auto& [condition, count] : per_condition) {
    EXPECT_EQ(count, 6) << condition;
    EXPECT_EQ(reference_first.at(condition), 3) << condition;
  }
  EXPECT_EQ(blur, (std::set<double>{0, 1}));
  EXPECT_EQ(plan.stimuli.size(), 3u + 36u);
}

}  // namespace
}  // namespace fovlab
