// Tests of study/config/study_config.h and toml_fields.h: valid configs of every protocol kind,
// and the one-line "path:LINE: key: what was expected" InputError of every kind of bad input.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <regex>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "protocols/stimuli/stimulus_settings.h"
#include "core/content_hash.h"
#include "core/input_error.h"
#include "study/config/study_config.h"
#include "study/log/event_log.h"
#include "tests/study/config/config_error_test_support.h"
#include "tests/support/temp_dir.h"

namespace fovlab {
namespace {

const std::string kPath = "studies/unit.toml";

// The sections of a valid 2afc same/different study; tests replace sections or lines.
struct ConfigText {
  std::string study = R"([study]
name = "unit"
seed = 7
instructions = "Go."
)";
  std::string display = R"([display]
width_px = 320
height_px = 180
refresh_hz = 60
diagonal_in = 27
viewing_distance_mm = 500
)";
  std::string stimulus = R"([stimulus]
duration_s = 0.5
frames_per_second = 10
camera_start_s = 1.0

[stimulus.reference]
method = "gt"

[stimulus.test]
method = "gt"
)";
  std::string levels = R"([levels]
parameter = "max_steps"
values = [4, 8, 16, 32, 64]
higher_is_better = true
)";
  std::string protocol = R"([protocol]
kind = "2afc"
question = "same"
repeats = 2
)";
  std::string timing = R"([timing]
black_interval_s = 0.25
inter_trial_s = 0.75
)";
  std::string attention = R"([attention]
share = 0.2
break_s = 5
max_errors = 3
)";
  std::string blocks = R"([[block]]
scene = "primitives"

[[block]]
scene = "columns"
name = "cols"
)";

  std::string text() const {
    std::string result;
    for (const std::string* section : {&study, &display, &stimulus, &levels, &protocol, &timing, &attention, &blocks})
      if (!section->empty()) result += *section + "\n";
    return result;
  }
};

// Replaces the one occurrence of `from` (the test fails when there is none or more than one).
std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "not found: " << from;
  if (at == std::string::npos) return text;
  EXPECT_EQ(text.find(from, at + 1), std::string::npos) << "found twice: " << from;
  return text.replace(at, from.size(), to);
}

using test::line_of;

std::string error_of(const std::string& text) { return test::config_error_of(text, kPath); }

// The error must be one line "studies/unit.toml:LINE: KEY: ..." containing `fragment`.
void expect_error(const std::string& text, int line, const std::string& key, const std::string& fragment) {
  const std::string message = test::expect_config_error(text, kPath, line, key, fragment);
  EXPECT_TRUE(std::regex_match(message, std::regex(R"(studies/unit\.toml:[0-9]+: [A-Za-z0-9_.\[\]]+: .+)")))
      << "not of the form path:LINE: key: expected: " << message;
}

StudyConfig parse(const std::string& text) { return parse_study_config_text(text, kPath, renderer_scene_catalog()); }

std::vector<std::string> answer_names(const StudyConfig& config) {
  std::vector<std::string> names;
  for (const auto& [answer, keys] : config.protocol.question.answers) names.push_back(answer);
  return names;
}

std::vector<std::string> keys_of(const StudyConfig& config, const std::string& answer) {
  for (const auto& [name, keys] : config.protocol.question.answers)
    if (name == answer) return keys;
  ADD_FAILURE() << "no answer " << answer;
  return {};
}

// [gaze] require: one kind or an array of kinds (docs/config.md, docs/gaze.md). An optional table:
// a config without it keeps its version (content_hash); one with it is another version.
TEST(ProtocolsConfig, GazeRequireTakesOneKindOrAnArrayAndNamesItsLineWhenBad) {
  const ConfigText base;
  const StudyConfig plain = parse(base.text());
  EXPECT_TRUE(plain.gaze.require.empty());
  EXPECT_FALSE(is_gaze_contingent(plain));
  EXPECT_EQ(parse(base.text()).content_hash, plain.content_hash);

  const StudyConfig one = parse(base.text() + "[gaze]\nrequire = \"tracker\"\n");
  EXPECT_EQ(one.gaze.require, (std::vector<GazeSourceKind>{GazeSourceKind::tracker}));
  EXPECT_EQ(one.gaze.require_text(), "tracker");
  EXPECT_TRUE(one.gaze.allows(GazeSourceKind::tracker));
  EXPECT_FALSE(one.gaze.allows(GazeSourceKind::mouse));
  EXPECT_NE(one.content_hash, plain.content_hash) << "a config with [gaze] says more: another version";
  const StudyConfig several = parse(base.text() + "[gaze]\nrequire = [\"tracker\", \"trace\", \"mouse\"]\n");
  EXPECT_EQ(several.gaze.require,
            (std::vector<GazeSourceKind>{GazeSourceKind::tracker, GazeSourceKind::trace, GazeSourceKind::mouse}));
  EXPECT_EQ(several.gaze.require_text(), "tracker, trace or mouse");

  const std::string text = base.text() + "[gaze]\n";
  const int line = line_of(text + "require", "require");
  expect_error(text + "require = \"eyelink\"\n", line, "gaze.require", "tracker, trace, synthetic or mouse");
  expect_error(text + "require = \"pupil\"\n", line, "gaze.require", "Pupil Core is the kind \"tracker\"");
  expect_error(text + "require = 3\n", line, "gaze.require", "a non-empty array");
  expect_error(text + "require = []\n", line, "gaze.require", "a non-empty array");
  expect_error(text + "require = [\"mouse\", \"mouse\"]\n", line, "gaze.require", "given twice");
  expect_error(text + "require = \"tracker\"\nsource = \"pupil\"\n", line + 1, "gaze.source", "");
  const std::string missing = error_of(text + "\n");
  EXPECT_NE(missing.find("gaze.require: missing"), std::string::npos) << missing;

  // The kinds the logs name: the spec text of every source (GazeSource::describe()).
  EXPECT_EQ(gaze_source_kind_of_spec("mouse"), GazeSourceKind::mouse);
  EXPECT_EQ(gaze_source_kind_of_spec("trace:/data/p1.csv"), GazeSourceKind::trace);
  EXPECT_EQ(gaze_source_kind_of_spec("synthetic:seed=3,age_ms=40"), GazeSourceKind::synthetic);
  EXPECT_EQ(gaze_source_kind_of_spec("pupil:127.0.0.1:50020,surface=monitor"), GazeSourceKind::tracker);
  EXPECT_EQ(gaze_source_kind_of_spec(""), std::nullopt);
  EXPECT_EQ(gaze_source_kind_of_spec("mouse2"), std::nullopt);
}

// A study whose stimuli follow the gaze (fipr, fpt, the sampling models) is gaze-contingent.
TEST(ProtocolsConfig, AStudyIsGazeContingentWhenAMethodFollowsTheGaze) {
  ConfigText fipr;
  fipr.stimulus = replace_once(fipr.stimulus, "[stimulus.test]\nmethod = \"gt\"", "[stimulus.test]\nmethod = \"fipr\"");
  EXPECT_TRUE(is_gaze_contingent(parse(fipr.text())));
  ConfigText ipr;
  ipr.stimulus = replace_once(ipr.stimulus, "[stimulus.test]\nmethod = \"gt\"", "[stimulus.test]\nmethod = \"ipr\"");
  EXPECT_FALSE(is_gaze_contingent(parse(ipr.text())));
}

// --- valid configs ----------------------------------------------------------------------------------

TEST(ProtocolsConfig, ParsesTheBaseTwoAfcSameConfigFieldByField) {
  const ConfigText base;
  const std::string text = base.text();
  const StudyConfig config = parse(text);
  EXPECT_EQ(config.name, "unit");
  EXPECT_EQ(config.seed, 7u);
  EXPECT_EQ(config.instructions, "Go.");

  EXPECT_EQ(config.display.width_px, 320);
  EXPECT_EQ(config.display.height_px, 180);
  EXPECT_DOUBLE_EQ(config.display.refresh_hz, 60.0);
  // Square pixels: the 27" diagonal split in the 320:180 aspect ratio.
  const double diagonal_px = std::hypot(320.0, 180.0);
  EXPECT_NEAR(config.display.width_mm, 27 * 25.4 * 320 / diagonal_px, 1e-9);
  EXPECT_NEAR(config.display.height_mm, 27 * 25.4 * 180 / diagonal_px, 1e-9);
  EXPECT_NEAR(std::hypot(config.display.width_mm, config.display.height_mm), 27 * 25.4, 1e-9);
  EXPECT_DOUBLE_EQ(config.display.viewing_distance_mm, 500.0);
  EXPECT_FALSE(config.display.fullscreen);

  EXPECT_DOUBLE_EQ(config.stimulus.duration_s, 0.5);
  EXPECT_DOUBLE_EQ(config.stimulus.frames_per_second, 10.0);
  EXPECT_DOUBLE_EQ(config.stimulus.camera_start_s, 1.0);
  EXPECT_EQ(config.stimulus.frame_count(), 5);
  EXPECT_EQ(config.stimulus.refreshes_per_frame(60.0), 6);
  EXPECT_EQ(describe(config.stimulus.reference.method).name, "gt");
  EXPECT_TRUE(config.stimulus.reference.parameters.empty());
  EXPECT_EQ(describe(config.stimulus.test.method).name, "gt");
  EXPECT_TRUE(config.stimulus.test.parameters.empty());
  EXPECT_TRUE(config.stimulus.variants.empty());

  EXPECT_EQ(config.levels.parameter, "max_steps");
  EXPECT_EQ(config.levels.values, (std::vector<double>{4, 8, 16, 32, 64}));
  EXPECT_TRUE(config.levels.higher_is_better);

  EXPECT_EQ(config.protocol.kind, ProtocolKind::two_afc);
  EXPECT_EQ(config.protocol.two_afc_question, TwoAfcQuestion::same);
  EXPECT_EQ(config.protocol.repeats, 2);
  EXPECT_TRUE(config.protocol.counterbalance);                                // default for two-interval protocols
  EXPECT_TRUE(config.protocol.randomise_trials);                              // trial_order defaults to random
  EXPECT_EQ(config.protocol.block_order, ProtocolConfig::BlockOrder::fixed);  // block_order defaults to fixed
  EXPECT_EQ(config.protocol.question.text, "Was the quality the same in both sequences?");
  EXPECT_EQ(answer_names(config), (std::vector<std::string>{"same", "different"}));
  EXPECT_EQ(keys_of(config, "same"), (std::vector<std::string>{"s", "space", "pad_a"}));
  EXPECT_EQ(keys_of(config, "different"), (std::vector<std::string>{"d", "pad_b"}));

  EXPECT_DOUBLE_EQ(config.timing.black_interval_s, 0.25);
  EXPECT_DOUBLE_EQ(config.timing.inter_trial_s, 0.75);
  EXPECT_DOUBLE_EQ(config.timing.rest_between_blocks_s, 0.0);
  EXPECT_DOUBLE_EQ(config.timing.response_timeout_s, 0.0);

  EXPECT_DOUBLE_EQ(config.attention.share, 0.2);
  EXPECT_DOUBLE_EQ(config.attention.break_s, 5.0);
  EXPECT_EQ(config.attention.max_errors, 3);

  ASSERT_EQ(config.blocks.size(), 2u);
  EXPECT_EQ(config.blocks[0].name, "primitives");  // the scene's name by default
  EXPECT_EQ(config.blocks[0].scene, "primitives");
  EXPECT_EQ(config.blocks[1].name, "cols");
  EXPECT_EQ(config.blocks[1].scene, "columns");

  EXPECT_EQ(config.source_path, kPath);
  EXPECT_EQ(config.source_text, text);
  EXPECT_EQ(config.hash, ContentHash().add(text).hex());
  EXPECT_EQ(config.hash.size(), 16u);
  // One changed byte, another hash.
  EXPECT_NE(parse(replace_once(text, "seed = 7", "seed = 8")).hash, config.hash);
}

