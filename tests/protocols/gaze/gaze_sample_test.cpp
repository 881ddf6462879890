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
  EXPECT_TRUE(sanitize_gaze(make(0, 639.999, 479.999), 640, 480, nullptr).valid);
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
