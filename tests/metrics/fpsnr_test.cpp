#include "metrics/fpsnr.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "metrics/image_metrics.h"

namespace fovlab::metrics {
namespace {

// Foveation model of Geisler & Perry 1998 as used by Lee, Pattichis, Bovik 2002, restated here so
// the tests do not share it with the code under test: f_c(e) = e2 ln(1 / CT0) / (alpha (e + e2)).
double cutoff(double e_deg) { return 2.3 * std::log(64.0) / (0.106 * (e_deg + 2.3)); }
constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// A one-pixel-high strip: 400 px over 200 mm (pitch 0.5 mm) at 500 mm. Pixels per degree at the
// centre: 500 / (180 / pi) / 0.5 = 17.45, so the display Nyquist frequency is 8.73 cycles/degree,
// which the eye's cutoff frequency reaches at 90.24 / 8.73 - 2.3 = 8.04 degrees; the strip reaches
// atan(100 / 500) = 11.3 degrees. Pixel centres lie on the horizontal through the display's centre.
DisplayGeometry strip() { return display_from_size(400, 1, 200.0, 0.5, 500.0); }
double strip_nyquist() { return 0.5 * 500.0 / kDegPerRad / 0.5; }

// The weight of strip pixel x with the gaze on the centre of the display: the pixel's centre is
// (x + 0.5 - 200) * 0.5 mm from the gaze, on the screen's plane at 500 mm.
double strip_weight(int x) {
  const double e = std::atan(std::abs(x + 0.5 - 200.0) * 0.5 / 500.0) * kDegPerRad;
  const double f = std::min(cutoff(e), strip_nyquist()) / std::min(cutoff(0.0), strip_nyquist());
  return f * f;
}

Image constant(int width, int height, int channels, float value) {
  Image image(width, height, channels);
  for (float& v : image.pixels) v = value;
  return image;
}

TEST(Fpsnr, WeightsFollowTheFoveationModel) {
  const Image w = foveation_weights(strip(), 200.0, 0.5);
  ASSERT_EQ(w.width, 400);
  ASSERT_EQ(w.height, 1);
  ASSERT_EQ(w.channels, 1);
  EXPECT_FLOAT_EQ(w.at(200, 0, 0), 1.0f);  // display-limited near the gaze
  EXPECT_FLOAT_EQ(w.at(199, 0, 0), 1.0f);
  for (int x : {0, 10, 50, 100, 130, 300, 399}) {
    EXPECT_NEAR(w.at(x, 0, 0), strip_weight(x), 1e-6) << "pixel " << x;
  }
  // Beyond 8.04 degrees (about 70.7 mm, 141 px from the gaze) the eye limits: weight below 1.
  EXPECT_LT(w.at(0, 0, 0), 0.75f);
  EXPECT_FLOAT_EQ(w.at(80, 0, 0), 1.0f);  // 119.5 px = 59.75 mm: 6.8 degrees
  // Monotone in eccentricity on both sides.
  for (int x = 1; x <= 200; ++x) EXPECT_LE(w.at(x - 1, 0, 0), w.at(x, 0, 0));
  for (int x = 201; x < 400; ++x) EXPECT_GE(w.at(x - 1, 0, 0), w.at(x, 0, 0));
}

TEST(Fpsnr, OneWrongPixelIsWeightedByItsFoveationWeight) {
  const Image a = constant(400, 1, 3, 0.5f);
  for (int x : {5, 200, 390}) {
    Image b = a;
    b.at(x, 0, 1) = 0.75f;  // one channel off by 0.25
    const FpsnrResult r = fpsnr(a, b, strip(), 200.0, 0.5);
    double weight_sum = 0.0;
    for (int i = 0; i < 400; ++i) weight_sum += strip_weight(i);
    const double expected = strip_weight(x) * 0.0625 / (3.0 * weight_sum);
    EXPECT_NEAR(r.fmse, expected, 1e-12 * expected) << "pixel " << x;
    EXPECT_NEAR(r.fpsnr_db, 10.0 * std::log10(1.0 / expected), 1e-9);
    EXPECT_FALSE(r.identical);
  }
}

TEST(Fpsnr, ErrorsFarFromTheGazeCountLess) {
  const Image a = constant(400, 1, 3, 0.5f);
  Image near_gaze = a, periphery = a;
  near_gaze.at(200, 0, 0) = 0.7f;
  periphery.at(0, 0, 0) = 0.7f;
  const double at_gaze = fpsnr(a, near_gaze, strip(), 200.0, 0.5).fpsnr_db;
  const double far = fpsnr(a, periphery, strip(), 200.0, 0.5).fpsnr_db;
  EXPECT_GT(far, at_gaze);
  // Moving the gaze onto the peripheral error makes it count fully (weight 1 instead of 0.58).
  EXPECT_LT(fpsnr(a, periphery, strip(), 0.5, 0.5).fpsnr_db, far);
}

TEST(Fpsnr, EqualsPsnrWhenTheDisplayLimitsEverywhere) {
  // 64 x 48 pixels over 640 x 480 mm at 1000 mm: 1.75 pixels per degree at the centre (Nyquist
  // 0.87 cycles/degree), while the eye's cutoff is still 3.7 cycles/degree at the corners
  // (atan(400 / 1000) = 21.8 degrees): every weight is 1 and FMSE is the MSE.
  const DisplayGeometry d = display_from_size(64, 48, 640.0, 480.0, 1000.0);
  ASSERT_LT(0.5 * d.pixels_per_degree_at_centre(), cutoff(21.8));
  Image a(64, 48, 3), b(64, 48, 4);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 3; ++c) {
        a.at(x, y, c) = static_cast<float>(((x * 7 + y * 13 + c * 5) % 17) / 16.0);
        b.at(x, y, c) = static_cast<float>(((x * 3 + y * 11 + c * 2) % 19) / 18.0);
      }
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) b.at(x, y, 3) = 0.3f;
  const FpsnrResult f = fpsnr(a, b, d, 32.0, 24.0);
  const PsnrResult p = psnr(a, b);
  EXPECT_NEAR(f.fmse, p.mse, 1e-13 * p.mse);
  EXPECT_NEAR(f.fpsnr_db, p.psnr_db, 1e-9);
}

