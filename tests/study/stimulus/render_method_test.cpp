// The method descriptors (study/stimulus/render_method.h): every parameter binds to its own member,
// defaults are the descriptors', choices travel by name, configs of the previous schema still read
// when a log carries them, and docs/config.md's table is the one they make.
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/input_error.h"
#include "study/config/study_config.h"
#include "study/stimulus/render_method.h"
#include "study/stimulus/stimulus_spec.h"

namespace fovlab {
namespace {

const SceneCatalog kScenes{{"primitives"}, {"courtyard"}, ".obj", false};

// A sampling model is a SamplingModel on each source: one entry in core/render_choices.h makes
// both of its methods, named after it, each in its place in all_methods().
TEST(RenderMethod, EverySamplingModelIsAMethodOnEachSource) {
  size_t sampling_methods = 0;
  for (size_t index = 0; index < all_methods().size(); ++index) {
    const MethodDescriptor& method = all_methods()[index];
    EXPECT_EQ(method_index(method.method), index) << method.name;
    sampling_methods += is_sampling_model(method.method);
  }
  EXPECT_EQ(sampling_methods, std::size(kSamplingKinds) * kSamplingModelCount);
  for (size_t model = 0; model < kSamplingModelCount; ++model) {
    const auto sampling_model = static_cast<SamplingModel>(model);
    const std::string name = sampling_model_name(sampling_model);
    EXPECT_EQ(find_method(name), sampled_method(0, sampling_model)) << name;
    EXPECT_EQ(find_method("pt-" + name), sampled_method(1, sampling_model)) << name;
    EXPECT_EQ(describe(sampled_method(0, sampling_model)).scene_kind, SceneKind::signed_distance) << name;
    EXPECT_EQ(describe(sampled_method(1, sampling_model)).scene_kind, SceneKind::path_traced) << name;
    EXPECT_NE(sampled_method(0, sampling_model), sampled_method(1, sampling_model));
    EXPECT_EQ(find_method("img-" + name), sampled_method(2, sampling_model)) << name;
    EXPECT_EQ(describe(sampled_method(2, sampling_model)).scene_kind, SceneKind::image_sequence) << name;
    EXPECT_EQ(method_of(default_parameters(sampled_method(2, sampling_model))), sampled_method(2, sampling_model));
  }
}

TEST(RenderMethod, EveryParameterReadsBackWhatItWrote) {
  for (const MethodDescriptor& method : all_methods()) {
    SCOPED_TRACE(std::string(method.name));
    EXPECT_EQ(find_method(method.name), method.method);
    std::set<std::string_view> keys;
    MethodParameters parameters = default_parameters(method.method);
    ASSERT_EQ(method_of(parameters), method.method);
    for (const ParameterDescriptor& parameter : method.parameters) {
      EXPECT_TRUE(keys.insert(parameter.key).second) << "duplicate key " << parameter.key;
      EXPECT_EQ(parameter.read(parameters), parameter.default_value) << parameter.key;
    }
    // Each parameter set to a value of its own (the top of its range, or its last choice) changes
    // that parameter alone: no two keys share a member.
    for (const ParameterDescriptor& parameter : method.parameters) {
      const double value = !parameter.allowed.empty()                ? parameter.allowed.back()
                           : parameter.type == ParameterType::choice ? double(parameter.choices.size() - 1)
                                                                     : parameter.max_value;
      MethodParameters changed = default_parameters(method.method);
      parameter.write(changed, value);
      EXPECT_EQ(parameter.read(changed), value) << parameter.key;
      EXPECT_FALSE(check_parameter_value(parameter, value)) << parameter.key;
      for (const ParameterDescriptor& other : method.parameters) {
        if (&other == &parameter || other.default_value == value) continue;
        EXPECT_EQ(other.read(changed), other.default_value) << parameter.key << " moved " << other.key;
      }
    }
  }
}

TEST(RenderMethod, ChoicesTravelByNameInTheCanonicalTextAndJson) {
  StimulusSpec spec;
  spec.scene = "primitives";
  spec.parameters = default_parameters(RenderMethod::foveated_pyramid);
  std::get<FoveatedPyramidParameters>(spec.parameters).combine = MaskCombine::fovea_or_product;
  EXPECT_NE(spec.canonical().find(";combine=fovea-or-product;"), std::string::npos) << spec.canonical();
  EXPECT_NE(spec.canonical().find(";blur=off;"), std::string::npos);
  EXPECT_NE(spec.canonical().find(";fovea_radius_deg=7.5;"), std::string::npos);
  const nlohmann::json json = to_json(spec);
  EXPECT_EQ(json["method"], "fipr");
  EXPECT_EQ(json["parameters"]["combine"], "fovea-or-product");
  EXPECT_EQ(json["parameters"]["pyramid_levels"], 3);
  EXPECT_EQ(spec.method_name(), "fipr");
}

// Parameters added after logs were written (the pyramid's coarse_test and full_resolution_depth)
// leave the canonical text of older stimuli as it was at the values those logs had, and enter it
// otherwise: since log schema 10 IPR's defaults are the cone and no min filter, so a default
// stimulus names the cone; one of the paper's pyramid (ray, 3x3) has the older text.
TEST(RenderMethod, ParametersAddedLaterKeepTheCanonicalTextOfOlderStimuli) {
  StimulusSpec spec;
  spec.scene = "primitives";
  spec.width_px = 64;
  spec.height_px = 36;
  spec.parameters = default_parameters(RenderMethod::inverted_pyramid);
  EXPECT_EQ(spec.canonical(),
            "scene=primitives;method=ipr;coarse_test=cone;hit_threshold=0.25;max_steps=256;min_filter_size=1;"
            "pyramid_levels=3;samples_per_pixel=1;size=64x36;frames=1@1;camera_start_s=0");
  auto& ipr = std::get<InvertedPyramidParameters>(spec.parameters);
  ipr.coarse_test = CoarseTest::centre_ray;  // the older logs' pyramid
  ipr.min_filter_size = 3;
  EXPECT_EQ(spec.canonical(),
            "scene=primitives;method=ipr;hit_threshold=0.25;max_steps=256;min_filter_size=3;pyramid_levels=3;"
            "samples_per_pixel=1;size=64x36;frames=1@1;camera_start_s=0");
  EXPECT_FALSE(to_json(spec)["parameters"].contains("coarse_test"));
  ipr.coarse_test = CoarseTest::cone;
  ipr.full_resolution_depth = true;
  EXPECT_NE(spec.canonical().find(";coarse_test=cone;full_resolution_depth=on;"), std::string::npos)
      << spec.canonical();
  EXPECT_EQ(to_json(spec)["parameters"]["coarse_test"], "cone");
  EXPECT_EQ(to_json(spec)["parameters"]["full_resolution_depth"], "on");
}

TEST(RenderMethod, ValuesOutsideTheDescriptorAreRefusedWithWhatWasExpected) {
  const MethodDescriptor& fpt = describe(RenderMethod::foveated_path_traced);
  const ParameterDescriptor& bounces = *find_parameter(fpt, "periphery_bounces");
  EXPECT_EQ(check_parameter_value(bounces, -2), "a value in [-1, 1024]");
  EXPECT_EQ(check_parameter_value(bounces, 1.5), "a whole number");
  EXPECT_FALSE(check_parameter_value(bounces, -1));
  const ParameterDescriptor& combine = *find_parameter(describe(RenderMethod::foveated_pyramid), "combine");
  EXPECT_EQ(check_parameter_value(combine, 4), "one of \"max\", \"fovea-or-product\", \"product\", \"acuity\"");
  EXPECT_EQ(parse_choice(combine, "product"), 2.0);
  EXPECT_FALSE(parse_choice(combine, "Product"));
  EXPECT_FALSE(find_parameter(fpt, "foveal_deg"));
  EXPECT_EQ(find_parameter(fpt, "foveal_deg", /*legacy=*/true)->key, "foveal_aperture_deg");
}

// A FIPR study as fovlab wrote it before the typed model (log schema 2): old keys, numeric choices.
const char* kLegacyConfig = R"([study]
name = "legacy"
seed = 1
[display]
width_px = 64
height_px = 48
refresh_hz = 60
width_mm = 400
height_mm = 300
viewing_distance_mm = 600
[stimulus]
duration_s = 0.1
[stimulus.reference]
method = "gt"
[stimulus.test]
method = "fipr"
outer_periphery_deg = 40
combine = 2
[[stimulus.variant]]
name = "blurred"
blur = 1
[levels]
parameter = "fovea_deg"
values = [2.5, 5]
[protocol]
kind = "2afc"
question = "same"
[[block]]
scene = "primitives"
)";

TEST(RenderMethod, ConfigsOfThePreviousSchemaReadOnlyFromLogs) {
  const StudyConfig config = parse_logged_study_config(kLegacyConfig, "events.jsonl (config_toml)", 2, &kScenes);
  EXPECT_EQ(config.levels.parameter, "fovea_radius_deg");
  const auto test = std::get<FoveatedPyramidParameters>(parameters_with(
      config.stimulus.test.method, {&config.stimulus.test.parameters, &config.stimulus.variants[0].parameters}));
  EXPECT_EQ(test.outer_periphery_radius_deg, 40);
  EXPECT_EQ(test.combine, MaskCombine::product);
  EXPECT_TRUE(test.blur);
  // Without a catalog (a log read on another machine) the scene is taken as written.
  EXPECT_EQ(parse_logged_study_config(kLegacyConfig, "events.jsonl", 2, nullptr).blocks[0].scene, "primitives");
  // A config file of today must use today's keys: the old one is named as unknown.
  try {
    parse_study_config_text(kLegacyConfig, "old.toml", kScenes);
    FAIL() << "an old key was accepted in a config file";
  } catch (const InputError& error) {
    // (toml++ hands the table's keys over sorted: combine comes before outer_periphery_deg.)
    EXPECT_EQ(std::string(error.what()),
              "old.toml:18: stimulus.test.combine: expected one of \"max\", \"fovea-or-product\", \"product\", "
              "\"acuity\" (a name), got 2");
  }
  std::string without_combine = kLegacyConfig;
  without_combine.replace(without_combine.find("combine = 2\n"), 12, "");
  try {
    parse_study_config_text(without_combine, "old.toml", kScenes);
    FAIL() << "an old key was accepted in a config file";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what())
                  .rfind("old.toml:17: stimulus.test.outer_periphery_deg: not a parameter of method "
                         "\"fipr\"",
                         0),
              0u)
        << error.what();
  }
}

