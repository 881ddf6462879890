// FIPR as a study stimulus (protocols/stimuli/stimulus_spec.h, protocols/schedule/study_plan.cpp):
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

#include "core/input_error.h"
#include "protocols/config/study_config.h"
#include "protocols/schedule/study_plan.h"
#include "protocols/stimuli/stimulus_spec.h"
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
  std::string levels = "[levels]\nparameter = \"fovea_deg\"\nvalues = [2.5, 5, 7.5]\n";

  std::string text() const {
    return R"([study]
name = "fipr_unit"
seed = 3

)" + display + R"(
[stimulus]
duration_s = 0.1
frames_per_second = 20

[stimulus.reference]
method = "gt"

)" + test + "\n" + variants + "\n" + levels + R"(
[protocol]
kind = "2afc"
question = "same"
repeats = 2

[[block]]
scene = "primitives"
)";
  }
};

StudyConfig parse(const std::string& text) { return parse_study_config_text(text, kPath); }

int line_of(const std::string& text, const std::string& needle) {
  const size_t at = text.find(needle);
  if (at == std::string::npos) {
    ADD_FAILURE() << "not found: " << needle;
    return -1;
  }
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

// The error must be one line "studies/fipr.toml:LINE: KEY: ..." containing `fragment`.
void expect_error(const std::string& text, int line, const std::string& key, const std::string& fragment) {
  std::string message;
  try {
    parse(text);
    ADD_FAILURE() << "no error for:\n" << text;
    return;
  } catch (const InputError& error) {
    message = error.what();
  }
  SCOPED_TRACE(message);
  EXPECT_EQ(message.find('\n'), std::string::npos) << "more than one line";
  const std::string prefix = kPath + ":" + std::to_string(line) + ": " + key + ": ";
  EXPECT_EQ(message.rfind(prefix, 0), 0u) << "expected the prefix \"" << prefix << "\"";
  EXPECT_NE(message.find(fragment), std::string::npos) << "expected to contain \"" << fragment << "\"";
}

const MethodParameter& parameter_named(const std::vector<MethodParameter>& parameters, const std::string& name) {
  for (const MethodParameter& parameter : parameters)
    if (parameter.name == name) return parameter;
  throw std::logic_error("no parameter " + name);
}

// --- the method -------------------------------------------------------------------------------------

TEST(FiprStimulus, IsAKnownGazeDependentMethod) {
  EXPECT_NE(known_methods().find("fipr"), std::string::npos);
  EXPECT_TRUE(method_depends_on_gaze("fipr"));
  EXPECT_FALSE(method_depends_on_gaze("gt"));
  EXPECT_FALSE(method_depends_on_gaze("ipr"));
  ASSERT_TRUE(method_parameters("fipr"));
}

TEST(FiprStimulus, ParametersDefaultsRangesAndChoices) {
  const std::vector<MethodParameter> parameters = *method_parameters("fipr");
  std::set<std::string> names;
  for (const MethodParameter& parameter : parameters) names.insert(parameter.name);
  EXPECT_EQ(names, (std::set<std::string>{"samples_per_pixel", "max_steps", "hit_threshold", "pyramid_levels",
                                          "min_filter_size", "fovea_deg", "outer_periphery_deg", "periphery_refresh",
                                          "periphery_steps",
                                          "blur", "combine", "edge_threshold", "mask_seed", "display_width_mm",
                                          "display_height_mm", "viewing_distance_mm"}));
  const auto& levels = parameter_named(parameters, "pyramid_levels");
  EXPECT_EQ(levels.default_value, 3);
  EXPECT_EQ(levels.min_value, 3);  // low, mid and top
  EXPECT_EQ(levels.max_value, 5);
  EXPECT_EQ(parameter_named(parameters, "samples_per_pixel").choices, (std::vector<double>{1, 4, 16}));
  EXPECT_EQ(parameter_named(parameters, "min_filter_size").choices, (std::vector<double>{1, 3, 5}));
  EXPECT_EQ(parameter_named(parameters, "fovea_deg").default_value, 7.5);
  EXPECT_EQ(parameter_named(parameters, "fovea_deg").max_value, 180);
  EXPECT_EQ(parameter_named(parameters, "outer_periphery_deg").default_value, 180);
  EXPECT_EQ(parameter_named(parameters, "periphery_refresh").choices, (std::vector<double>{1, 2, 4}));
  EXPECT_EQ(parameter_named(parameters, "periphery_steps").default_value, FoveationSettings{}.periphery_steps);
  EXPECT_EQ(parameter_named(parameters, "periphery_steps").min_value, 0);  // 0: the mid level's colour
  EXPECT_EQ(parameter_named(parameters, "blur").choices, (std::vector<double>{0, 1}));
  EXPECT_EQ(parameter_named(parameters, "combine").choices, (std::vector<double>{0, 1, 2, 3}));
  EXPECT_EQ(parameter_named(parameters, "edge_threshold").default_value, 0.4);
  EXPECT_GT(parameter_named(parameters, "edge_threshold").min_value, 0.0);
  EXPECT_TRUE(parameter_named(parameters, "mask_seed").integral);
  EXPECT_EQ(parameter_named(parameters, "mask_seed").max_value, 4294967295.0);
  for (const char* display : {"display_width_mm", "display_height_mm", "viewing_distance_mm"})
    EXPECT_EQ(parameter_named(parameters, display).default_value, 0) << display << ": 0 means from [display]";
  // The other methods do not have them.
  const std::vector<MethodParameter> ipr = *method_parameters("ipr");
  for (const MethodParameter& parameter : ipr) EXPECT_EQ(names.count(parameter.name), 1u);
  EXPECT_EQ(method_parameters("ipr")->size(), 5u);
}

TEST(FiprStimulus, SettingsForTheRenderer) {
  StimulusSpec spec;
  spec.scene = "primitives";
  spec.method = "fipr";
  const std::vector<MethodParameter> fipr = *method_parameters("fipr");
  for (const MethodParameter& parameter : fipr) spec.parameters[parameter.name] = parameter.default_value;
  spec.width_px = 64;
  spec.height_px = 48;
  spec.frame_count = 3;
  spec.frames_per_second = 20;
  spec.camera_start_s = 1.0;
  // Without its display a FIPR spec cannot be rendered (the schedule always fills it in).
  EXPECT_THROW(sphere_trace_settings(spec, 0), InputError);

  spec.parameters["display_width_mm"] = 400;
  spec.parameters["display_height_mm"] = 300;
  spec.parameters["viewing_distance_mm"] = 600;
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
  EXPECT_EQ(f.acuity.fovea_deg, 7.5);
  EXPECT_EQ(f.acuity.outer_periphery_deg, std::numeric_limits<double>::infinity());  // 180: none
  EXPECT_EQ(f.periphery_refresh, 1);
  EXPECT_EQ(f.periphery_steps, FoveationSettings{}.periphery_steps);
  EXPECT_FALSE(f.blur);
  EXPECT_EQ(f.combine, MaskCombine::max);
  EXPECT_FLOAT_EQ(f.edge_threshold, 0.4f);
  EXPECT_EQ(f.seed, 0u);
  EXPECT_NO_THROW(validate(settings));

  spec.parameters["fovea_deg"] = 12.5;
  spec.parameters["outer_periphery_deg"] = 40;
  spec.parameters["periphery_refresh"] = 4;
  spec.parameters["periphery_steps"] = 0;
  spec.parameters["blur"] = 1;
  spec.parameters["combine"] = 2;
  spec.parameters["edge_threshold"] = 0.1;
  spec.parameters["mask_seed"] = 4294967295.0;
  settings = sphere_trace_settings(spec, 0);
  EXPECT_EQ(settings.foveation.acuity.fovea_deg, 12.5);
  EXPECT_EQ(settings.foveation.acuity.outer_periphery_deg, 40);
  EXPECT_EQ(settings.foveation.periphery_refresh, 4);
  EXPECT_EQ(settings.foveation.periphery_steps, 0);
  EXPECT_TRUE(settings.foveation.blur);
  EXPECT_EQ(settings.foveation.combine, MaskCombine::product);
  EXPECT_FLOAT_EQ(settings.foveation.edge_threshold, 0.1f);
  EXPECT_EQ(settings.foveation.seed, 4294967295u);
  EXPECT_NO_THROW(validate(settings));
}

TEST(FiprStimulus, OuterPeripheryRule) {
  std::map<std::string, double> parameters;
  const std::vector<MethodParameter> fipr = *method_parameters("fipr");
  for (const MethodParameter& parameter : fipr) parameters[parameter.name] = parameter.default_value;
  EXPECT_FALSE(parameter_conflict("fipr", parameters));
  parameters["outer_periphery_deg"] = 7.5;  // equal: allowed
  EXPECT_FALSE(parameter_conflict("fipr", parameters));
  parameters["outer_periphery_deg"] = 5;
  const auto conflict = parameter_conflict("fipr", parameters);
  ASSERT_TRUE(conflict);
  EXPECT_NE(conflict->expected.find("outer_periphery_deg (5) >= fovea_deg (7.5)"), std::string::npos)
      << conflict->expected;
  EXPECT_FALSE(parameter_conflict("gt", {{"max_steps", 4}}));
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
outer_periphery_deg = 40
periphery_refresh = 2
periphery_steps = 16
blur = 1
combine = 3
edge_threshold = 0.25
mask_seed = 77
display_width_mm = 200
display_height_mm = 150
viewing_distance_mm = 300
)";
  const StudyConfig config = parse(base.text());
  EXPECT_EQ(config.stimulus.test.method, "fipr");
  EXPECT_EQ(config.stimulus.test.parameters.size(), 15u);
  EXPECT_EQ(config.stimulus.test.parameters.at("mask_seed"), 77);
}