// The config's version (content_hash): what it says, comments and formatting aside. `fovlab run`
// keeps sessions of different versions apart by it (study/log/study_versions.h).
TEST(ProtocolsConfig, ContentHashIgnoresCommentsAndFormattingNotValues) {
  const std::string text = ConfigText().text();
  const StudyConfig config = parse(text);
  EXPECT_EQ(config.content_hash.size(), 16u);
  // Comments, blank lines, spacing, quoting, key order, number notation and inline tables: the same version.
  std::string reformatted = "# edited: comments only\n\n" + text;
  reformatted = replace_once(reformatted, "seed = 7\n", "seed   =   0x7   # hexadecimal\n");
  reformatted = replace_once(reformatted, "name = \"unit\"\n", "name = 'unit'\n");
  reformatted = replace_once(reformatted, "duration_s = 0.5\nframes_per_second = 10\n",
                             "frames_per_second = 10\nduration_s = 0.50\n");
  reformatted =
      replace_once(reformatted, "values = [4, 8, 16, 32, 64]", "values = [\n  4, 8, 16,\n  32, 64,  # the ladder\n]");
  reformatted = replace_once(reformatted, "[stimulus.reference]\nmethod = \"gt\"\n\n", "");
  reformatted =
      replace_once(reformatted, "camera_start_s = 1.0\n", "camera_start_s = 1.0\nreference = { method = \"gt\" }\n");
  const StudyConfig same = parse(reformatted);
  EXPECT_NE(same.hash, config.hash);  // other bytes
  EXPECT_EQ(same.content_hash, config.content_hash);
  // A changed value, an added key (even one at its default) or another ladder: another version.
  EXPECT_NE(parse(replace_once(text, "repeats = 2", "repeats = 3")).content_hash, config.content_hash);
  EXPECT_NE(parse(replace_once(text, "values = [4, 8, 16, 32, 64]", "values = [4, 8, 16, 32, 128]")).content_hash,
            config.content_hash);
  EXPECT_NE(parse(replace_once(text, "instructions = \"Go.\"", "instructions = \"Go!\"")).content_hash,
            config.content_hash);
  // A session log's copy of the config is the same version.
  EXPECT_EQ(parse_logged_study_config(text, "x.toml (config_toml)", log_schema_version, nullptr).content_hash,
            config.content_hash);
}

TEST(ProtocolsConfig, DefaultsOfOptionalTablesAndKeys) {
  ConfigText base;
  base.timing.clear();
  base.attention.clear();
  base.study = "[study]\nname = \"unit\"\nseed = 0\n";
  base.stimulus = replace_once(base.stimulus, "frames_per_second = 10\ncamera_start_s = 1.0\n", "");
  base.levels = "[levels]\nparameter = \"max_steps\"\nvalues = [4, 8]\n";
  const StudyConfig config = parse(base.text());
  EXPECT_EQ(config.seed, 0u);
  EXPECT_EQ(config.instructions, "Press any answer key to begin.");
  EXPECT_DOUBLE_EQ(config.stimulus.frames_per_second, 60.0);  // the display's refresh rate
  EXPECT_DOUBLE_EQ(config.stimulus.camera_start_s, 0.0);
  EXPECT_EQ(config.stimulus.frame_count(), 30);
  EXPECT_EQ(config.stimulus.refreshes_per_frame(60.0), 1);
  EXPECT_TRUE(config.levels.higher_is_better);
  EXPECT_DOUBLE_EQ(config.timing.black_interval_s, 0.5);
  EXPECT_DOUBLE_EQ(config.timing.inter_trial_s, 0.5);
  EXPECT_DOUBLE_EQ(config.attention.share, 0.0);
  EXPECT_DOUBLE_EQ(config.attention.break_s, 30.0);
  EXPECT_EQ(config.attention.max_errors, 3);
}

TEST(ProtocolsConfig, NoLevelsTableMeansOneCondition) {
  ConfigText base;
  base.levels.clear();
  const StudyConfig config = parse(base.text());
  EXPECT_TRUE(config.levels.parameter.empty());
  EXPECT_TRUE(config.levels.values.empty());
}

TEST(ProtocolsConfig, ParsesTheShippedExperiments) {
  // The shipped configs must stay valid (their contents may change, so only their identity is pinned).
  const StudyConfig demo =
      parse_study_config_file(std::string(FOVLAB_SOURCE_DIR) + "/experiments/demo.toml", renderer_scene_catalog());
  EXPECT_EQ(demo.name, "demo");
  EXPECT_EQ(demo.source_path, std::string(FOVLAB_SOURCE_DIR) + "/experiments/demo.toml");
  EXPECT_FALSE(demo.blocks.empty());
  EXPECT_EQ(demo.hash, ContentHash().add(demo.source_text).hex());

  const StudyConfig pilot =
      parse_study_config_file(std::string(FOVLAB_SOURCE_DIR) + "/experiments/ipr_pilot.toml", renderer_scene_catalog());
  EXPECT_EQ(pilot.name, "ipr_pilot");
  EXPECT_EQ(describe(pilot.stimulus.test.method).name, "ipr");
  EXPECT_FALSE(pilot.blocks.empty());
}

TEST(ProtocolsConfig, MissingFileIsAnInputError) {
  EXPECT_THROW(parse_study_config_file("/nonexistent/fovlab/none.toml", renderer_scene_catalog()), InputError);
}

// --- guards in front of the file and of toml++ ----------------------------------------------------

// The error of reading `path` as a study config ("" and a test failure when it is read).
std::string file_error_of(const std::string& path) {
  try {
    parse_study_config_file(path, renderer_scene_catalog());
  } catch (const InputError& error) {
    return error.what();
  }
  ADD_FAILURE() << "read without an error: " << path;
  return "";
}

TEST(ProtocolsConfig, ADirectoryIsNotAConfig) {
  const testing::TempDir dir;
  const std::string message = file_error_of(dir.path().string());
  EXPECT_EQ(message, dir.path().string() + ": not a regular file (a directory): expected a study config (.toml)");
}

TEST(ProtocolsConfig, ADeviceIsRefusedBeforeItIsRead) {
  // /dev/zero never ends: reading it whole took 2.2 GB before it failed.
  EXPECT_EQ(file_error_of("/dev/zero"),
            "/dev/zero: not a regular file (a character device): expected a study config (.toml)");
}

TEST(ProtocolsConfig, AFileOverTheSizeCapIsRefusedFromItsSize) {
  const testing::TempDir dir;
  const std::string path = dir.file("big.toml");
  {
    // A valid config, then a comment that takes the file one byte past the cap; sparse, so cheap.
    std::ofstream out(path, std::ios::binary);
    out << ConfigText().text() << "#";
  }
  std::filesystem::resize_file(path, kMaxStudyConfigBytes + 1);
  EXPECT_EQ(file_error_of(path), path + ": larger than 16 MiB (" + std::to_string(kMaxStudyConfigBytes + 1) +
                                     " bytes): expected a study config (.toml) of at most 16 MiB");
  // The same text from a session log's header (replay, analyze) passes the same cap.
  const std::string message = error_of(std::string(kMaxStudyConfigBytes + 1, '#'));
  EXPECT_EQ(message, kPath + ": " + std::to_string(kMaxStudyConfigBytes + 1) +
                         " bytes: expected a study config of at most 16 MiB");
  // At the cap it is read and parsed (the padding is a comment).
  std::string text = ConfigText().text() + "#";
  text.resize(kMaxStudyConfigBytes, ' ');
  EXPECT_EQ(parse_study_config_file(dir.write("at_cap.toml", text), renderer_scene_catalog()).source_text.size(),
            kMaxStudyConfigBytes);
}

