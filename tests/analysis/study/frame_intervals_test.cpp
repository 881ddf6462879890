// The intervals between presented refreshes (issue 38): their summary on small known sets, pooling
// sessions into a study, and what `fovlab analyze` gathers from a real session log (a headless
// session's virtual clock presents every refresh exactly one period after the last).
#include "analysis/statistics/frame_intervals.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "analysis/study/study_data.h"
#include "tests/app/cli_test_support.h"

namespace fovlab::analysis {
namespace {

namespace fs = std::filesystem;

TEST(FrameIntervals, SummaryOfAKnownSet) {
  // 16, 16, 16, 17, 34, 50 ms at 60 Hz: late beyond 1.5 x 16.667 = 25 ms: 34 and 50.
  const FrameIntervalSummary summary = summarise_frame_intervals({0.016, 0.017, 0.050, 0.016, 0.034, 0.016}, 60.0);
  EXPECT_EQ(summary.refresh_hz, 60.0);
  EXPECT_EQ(summary.intervals, 6u);
  // Nearest rank: the median is rank ceil(3) = 3 (16), p99 rank ceil(5.94) = 6 (50).
  EXPECT_EQ(summary.median_ms, 16.0);
  EXPECT_EQ(summary.p99_ms, 50.0);
  EXPECT_EQ(summary.max_ms, 50.0);
  // Mean 149 / 6; sample SD by hand.
  const double mean = 149.0 / 6.0;
  double squares = 0.0;
  for (double v : {16.0, 16.0, 16.0, 17.0, 34.0, 50.0}) squares += (v - mean) * (v - mean);
  ASSERT_TRUE(summary.sd_ms.has_value());
  EXPECT_NEAR(*summary.sd_ms, std::sqrt(squares / 5.0), 1e-12);
  EXPECT_EQ(summary.late, 2u);
  EXPECT_DOUBLE_EQ(*summary.late_share, 2.0 / 6.0);
}

TEST(FrameIntervals, RoundedToTheMicrosecondAndOnlyBeyondOneAndAHalfPeriodsIsLate) {
  // 1/60 s rounds to 16.667 ms; exactly 25 ms (1.5 periods) is not late, 25.001 ms is.
  const FrameIntervalSummary summary = summarise_frame_intervals({1.0 / 60.0, 0.025, 0.025001}, 60.0);
  EXPECT_EQ(summary.count_by_us.count(16667), 1u);
  EXPECT_EQ(summary.median_ms, 25.0);
  EXPECT_EQ(summary.late, 1u);
  // Negative and non-finite values are left out; one value has no SD.
  const FrameIntervalSummary one =
      summarise_frame_intervals({-0.001, std::numeric_limits<double>::quiet_NaN(), 0.02}, 60.0);
  EXPECT_EQ(one.intervals, 1u);
  EXPECT_EQ(one.sd_ms, std::nullopt);
  EXPECT_EQ(one.median_ms, 20.0);
  // No refresh rate: nothing is counted late; nothing at all: no numbers.
  const FrameIntervalSummary unknown = summarise_frame_intervals({0.016, 0.1}, std::nullopt);
  EXPECT_EQ(unknown.refresh_hz, std::nullopt);
  EXPECT_EQ(unknown.late, 0u);
  EXPECT_EQ(unknown.late_share, 0.0);
  const FrameIntervalSummary empty = summarise_frame_intervals({}, 60.0);
  EXPECT_EQ(empty.intervals, 0u);
  EXPECT_EQ(empty.median_ms, std::nullopt);
  EXPECT_EQ(empty.late_share, std::nullopt);
}

TEST(FrameIntervals, PoolingAddsTheSessionsAndCountsEachLateAgainstItsOwnRate) {
  const FrameIntervalSummary a = summarise_frame_intervals({0.016, 0.034}, 60.0);   // 34 > 25: late
  const FrameIntervalSummary b = summarise_frame_intervals({0.008, 0.016}, 120.0);  // 16 > 12.5: late
  const FrameIntervalSummary pooled = pool_frame_intervals({&a, &b});
  EXPECT_EQ(pooled.intervals, 4u);
  EXPECT_EQ(pooled.late, 2u);
  EXPECT_EQ(pooled.refresh_hz, std::nullopt) << "two rates: none for the pool";
  EXPECT_EQ(pooled.median_ms, 16.0);  // 8, 16, 16, 34: rank 2
  EXPECT_EQ(pooled.max_ms, 34.0);
  const FrameIntervalSummary c = summarise_frame_intervals({0.017}, 60.0);
  const FrameIntervalSummary empty;
  EXPECT_EQ(pool_frame_intervals({&a, &c, &empty}).refresh_hz, 60.0);
  // Pooling one session gives it back.
  const FrameIntervalSummary same = pool_frame_intervals({&a});
  EXPECT_EQ(same.count_by_us, a.count_by_us);
  EXPECT_EQ(same.sd_ms, a.sd_ms);
}

TEST(FrameIntervals, GatheredFromAHeadlessSessionLog) {
  const fs::path folder = fovlab::cli_test::scratch("fovlab-frame-intervals");
  const std::string scene = (fs::path(FOVLAB_SOURCE_DIR) / "tests/fixtures/scenes/sphere.glsl").string();
  const fs::path config = fovlab::cli_test::write_file(
      folder / "frames.toml",
      "[study]\nname = \"frames\"\nseed = 38\n\n"
      "[display]\nwidth_px = 64\nheight_px = 36\nrefresh_hz = 60\nwidth_mm = 600\nheight_mm = 337.5\n"
      "viewing_distance_mm = 500\n\n"
      "[stimulus]\nduration_s = 0.1\nframes_per_second = 20\ncamera_start_s = 0.5\n\n"
      "[stimulus.reference]\nmethod = \"gt\"\n\n[stimulus.test]\nmethod = \"ipr\"\n\n"
      "[levels]\nparameter = \"max_steps\"\nvalues = [4, 16]\n\n"
      "[protocol]\nkind = \"2afc\"\nquestion = \"same\"\nrepeats = 1\n\n"
      "[timing]\nblack_interval_s = 0.1\ninter_trial_s = 0.1\n\n"
      "[[block]]\nname = \"sphere\"\nscene = \"" +
          scene + "\"\n");
  const fs::path results = folder / "results";
  const auto run = fovlab::cli_test::run("run " + config.string() + " --participant next --headless --results " +
                                             results.string() + " --observer simulated",
                                         "env -u DISPLAY -u WAYLAND_DISPLAY");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const StudyData data = load_study({results.string()});
  ASSERT_EQ(data.participants.size(), 1u);
  const FrameIntervalSummary& frames = data.participants[0].frame_intervals;
  // 0.1 s at 60 Hz: 6 refreshes a stimulus, 5 intervals; two stimuli a trial, two trials.
  EXPECT_EQ(frames.intervals, 2u * 2u * 5u);
  EXPECT_EQ(frames.refresh_hz, 60.0);
  EXPECT_EQ(frames.median_ms, 16.667);
  EXPECT_EQ(frames.p99_ms, 16.667);
  EXPECT_EQ(frames.sd_ms, 0.0);
  EXPECT_EQ(frames.late, 0u);
}

}  // namespace
}  // namespace fovlab::analysis