// FIPR's periphery_reconstruction came with log schema 5, defaulting to bilinear: a config read now,
// or carried by a schema 5 log, means bilinear when it leaves the key out; one carried by a schema
// 1-4 log means mid-footprint-bilinear, what that log's frames showed. The canonical text leaves out
// mid-footprint-bilinear, so the stimuli of older logs keep theirs.
TEST(RenderMethod, ADefaultChangedInASchemaIsTheLogsOwnDefault) {
  std::string config_text = kLegacyConfig;
  for (const auto& [from, to] :
       std::vector<std::pair<std::string, std::string>>{{"outer_periphery_deg = 40\ncombine = 2\n", ""},
                                                        {"blur = 1", "blur = \"on\""},
                                                        {"\"fovea_deg\"", "\"fovea_radius_deg\""}})
    config_text.replace(config_text.find(from), from.size(), to);
  const auto test_of = [](const StudyConfig& config, const ParameterLayer* variant) {
    const ParameterLayer none;
    return std::get<FoveatedPyramidParameters>(
        parameters_with(config.stimulus.test.method, {&config.stimulus.test.parameters, variant ? variant : &none}));
  };
  const StudyConfig now = parse_study_config_text(config_text, "x.toml", kScenes);
  EXPECT_EQ(test_of(now, nullptr).periphery_reconstruction, PeripheryReconstruction::bilinear);
  const StudyConfig schema5 = parse_logged_study_config(config_text, "events.jsonl", 5, nullptr);
  EXPECT_EQ(test_of(schema5, nullptr).periphery_reconstruction, PeripheryReconstruction::bilinear);
  // near_misses changed in schema 6 (two parameters' defaults, each from its own schema).
  EXPECT_EQ(test_of(now, nullptr).near_misses, NearMisses::promote);
  EXPECT_EQ(test_of(parse_logged_study_config(config_text, "events.jsonl", 6, nullptr), nullptr).near_misses,
            NearMisses::promote);
  for (const int schema : {1, 2, 3, 4, 5}) {
    EXPECT_EQ(test_of(parse_logged_study_config(config_text, "events.jsonl", schema, nullptr), nullptr).near_misses,
              NearMisses::ignore)
        << schema;
  }
  for (const int schema : {1, 2, 3, 4}) {
    const StudyConfig old = parse_logged_study_config(config_text, "events.jsonl", schema, nullptr);
    EXPECT_EQ(test_of(old, nullptr).periphery_reconstruction, PeripheryReconstruction::mid_footprint_bilinear)
        << schema;
    // A variant that names it is still obeyed (a config of schema 5 read from a schema 4 log
    // cannot name it, but the layering must not hide what a config says).
    const ParameterLayer variant{{"periphery_reconstruction", 2.0}};
    EXPECT_EQ(test_of(old, &variant).periphery_reconstruction, PeripheryReconstruction::catmull_rom) << schema;
    // The reference's method (gt) has no such parameter and gains none.
    EXPECT_TRUE(old.stimulus.reference.parameters.empty());
  }
  // Named in the config, it is what the config says, whatever the schema.
  config_text.replace(config_text.find("method = \"fipr\"\n"), 16,
                      "method = \"fipr\"\nperiphery_reconstruction = \"catmull-rom\"\n");
  EXPECT_EQ(test_of(parse_study_config_text(config_text, "x.toml", kScenes), nullptr).periphery_reconstruction,
            PeripheryReconstruction::catmull_rom);
  EXPECT_EQ(
      test_of(parse_logged_study_config(config_text, "events.jsonl", 4, nullptr), nullptr).periphery_reconstruction,
      PeripheryReconstruction::catmull_rom);

  StimulusSpec spec;
  spec.scene = "primitives";
  spec.width_px = 64;
  spec.height_px = 36;
  spec.parameters = default_parameters(RenderMethod::foveated_pyramid);
  EXPECT_NE(spec.canonical().find(";periphery_reconstruction=bilinear;"), std::string::npos) << spec.canonical();
  EXPECT_EQ(to_json(spec)["parameters"]["periphery_reconstruction"], "bilinear");
  std::get<FoveatedPyramidParameters>(spec.parameters).periphery_reconstruction =
      PeripheryReconstruction::mid_footprint_bilinear;
  EXPECT_EQ(spec.canonical().find("periphery_reconstruction"), std::string::npos) << spec.canonical();
  EXPECT_FALSE(to_json(spec)["parameters"].contains("periphery_reconstruction"));
  EXPECT_NE(spec.canonical().find(";near_misses=promote;"), std::string::npos) << spec.canonical();
  std::get<FoveatedPyramidParameters>(spec.parameters).near_misses = NearMisses::ignore;
  EXPECT_EQ(spec.canonical().find("near_misses"), std::string::npos) << spec.canonical();
  EXPECT_FALSE(to_json(spec)["parameters"].contains("near_misses"));
}

TEST(RenderMethod, DocsConfigCarriesTheTableTheDescriptorsMake) {
  std::ifstream file(std::string(FOVLAB_SOURCE_DIR) + "/docs/config.md");
  std::stringstream text;
  text << file.rdbuf();
  const std::string doc = text.str();
  const std::string begin = "<!-- methods: made by `fovlab methods`; begin -->\n";
  const std::string end = "<!-- methods: end -->";
  const size_t from = doc.find(begin);
  const size_t to = doc.find(end);
  ASSERT_NE(from, std::string::npos);
  ASSERT_NE(to, std::string::npos);
  EXPECT_EQ(doc.substr(from + begin.size(), to - from - begin.size()), methods_markdown())
      << "docs/config.md is out of date: replace its table with the output of `fovlab methods`";
}

}  // namespace
}  // namespace fovlab