TEST(ProtocolsConfig, AByteOrderMarkIsAcceptedAndIgnored) {
  // Editors on Windows write one; a config with it is the same study (and hashes its own bytes).
  const std::string text = ConfigText().text();
  const StudyConfig plain = parse(text);
  const StudyConfig marked = parse("\xEF\xBB\xBF" + text);
  EXPECT_EQ(marked.name, plain.name);
  EXPECT_EQ(marked.blocks.size(), plain.blocks.size());
  EXPECT_EQ(marked.source_text, "\xEF\xBB\xBF" + text);
  const testing::TempDir dir;
  EXPECT_EQ(parse_study_config_file(dir.write("bom.toml", "\xEF\xBB\xBF" + text), renderer_scene_catalog()).name,
            plain.name);
  // Lines are counted as without it, and only the first three bytes may be one.
  expect_error("\xEF\xBB\xBF" + replace_once(text, "seed = 7", "seed = -7"), line_of(text, "seed = 7"), "study.seed",
               "non-negative");
  EXPECT_EQ(error_of("\n\xEF\xBB\xBF" + text).rfind(kPath + ":2: ", 0), 0u);
}

// --- the renderers' frame-size rules, named after the config's fields -------------------------------

TEST(ProtocolsConfig, FptFramesOfAnySizeAreAccepted) {
  // Issue 18: fpt used to need sides that are multiples of 4 (a 1366x768 panel could not run it).
  ConfigText base;
  base.stimulus = replace_once(
      replace_once(base.stimulus, "method = \"gt\"\n\n[stimulus.test]", "method = \"pt\"\n\n[stimulus.test]"),
      "[stimulus.test]\nmethod = \"gt\"", "[stimulus.test]\nmethod = \"fpt\"");
  base.levels = "";
  base.blocks = "[[block]]\nscene = \"courtyard\"\n";
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"width_px = 320", "width_px = 318"},
                                 {"height_px = 180", "height_px = 181"}}) {
    ConfigText odd = base;
    odd.display = replace_once(odd.display, from, to);
    EXPECT_EQ(parse(odd.text()).stimulus.test.method, RenderMethod::foveated_path_traced) << to;
  }
}

TEST(ProtocolsConfig, SphereTracedSamplesAFrameNamingTheDisplayField) {
  // 16384 x 16384 x 4 samples: refused by the renderer at run as "--width x --height x --spp = ...".
  ConfigText base;
  base.display = replace_once(replace_once(base.display, "width_px = 320", "width_px = 16384"), "height_px = 180",
                              "height_px = 16384");
  base.stimulus = replace_once(base.stimulus, "[stimulus.test]\nmethod = \"gt\"",
                               "[stimulus.test]\nmethod = \"gt\"\nsamples_per_pixel = 4");
  std::string text = base.text();
  expect_error(text, line_of(text, "width_px = 16384"), "display.width_px",
               "expected width_px x height_px x samples_per_pixel of at most 268435456 samples a frame (gt), got "
               "16384 x 16384 x 4 = 1073741824");
  // Every stimulus counts: here only the level 16 of 8192 x 4096 is too many.
  base.display = replace_once(replace_once(base.display, "width_px = 16384", "width_px = 8192"), "height_px = 16384",
                              "height_px = 4096");
  base.stimulus = replace_once(base.stimulus, "\nsamples_per_pixel = 4", "");
  base.levels = "[levels]\nparameter = \"samples_per_pixel\"\nvalues = [1, 4, 16]\n";
  text = base.text();
  expect_error(text, line_of(text, "width_px = 8192"), "display.width_px", "8192 x 4096 x 16 = 536870912");
  base.levels = "[levels]\nparameter = \"samples_per_pixel\"\nvalues = [1, 4]\n";
  EXPECT_EQ(parse(base.text()).display.width_px, 8192);
}

TEST(ProtocolsConfig, TwoAfcBetter) {
  ConfigText base;
  base.attention.clear();
  base.protocol = replace_once(base.protocol, "question = \"same\"", "question = \"better\"");
  const StudyConfig config = parse(base.text());
  EXPECT_EQ(config.protocol.kind, ProtocolKind::two_afc);
  EXPECT_EQ(config.protocol.two_afc_question, TwoAfcQuestion::better);
  EXPECT_EQ(answer_names(config), (std::vector<std::string>{"first", "second"}));
  EXPECT_EQ(keys_of(config, "first"), (std::vector<std::string>{"1", "left", "pad_left"}));
  EXPECT_EQ(keys_of(config, "second"), (std::vector<std::string>{"2", "right", "pad_right"}));
  EXPECT_EQ(config.protocol.question.text, "Which sequence had the better quality?");
  EXPECT_EQ(protocol_answers(ProtocolKind::two_afc, TwoAfcQuestion::better),
            (std::vector<std::string>{"first", "second"}));
}

TEST(ProtocolsConfig, TwoAfcNeedsAKnownQuestion) {
  ConfigText base;
  base.protocol = replace_once(base.protocol, "question = \"same\"", "question = \"worse\"");
  const std::string text = base.text();
  expect_error(text, line_of(text, "question = \"worse\""), "protocol.question", "\"worse\"");
  base.protocol = replace_once(base.protocol, "question = \"worse\"\n", "");
  const std::string missing = base.text();
  // A missing key: the error names the table's line ([protocol]).
  expect_error(missing, line_of(missing, "[protocol]"), "protocol.question", "missing");
}

TEST(ProtocolsConfig, Pair) {
  ConfigText base;
  base.protocol =
      "[protocol]\nkind = \"pair\"\nrepeats = 4\nquestion_text = \"Better?\"\ntrial_order = \"fixed\"\n"
      "block_order = \"random\"\n";
  const StudyConfig config = parse(base.text());
  EXPECT_EQ(config.protocol.kind, ProtocolKind::pair);
  EXPECT_EQ(config.protocol.repeats, 4);
  EXPECT_TRUE(config.protocol.counterbalance);
  EXPECT_FALSE(config.protocol.randomise_trials);
  EXPECT_EQ(config.protocol.block_order, ProtocolConfig::BlockOrder::random);
  EXPECT_EQ(config.protocol.question.text, "Better?");
  EXPECT_EQ(answer_names(config), (std::vector<std::string>{"first", "second", "same"}));
  EXPECT_EQ(keys_of(config, "same"), (std::vector<std::string>{"s", "space", "pad_a"}));
  EXPECT_DOUBLE_EQ(config.attention.share, 0.2);  // pair has a "same" answer
}

TEST(ProtocolsConfig, PairRejectsTheTwoAfcQuestionKey) {
  ConfigText base;
  base.protocol = "[protocol]\nkind = \"pair\"\nquestion = \"same\"\nrepeats = 2\n";
  const std::string text = base.text();
  expect_error(text, line_of(text, "question = \"same\""), "protocol.question", "unknown key");
}

TEST(ProtocolsConfig, Ramp) {
  ConfigText base;
  base.attention.clear();
  base.levels = replace_once(base.levels, "higher_is_better = true", "higher_is_better = false");
  base.protocol = "[protocol]\nkind = \"ramp\"\nrepeats = 3\n";
  const StudyConfig config = parse(base.text());
  EXPECT_EQ(config.protocol.kind, ProtocolKind::ramp);
  EXPECT_EQ(config.protocol.repeats, 3);  // odd is fine: no counterbalancing for ramps
  EXPECT_FALSE(config.protocol.counterbalance);
  EXPECT_FALSE(config.levels.higher_is_better);
  EXPECT_EQ(answer_names(config), (std::vector<std::string>{"increased", "decreased", "same"}));
  EXPECT_EQ(keys_of(config, "increased"), (std::vector<std::string>{"up", "pad_up"}));
  EXPECT_EQ(keys_of(config, "decreased"), (std::vector<std::string>{"down", "pad_down"}));
  EXPECT_EQ(config.protocol.question.text, "Did the quality increase, decrease or stay the same?");
}

TEST(ProtocolsConfig, Slider) {
  ConfigText base;
  base.attention.clear();
  base.protocol = "[protocol]\nkind = \"slider\"\n";
  StudyConfig config = parse(base.text());
  EXPECT_EQ(config.protocol.kind, ProtocolKind::slider);
  EXPECT_EQ(config.protocol.repeats, 1);
  EXPECT_FALSE(config.protocol.counterbalance);
  EXPECT_DOUBLE_EQ(config.protocol.slider.start_level, 4.0);  // the first level by default
  EXPECT_EQ(answer_names(config), (std::vector<std::string>{"up", "down", "reference", "save"}));
  EXPECT_EQ(keys_of(config, "save"), (std::vector<std::string>{"enter", "space", "pad_a"}));

  base.protocol = "[protocol]\nkind = \"slider\"\nstart_level = 16\n";
  config = parse(base.text());
  EXPECT_DOUBLE_EQ(config.protocol.slider.start_level, 16.0);

  base.protocol = "[protocol]\nkind = \"slider\"\nstart_level = 17\n";
  const std::string text = base.text();
  expect_error(text, line_of(text, "start_level = 17"), "protocol.start_level", "[levels]");
}

TEST(ProtocolsConfig, Rating) {
  ConfigText base;
  base.protocol = "[protocol]\nkind = \"rating\"\nrepeats = 2\ncounterbalance = false\n";
  const StudyConfig config = parse(base.text());
  EXPECT_EQ(config.protocol.kind, ProtocolKind::rating);
  EXPECT_FALSE(config.protocol.counterbalance);
  EXPECT_EQ(answer_names(config), (std::vector<std::string>{"1", "2", "3"}));
  EXPECT_EQ(keys_of(config, "1"), (std::vector<std::string>{"1", "pad_b"}));
  EXPECT_EQ(keys_of(config, "3"), (std::vector<std::string>{"3", "pad_a"}));
  EXPECT_DOUBLE_EQ(config.attention.share, 0.2);
}

