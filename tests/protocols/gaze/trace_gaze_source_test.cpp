#include <sys/stat.h>

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/input_error.h"
#include "core/prng.h"
#include "protocols/gaze/trace_gaze_source.h"
#include "tests/support/temp_dir.h"

namespace fovlab {
namespace {

using fovlab::testing::TempDir;

// The InputError message of constructing a trace from this file (empty when none was thrown).
std::string error_of(const std::string& path) {
  try {
    TraceGazeSource source(path);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(GazeTrace, StepFunctionReturnsTheLatestSampleAtOrBeforeT) {
  const TempDir dir;
  const std::string path = dir.write("gaze.csv",
                                     "time_s,x_px,y_px\n"
                                     "0.0,100,200\n"
                                     "0.5,110.5,210.25\n"
                                     "1.0,300,400\n");
  TraceGazeSource source(path);
  EXPECT_EQ(source.describe(), "trace:" + path);
  ASSERT_EQ(source.samples().size(), 3u);

  struct Case {
    double t;
    double time, x, y;
  };
  for (const Case& c : std::vector<Case>{{-1.0, 0.0, 100, 200},  // before the trace: the first sample
                                         {0.0, 0.0, 100, 200},
                                         {0.25, 0.0, 100, 200},  // no interpolation
                                         {0.5, 0.5, 110.5, 210.25},
                                         {0.999, 0.5, 110.5, 210.25},
                                         {1.0, 1.0, 300, 400},
                                         {1e6, 1.0, 300, 400}}) {
    SCOPED_TRACE("t = " + std::to_string(c.t));
    const GazeSample sample = source.sample(c.t);
    EXPECT_TRUE(sample.valid);
    EXPECT_EQ(sample.invalid_reason, "");
    EXPECT_DOUBLE_EQ(sample.time_s, c.time);
    EXPECT_DOUBLE_EQ(sample.x_px, c.x);
    EXPECT_DOUBLE_EQ(sample.y_px, c.y);
  }
  // Going backwards gives the same answers.
  EXPECT_DOUBLE_EQ(source.sample(0.25).x_px, 100.0);
}

TEST(GazeTrace, ValidColumnEmptyFieldsNanSpacesAndCrlf) {
  const TempDir dir;
  const std::string path = dir.write("gaze.csv",
                                     "\xEF\xBB\xBFtime_s, x_px, y_px, valid\r\n"
                                     "0.0, 10, 20, 1\r\n"
                                     "\r\n"
                                     "0.1,11,21,0\r\n"
                                     "0.2,,,1\r\n"
                                     "0.3,nan,5,1\r\n"
                                     "0.4,12,22,1\r\n"
                                     "0.4,13,23,1\r\n"
                                     "0.5,,,0\r\n");
  TraceGazeSource source(path);
  ASSERT_EQ(source.samples().size(), 7u);

  GazeSample s = source.sample(0.05);
  EXPECT_TRUE(s.valid);
  EXPECT_DOUBLE_EQ(s.x_px, 10.0);
  s = source.sample(0.15);
  EXPECT_FALSE(s.valid);
  EXPECT_EQ(s.invalid_reason, "blink");
  EXPECT_DOUBLE_EQ(s.x_px, 11.0);  // a blink keeps the recorded position
  s = source.sample(0.25);
  EXPECT_FALSE(s.valid);
  EXPECT_EQ(s.invalid_reason, "no_data");
  EXPECT_DOUBLE_EQ(s.x_px, 0.0);
  s = source.sample(0.35);
  EXPECT_FALSE(s.valid);
  EXPECT_EQ(s.invalid_reason, "not_finite");
  EXPECT_DOUBLE_EQ(s.x_px, 0.0);
  s = source.sample(0.45);  // equal times: the later line wins
  EXPECT_TRUE(s.valid);
  EXPECT_DOUBLE_EQ(s.x_px, 13.0);
  EXPECT_DOUBLE_EQ(s.y_px, 23.0);
  s = source.sample(0.5);
  EXPECT_EQ(s.invalid_reason, "blink");  // valid=0 wins over empty fields
}

TEST(GazeTrace, BinarySearchAgreesWithALinearScan) {
  std::string text = "time_s,x_px,y_px\n";
  std::vector<double> times;
  Pcg32 rng(7);
  double t = 0.0;
  for (int i = 0; i < 2000; ++i) {
    t += rng.below(3) * 0.004;  // repeats included
    times.push_back(t);
    text += std::to_string(t) + "," + std::to_string(i) + ",0\n";
  }
  const std::vector<GazeSample> samples = parse_gaze_trace(text, "inline.csv");
  ASSERT_EQ(samples.size(), 2000u);
  const TempDir dir;
  TraceGazeSource source(dir.write("big.csv", text));
  for (int query = 0; query < 500; ++query) {
    const double q = rng.uniform(-0.1, t + 0.1);
    size_t expected = 0;
    for (size_t i = 0; i < samples.size(); ++i) {
      if (samples[i].time_s <= q) expected = i;
    }
    ASSERT_DOUBLE_EQ(source.sample(q).x_px, static_cast<double>(expected)) << "t = " << q;
  }
}

TEST(GazeTrace, MalformedLinesNameFileLineAndField) {
  const TempDir dir;
  const auto error_for = [&](const std::string& text) { return error_of(dir.write("gaze.csv", text)); };
  const std::string p = (dir.path() / "gaze.csv").string();

  EXPECT_EQ(error_for("time_s,x_px,y_px\n0,1,2\nabc,1,2\n"), p + ":3: time_s: expected a number, got \"abc\"");
  EXPECT_EQ(error_for("time_s,x_px,y_px\n0,1,2\n1.5,1,2\n\n1.2,1,2\n"),
            p + ":5: time_s: 1.2 is earlier than the previous sample (1.5)");
  EXPECT_EQ(error_for("time_s,x_px,y_px\nnan,1,2\n"), p + ":2: time_s: expected a finite number, got \"nan\"");
  EXPECT_EQ(error_for("time_s,x_px,y_px\n0,1x,2\n"),
            p + ":2: x_px: expected a number, an empty field or nan, got \"1x\"");
  EXPECT_EQ(error_for("time_s,x_px,y_px,valid\n0,1,2,yes\n"), p + ":2: valid: expected 0 or 1, got \"yes\"");
  EXPECT_EQ(error_for("time_s,x_px,y_px\n0,1\n"),
            p + ":2: expected 3 comma-separated fields (time_s,x_px,y_px), got 2");
  EXPECT_EQ(error_for("t,x,y\n0,1,2\n"),
            p + ":1: expected the header \"time_s,x_px,y_px\" or \"time_s,x_px,y_px,valid\", got \"t,x,y\"");
  EXPECT_EQ(error_for(""),
            p + ":1: expected the header \"time_s,x_px,y_px\" or \"time_s,x_px,y_px,valid\", got an empty file");
  EXPECT_EQ(error_for("time_s,x_px,y_px\n"), p + ": expected at least one gaze sample after the header, got none");
  EXPECT_EQ(error_for("time_s,x_px,y_px\n0,1,2\n"), "");  // and a good one passes
}

// A sample's time is seconds on the session clock within 1e6 either way, so every age computed from
// it (session time - time_s, in ms) stays finite: 1e308 made the latency -inf, -1e308 inf.
TEST(GazeTrace, TimesFarFromTheSessionAreRefusedAsWritten) {
  const TempDir dir;
  const auto error_for = [&](const std::string& text) { return error_of(dir.write("gaze.csv", text)); };
  const std::string p = (dir.path() / "gaze.csv").string();
  const std::string expected = "time_s: expected seconds on the session clock from -1e+06 to 1e+06 (11.6 days), got ";
  EXPECT_EQ(error_for("time_s,x_px,y_px\n0,1,2\n1e308,1,2\n"), p + ":3: " + expected + "\"1e308\"");
  EXPECT_EQ(error_for("time_s,x_px,y_px\n-1e308,1,2\n"), p + ":2: " + expected + "\"-1e308\"");
  EXPECT_EQ(error_for("time_s,x_px,y_px\n1000000.5,1,2\n"), p + ":2: " + expected + "\"1000000.5\"");
  EXPECT_EQ(error_for("time_s,x_px,y_px\n-1000000,1,2\n0,1,2\n1000000,1,2\n"), "");  // the ends are in
  // The order message quotes the times as given, not at 6 digits.
  EXPECT_EQ(error_for("time_s,x_px,y_px\n0.1234567,1,2\n0.1234566,1,2\n"),
            p + ":3: time_s: 0.1234566 is earlier than the previous sample (0.1234567)");
}

TEST(GazeTrace, MissingFileIsAnInputError) {
  const TempDir dir;
  const std::string path = (dir.path() / "absent.csv").string();
  EXPECT_EQ(error_of(path), path + ": cannot open (No such file or directory): expected a gaze trace (.csv)");
  EXPECT_EQ(error_of(dir.path().string()),
            dir.path().string() + ": not a regular file (a directory): expected a gaze trace (.csv)");
}

TEST(GazeTrace, OnlyARegularFileWithinTheSizeCapIsRead) {
  // /dev/zero was read until memory ran out, and a FIFO without a writer blocked for ever.
  EXPECT_EQ(error_of("/dev/zero"), "/dev/zero: not a regular file (a character device): expected a gaze trace (.csv)");
  const TempDir dir;
  const std::string fifo = dir.file("gaze.fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(error_of(fifo), fifo + ": not a regular file (a FIFO or pipe): expected a gaze trace (.csv)");
  // One byte over the cap (sparse: nothing is written), refused from its size.
  const std::string big = dir.write("big.csv", "time_s,x_px,y_px\n0,1,2\n");
  std::filesystem::resize_file(big, kMaxGazeTraceBytes + 1);
  EXPECT_EQ(error_of(big), big + ": larger than 256 MiB (" + std::to_string(kMaxGazeTraceBytes + 1) +
                               " bytes): expected a gaze trace (.csv) of at most 256 MiB");
}

TEST(GazeTrace, LongLinesAndOddBytesGiveOneReadableLine) {
  const auto error_for = [](const std::string& text) {
    try {
      parse_gaze_trace(text, "g.csv");
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  // Spaces around fields are accepted, but not without end.
  const std::string padded = "0,1," + std::string(kMaxGazeTraceLineBytes, ' ') + "2";
  EXPECT_EQ(error_for("time_s,x_px,y_px\n" + padded + "\n"),
            "g.csv:2: a line of " + std::to_string(padded.size()) + " bytes: expected at most " +
                std::to_string(kMaxGazeTraceLineBytes) + " (time_s,x_px,y_px[,valid])");
  EXPECT_EQ(error_for("time_s,x_px,y_px\n0,1," + std::string(kMaxGazeTraceLineBytes - 5, ' ') + "2\n"), "");
  // A carriage return or NUL inside a field is quoted escaped, and a long field is cut short.
  EXPECT_EQ(error_for("time_s,x_px,y_px\n0,1\r2,3\n"),
            "g.csv:2: x_px: expected a number, an empty field or nan, got \"1\\x0d2\"");
  EXPECT_EQ(error_for(std::string("time_s,x_px,y_px\n0,1,\"\0\"\n", 25)),
            "g.csv:2: y_px: expected a number, an empty field or nan, got \"\\x22\\x00\\x22\"");
  EXPECT_EQ(error_for("time_s,x_px,y_px\n" + std::string(300, '7') + "x,1,2\n"),
            "g.csv:2: time_s: expected a number, got \"" + std::string(48, '7') + "\" (301 bytes)");
  // The text's own cap, for bytes that come from elsewhere than a file (the fuzzer).
  EXPECT_EQ(error_for(std::string(kMaxGazeTraceBytes + 1, '\n')),
            "g.csv: " + std::to_string(kMaxGazeTraceBytes + 1) + " bytes: expected a gaze trace of at most 256 MiB");
}

TEST(GazeTrace, NonFiniteQueryTimeIsABug) {
  const std::vector<GazeSample> samples = parse_gaze_trace("time_s,x_px,y_px\n0,1,2\n", "x.csv");
  ASSERT_EQ(samples.size(), 1u);
  const TempDir dir;
  TraceGazeSource source(dir.write("gaze.csv", "time_s,x_px,y_px\n0,1,2\n"));
  EXPECT_THROW(source.sample(std::nan("")), std::invalid_argument);
}

}  // namespace
}  // namespace fovlab