TEST(Fpsnr, UniformErrorGivesThePsnrWhateverTheWeights) {
  const Image a = constant(400, 1, 1, 0.25f);
  const Image b = constant(400, 1, 1, 0.5f);
  const FpsnrResult r = fpsnr(a, b, strip(), 37.0, 0.5);
  EXPECT_NEAR(r.fmse, 0.0625, 1e-15);
  EXPECT_NEAR(r.fpsnr_db, psnr(a, b).psnr_db, 1e-12);
}

TEST(Fpsnr, IdenticalImagesGiveInfinity) {
  const Image a = constant(400, 1, 3, 0.4f);
  const FpsnrResult r = fpsnr(a, a, strip(), 200.0, 0.5);
  EXPECT_TRUE(r.identical);
  EXPECT_EQ(r.fmse, 0.0);
  EXPECT_EQ(r.fpsnr_db, std::numeric_limits<double>::infinity());
}

TEST(Fpsnr, GazeOffTheScreenIsAllowed) {
  const Image a = constant(400, 1, 3, 0.4f);
  Image b = a;
  b.at(3, 0, 2) = 0.9f;
  const FpsnrResult r = fpsnr(a, b, strip(), -1000.0, 50.0);
  EXPECT_TRUE(std::isfinite(r.fpsnr_db));
  EXPECT_GT(r.fmse, 0.0);
}

TEST(Fpsnr, RejectsBadInput) {
  const DisplayGeometry d = strip();
  const Image a = constant(400, 1, 3, 0.4f);
  EXPECT_THROW(fpsnr(a, constant(399, 1, 3, 0.4f), d, 200, 0.5), std::invalid_argument);  // sizes differ
  EXPECT_THROW(fpsnr(constant(200, 2, 3, 0.4f), constant(200, 2, 3, 0.4f), d, 200, 0.5),
               std::invalid_argument);                                                    // not the display's size
  EXPECT_THROW(fpsnr(a, constant(400, 1, 1, 0.4f), d, 200, 0.5), std::invalid_argument);  // grey vs colour
  EXPECT_THROW(fpsnr(a, constant(400, 1, 2, 0.4f), d, 200, 0.5), std::invalid_argument);
  EXPECT_THROW(fpsnr(a, a, d, std::numeric_limits<double>::quiet_NaN(), 0.5), std::invalid_argument);
  EXPECT_THROW(fpsnr(a, a, d, 200, std::numeric_limits<double>::infinity()), std::invalid_argument);
  DisplayGeometry bad = d;
  bad.viewing_distance_mm = 0.0;
  EXPECT_THROW(fpsnr(a, a, bad, 200, 0.5), std::invalid_argument);
  EXPECT_THROW(foveation_weights(bad, 200, 0.5), std::invalid_argument);
  Image short_buffer = a;
  short_buffer.pixels.pop_back();
  EXPECT_THROW(fpsnr(short_buffer, a, d, 200, 0.5), std::invalid_argument);
}

}  // namespace
}  // namespace fovlab::metrics