TEST(ProtocolsConfig, ProtocolNamesAndAnswers) {
  EXPECT_STREQ(protocol_name(ProtocolKind::two_afc), "2afc");
  EXPECT_STREQ(protocol_name(ProtocolKind::pair), "pair");
  EXPECT_STREQ(protocol_name(ProtocolKind::ramp), "ramp");
  EXPECT_STREQ(protocol_name(ProtocolKind::slider), "slider");
  EXPECT_STREQ(protocol_name(ProtocolKind::rating), "rating");
  EXPECT_EQ(protocol_answers(ProtocolKind::two_afc, TwoAfcQuestion::same),
            (std::vector<std::string>{"same", "different"}));
  EXPECT_EQ(protocol_answers(ProtocolKind::rating, TwoAfcQuestion::same), (std::vector<std::string>{"1", "2", "3"}));
}

TEST(ProtocolsConfig, UnknownProtocolKind) {
  ConfigText base;
  base.protocol = "[protocol]\nkind = \"3afc\"\n";
  const std::string text = base.text();
  expect_error(text, line_of(text, "kind = \"3afc\""), "protocol.kind", "\"3afc\"");
}

TEST(ProtocolsConfig, Variants) {
  ConfigText base;
  base.stimulus = R"([stimulus]
duration_s = 0.5
frames_per_second = 10

[stimulus.reference]
method = "gt"
samples_per_pixel = 4

[stimulus.test]
method = "ipr"
pyramid_levels = 3

[[stimulus.variant]]
name = "coarse"
pyramid_levels = 2

[[stimulus.variant]]
name = "fine"
pyramid_levels = 5
min_filter_size = 1
)";
  const StudyConfig config = parse(base.text());
  EXPECT_EQ(config.stimulus.reference.parameters, (std::map<std::string, double>{{"samples_per_pixel", 4.0}}));
  EXPECT_EQ(describe(config.stimulus.test.method).name, "ipr");
  EXPECT_EQ(config.stimulus.test.parameters, (std::map<std::string, double>{{"pyramid_levels", 3.0}}));
  ASSERT_EQ(config.stimulus.variants.size(), 2u);
  EXPECT_EQ(config.stimulus.variants[0].name, "coarse");
  EXPECT_EQ(config.stimulus.variants[0].parameters, (std::map<std::string, double>{{"pyramid_levels", 2.0}}));
  EXPECT_EQ(config.stimulus.variants[1].name, "fine");
  EXPECT_EQ(config.stimulus.variants[1].parameters,
            (std::map<std::string, double>{{"min_filter_size", 1.0}, {"pyramid_levels", 5.0}}));
}

TEST(ProtocolsConfig, VariantErrors) {
  ConfigText base;
  const std::string variants =
      "\n[[stimulus.variant]]\nname = \"a\"\nmax_steps = 8\n\n[[stimulus.variant]]\nname = \"a\"\n";
  base.stimulus += variants;
  std::string text = base.text();
  expect_error(text, line_of(text, "name = \"a\"", 2), "stimulus.variant[2].name", "duplicate variant \"a\"");

  base = ConfigText{};
  base.stimulus += "\n[[stimulus.variant]]\nname = \"a\"\npyramid_levels = 3\n";  // the test method is gt
  text = base.text();
  expect_error(text, line_of(text, "pyramid_levels = 3"), "stimulus.variant[1].pyramid_levels",
               "not a parameter of method \"gt\"");

  base = ConfigText{};
  base.stimulus += "\n[[stimulus.variant]]\nname = \"a/b\"\n";
  text = base.text();
  expect_error(text, line_of(text, "name = \"a/b\""), "stimulus.variant[1].name", "expected");

  base = ConfigText{};
  base.stimulus += "\n[[stimulus.variant]]\nmax_steps = 8\n";
  text = base.text();
  expect_error(text, line_of(text, "[[stimulus.variant]]"), "stimulus.variant[1].name", "missing");
}

TEST(ProtocolsConfig, CustomKeys) {
  ConfigText base;
  base.protocol += "\n[protocol.keys]\nsame = [\"j\", \"pad_x\"]\ndifferent = [\"k\"]\n";
  const StudyConfig config = parse(base.text());
  EXPECT_EQ(answer_names(config), (std::vector<std::string>{"same", "different"}));
  EXPECT_EQ(keys_of(config, "same"), (std::vector<std::string>{"j", "pad_x"}));
  EXPECT_EQ(keys_of(config, "different"), (std::vector<std::string>{"k"}));

  // Only one answer rebound: the other keeps its defaults.
  base = ConfigText{};
  base.protocol += "\n[protocol.keys]\ndifferent = [\"k\", \"enter\"]\n";
  const StudyConfig partial = parse(base.text());
  EXPECT_EQ(keys_of(partial, "same"), (std::vector<std::string>{"s", "space", "pad_a"}));
  EXPECT_EQ(keys_of(partial, "different"), (std::vector<std::string>{"k", "enter"}));
}

TEST(ProtocolsConfig, KeyBoundToTwoAnswers) {
  ConfigText base;
  // "d" is the default key of "different".
  base.protocol += "\n[protocol.keys]\nsame = [\"d\"]\n";
  const std::string text = base.text();
  const std::string message = error_of(text);
  SCOPED_TRACE(message);
  EXPECT_EQ(message.find('\n'), std::string::npos);
  EXPECT_EQ(message.rfind(kPath + ":" + std::to_string(line_of(text, "[protocol.keys]")) + ": protocol.keys: ", 0), 0u);
  EXPECT_NE(message.find("\"d\""), std::string::npos);
  EXPECT_NE(message.find("\"same\""), std::string::npos);
  EXPECT_NE(message.find("\"different\""), std::string::npos);

  base = ConfigText{};
  base.protocol += "\n[protocol.keys]\nsame = [\"j\"]\ndifferent = [\"k\", \"j\"]\n";
  const std::string both = base.text();
  EXPECT_NE(error_of(both).find("\"j\""), std::string::npos);
}

TEST(ProtocolsConfig, KeyErrors) {
  ConfigText base;
  base.protocol += "\n[protocol.keys]\nsame = [\"F1\"]\n";
  std::string text = base.text();
  expect_error(text, line_of(text, "same = [\"F1\"]"), "protocol.keys.same", "unknown key \"F1\"");

  base = ConfigText{};
  base.protocol += "\n[protocol.keys]\nfirst = [\"f\"]\n";
  text = base.text();
  expect_error(text, line_of(text, "first = [\"f\"]"), "protocol.keys.first", "not an answer of this protocol");

  base = ConfigText{};
  base.protocol += "\n[protocol.keys]\nsame = \"s\"\n";
  text = base.text();
  expect_error(text, line_of(text, "same = \"s\""), "protocol.keys.same", "array of strings");

  base = ConfigText{};
  base.protocol += "\n[protocol.keys]\nsame = []\n";
  text = base.text();
  expect_error(text, line_of(text, "same = []"), "protocol.keys.same", "non-empty");
}

// --- errors ---------------------------------------------------------------------------------------

TEST(ProtocolsConfig, UnknownKeyWithItsLine) {
  ConfigText base;
  base.display = replace_once(base.display, "refresh_hz = 60\n", "refresh_hz = 60\ncolour = 3\n");
  std::string text = base.text();
  expect_error(text, line_of(text, "colour = 3"), "display.colour", "unknown key");

  base = ConfigText{};
  base.study += "sede = 3\n";
  text = base.text();
  expect_error(text, line_of(text, "sede = 3"), "study.sede", "unknown key");

  base = ConfigText{};
  base.timing += "black_intervall_s = 1\n";
  text = base.text();
  expect_error(text, line_of(text, "black_intervall_s"), "timing.black_intervall_s", "unknown key");

  base = ConfigText{};
  base.blocks += "scale = 2\n";  // in the second block
  text = base.text();
  expect_error(text, line_of(text, "scale = 2"), "block[2].scale", "unknown key");

  base = ConfigText{};
  base.protocol += "repeat = 2\n";
  text = base.text();
  expect_error(text, line_of(text, "repeat = 2"), "protocol.repeat", "unknown key");

  base = ConfigText{};
  base.levels += "higher_is_beter = false\n";
  text = base.text();
  expect_error(text, line_of(text, "higher_is_beter"), "levels.higher_is_beter", "unknown key");

  base = ConfigText{};
  base.attention += "breaks = 2\n";
  text = base.text();
  expect_error(text, line_of(text, "breaks = 2"), "attention.breaks", "unknown key");
}

TEST(ProtocolsConfig, UnknownTopLevelTable) {
  ConfigText base;
  base.blocks += "\n[extras]\nfoo = 1\n";
  const std::string text = base.text();
  expect_error(text, line_of(text, "[extras]"), "extras", "unknown key");
}

TEST(ProtocolsConfig, WrongType) {
  ConfigText base;
  base.display = replace_once(base.display, "width_px = 320", "width_px = \"320\"");
  std::string text = base.text();
  expect_error(text, line_of(text, "width_px = \"320\""), "display.width_px", "expected an integer, got a string");

  base = ConfigText{};
  base.display = replace_once(base.display, "width_px = 320", "width_px = 320.5");
  text = base.text();
  expect_error(text, line_of(text, "width_px = 320.5"), "display.width_px", "expected an integer, got a number");

  base = ConfigText{};
  base.display = replace_once(base.display, "refresh_hz = 60", "refresh_hz = \"60\"");
  text = base.text();
  expect_error(text, line_of(text, "refresh_hz = \"60\""), "display.refresh_hz", "expected a number, got a string");

  base = ConfigText{};
  base.display += "fullscreen = 1\n";
  text = base.text();
  expect_error(text, line_of(text, "fullscreen = 1"), "display.fullscreen", "expected true or false, got an integer");

  base = ConfigText{};
  base.study = replace_once(base.study, "name = \"unit\"", "name = 3");
  text = base.text();
  expect_error(text, line_of(text, "name = 3"), "study.name", "expected a string, got an integer");

  base = ConfigText{};
  base.levels = replace_once(base.levels, "values = [4, 8, 16, 32, 64]", "values = 4");
  text = base.text();
  expect_error(text, line_of(text, "values = 4"), "levels.values", "array of numbers");

  base = ConfigText{};
  base.levels = replace_once(base.levels, "values = [4, 8, 16, 32, 64]", "values = [4, \"8\"]");
  text = base.text();
  expect_error(text, line_of(text, "values = [4"), "levels.values", "a string");

  base = ConfigText{};
  base.study += "\ndisplay = 3\n";  // a value where a table is required
  base.display.clear();
  text = base.text();
  expect_error(text, line_of(text, "display = 3"), "study.display", "unknown key");
}

