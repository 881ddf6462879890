#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "core/input_error.h"
#include "core/prng.h"
#include "protocols/gaze/gaze_spec.h"
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

TEST(GazeSpecParse, RejectsEverythingElse) {
  try {
    parse_gaze_spec("eyelink");
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()),
              "--gaze: expected mouse, trace:FILE, synthetic[:seed=N] or pupil:HOST:PORT, got \"eyelink\"");
  }
  for (const char* text : {"", "Mouse", "mouse:", "trace:", "trace", "synthetic:", "synthetic:seed=",
                           "synthetic:seed=-1", "synthetic:seed=1x", "synthetic:seed=18446744073709551616",
                           "synthetic:42", "pupil:", "pupil::50020", "pupil:host:", "pupil:host:0",
                           "pupil:host:65536", "pupil:host:port", "pupil:a:b:1", "pupils"}) {
    EXPECT_THROW(parse_gaze_spec(text), InputError) << '"' << text << '"';
  }
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
  EXPECT_THROW(make_gaze_source(parse_gaze_spec("trace:" + path + ".missing"), 800, 600, 7), InputError);
}

}  // namespace
}  // namespace fovlab
