#include <optional>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "core/input_error.h"
#include "core/prng.h"
#include "protocols/gaze/gaze_spec.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "tests/support/temp_dir.h"

namespace fovlab {
namespace {

TEST(GazeSpecParse, AcceptsEveryForm) {
  EXPECT_EQ(parse_gaze_spec("mouse").kind, GazeSpec::Kind::mouse);

  GazeSpec spec = parse_gaze_spec("trace:data/run 1:a.csv");
  EXPECT_EQ(spec.kind, GazeSpec::Kind::trace);
  EXPECT_EQ(spec.trace_path, "data/run 1:a.csv");

  spec = parse_gaze_spec("synthetic");
  EXPECT_EQ(spec.kind, GazeSpec::Kind::synthetic);
  EXPECT_FALSE(spec.seed_given);

  spec = parse_gaze_spec("synthetic:seed=18446744073709551615");
  EXPECT_EQ(spec.kind, GazeSpec::Kind::synthetic);
  EXPECT_TRUE(spec.seed_given);
  EXPECT_EQ(spec.seed, 18446744073709551615ULL);

  spec = parse_gaze_spec("pupil");
  EXPECT_EQ(spec.kind, GazeSpec::Kind::pupil);
  EXPECT_EQ(spec.host, "127.0.0.1");
  EXPECT_EQ(spec.port, 50020);

  spec = parse_gaze_spec("pupil:192.168.1.20:50021");
  EXPECT_EQ(spec.kind, GazeSpec::Kind::pupil);
  EXPECT_EQ(spec.host, "192.168.1.20");
  EXPECT_EQ(spec.port, 50021);

  spec = parse_gaze_spec("pupil:tracker.local");
  EXPECT_EQ(spec.host, "tracker.local");
  EXPECT_EQ(spec.port, 50020);
}

TEST(GazeSpecParse, PupilSurfaceAndConfidenceAreSettable) {
  // Issue 18: both were only in a header file.
  GazeSpec spec = parse_gaze_spec("pupil");
  EXPECT_EQ(spec.surface, "screen");
  EXPECT_EQ(spec.min_confidence, 0.6);
  spec = parse_gaze_spec("pupil:10.0.0.2:50021,surface=lab monitor,min_confidence=0.8");
  EXPECT_EQ(spec.kind, GazeSpec::Kind::pupil);
  EXPECT_EQ(spec.host, "10.0.0.2");
  EXPECT_EQ(spec.port, 50021);
  EXPECT_EQ(spec.surface, "lab monitor");
  EXPECT_EQ(spec.min_confidence, 0.8);
  spec = parse_gaze_spec("pupil,min_confidence=0");
  EXPECT_EQ(spec.host, "127.0.0.1");
  EXPECT_EQ(spec.surface, "screen");
  EXPECT_EQ(spec.min_confidence, 0.0);
}

TEST(GazeSpecParse, RejectsEverythingElse) {
  try {
    parse_gaze_spec("eyelink");
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "--gaze: expected mouse, trace:FILE, synthetic[:seed=N], "
              "pupil[:HOST[:PORT]][,surface=NAME][,min_confidence=C] or openxr, got \"eyelink\"");
  }
  for (const char* text : {"",
                           "Mouse",
                           "mouse:",
                           "trace:",
                           "trace",
                           "synthetic:",
                           "synthetic:seed=",
                           "synthetic:seed=-1",
                           "synthetic:seed=1x",
                           "synthetic:seed=18446744073709551616",
                           "synthetic:42",
                           "pupil:",
                           "pupil::50020",
                           "pupil:host:",
                           "pupil:host:0",
                           "pupil:host:65536",
                           "pupil:host:port",
                           "pupil:a:b:1",
                           "pupils",
                           "pupil,",
                           "pupil,surface=",
                           "pupil,surface=a/b",
                           "pupil,min_confidence=1.5",
                           "pupil,min_confidence=-0.1",
                           "pupil,min_confidence=x",
                           "pupil,colour=red",
                           "pupil,surface=a,surface=b",
                           "synthetic,surface=a",
                           "pupils,surface=a"}) {
    EXPECT_THROW(parse_gaze_spec(text), InputError) << '"' << text << '"';
  }
}

TEST(GazeSpecParse, SyntheticSampleAge) {
  GazeSpec spec = parse_gaze_spec("synthetic:age_ms=40");
  EXPECT_EQ(spec.kind, GazeSpec::Kind::synthetic);
  EXPECT_FALSE(spec.seed_given);
  EXPECT_DOUBLE_EQ(spec.age_ms, 40.0);
  spec = parse_gaze_spec("synthetic:seed=5,age_ms=12.5");
  EXPECT_TRUE(spec.seed_given);
  EXPECT_EQ(spec.seed, 5u);
  EXPECT_DOUBLE_EQ(spec.age_ms, 12.5);
  spec = parse_gaze_spec("synthetic:age_ms=0,seed=9");
  EXPECT_EQ(spec.seed, 9u);
  EXPECT_DOUBLE_EQ(spec.age_ms, 0.0);
  EXPECT_DOUBLE_EQ(parse_gaze_spec("synthetic").age_ms, 0.0);  // the default

  try {
    parse_gaze_spec("synthetic:age_ms=-3");
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), "--gaze: age_ms: expected milliseconds 0..10000, got \"-3\"");
  }
  for (const char* text : {"synthetic:age_ms=", "synthetic:age_ms=nan", "synthetic:age_ms=inf",
                           "synthetic:age_ms=10001", "synthetic:age_ms=4x", "synthetic:age_ms=1,age_ms=2",
                           "synthetic:seed=1,seed=2", "synthetic:seed=1,", "synthetic:,age_ms=1", "synthetic:age=40"}) {
    EXPECT_THROW(parse_gaze_spec(text), InputError) << '"' << text << '"';
  }
}