TEST(ProtocolsConfig, TableWhereAValueIsRequired) {
  ConfigText base;
  base.display.clear();
  base.study = "display = 3\n" + base.study;  // a root key, before [study]
  const std::string text = base.text();
  expect_error(text, line_of(text, "display = 3"), "display", "expected a table ([display]), got an integer");
}

TEST(ProtocolsConfig, OutOfRange) {
  ConfigText base;
  base.display = replace_once(base.display, "width_px = 320", "width_px = 4");
  std::string text = base.text();
  expect_error(text, line_of(text, "width_px = 4"), "display.width_px", "expected a value in [8, 16384], got 4");

  base = ConfigText{};
  base.attention = replace_once(base.attention, "share = 0.2", "share = 0.95");
  text = base.text();
  expect_error(text, line_of(text, "share = 0.95"), "attention.share", "expected a value in [0, 0.9], got 0.95");

  base = ConfigText{};
  base.protocol = replace_once(base.protocol, "repeats = 2", "repeats = 0");
  text = base.text();
  expect_error(text, line_of(text, "repeats = 0"), "protocol.repeats", "[1, 1000]");

  base = ConfigText{};
  base.stimulus = replace_once(base.stimulus, "[stimulus.reference]\nmethod = \"gt\"\n",
                               "[stimulus.reference]\nmethod = \"gt\"\nsamples_per_pixel = 3\n");
  text = base.text();
  expect_error(text, line_of(text, "samples_per_pixel = 3"), "stimulus.reference.samples_per_pixel",
               "expected one of 1 4 16, got 3");

  base = ConfigText{};
  base.levels = replace_once(base.levels, "values = [4, 8, 16, 32, 64]", "values = [4, 8, 5000]");
  text = base.text();
  expect_error(text, line_of(text, "values = [4, 8, 5000]"), "levels.values", "got 5000");

  base = ConfigText{};
  base.levels = replace_once(base.levels, "values = [4, 8, 16, 32, 64]", "values = [4, 8.5]");
  text = base.text();
  expect_error(text, line_of(text, "values = [4, 8.5]"), "levels.values", "whole number");

  base = ConfigText{};
  base.levels = replace_once(base.levels, "values = [4, 8, 16, 32, 64]", "values = [8, 4]");
  text = base.text();
  expect_error(text, line_of(text, "values = [8, 4]"), "levels.values", "ascending");

  base = ConfigText{};
  base.levels = replace_once(base.levels, "values = [4, 8, 16, 32, 64]", "values = [4, 4]");
  text = base.text();
  expect_error(text, line_of(text, "values = [4, 4]"), "levels.values", "ascending");

  base = ConfigText{};
  base.study = replace_once(base.study, "seed = 7", "seed = -1");
  text = base.text();
  expect_error(text, line_of(text, "seed = -1"), "study.seed", "non-negative");

  base = ConfigText{};
  base.stimulus = replace_once(base.stimulus, "duration_s = 0.5", "duration_s = 0");
  text = base.text();
  expect_error(text, line_of(text, "duration_s = 0"), "stimulus.duration_s", "expected a value in");

  base = ConfigText{};
  base.timing = replace_once(base.timing, "black_interval_s = 0.25", "black_interval_s = -0.1");
  text = base.text();
  expect_error(text, line_of(text, "black_interval_s = -0.1"), "timing.black_interval_s", "expected a value in");

  base = ConfigText{};
  base.attention = replace_once(base.attention, "max_errors = 3", "max_errors = 0");
  text = base.text();
  expect_error(text, line_of(text, "max_errors = 0"), "attention.max_errors", "expected a value in [1, 1000]");

  base = ConfigText{};
  base.display = replace_once(base.display, "refresh_hz = 60", "refresh_hz = inf");
  text = base.text();
  expect_error(text, line_of(text, "refresh_hz = inf"), "display.refresh_hz", "finite");
}

// A number out of its range is quoted as it was given: not rounded to 6 digits (0.9000001 is not
// "0.9", which is in range), not at 17 (0.00001 is not 1.0000000000000001e-05), and the range's
// ends as people write them.
TEST(ProtocolsConfig, OutOfRangeNumbersAreQuotedAtThePrecisionGiven) {
  ConfigText base;
  base.attention = replace_once(base.attention, "share = 0.2", "share = 0.9000001");
  std::string text = base.text();
  expect_error(text, line_of(text, "share = 0.9000001"), "attention.share",
               "expected a value in [0, 0.9], got 0.9000001");

  base = ConfigText{};
  base.levels = replace_once(base.levels, "parameter = \"max_steps\"\nvalues = [4, 8, 16, 32, 64]",
                             "parameter = \"hit_threshold\"\nvalues = [0.00001, 0.3]");
  text = base.text();
  expect_error(text, line_of(text, "values = [0.00001, 0.3]"), "levels.values",
               "expected a value in [0.0001, 8], got 1e-05");

  base = ConfigText{};
  base.stimulus = replace_once(base.stimulus, "[stimulus.test]\nmethod = \"gt\"\n",
                               "[stimulus.test]\nmethod = \"gt\"\nhit_threshold = 8.000000000000002\n");
  text = base.text();
  expect_error(text, line_of(text, "hit_threshold = 8.000000000000002"), "stimulus.test.hit_threshold",
               "expected a value in [0.0001, 8], got 8.000000000000002");
}

// QUEST+'s threshold grid is in the levels' units: a grid of +-1e308 (whose span overflows) or one
// far past every level is refused naming the key and the range it may take.
TEST(ProtocolsConfig, AQuestPlusThresholdGridFarPastTheLevelsIsRefused) {
  ConfigText base;
  base.blocks =
      "[[block]]\nscene = \"primitives\"\nprocedure = \"q\"\n\n[procedure.q]\nkind = \"quest_plus\"\n"
      "max_trials = 20\nthresholds = [-1e308, 1e308]\n";
  std::string text = base.text();
  expect_error(text, line_of(text, "thresholds = [-1e308, 1e308]"), "procedure.q.thresholds",
               "expected values from -596 to 664 (the levels' range, 4 to 64, widened by 10 times its span on each "
               "side), got -1e+308");
  base.blocks = replace_once(base.blocks, "thresholds = [-1e308, 1e308]", "thresholds = [4, 664.5]");
  text = base.text();
  expect_error(text, line_of(text, "thresholds = [4, 664.5]"), "procedure.q.thresholds", "got 664.5");
  base.blocks = replace_once(base.blocks, "thresholds = [4, 664.5]", "thresholds = [-596, 664]");
  EXPECT_NO_THROW(parse(base.text()));
}

TEST(ProtocolsConfig, HugeIntegersAreOutOfRangeNotWrapped) {
  // 2^32 + 320 is far outside [8, 16384]; it must not be read as 320 (an int cast before the range
  // check would wrap it into range).
  ConfigText base;
  base.display = replace_once(base.display, "width_px = 320", "width_px = 4294967616");
  std::string text = base.text();
  expect_error(text, line_of(text, "width_px = 4294967616"), "display.width_px", "expected a value in [8, 16384]");

  base = ConfigText{};
  base.protocol = replace_once(base.protocol, "repeats = 2", "repeats = 4294967298");  // 2^32 + 2
  text = base.text();
  expect_error(text, line_of(text, "repeats = 4294967298"), "protocol.repeats", "expected a value in [1, 1000]");

  base = ConfigText{};
  base.attention = replace_once(base.attention, "max_errors = 3", "max_errors = -4294967293");  // -2^32 + 3
  text = base.text();
  expect_error(text, line_of(text, "max_errors = -4294967293"), "attention.max_errors",
               "expected a value in [1, 1000]");
}

TEST(ProtocolsConfig, UnsafeNames) {
  ConfigText base;
  base.study = replace_once(base.study, "name = \"unit\"", "name = \"../unit\"");
  std::string text = base.text();
  expect_error(text, line_of(text, "name = \"../unit\""), "study.name", "expected");

  base = ConfigText{};
  base.study = replace_once(base.study, "name = \"unit\"", "name = \"\"");
  text = base.text();
  expect_error(text, line_of(text, "name = \"\""), "study.name", "expected");

  base = ConfigText{};
  base.study = replace_once(base.study, "name = \"unit\"", "name = \"" + std::string(65, 'a') + "\"");
  text = base.text();
  expect_error(text, line_of(text, "name = \"aaa"), "study.name", "expected");

  base = ConfigText{};
  base.blocks = replace_once(base.blocks, "name = \"cols\"", "name = \"a b\"");
  text = base.text();
  expect_error(text, line_of(text, "name = \"a b\""), "block[2].name", "expected");
}

