// Tests of protocols/gaze/tracker_validation.h: accuracy and precision in degrees against angles
// computed here from the set-up's geometry, invalid samples, and the attempt's verdict.
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "core/input_error.h"
#include "protocols/gaze/tracker_validation.h"

namespace fovlab {
namespace {

// 1920 x 1080 px on 600 x 337.5 mm (square 0.3125 mm pixels) at 600 mm.
DisplayConfig test_display() {
  DisplayConfig display;
  display.width_px = 1920;
  display.height_px = 1080;
  display.width_mm = 600.0;
  display.height_mm = 337.5;
  display.viewing_distance_mm = 600.0;
  return display;
}

double degrees(double radians) { return radians * 180.0 / std::numbers::pi; }

GazeSample at(double x_px, double y_px, bool valid = true) {
  GazeSample sample;
  sample.x_px = x_px;
  sample.y_px = y_px;
  sample.valid = valid;
  if (!valid) sample.invalid_reason = "blink";
  return sample;
}

TEST(TrackerValidation, AccuracyIsTheAngleFromTheTargetToTheGazeCentroid) {
  const DisplayGeometry display = display_geometry(test_display());
  // The target at the centre; every sample about 1 degree to its right (600 tan 1deg mm, at the
  // 0.01 px the positions are measured at): accuracy atan(offset / D), precision 0 (no movement).
  const double offset_px = std::round(600.0 * std::tan(std::numbers::pi / 180.0) / 0.3125 * 100.0) / 100.0;
  const std::vector<GazeSample> samples(30, at(960.0 + offset_px, 540.0));
  const ValidationTarget target = measure_validation_target(display, 960.0, 540.0, samples);
  EXPECT_EQ(target.samples, 30);
  EXPECT_EQ(target.valid_samples, 30);
  ASSERT_TRUE(target.accuracy_deg && target.precision_deg);
  EXPECT_NEAR(*target.accuracy_deg, degrees(std::atan(offset_px * 0.3125 / 600.0)), 1e-12);
  EXPECT_NEAR(*target.accuracy_deg, 1.0, 2e-4);  // 0.005 px of rounding is 1.5e-4 deg here
  EXPECT_EQ(*target.precision_deg, 0.0);
}

TEST(TrackerValidation, PrecisionIsTheRmsOfSuccessiveSampleAngles) {
  const DisplayGeometry display = display_geometry(test_display());
  // Samples alternating 4 px left and right of the centre target: the centroid is on the target
  // (accuracy 0) and every step spans 8 px, 2 atan(4 x 0.3125 / 600) at the eye.
  std::vector<GazeSample> samples;
  for (int i = 0; i < 20; ++i) samples.push_back(at(i % 2 ? 964.0 : 956.0, 540.0));
  const ValidationTarget target = measure_validation_target(display, 960.0, 540.0, samples);
  ASSERT_TRUE(target.accuracy_deg && target.precision_deg);
  EXPECT_NEAR(*target.accuracy_deg, 0.0, 1e-12);
  EXPECT_NEAR(*target.precision_deg, degrees(2.0 * std::atan(4.0 * 0.3125 / 600.0)), 1e-12);
}

TEST(TrackerValidation, InvalidSamplesCountButBreakTheSuccessionAndTooFewLeaveNoResult) {
  const DisplayGeometry display = display_geometry(test_display());
  // valid, blink, valid, valid: one succession (the last two, 10 px apart) and the centroid of the three.
  const std::vector<GazeSample> samples = {at(900.0, 540.0), at(0.0, 0.0, false), at(960.0, 540.0), at(970.0, 540.0)};
  const ValidationTarget target = measure_validation_target(display, 960.0, 540.0, samples);
  EXPECT_EQ(target.samples, 4);
  EXPECT_EQ(target.valid_samples, 3);
  ASSERT_TRUE(target.accuracy_deg && target.precision_deg);
  EXPECT_NEAR(*target.precision_deg, eccentricity_deg(display, 960.0, 540.0, 970.0, 540.0), 1e-12);
  EXPECT_NEAR(*target.accuracy_deg, eccentricity_deg(display, 960.0, 540.0, (900.0 + 960.0 + 970.0) / 3.0, 540.0),
              1e-12);
  // Fewer than half valid: no result.
  const std::vector<GazeSample> mostly_blinks = {at(960.0, 540.0), at(0, 0, false), at(0, 0, false), at(961.0, 540.0),
                                                 at(0, 0, false)};
  const ValidationTarget blinked = measure_validation_target(display, 960.0, 540.0, mostly_blinks);
  EXPECT_EQ(blinked.valid_samples, 2);
  EXPECT_FALSE(blinked.accuracy_deg);
  EXPECT_FALSE(blinked.precision_deg);
  EXPECT_FALSE(measure_validation_target(display, 960.0, 540.0, {}).accuracy_deg);
}

TEST(TrackerValidation, NoTwoValidSamplesInARowGiveNoPrecisionNotAPerfectOne) {
  // A tracker whose confidence flickers: valid, invalid, valid, invalid. Half the samples are valid
  // but no step between two of them can be measured: no result (it used to read as precision 0).
  const DisplayGeometry display = display_geometry(test_display());
  const std::vector<GazeSample> flicker = {at(960, 540), at(0, 0, false), at(990, 540), at(0, 0, false)};
  const ValidationTarget target = measure_validation_target(display, 960.0, 540.0, flicker);
  EXPECT_EQ(target.valid_samples, 2);
  EXPECT_FALSE(target.precision_deg);
  EXPECT_FALSE(target.accuracy_deg);
}

TEST(TrackerValidation, ASampleReadAgainCountsOnceAndGazeOffTheScreenStillCounts) {
  const DisplayGeometry display = display_geometry(test_display());
  // A 30 Hz tracker read at 60 Hz: each sample twice. Precision is per tracker sample: the repeats'
  // zero steps do not dilute it.
  std::vector<GazeSample> samples;
  for (int i = 0; i < 20; ++i) {
    GazeSample sample = at(i / 2 % 2 ? 964.0 : 956.0, 540.0);
    sample.acquired_s = (i / 2) / 30.0;
    samples.push_back(sample);
  }
  const ValidationTarget target = measure_validation_target(display, 960.0, 540.0, samples);
  EXPECT_EQ(target.samples, 10);
  ASSERT_EQ(target.gaze.size(), 10u);
  ASSERT_TRUE(target.precision_deg);
  EXPECT_NEAR(*target.precision_deg, degrees(2.0 * std::atan(4.0 * 0.3125 / 600.0)), 1e-12);
  // An outer target at the left edge, the gaze 5 px beyond it (off the screen): the tracker says the
  // eye looks there, so the sample counts (dropping it would flatter the accuracy).
  const std::vector<GazeSample> beyond(10, at(-5.0, 540.0));
  const ValidationTarget edge = measure_validation_target(display, 3.0, 540.0, beyond);
  EXPECT_EQ(edge.valid_samples, 10);
  ASSERT_TRUE(edge.accuracy_deg);
  EXPECT_NEAR(*edge.accuracy_deg, eccentricity_deg(display, 3.0, 540.0, -5.0, 540.0), 1e-12);
  // The logged positions are the rounded ones the figures come from; non-finite ones are invalid.
  const ValidationTarget rounded = measure_validation_target(
      display, 960.0, 540.0, {at(960.004, 540.0), at(NAN, 1.0), at(961.0, 540.0), at(962.0, 540.0)});
  ASSERT_EQ(rounded.gaze.size(), 4u);
  EXPECT_EQ(rounded.gaze[0], (std::array<double, 2>{960.0, 540.0}));
  EXPECT_FALSE(rounded.gaze[1]);
  EXPECT_EQ(rounded.valid_samples, 3);
}

TEST(TrackerValidation, AnAttemptPassesOnlyWithEveryTargetMeasuredAndBothMeansWithinTheLimits) {
  ValidationConfig limits;
  limits.max_accuracy_deg = 1.0;
  limits.max_precision_deg = 0.2;
  const auto target = [](std::optional<double> accuracy, std::optional<double> precision) {
    ValidationTarget result;
    result.accuracy_deg = accuracy;
    result.precision_deg = precision;
    return result;
  };
  TrackerValidationEvent attempt;
  attempt.targets = {target(0.5, 0.1), target(1.3, 0.2)};
  summarise_validation(attempt, limits);
  ASSERT_TRUE(attempt.accuracy_deg && attempt.precision_deg);
  EXPECT_DOUBLE_EQ(*attempt.accuracy_deg, 0.9);
  EXPECT_NEAR(*attempt.precision_deg, 0.15, 1e-15);
  EXPECT_TRUE(attempt.passed);  // the mean is the criterion, not the worst target
  EXPECT_EQ(attempt.max_accuracy_deg, 1.0);
  EXPECT_EQ(attempt.max_precision_deg, 0.2);
  attempt.stopped = true;  // the session stopped during the attempt: never a pass
  summarise_validation(attempt, limits);
  EXPECT_FALSE(attempt.passed);
  attempt.stopped = false;
  attempt.targets.push_back(target(1.3, 0.3));
  summarise_validation(attempt, limits);
  EXPECT_FALSE(attempt.passed);  // accuracy 1.033
  attempt.targets = {target(0.1, 0.1), target(std::nullopt, std::nullopt)};
  summarise_validation(attempt, limits);
  EXPECT_FALSE(attempt.passed);
  EXPECT_FALSE(attempt.accuracy_deg);
  attempt.targets = {target(0.1, 0.3)};
  summarise_validation(attempt, limits);
  EXPECT_FALSE(attempt.passed);  // precision over its limit
}

TEST(TrackerValidation, TheEventRoundTripsThroughItsJson) {
  TrackerValidationEvent attempt;
  attempt.stamp.t = 3.5;
  attempt.reason = TrackerValidationEvent::rest;
  attempt.attempt = 2;
  attempt.start_s = 1.25;
  ValidationTarget measured;
  measured.x_px = 960.0;
  measured.y_px = 540.0;
  measured.samples = 60;
  measured.valid_samples = 58;
  measured.accuracy_deg = 0.4;
  measured.precision_deg = 0.05;
  measured.gaze = {std::array<double, 2>{960.25, 540.5}, std::nullopt};
  ValidationTarget blinked;
  blinked.x_px = 100.5;
  blinked.y_px = 80.25;
  blinked.samples = 60;
  attempt.targets = {measured, blinked};
  summarise_validation(attempt, ValidationConfig{});
  EXPECT_EQ(parse_tracker_validation(to_json(attempt)), attempt);
  EXPECT_FALSE(to_json(attempt).contains("stopped"));  // written only when true
  attempt.stopped = true;
  EXPECT_EQ(parse_tracker_validation(to_json(attempt)), attempt);
  EXPECT_EQ(std::get<TrackerValidationEvent>(parse_log_event(to_json(attempt))), attempt);
  nlohmann::json forged = to_json(attempt);
  forged["targets"][0]["accuracy_deg"] = "0.4";
  EXPECT_THROW(parse_tracker_validation(forged), InputError);
}

}  // namespace
}  // namespace fovlab
