#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "protocols/gaze/gaze_sample.h"

namespace fovlab {
namespace {

GazeSample make(double t, double x, double y, bool valid = true, const std::string& reason = "") {
  GazeSample sample;
  sample.time_s = t;
  sample.x_px = x;
  sample.y_px = y;
  sample.valid = valid;
  sample.invalid_reason = reason;
  return sample;
}

TEST(GazeSanitize, ValidSampleIsReturnedUnchanged) {
  const GazeSample last = make(0.5, 10.0, 20.0);
  const GazeSample out = sanitize_gaze(make(1.25, 100.5, 200.25), 640, 480, &last);
  EXPECT_TRUE(out.valid);
  EXPECT_EQ(out.invalid_reason, "");
  EXPECT_DOUBLE_EQ(out.time_s, 1.25);
  EXPECT_DOUBLE_EQ(out.x_px, 100.5);
  EXPECT_DOUBLE_EQ(out.y_px, 200.25);
  // Corners: 0 is inside, width - tiny is inside.
  EXPECT_TRUE(sanitize_gaze(make(0, 0.0, 0.0), 640, 480, nullptr).valid);
  EXPECT_TRUE(sanitize_gaze(make(0, 639.994, 479.994), 640, 480, nullptr).valid);
}

TEST(GazeSanitize, ValidityIsDecidedOnThePositionRoundedAsUsed) {
  // x = 31.996 on a 32-pixel-wide display was used and logged as 32.00 (off the screen) but valid.
  const GazeSample last = make(0.5, 3.0, 4.0);
  for (const GazeSample& raw : {make(1.0, 31.996, 5.0), make(1.0, 5.0, 15.996)}) {
    const GazeSample out = sanitize_gaze(raw, 32, 16, &last);
    EXPECT_FALSE(out.valid) << raw.x_px << "," << raw.y_px;
    EXPECT_EQ(out.invalid_reason, "off_screen");
    EXPECT_DOUBLE_EQ(out.x_px, 3.0);
    EXPECT_DOUBLE_EQ(out.y_px, 4.0);
  }
  // Just inside: valid, and the position returned is the rounded one the session uses.
  const GazeSample inside = sanitize_gaze(make(1.0, 31.994, 15.9949), 32, 16, &last);
  EXPECT_TRUE(inside.valid);
  EXPECT_EQ(inside.x_px, round_gaze_px(31.994));
  EXPECT_DOUBLE_EQ(inside.x_px, 31.99);
  EXPECT_DOUBLE_EQ(inside.y_px, 15.99);
  // Rounding never makes -0 (a JSON "-0.0" in the log): -0.004 is 0, on the screen.
  const GazeSample edge = sanitize_gaze(make(1.0, -0.004, 0.0), 32, 16, &last);
  EXPECT_TRUE(edge.valid);
  EXPECT_FALSE(std::signbit(edge.x_px));
  // A held position that rounds off the screen is not held: the centre is used.
  const GazeSample held_outside = make(0.5, 31.996, 4.0);
  const GazeSample centre = sanitize_gaze(make(1.0, -1.0, 1.0), 32, 16, &held_outside);
  EXPECT_DOUBLE_EQ(centre.x_px, 16.0);
  EXPECT_DOUBLE_EQ(centre.y_px, 8.0);
  // Rounding is idempotent (the session's own rounding of the result changes nothing), and a
  // position too far off to round is kept, off_screen rather than not_finite.
  EXPECT_EQ(round_gaze_px(round_gaze_px(123.456789)), round_gaze_px(123.456789));
  EXPECT_EQ(sanitize_gaze(make(1.0, 1.7e308, 1.0), 32, 16, nullptr).invalid_reason, "off_screen");
}

TEST(GazeSanitize, NotFiniteUsesCentreBeforeAnyValidSample) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const GazeSample& raw : {make(2.0, nan, 10.0), make(2.0, 10.0, inf), make(2.0, -inf, nan)}) {
    const GazeSample out = sanitize_gaze(raw, 640, 480, nullptr);
    EXPECT_FALSE(out.valid);
    EXPECT_EQ(out.invalid_reason, "not_finite");
    EXPECT_DOUBLE_EQ(out.time_s, 2.0);
    EXPECT_DOUBLE_EQ(out.x_px, 320.0);
    EXPECT_DOUBLE_EQ(out.y_px, 240.0);
  }
}

TEST(GazeSanitize, OffScreenHoldsTheLastValidPosition) {
  const GazeSample last = make(0.5, 11.0, 22.0);
  for (const GazeSample& raw : {make(3.0, 640.0, 10.0), make(3.0, 10.0, 480.0), make(3.0, -0.01, 10.0),
                                make(3.0, 10.0, -5.0), make(3.0, 1e9, 1e9)}) {
    const GazeSample out = sanitize_gaze(raw, 640, 480, &last);
    EXPECT_FALSE(out.valid);
    EXPECT_EQ(out.invalid_reason, "off_screen");
    EXPECT_DOUBLE_EQ(out.time_s, 3.0);
    EXPECT_DOUBLE_EQ(out.x_px, 11.0);
    EXPECT_DOUBLE_EQ(out.y_px, 22.0);
  }
}

TEST(GazeSanitize, AlreadyInvalidKeepsItsReason) {
  const GazeSample last = make(0.5, 11.0, 22.0);
  const GazeSample out = sanitize_gaze(make(4.0, 100.0, 100.0, false, "blink"), 640, 480, &last);
  EXPECT_FALSE(out.valid);
  EXPECT_EQ(out.invalid_reason, "blink");
  EXPECT_DOUBLE_EQ(out.time_s, 4.0);
  EXPECT_DOUBLE_EQ(out.x_px, 11.0);
  EXPECT_DOUBLE_EQ(out.y_px, 22.0);
  // An invalid sample with a non-finite position keeps its own reason too.
  const GazeSample low = sanitize_gaze(make(4.0, std::nan(""), 1.0, false, "low_confidence"), 640, 480, nullptr);
  EXPECT_EQ(low.invalid_reason, "low_confidence");
  EXPECT_DOUBLE_EQ(low.x_px, 320.0);
  EXPECT_DOUBLE_EQ(low.y_px, 240.0);
}

TEST(GazeSanitize, UnusableLastValidFallsBackToTheCentre) {
  const GazeSample not_valid = make(0.5, 11.0, 22.0, false, "blink");
  const GazeSample outside = make(0.5, 900.0, 22.0);
  for (const GazeSample* last : {&not_valid, &outside}) {
    const GazeSample out = sanitize_gaze(make(1.0, -1.0, -1.0), 800, 600, last);
    EXPECT_EQ(out.invalid_reason, "off_screen");
    EXPECT_DOUBLE_EQ(out.x_px, 400.0);
    EXPECT_DOUBLE_EQ(out.y_px, 300.0);
  }
}

}  // namespace
}  // namespace fovlab