TEST(ProtocolsConfig, MissingRequiredKey) {
  // A missing key is reported at the line of its table (the header says LINE may be omitted; when
  // it is present it must be the table's line).
  const auto check_missing = [](const std::string& text, const std::string& table_header, const std::string& key) {
    const std::string message = error_of(text);
    SCOPED_TRACE(message);
    EXPECT_EQ(message.find('\n'), std::string::npos);
    const std::string with_line = kPath + ":" + std::to_string(line_of(text, table_header)) + ": " + key + ": ";
    const std::string without_line = kPath + ": " + key + ": ";
    EXPECT_TRUE(message.rfind(with_line, 0) == 0 || message.rfind(without_line, 0) == 0)
        << "expected \"" << with_line << "\" or \"" << without_line << "\"";
    EXPECT_NE(message.find("missing"), std::string::npos);
  };
  ConfigText base;
  base.display = replace_once(base.display, "height_px = 180\n", "");
  check_missing(base.text(), "[display]", "display.height_px");

  base = ConfigText{};
  base.display = replace_once(base.display, "viewing_distance_mm = 500\n", "");
  check_missing(base.text(), "[display]", "display.viewing_distance_mm");

  base = ConfigText{};
  base.study = replace_once(base.study, "seed = 7\n", "");
  check_missing(base.text(), "[study]", "study.seed");

  base = ConfigText{};
  base.stimulus = replace_once(base.stimulus, "duration_s = 0.5\n", "");
  check_missing(base.text(), "[stimulus]", "stimulus.duration_s");

  base = ConfigText{};
  base.stimulus = replace_once(base.stimulus, "[stimulus.test]\nmethod = \"gt\"\n", "[stimulus.test]\n");
  check_missing(base.text(), "[stimulus.test]", "stimulus.test.method");

  base = ConfigText{};
  base.protocol = replace_once(base.protocol, "kind = \"2afc\"\n", "");
  check_missing(base.text(), "[protocol]", "protocol.kind");

  base = ConfigText{};
  base.attention = replace_once(base.attention, "share = 0.2\n", "");
  check_missing(base.text(), "[attention]", "attention.share");

  base = ConfigText{};
  base.blocks = replace_once(base.blocks, "scene = \"columns\"\n", "");
  const std::string no_scene = base.text();
  const std::string message = error_of(no_scene);
  EXPECT_NE(message.find("block[2].scene: missing"), std::string::npos) << message;
}

TEST(ProtocolsConfig, MissingRequiredTable) {
  for (const char* table : {"protocol", "block", "display", "study", "stimulus"}) {
    ConfigText base;
    if (std::string(table) == "protocol") base.protocol.clear();
    if (std::string(table) == "block") base.blocks.clear();
    if (std::string(table) == "display") base.display.clear();
    if (std::string(table) == "study") base.study.clear();
    if (std::string(table) == "stimulus") base.stimulus.clear();
    const std::string message = error_of(base.text());
    SCOPED_TRACE(message);
    EXPECT_EQ(message.find('\n'), std::string::npos);
    EXPECT_EQ(message.rfind(kPath + ":", 0), 0u);
    EXPECT_NE(message.find(std::string(" ") + table + ": "), std::string::npos);
    EXPECT_NE(message.find("missing"), std::string::npos);
  }
}

TEST(ProtocolsConfig, DuplicateBlockName) {
  ConfigText base;
  base.blocks =
      "[[block]]\nscene = \"primitives\"\n\n[[block]]\nscene = \"columns\"\n\n[[block]]\nscene = \"primitives\"\n";
  std::string text = base.text();
  // The third block has no name key: the error points at its [[block]] header.
  expect_error(text, line_of(text, "[[block]]", 3), "block[3].name", "duplicate block \"primitives\"");

  base.blocks = "[[block]]\nscene = \"primitives\"\nname = \"x\"\n\n[[block]]\nscene = \"columns\"\nname = \"x\"\n";
  text = base.text();
  expect_error(text, line_of(text, "name = \"x\"", 2), "block[2].name", "duplicate block \"x\"");

  // The same scene under two names is fine.
  base.blocks =
      "[[block]]\nscene = \"primitives\"\nname = \"p1\"\n\n[[block]]\nscene = \"primitives\"\nname = \"p2\"\n";
  const StudyConfig config = parse(base.text());
  ASSERT_EQ(config.blocks.size(), 2u);
  EXPECT_EQ(config.blocks[1].name, "p2");
  EXPECT_EQ(config.blocks[1].scene, "primitives");
}

TEST(ProtocolsConfig, UnknownScene) {
  ConfigText base;
  base.blocks = replace_once(base.blocks, "scene = \"columns\"", "scene = \"no_such_scene\"");
  const std::string text = base.text();
  expect_error(text, line_of(text, "scene = \"no_such_scene\""), "block[2].scene",
               "no built-in scene or file \"no_such_scene\"");
  // The message lists the built-in scenes.
  EXPECT_NE(error_of(text).find("primitives"), std::string::npos);
}