TEST(FiprStimulus, BadValuesAreOneLineErrorsNamingTheField) {
  const struct {
    std::string line;
    std::string fragment;
  } cases[] = {
      {"fovea_deg = 200", "expected a value in [0, 180], got 200"},
      {"fovea_deg = -1", "expected a value in [0, 180]"},
      {"outer_periphery_deg = 181", "expected a value in [0, 180]"},
      {"pyramid_levels = 2", "expected a value in [3, 5], got 2"},
      {"min_filter_size = 2", "expected one of 1 3 5, got 2"},
      {"samples_per_pixel = 2", "expected one of 1 4 16, got 2"},
      {"periphery_refresh = 3", "expected one of 1 2 4, got 3"},
      {"periphery_steps = -1", "expected a value in [0, 4096], got -1"},
      {"periphery_steps = 2.5", "whole number"},
      {"blur = 0.5", "expected one of 0 1, got 0.5"},
      {"combine = 4", "expected one of 0 1 2 3, got 4"},
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
  base.levels = "[levels]\nparameter = \"fovea_deg\"\nvalues = [2.5, 190]\n";
  std::string text = base.text();
  expect_error(text, line_of(text, "values = [2.5, 190]"), "levels.values", "got 190");
  // A FIPR parameter on an IPR test is not a parameter of that method.
  base = FiprText{};
  base.test = "[stimulus.test]\nmethod = \"ipr\"\nfovea_deg = 5\n";
  base.levels.clear();
  text = base.text();
  expect_error(text, line_of(text, "fovea_deg = 5"), "stimulus.test.fovea_deg", "not a parameter of method \"ipr\"");
}

TEST(FiprStimulus, OuterPeripheryInsideTheFoveaNamesTheFieldThatSetIt) {
  // In the test table, against the default fovea.
  FiprText base;
  base.levels.clear();
  base.test += "outer_periphery_deg = 5\n";
  std::string text = base.text();
  expect_error(text, line_of(text, "outer_periphery_deg = 5"), "stimulus.test.outer_periphery_deg",
               "expected outer_periphery_deg (5) >= fovea_deg (7.5)");

  // A level value beyond the test's outer periphery: the levels are named.
  base = FiprText{};
  base.test += "outer_periphery_deg = 6\n";
  text = base.text();
  expect_error(text, line_of(text, "values = [2.5, 5, 7.5]"), "levels.values",
               "value 7.5: expected outer_periphery_deg (6)");

  // A variant's outer periphery inside a level's fovea: the level is what moved last.
  base = FiprText{};
  base.variants = "[[stimulus.variant]]\nname = \"near\"\nouter_periphery_deg = 3\n";
  text = base.text();
  expect_error(text, line_of(text, "values = [2.5, 5, 7.5]"), "levels.values", "value 5:");

  // Without levels, the variant that set it.
  base = FiprText{};
  base.levels.clear();
  base.variants =
      "[[stimulus.variant]]\nname = \"wide\"\n\n[[stimulus.variant]]\nname = \"near\"\nouter_periphery_deg = 3\n";
  text = base.text();
  expect_error(text, line_of(text, "outer_periphery_deg = 3"), "stimulus.variant[2].outer_periphery_deg",
               "expected outer_periphery_deg (3) >= fovea_deg (7.5)");

  // The reference may be FIPR too.
  text = FiprText{}.text();
  const std::string gt_reference = "[stimulus.reference]\nmethod = \"gt\"\n";
  text.replace(text.find(gt_reference), gt_reference.size(),
               "[stimulus.reference]\nmethod = \"fipr\"\nouter_periphery_deg = 10\nfovea_deg = 20\n");
  expect_error(text, line_of(text, "fovea_deg = 20"), "stimulus.reference.fovea_deg", "outer_periphery_deg (10)");
}

// --- the schedule -----------------------------------------------------------------------------------

TEST(FiprStimulus, TheScheduleFillsTheDisplayFromTheConfig) {
  const StudyPlan plan = make_study_plan(parse(FiprText{}.text()), "P1");
  int fipr = 0;
  for (const PlannedStimulus& stimulus : plan.stimuli) {
    if (stimulus.spec.method != "fipr") {
      EXPECT_EQ(stimulus.spec.parameters.count("display_width_mm"), 0u);  // GT has no display parameters
      continue;
    }
    ++fipr;
    EXPECT_EQ(stimulus.spec.parameters.at("display_width_mm"), 400);
    EXPECT_EQ(stimulus.spec.parameters.at("display_height_mm"), 300);
    EXPECT_EQ(stimulus.spec.parameters.at("viewing_distance_mm"), 600);
    EXPECT_NE(stimulus.spec.canonical().find("display_width_mm=400"), std::string::npos);
    EXPECT_EQ(stimulus.spec.parameters.at("fovea_deg"), *stimulus.level);
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
  ASSERT_EQ(spec.method, "fipr");
  EXPECT_DOUBLE_EQ(spec.parameters.at("display_width_mm"), 20 * 25.4 * 0.8);  // 4:3
  EXPECT_DOUBLE_EQ(spec.parameters.at("display_height_mm"), 20 * 25.4 * 0.6);
  EXPECT_EQ(spec.parameters.at("viewing_distance_mm"), 700);
  EXPECT_DOUBLE_EQ(spec.parameters.at("display_width_mm"), config.display.width_mm);
}

TEST(FiprStimulus, ADisplayTheConfigSetsIsKeptAndMakesAnotherStimulus) {
  FiprText base;
  base.test += "viewing_distance_mm = 450\n";
  base.variants = "[[stimulus.variant]]\nname = \"here\"\n\n[[stimulus.variant]]\nname = \"small\"\n"
                  "display_width_mm = 200\ndisplay_height_mm = 150\n";
  const StudyPlan plan = make_study_plan(parse(base.text()), "P1");
  std::set<std::string> canonical;
  int fipr = 0;
  for (const PlannedStimulus& stimulus : plan.stimuli) {
    canonical.insert(stimulus.spec.canonical());
    if (stimulus.spec.method != "fipr") continue;
    ++fipr;
    EXPECT_EQ(stimulus.spec.parameters.at("viewing_distance_mm"), 450);
    const bool small = stimulus.variant == "small";
    EXPECT_EQ(stimulus.spec.parameters.at("display_width_mm"), small ? 200 : 400) << stimulus.variant;
    EXPECT_EQ(stimulus.spec.parameters.at("display_height_mm"), small ? 150 : 300) << stimulus.variant;
  }
  EXPECT_EQ(fipr, 6);  // 2 variants x 3 levels
  EXPECT_EQ(canonical.size(), plan.stimuli.size());  // the display tells them apart

  // Levels may set a display parameter too (e.g. a viewing distance as the study's variable).
  base = FiprText{};
  base.levels = "[levels]\nparameter = \"viewing_distance_mm\"\nvalues = [300, 900]\n";
  const StudyPlan by_distance = make_study_plan(parse(base.text()), "P1");
  std::set<double> distances;
  for (const PlannedStimulus& stimulus : by_distance.stimuli)
    if (stimulus.spec.method == "fipr") distances.insert(stimulus.spec.parameters.at("viewing_distance_mm"));
  EXPECT_EQ(distances, (std::set<double>{300, 900}));
}

TEST(FiprStimulus, TheShippedMainStudy) {
  const std::string path = std::string(FOVLAB_SOURCE_DIR) + "/experiments/fipr_main.toml";
  const StudyConfig config = parse_study_config_file(path);
  EXPECT_EQ(config.name, "fipr_main");
  EXPECT_EQ(config.protocol.kind, ProtocolKind::two_afc);
  EXPECT_EQ(config.protocol.two_afc_question, TwoAfcQuestion::same);
  EXPECT_EQ(config.stimulus.reference.method, "gt");
  EXPECT_EQ(config.stimulus.test.method, "fipr");
  EXPECT_EQ(config.levels.parameter, "fovea_deg");
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
      if (spec.method == "fipr") blur.insert(spec.parameters.at("blur"));
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