// Which source a session runs with (docs/gaze.md, "Which source a session may use"): the default
// by where it runs and what the study shows, and the config's [gaze] require, kept strictly.
TEST(GazeSpecChoose, DefaultsAndTheConfigsRequirement) {
  const auto config = [](const std::string& test_method, const std::string& gaze_table) {
    const std::string text =
        "[study]\nname = \"g\"\nseed = 1\n[display]\nwidth_px = 64\nheight_px = 36\nrefresh_hz = 60\n"
        "width_mm = 600\nheight_mm = 337.5\nviewing_distance_mm = 500\n[stimulus]\nduration_s = 0.1\n"
        "[stimulus.reference]\nmethod = \"gt\"\n[stimulus.test]\nmethod = \"" +
        test_method +
        "\"\n"
        "[protocol]\nkind = \"2afc\"\nquestion = \"same\"\n" +
        gaze_table + "[[block]]\nscene = \"primitives\"\n";
    return parse_study_config_text(text, "g.toml", renderer_scene_catalog());
  };
  const auto kind_of = [](const ChosenGaze& chosen) { return source_kind(chosen.spec); };
  const auto refusal = [](const StudyConfig& study, const std::string& option, bool headless) {
    try {
      choose_gaze(study, option, headless);
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("no refusal");
  };
  const StudyConfig plain = config("ipr", "");
  const StudyConfig contingent = config("fipr", "");
  // Headless: synthetic; in a window: the mouse, unless the study is gaze-contingent.
  EXPECT_EQ(kind_of(choose_gaze(plain, "", true)), GazeSourceKind::synthetic);
  EXPECT_EQ(kind_of(choose_gaze(contingent, "", true)), GazeSourceKind::synthetic);
  EXPECT_FALSE(choose_gaze(contingent, "", true).requested);
  EXPECT_EQ(kind_of(choose_gaze(plain, "", false)), GazeSourceKind::mouse);
  EXPECT_NE(refusal(contingent, "", false).find("g.toml: a gaze-contingent study (fipr follows the gaze) in a window"),
            std::string::npos);
  EXPECT_EQ(kind_of(choose_gaze(contingent, "mouse", false)), GazeSourceKind::mouse);
  EXPECT_TRUE(choose_gaze(contingent, "mouse", false).requested);
  EXPECT_EQ(kind_of(choose_gaze(contingent, "pupil:10.0.0.2", false)), GazeSourceKind::tracker);
  // require: strict, headless too; the mouse alone (a demo) is the window's default.
  const StudyConfig tracker = config("fipr", "[gaze]\nrequire = \"tracker\"\n");
  EXPECT_EQ(kind_of(choose_gaze(tracker, "pupil", false)), GazeSourceKind::tracker);
  EXPECT_EQ(kind_of(choose_gaze(tracker, "pupil", true)), GazeSourceKind::tracker);
  EXPECT_NE(refusal(tracker, "mouse", false)
                .find("--gaze mouse: g.toml:21: gaze.require = tracker: expected a source of that "
                      "kind, got a mouse (give --gaze pupil[:HOST[:PORT]] for the eye tracker)"),
            std::string::npos)
      << refusal(tracker, "mouse", false);
  EXPECT_NE(refusal(tracker, "trace:x.csv", true).find("got a trace"), std::string::npos);
  EXPECT_NE(refusal(tracker, "", true).find("a headless session's default gaze is synthetic"), std::string::npos);
  EXPECT_NE(refusal(tracker, "", false).find("a session in a window needs its gaze source named"), std::string::npos);
  const StudyConfig plain_tracker = config("ipr", "[gaze]\nrequire = \"tracker\"\n");
  EXPECT_NE(refusal(plain_tracker, "", false).find("needs its gaze source named"), std::string::npos);
  const StudyConfig demo = config("fipr", "[gaze]\nrequire = \"mouse\"\n");
  EXPECT_EQ(kind_of(choose_gaze(demo, "", false)), GazeSourceKind::mouse);
  const StudyConfig either = config("fipr", "[gaze]\nrequire = [\"trace\", \"synthetic\"]\n");
  EXPECT_EQ(kind_of(choose_gaze(either, "", true)), GazeSourceKind::synthetic);
  EXPECT_NE(refusal(either, "", false).find("give --gaze trace:FILE for a recorded trace or --gaze synthetic"),
            std::string::npos);
  // A bad spec is the spec's error, before the requirement.
  EXPECT_NE(refusal(tracker, "eyes", false).find("--gaze: expected"), std::string::npos);
}

TEST(GazeSpecMake, SyntheticSamplesAreAsOldAsConfigured) {
  auto source = make_gaze_source(parse_gaze_spec("synthetic:seed=5,age_ms=40"), 800, 600, 7);
  EXPECT_EQ(source->describe(), "synthetic:seed=5,age_ms=40");
  const auto fresh = make_gaze_source(parse_gaze_spec("synthetic:seed=5"), 800, 600, 7);
  const GazeSample aged = source->sample(1.0);
  EXPECT_DOUBLE_EQ(aged.time_s, 1.0);
  ASSERT_TRUE(aged.acquired_s.has_value());
  EXPECT_DOUBLE_EQ(*aged.acquired_s, 1.0 - 0.040);
  // The position is the one of the moment the sample was taken.
  const GazeSample then = fresh->sample(1.0 - 0.040);
  EXPECT_DOUBLE_EQ(aged.x_px, then.x_px);
  EXPECT_DOUBLE_EQ(aged.y_px, then.y_px);
  ASSERT_TRUE(then.acquired_s.has_value());
  EXPECT_DOUBLE_EQ(*then.acquired_s, 1.0 - 0.040);  // age 0: taken when asked
}

TEST(GazeSpecMake, MakesTraceAndSyntheticSources) {
  EXPECT_THROW(make_gaze_source(parse_gaze_spec("mouse"), 800, 600, 1), std::logic_error);

  auto source = make_gaze_source(parse_gaze_spec("synthetic"), 800, 600, 7);
  EXPECT_EQ(source->describe(), "synthetic:seed=" + std::to_string(derive_seed(7, "gaze")));
  source = make_gaze_source(parse_gaze_spec("synthetic:seed=5"), 800, 600, 7);
  EXPECT_EQ(source->describe(), "synthetic:seed=5");
  EXPECT_TRUE(source->sample(0.0).valid);

  const fovlab::testing::TempDir dir;
  const std::string path = dir.write("g.csv", "time_s,x_px,y_px\n0,5,6\n");
  source = make_gaze_source(parse_gaze_spec("trace:" + path), 800, 600, 7);
  EXPECT_EQ(source->describe(), "trace:" + path);
  EXPECT_DOUBLE_EQ(source->sample(1.0).y_px, 6.0);
  EXPECT_EQ(source->sample(1.0).acquired_s, std::optional<double>(0.0));  // the trace sample's own time
  EXPECT_THROW(make_gaze_source(parse_gaze_spec("trace:" + path + ".missing"), 800, 600, 7), InputError);
}

}  // namespace
}  // namespace fovlab