TEST(ProtocolsConfig, SceneFileRelativeToTheConfig) {
  static std::atomic<int> counter{0};
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("fovlab_config_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  std::filesystem::create_directories(dir / "scenes");
  {
    std::ofstream scene(dir / "scenes" / "my_scene.glsl");
    scene << "// a scene\n";
  }
  ConfigText base;
  base.blocks = "[[block]]\nscene = \"scenes/my_scene.glsl\"\n";
  const std::string config_path = (dir / "study.toml").string();
  const StudyConfig config = parse_study_config_text(base.text(), config_path, renderer_scene_catalog());
  ASSERT_EQ(config.blocks.size(), 1u);
  EXPECT_EQ(config.blocks[0].name, "my_scene");
  EXPECT_EQ(std::filesystem::path(config.blocks[0].scene), (dir / "scenes" / "my_scene.glsl").lexically_normal());
  // The same file relative to another folder does not exist.
  EXPECT_THROW(parse_study_config_text(base.text(), kPath, renderer_scene_catalog()), InputError);
  std::filesystem::remove_all(dir);
}

TEST(ProtocolsConfig, UnknownMethod) {
  ConfigText base;
  base.stimulus =
      replace_once(base.stimulus, "[stimulus.test]\nmethod = \"gt\"", "[stimulus.test]\nmethod = \"foveated\"");
  const std::string text = base.text();
  expect_error(text, line_of(text, "method = \"foveated\""), "stimulus.test.method",
               "expected one of gt, ipr, fipr, pt, fpt, rmfr, hyperbolic, linear, kfr, pt-rmfr, pt-hyperbolic, "
               "pt-linear, pt-kfr, img-rmfr, img-hyperbolic, img-linear, img-kfr, volume, fvolume, got \"foveated\"");
}

TEST(ProtocolsConfig, ParameterNotOfTheMethod) {
  ConfigText base;
  base.stimulus = replace_once(base.stimulus, "[stimulus.test]\nmethod = \"gt\"",
                               "[stimulus.test]\nmethod = \"gt\"\npyramid_levels = 3");
  std::string text = base.text();
  expect_error(text, line_of(text, "pyramid_levels = 3"), "stimulus.test.pyramid_levels",
               "not a parameter of method \"gt\"");

  // The levels parameter must be one of the test method's parameters too.
  base = ConfigText{};
  base.levels = replace_once(base.levels, "parameter = \"max_steps\"", "parameter = \"pyramid_levels\"");
  text = base.text();
  expect_error(text, line_of(text, "parameter = \"pyramid_levels\""), "levels.parameter", "\"gt\"");
}

TEST(ProtocolsConfig, CounterbalanceNeedsEvenRepeats) {
  ConfigText base;
  base.protocol = replace_once(base.protocol, "repeats = 2", "repeats = 3");
  // Odd repeats: not counterbalanced by default (a fair coin per trial)...
  EXPECT_FALSE(parse(base.text()).protocol.counterbalance);
  // ...and asking for counterbalancing with them is an error.
  base.protocol += "counterbalance = true\n";
  std::string text = base.text();
  expect_error(text, line_of(text, "repeats = 3"), "protocol.repeats", "even");

  // Ramps and sliders have no order to counterbalance.
  base = ConfigText{};
  base.attention.clear();
  base.protocol = "[protocol]\nkind = \"ramp\"\ncounterbalance = true\nrepeats = 2\n";
  text = base.text();
  expect_error(text, line_of(text, "counterbalance = true"), "protocol.counterbalance", "counterbalance");
}

TEST(ProtocolsConfig, RampAndSliderNeedLevels) {
  for (const char* kind : {"ramp", "slider"}) {
    ConfigText base;
    base.attention.clear();
    base.levels.clear();
    base.protocol = std::string("[protocol]\nkind = \"") + kind + "\"\n";
    std::string text = base.text();
    expect_error(text, line_of(text, "kind = "), "protocol.kind", "[levels]");

    base.levels = "[levels]\nparameter = \"max_steps\"\nvalues = [16]\n";  // one level is not a ladder
    text = base.text();
    expect_error(text, line_of(text, "kind = "), "protocol.kind", "at least two");
  }
}

TEST(ProtocolsConfig, AttentionChecksNeedAnIdenticalAnswer) {
  const std::vector<std::string> protocols = {"[protocol]\nkind = \"2afc\"\nquestion = \"better\"\nrepeats = 2\n",
                                              "[protocol]\nkind = \"ramp\"\n", "[protocol]\nkind = \"slider\"\n"};
  for (const std::string& protocol : protocols) {
    ConfigText base;
    base.protocol = protocol;
    const std::string text = base.text();
    expect_error(text, line_of(text, "share = 0.2"), "attention.share", "identical");
    // share = 0 is allowed with any protocol.
    base.attention = replace_once(base.attention, "share = 0.2", "share = 0");
    EXPECT_DOUBLE_EQ(parse(base.text()).attention.share, 0.0);
  }
}

TEST(ProtocolsConfig, InvalidTomlSyntaxWithItsLine) {
  ConfigText base;
  base.display = replace_once(base.display, "height_px = 180", "height_px = = 180");
  std::string text = base.text();
  std::string message = error_of(text);
  EXPECT_EQ(message.rfind(kPath + ":" + std::to_string(line_of(text, "height_px = = 180")) + ": ", 0), 0u) << message;
  EXPECT_NE(message.find("not valid TOML"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;

  base = ConfigText{};
  base.blocks += "[[block]\nscene = \"temple\"\n";  // unclosed array-of-tables header
  text = base.text();
  message = error_of(text);
  EXPECT_EQ(message.rfind(kPath + ":" + std::to_string(line_of(text, "[[block]\n")) + ": ", 0), 0u) << message;
  EXPECT_NE(message.find("not valid TOML"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;

  // A key given twice is invalid TOML, reported at the second one.
  base = ConfigText{};
  base.display += "width_px = 640\n";
  text = base.text();
  message = error_of(text);
  EXPECT_EQ(message.rfind(kPath + ":" + std::to_string(line_of(text, "width_px = 640")) + ": ", 0), 0u) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(ProtocolsConfig, FramesPerSecondMustDivideTheRefreshRate) {
  ConfigText base;
  base.stimulus = replace_once(base.stimulus, "frames_per_second = 10", "frames_per_second = 25");
  std::string text = base.text();
  expect_error(text, line_of(text, "frames_per_second = 25"), "stimulus.frames_per_second", "refresh rate");

  base = ConfigText{};
  base.stimulus = replace_once(base.stimulus, "frames_per_second = 10", "frames_per_second = 120");
  text = base.text();
  expect_error(text, line_of(text, "frames_per_second = 120"), "stimulus.frames_per_second", "expected a value in");

  base = ConfigText{};
  base.stimulus = replace_once(base.stimulus, "frames_per_second = 10", "frames_per_second = 20");
  const StudyConfig config = parse(base.text());
  EXPECT_EQ(config.stimulus.refreshes_per_frame(60.0), 3);
  EXPECT_EQ(config.stimulus.frame_count(), 10);

  // 144 Hz: 48 fps divides it, 60 does not.
  base = ConfigText{};
  base.display = replace_once(base.display, "refresh_hz = 60", "refresh_hz = 144");
  base.stimulus = replace_once(base.stimulus, "frames_per_second = 10", "frames_per_second = 48");
  EXPECT_EQ(parse(base.text()).stimulus.refreshes_per_frame(144.0), 3);
  base.stimulus = replace_once(base.stimulus, "frames_per_second = 48", "frames_per_second = 60");
  text = base.text();
  expect_error(text, line_of(text, "frames_per_second = 60"), "stimulus.frames_per_second", "refresh rate");
}

TEST(ProtocolsConfig, DiagonalOrPhysicalSizeNotBoth) {
  ConfigText base;
  base.display += "width_mm = 600\n";
  std::string text = base.text();
  expect_error(text, line_of(text, "[display]"), "display", "not both or neither");

  base = ConfigText{};
  base.display += "width_mm = 600\nheight_mm = 340\n";
  text = base.text();
  expect_error(text, line_of(text, "[display]"), "display", "not both or neither");

  base = ConfigText{};
  base.display = replace_once(base.display, "diagonal_in = 27\n", "");
  text = base.text();
  expect_error(text, line_of(text, "[display]"), "display", "not both or neither");

  base = ConfigText{};
  base.display = replace_once(base.display, "diagonal_in = 27\n", "width_mm = 600\nheight_mm = 340\n");
  const StudyConfig config = parse(base.text());
  EXPECT_DOUBLE_EQ(config.display.width_mm, 600.0);
  EXPECT_DOUBLE_EQ(config.display.height_mm, 340.0);

  base = ConfigText{};
  base.display = replace_once(base.display, "diagonal_in = 27\n", "width_mm = 600\n");
  text = base.text();
  const std::string message = error_of(text);
  EXPECT_NE(message.find("display.height_mm: missing"), std::string::npos) << message;
}

TEST(ProtocolsConfig, TheFirstErrorIsReported) {
  // Two errors: the one met first ([display] is read before [protocol]) is reported.
  ConfigText base;
  base.display = replace_once(base.display, "width_px = 320", "width_px = 2");
  base.protocol = replace_once(base.protocol, "repeats = 2", "repeats = 3");
  const std::string message = error_of(base.text());
  EXPECT_NE(message.find("display.width_px"), std::string::npos) << message;
}

}  // namespace
}  // namespace fovlab

namespace fovlab {
namespace {

// [validation]: defaults, the target layout, and its bad input.
TEST(StudyConfigValidation, ReadsTheTableAndPlacesTargetsAtTheGivenAngle) {
  ConfigText config;
  EXPECT_FALSE(parse(config.text()).validation.enabled);
  config.attention +=
      "\n[validation]\ntargets = 5\ntarget_offset_deg = 4\nmax_accuracy_deg = 0.8\nafter_breaks = false\n";
  const StudyConfig parsed = parse(config.text());
  const ValidationConfig& validation = parsed.validation;
  EXPECT_TRUE(validation.enabled);
  EXPECT_EQ(validation.targets, 5);
  EXPECT_DOUBLE_EQ(validation.max_accuracy_deg, 0.8);
  EXPECT_DOUBLE_EQ(validation.max_precision_deg, 0.5);
  EXPECT_FALSE(validation.after_breaks);
  const auto targets = validation_targets_px(parsed.display, validation);
  ASSERT_EQ(targets.size(), 5u);
  // Centre and corners, in reading order; each corner 4 deg from the centre along each axis.
  const double centre_x = 160.0, centre_y = 90.0;
  EXPECT_DOUBLE_EQ(targets[2].first, centre_x);
  EXPECT_DOUBLE_EQ(targets[2].second, centre_y);
  const double pitch_mm = parsed.display.width_mm / 320.0;
  for (const auto& [x_px, y_px] : targets) {
    if (x_px == centre_x) continue;
    EXPECT_NEAR(std::atan(std::abs(x_px - centre_x) * pitch_mm / 500.0) * 180.0 / std::numbers::pi, 4.0, 1e-12);
    EXPECT_NEAR(std::atan(std::abs(y_px - centre_y) * pitch_mm / 500.0) * 180.0 / std::numbers::pi, 4.0, 1e-12);
  }
  EXPECT_LT(targets[0].first, centre_x);
  EXPECT_LT(targets[0].second, centre_y);
  EXPECT_GT(targets[4].first, centre_x);
  EXPECT_GT(targets[4].second, centre_y);
  ValidationConfig nine = validation;
  nine.targets = 9;
  EXPECT_EQ(validation_targets_px(parsed.display, nine).size(), 9u);
}

TEST(StudyConfigValidation, BadValuesNameTheirKey) {
  ConfigText config;
  const auto with = [&](const std::string& table) {
    ConfigText changed = config;
    changed.attention += "\n[validation]\n" + table;
    return changed.text();
  };
  std::string text = with("targets = 7\n");
  expect_error(text, line_of(text, "targets = 7"), "validation.targets", "expected 5 or 9");
  // 320 x 180 px, 27 in at 500 mm: 18.6 deg from the centre to the top edge.
  text = with("target_offset_deg = 20\n");
  expect_error(text, line_of(text, "target_offset_deg"), "validation.target_offset_deg", "fall off this display");
  text = with("target_s = 1\nsettle_s = 1\n");
  expect_error(text, line_of(text, "settle_s"), "validation.settle_s", "");
  text = with("max_attempts = 0\n");
  expect_error(text, line_of(text, "max_attempts"), "validation.max_attempts", "");
  text = with("targets_deg = 3\n");
  expect_error(text, line_of(text, "targets_deg"), "validation.targets_deg", "");
}

}  // namespace
}  // namespace fovlab

namespace fovlab {
namespace {

// [conditions] file: a conditions CSV beside the config in a temporary folder.
struct ConditionsStudy {
  testing::TempDir dir;
  std::string config_path;
  ConditionsStudy(const std::string& csv, const std::string& levels = "[levels]\nparameter = \"max_steps\"\n",
                  const std::string& protocol = "") {
    ConfigText config;
    config.stimulus = R"([stimulus]
duration_s = 0.5
frames_per_second = 10

[stimulus.reference]
method = "gt"

[stimulus.test]
method = "ipr"
)";
    config.levels = levels + "\n[conditions]\nfile = \"conditions.csv\"\n";
    if (!protocol.empty()) config.protocol = protocol;
    config.attention = "";
    std::ofstream(dir.file("conditions.csv"), std::ios::binary) << csv;
    config_path = dir.file("unit.toml");
    std::ofstream(config_path, std::ios::binary) << config.text();
  }
  StudyConfig parse() const { return parse_study_config_file(config_path, renderer_scene_catalog()); }
  std::string error() const {
    try {
      parse();
    } catch (const InputError& error) {
      return error.what();
    }
    return "no error";
  }
};

TEST(StudyConfigConditions, RowsBecomeVariantsWithTheirOwnLevels) {
  const ConditionsStudy study(
      "variant,max_steps,hit_threshold,min_filter_size\n"
      "coarse,4,0.5,5\n"
      "coarse,2,0.5,5\n"
      "fine,16,,1\n"
      "fine,64,,1\n"
      "fine,4,,1\n");
  const StudyConfig config = study.parse();
  ASSERT_EQ(config.stimulus.variants.size(), 2u);
  const VariantConfig& coarse = config.stimulus.variants[0];
  EXPECT_EQ(coarse.name, "coarse");
  EXPECT_EQ(coarse.levels, (std::vector<double>{2, 4}));
  EXPECT_EQ(coarse.parameters, (ParameterLayer{{"hit_threshold", 0.5}, {"min_filter_size", 5}}));
  const VariantConfig& fine = config.stimulus.variants[1];
  EXPECT_EQ(fine.levels, (std::vector<double>{4, 16, 64}));
  EXPECT_EQ(fine.parameters, (ParameterLayer{{"min_filter_size", 1}}));  // an empty cell keeps the method's
  EXPECT_EQ(config.levels.values, (std::vector<double>{2, 4, 16, 64}));
  EXPECT_EQ(variant_levels(config.levels, &coarse), coarse.levels);
  EXPECT_EQ(config.conditions_path, "conditions.csv");
  // The schedule: each variant at its own levels only (2 repeats each in the fixture's protocol).
  const StudyPlan plan = make_study_plan(config, "P1");
  std::map<std::string, int> trials;
  for (const Trial& trial : plan.trials)
    if (!trial.attention_check && trial.block == 0) ++trials[trial.condition];
  EXPECT_EQ(trials, (std::map<std::string, int>{{"coarse/level=2", 2},
                                                {"coarse/level=4", 2},
                                                {"fine/level=16", 2},
                                                {"fine/level=4", 2},
                                                {"fine/level=64", 2}}));
  // The hash covers the conditions: the same config with another file is another config.
  const ConditionsStudy other("variant,max_steps\ncoarse,4\ncoarse,2\n");
  EXPECT_NE(other.parse().hash, config.hash);
  // And a log carries them: the logged config parses from the header's text alone.
  const StudyConfig logged = parse_logged_study_config(config.source_text, "x.toml (config_toml)", log_schema_version,
                                                       nullptr, config.conditions_csv);
  EXPECT_EQ(logged.hash, config.hash);
  EXPECT_EQ(logged.stimulus.variants.size(), 2u);
  EXPECT_THROW(parse_logged_study_config(config.source_text, "x.toml (config_toml)", log_schema_version, nullptr),
               InputError);
}

TEST(StudyConfigConditions, BadFilesNameTheFileLineAndColumn) {
  const auto error = [](const std::string& csv, const std::string& levels = "[levels]\nparameter = \"max_steps\"\n") {
    const ConditionsStudy study(csv, levels);
    const std::string message = study.error();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    const std::string file = (std::filesystem::path(study.config_path).parent_path() / "conditions.csv").string();
    return message.rfind(file + ":", 0) == 0 ? message.substr(file.size() + 1) : message;
  };
  EXPECT_EQ(
      error("variant,max_steps,warp\na,4,1\n")
          .rfind(
              "1: column \"warp\": expected variant, max_steps (the level) or a parameter of the test method \"ipr\"",
              0),
      0u);
  EXPECT_EQ(error("variant,hit_threshold\na,0.5\n"),
            "1: expected a column \"max_steps\" ([levels] parameter) holding each condition's level");
  EXPECT_EQ(error("max_steps,hit_threshold\n4,0.5\n").rfind("1: expected a column \"variant\"", 0), 0u);
  EXPECT_EQ(error("variant,max_steps\na,4,5\n"), "2: expected 2 cells as the header has, got 3");
  EXPECT_EQ(error("variant,max_steps\na,four\n"), "2: column \"max_steps\": expected a number, got \"four\"");
  EXPECT_EQ(error("variant,max_steps\na,0\n"), "2: column \"max_steps\": expected a value in [1, 4096], got 0");
  EXPECT_EQ(error("variant,max_steps\na,\n"),
            "2: column \"max_steps\": expected the condition's level, got an empty cell");
  EXPECT_EQ(error("variant,max_steps\na,4\nb,4\na,4\n"), "4: the condition a at max_steps = 4 appears twice");
  EXPECT_EQ(error("variant,max_steps,hit_threshold\na,4,0.5\na,8,0.25\n")
                .rfind("3: variant \"a\" sets other parameters than on line 2", 0),
            0u);
  EXPECT_EQ(error("variant,max_steps\n../x,4\n").rfind("2: variant \"../x\": expected", 0), 0u);
  EXPECT_EQ(error("variant,max_steps\n").rfind("1: expected a header row and at least one condition", 0), 0u);
  EXPECT_EQ(error("variant,variant\na,b\n"), "1: column \"variant\" appears twice");
  // The config's side: values and conditions both, or no file.
  const ConditionsStudy both("variant,max_steps\na,4\n", "[levels]\nparameter = \"max_steps\"\nvalues = [4]\n");
  EXPECT_NE(both.error().find("levels.values: the [conditions] file gives the levels"), std::string::npos)
      << both.error();
  // An empty path names the key: it is not the config's folder, nor a file called "".
  ConditionsStudy empty_path("variant,max_steps\na,4\n");
  std::string config_text;
  {
    std::ifstream in(empty_path.config_path, std::ios::binary);
    config_text.assign(std::istreambuf_iterator<char>(in), {});
  }
  config_text = replace_once(config_text, "file = \"conditions.csv\"", "file = \"\"");
  std::ofstream(empty_path.config_path, std::ios::binary) << config_text;
  EXPECT_EQ(empty_path.error(), empty_path.config_path + ":" + std::to_string(line_of(config_text, "file = \"\"")) +
                                    ": conditions.file: expected the path of a conditions file (.csv, relative to the "
                                    "config's folder), got \"\"");
  ConditionsStudy missing("variant,max_steps\na,4\n");
  std::filesystem::remove(std::filesystem::path(missing.config_path).parent_path() / "conditions.csv");
  EXPECT_NE(missing.error().find("conditions.csv"), std::string::npos) << missing.error();
  // Ramp and slider: every variant needs a ladder.
  const ConditionsStudy ramp("variant,max_steps\na,4\na,8\nb,4\n", "[levels]\nparameter = \"max_steps\"\n",
                             "[protocol]\nkind = \"ramp\"\n");
  EXPECT_NE(ramp.error().find("protocol.kind: ramp needs at least two levels in every variant (\"b\""),
            std::string::npos)
      << ramp.error();
}

}  // namespace
}  // namespace fovlab

namespace fovlab {
namespace {

TEST(ShippedExperiments, EveryConfigInExperimentsParses) {
  // The configs the README and docs point users to must stay valid as the config grows.
  int parsed = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::filesystem::path(FOVLAB_SOURCE_DIR) / "experiments")) {
    if (entry.path().extension() != ".toml") continue;
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW(parse_study_config_file(entry.path().string(), renderer_scene_catalog()));
    ++parsed;
  }
  EXPECT_GE(parsed, 19);
  // The lab template uses what a lab expects of a study (issue 18).
  const StudyConfig lab =
      parse_study_config_file(std::string(FOVLAB_SOURCE_DIR) + "/experiments/lab_study.toml", renderer_scene_catalog());
  EXPECT_TRUE(lab.validation.enabled);
  EXPECT_EQ(lab.practice.trials, 4);
  EXPECT_EQ(lab.stimulus.variants.size(), 2u);
  EXPECT_EQ(lab.participant_fields, (std::vector<std::string>{"age", "handedness"}));
}

// [analysis] headline: the design's estimate by default, the paper's rule when asked; a config
// without the table keeps its version (content_hash).
TEST(StudyConfigAnalysis, HeadlineChoosesThePapersRuleAndLeavesOtherConfigsTheirVersion) {
  ConfigText config;
  const StudyConfig plain = parse_study_config_text(config.text(), kPath, renderer_scene_catalog());
  EXPECT_FALSE(plain.analysis.headline_is_paper_rule);
  ConfigText paper = config;
  paper.attention += "\n[analysis]\nheadline = \"paper\"\n";
  const StudyConfig chosen = parse_study_config_text(paper.text(), kPath, renderer_scene_catalog());
  EXPECT_TRUE(chosen.analysis.headline_is_paper_rule);
  EXPECT_NE(chosen.content_hash, plain.content_hash);
  ConfigText commented = config;
  commented.attention += "\n# a comment\n";
  EXPECT_EQ(parse_study_config_text(commented.text(), kPath, renderer_scene_catalog()).content_hash,
            plain.content_hash);
  ConfigText bad = config;
  bad.attention += "\n[analysis]\nheadline = \"walk\"\n";
  const std::string text = bad.text();
  expect_error(text, line_of(text, "headline = \"walk\""), "analysis.headline", "expected \"estimate\"");
}

// The sampling models' equalise by name: "on" is "samples" in a config read now and in one that a
// schema 8 log carries, and the choice "on" (the density, what those sessions showed) in one that an
// earlier log carries; the config's version is its text either way. Other names are refused with the
// names allowed.
TEST(StudyConfigEqualise, OnIsReadByTheLogsSchema) {
  ConfigText config;
  config.stimulus = replace_once(config.stimulus, "[stimulus.test]\nmethod = \"gt\"\n",
                                 "[stimulus.test]\nmethod = \"hyperbolic\"\nequalise = \"on\"\n");
  config.levels = "[levels]\nparameter = \"sigma\"\nvalues = [2, 2.6]\nhigher_is_better = false\n";
  const std::string text = config.text();
  const StudyConfig now = parse_study_config_text(text, kPath, renderer_scene_catalog());
  EXPECT_EQ(now.stimulus.test.parameters.at("equalise"), 2.0);  // samples
  EXPECT_EQ(parse_logged_study_config(text, kPath, 8, nullptr).stimulus.test.parameters.at("equalise"), 2.0);
  const StudyConfig earlier = parse_logged_study_config(text, kPath, 7, nullptr);
  EXPECT_EQ(earlier.stimulus.test.parameters.at("equalise"), 1.0);  // "on", the density
  EXPECT_EQ(earlier.content_hash, now.content_hash);
  const std::string density = replace_once(text, "equalise = \"on\"", "equalise = \"density\"");
  EXPECT_EQ(parse_logged_study_config(density, kPath, 7, nullptr).stimulus.test.parameters.at("equalise"), 3.0);
  const std::string bad = replace_once(text, "equalise = \"on\"", "equalise = \"equal\"");
  expect_error(bad, line_of(bad, "equalise = "), "stimulus.test.equalise",
               "expected one of \"off\", \"on\", \"samples\", \"density\", got \"equal\"");
}

}  // namespace
}  // namespace fovlab
