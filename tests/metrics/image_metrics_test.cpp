#include "metrics/image_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace fovlab::metrics {
namespace {

// Constants of Wang et al. 2004 for data range L = 1, restated here so the
// tests do not share them with the code under test.
constexpr double kC1 = 0.01 * 0.01;
constexpr double kC2 = 0.03 * 0.03;

// SplitMix64 (Steele, Lea, Flood 2014): a fixed, portable sequence, unlike
// the std:: distributions whose output is implementation-defined.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1) from the top 24 bits, exactly representable as float.
  float unit() { return static_cast<float>(next() >> 40) / 16777216.0f; }

 private:
  std::uint64_t state_;
};

Image random_image(int width, int height, int channels, std::uint64_t seed) {
  SplitMix64 rng(seed);
  Image image(width, height, channels);
  for (float& value : image.pixels) value = rng.unit();
  return image;
}

Image constant_image(int width, int height, int channels, float value) {
  Image image(width, height, channels);
  for (float& v : image.pixels) v = value;
  return image;
}

// A smooth grey test pattern with some structure (so it has local variance).
Image pattern_image(int width, int height) {
  Image image(width, height, 1);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      image.at(x, y, 0) = static_cast<float>(0.5 + 0.3 * std::sin(0.4 * x) * std::cos(0.3 * y));
    }
  }
  return image;
}

// Luma in double straight from the BT.601 definition (independent of luma()).
double reference_luma(const Image& image, int x, int y) {
  if (image.channels == 1) return image.at(x, y, 0);
  return 0.299 * image.at(x, y, 0) + 0.587 * image.at(x, y, 1) + 0.114 * image.at(x, y, 2);
}

struct LocalStatistics {
  double mean_x, mean_y, variance_x, variance_y, covariance;
};

// Direct, non-separable evaluation of eqs. 14-16 of Wang et al. 2004 with the
// 11x11 Gaussian (sigma 1.5) normalised over the square, for the window whose
// top-left corner is (left, top). Variances are taken about the local mean,
// not as E[x^2] - E[x]^2 as the fast code does.
LocalStatistics reference_statistics(const Image& a, const Image& b, int left, int top) {
  double weights[11][11];
  double weight_sum = 0.0;
  for (int j = 0; j < 11; ++j) {
    for (int i = 0; i < 11; ++i) {
      const double dx = i - 5, dy = j - 5;
      weights[j][i] = std::exp(-(dx * dx + dy * dy) / (2.0 * 1.5 * 1.5));
      weight_sum += weights[j][i];
    }
  }
  LocalStatistics s{0, 0, 0, 0, 0};
  for (int j = 0; j < 11; ++j) {
    for (int i = 0; i < 11; ++i) {
      const double w = weights[j][i] / weight_sum;
      s.mean_x += w * reference_luma(a, left + i, top + j);
      s.mean_y += w * reference_luma(b, left + i, top + j);
    }
  }
  for (int j = 0; j < 11; ++j) {
    for (int i = 0; i < 11; ++i) {
      const double w = weights[j][i] / weight_sum;
      const double dx = reference_luma(a, left + i, top + j) - s.mean_x;
      const double dy = reference_luma(b, left + i, top + j) - s.mean_y;
      s.variance_x += w * dx * dx;
      s.variance_y += w * dy * dy;
      s.covariance += w * dx * dy;
    }
  }
  return s;
}

double reference_local_ssim(const LocalStatistics& s) {
  return (2 * s.mean_x * s.mean_y + kC1) * (2 * s.covariance + kC2) /
         ((s.mean_x * s.mean_x + s.mean_y * s.mean_y + kC1) * (s.variance_x + s.variance_y + kC2));
}

double reference_luminance_term(const LocalStatistics& s) {
  return (2 * s.mean_x * s.mean_y + kC1) / (s.mean_x * s.mean_x + s.mean_y * s.mean_y + kC1);
}

// Checks the fast SSIM against the brute-force one at every valid window.
void expect_matches_reference(const Image& a, const Image& b) {
  const SsimResult fast = ssim(a, b);
  ASSERT_EQ(fast.map.width, a.width - 10);
  ASSERT_EQ(fast.map.height, a.height - 10);
  ASSERT_EQ(fast.map.channels, 1);
  double sum = 0.0;
  for (int y = 0; y < fast.map.height; ++y) {
    for (int x = 0; x < fast.map.width; ++x) {
      const double expected = reference_local_ssim(reference_statistics(a, b, x, y));
      sum += expected;
      // The map is stored as float, so compare it at float precision.
      EXPECT_NEAR(fast.map.at(x, y, 0), expected, 1e-6) << "at " << x << "," << y;
    }
  }
  const double expected_mean = sum / (fast.map.width * fast.map.height);
  EXPECT_NEAR(fast.mean_ssim, expected_mean, 1e-9);
}

// ---------------------------------------------------------------- luma

TEST(Luma, AppliesBt601WeightsToEachPrimary) {
  Image rgb(4, 1, 3);
  const float colours[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.2f, 0.4f, 0.6f}};
  for (int x = 0; x < 4; ++x)
    for (int c = 0; c < 3; ++c) rgb.at(x, 0, c) = colours[x][c];
  const Image grey = luma(rgb);
  ASSERT_EQ(grey.channels, 1);
  ASSERT_EQ(grey.width, 4);
  ASSERT_EQ(grey.height, 1);
  EXPECT_NEAR(grey.at(0, 0, 0), 0.299, 1e-7);
  EXPECT_NEAR(grey.at(1, 0, 0), 0.587, 1e-7);
  EXPECT_NEAR(grey.at(2, 0, 0), 0.114, 1e-7);
  EXPECT_NEAR(grey.at(3, 0, 0), 0.299 * 0.2 + 0.587 * 0.4 + 0.114 * 0.6, 1e-6);
}

TEST(Luma, IgnoresAlpha) {
  Image rgba(2, 1, 4);
  rgba.pixels = {1, 1, 1, 0, 1, 1, 1, 1};
  const Image grey = luma(rgba);
  EXPECT_NEAR(grey.at(0, 0, 0), 1.0, 1e-7);
  EXPECT_NEAR(grey.at(1, 0, 0), 1.0, 1e-7);
}

TEST(Luma, ReturnsGreyImagesUnchanged) {
  const Image grey = random_image(5, 3, 1, 7);
  const Image result = luma(grey);
  EXPECT_EQ(result.width, 5);
  EXPECT_EQ(result.height, 3);
  EXPECT_EQ(result.channels, 1);
  EXPECT_EQ(result.pixels, grey.pixels);
}

TEST(Luma, RejectsUnsupportedChannelCounts) {
  EXPECT_THROW(luma(Image(2, 2, 2)), std::invalid_argument);
  Image inconsistent(2, 2, 3);
  inconsistent.pixels.pop_back();
  EXPECT_THROW(luma(inconsistent), std::invalid_argument);
}

// ---------------------------------------------------------------- PSNR

TEST(Psnr, IdenticalImagesHaveInfinitePsnr) {
  const Image image = random_image(8, 6, 3, 1);
  const PsnrResult result = psnr(image, image);
  EXPECT_TRUE(result.identical);
  EXPECT_EQ(result.mse, 0.0);
  EXPECT_EQ(result.psnr_db, std::numeric_limits<double>::infinity());
}

TEST(Psnr, MatchesHandComputedValue) {
  // Two 2x2 RGB images, 12 samples; errors 0.5 and 0.25 in two of them:
  // MSE = (0.25 + 0.0625) / 12, PSNR = 10 log10(12 / 0.3125) = 10 log10(38.4).
  const Image a = constant_image(2, 2, 3, 0.0f);
  Image b = a;
  b.at(0, 0, 0) = 0.5f;
  b.at(1, 1, 2) = 0.25f;
  const PsnrResult result = psnr(a, b);
  EXPECT_FALSE(result.identical);
  EXPECT_DOUBLE_EQ(result.mse, 0.3125 / 12.0);
  EXPECT_NEAR(result.psnr_db, 15.843312243675307, 1e-12);
  EXPECT_NEAR(result.psnr_db, 10.0 * std::log10(38.4), 1e-12);
}

TEST(Psnr, IgnoresAlpha) {
  Image a(2, 1, 4), b(2, 1, 4);
  a.pixels = {0.5f, 0.5f, 0.5f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f};
  b.pixels = {0.5f, 0.5f, 0.5f, 0.0f, 0.0f, 0.0f, 0.5f, 0.0f};
  const PsnrResult result = psnr(a, b);
  EXPECT_DOUBLE_EQ(result.mse, 0.25 / 6.0);  // six colour samples, one differs by 0.5
  const PsnrResult same_colour = psnr(a, a);
  Image a_other_alpha = a;
  a_other_alpha.at(0, 0, 3) = 0.0f;
  EXPECT_TRUE(psnr(a, a_other_alpha).identical);
  EXPECT_TRUE(same_colour.identical);
}

TEST(Psnr, ComparesRgbWithRgba) {
  Image rgb(1, 1, 3), rgba(1, 1, 4);
  rgb.pixels = {0.1f, 0.2f, 0.3f};
  rgba.pixels = {0.1f, 0.2f, 0.3f, 0.0f};
  EXPECT_TRUE(psnr(rgb, rgba).identical);
}

TEST(Psnr, GreyImages) {
  Image a(2, 1, 1), b(2, 1, 1);
  a.pixels = {0.0f, 0.0f};
  b.pixels = {0.1f, 0.0f};
  const PsnrResult result = psnr(a, b);
  const double expected_mse = static_cast<double>(0.1f) * static_cast<double>(0.1f) / 2.0;
  EXPECT_DOUBLE_EQ(result.mse, expected_mse);
  EXPECT_NEAR(result.psnr_db, -10.0 * std::log10(expected_mse), 1e-12);
}

TEST(Psnr, RejectsMismatchedImages) {
  try {
    psnr(Image(64, 36, 3), Image(32, 18, 3));
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("64x36 vs 32x18"), std::string::npos) << error.what();
  }
  EXPECT_THROW(psnr(Image(4, 4, 1), Image(4, 4, 3)), std::invalid_argument);
  EXPECT_THROW(psnr(Image(0, 0, 3), Image(0, 0, 3)), std::invalid_argument);
}

// ---------------------------------------------------------------- SSIM

TEST(Ssim, IdenticalImagesGiveExactlyOne) {
  for (int channels : {1, 3, 4}) {
    const Image image = random_image(40, 30, channels, 11 + static_cast<std::uint64_t>(channels));
    const SsimResult result = ssim(image, image);
    EXPECT_NEAR(result.mean_ssim, 1.0, 1e-12) << channels << " channels";
  }
}

TEST(Ssim, MapHasValidWindowPositionsOnly) {
  const SsimResult result = ssim(random_image(64, 36, 3, 2), random_image(64, 36, 3, 3));
  EXPECT_EQ(result.map.width, 54);
  EXPECT_EQ(result.map.height, 26);
  EXPECT_EQ(result.map.channels, 1);
  double sum = 0.0;
  for (float value : result.map.pixels) sum += value;
  EXPECT_NEAR(result.mean_ssim, sum / static_cast<double>(result.map.pixels.size()), 1e-6);

  const SsimResult smallest = ssim(random_image(11, 11, 1, 4), random_image(11, 11, 1, 5));
  EXPECT_EQ(smallest.map.width, 1);
  EXPECT_EQ(smallest.map.height, 1);
}

TEST(Ssim, ConstantImagesFollowClosedForm) {
  // Zero variances leave only the luminance term (2ab + C1) / (a^2 + b^2 + C1).
  const float levels[][2] = {{0.3f, 0.7f}, {0.0f, 1.0f}, {0.5f, 0.5f}, {0.02f, 0.9f}};
  for (const auto& level : levels) {
    const double a = level[0], b = level[1];
    const SsimResult result = ssim(constant_image(20, 15, 1, level[0]), constant_image(20, 15, 1, level[1]));
    EXPECT_NEAR(result.mean_ssim, (2 * a * b + kC1) / (a * a + b * b + kC1), 1e-12) << a << " vs " << b;
  }
}

TEST(Ssim, MatchesBruteForceReferenceOnRandomGreyImages) {
  expect_matches_reference(random_image(37, 29, 1, 100), random_image(37, 29, 1, 200));
}

TEST(Ssim, MatchesBruteForceReferenceOnRandomColourImages) {
  expect_matches_reference(random_image(37, 29, 3, 300), random_image(37, 29, 4, 400));
}

TEST(Ssim, MatchesBruteForceReferenceOnCorrelatedImages) {
  // Random images are nearly uncorrelated (SSIM ~ 0); also check a pair
  // with high structural similarity, where the covariance term matters.
  const Image a = random_image(23, 31, 1, 500);
  Image b = a;
  SplitMix64 rng(600);
  for (float& value : b.pixels) value = 0.8f * value + 0.1f + 0.1f * (rng.unit() - 0.5f);
  expect_matches_reference(a, b);
}

TEST(Ssim, IsSymmetric) {
  const Image a = random_image(30, 25, 3, 21);
  const Image b = random_image(30, 25, 3, 22);
  const SsimResult ab = ssim(a, b);
  const SsimResult ba = ssim(b, a);
  EXPECT_NEAR(ab.mean_ssim, ba.mean_ssim, 1e-12);
  ASSERT_EQ(ab.map.pixels.size(), ba.map.pixels.size());
  for (std::size_t i = 0; i < ab.map.pixels.size(); ++i) {
    EXPECT_NEAR(ab.map.pixels[i], ba.map.pixels[i], 1e-6);
  }
}

TEST(Ssim, DecreasesAsNoiseGrows) {
  const Image clean = pattern_image(48, 40);
  std::vector<float> noise(clean.pixels.size());
  SplitMix64 rng(42);
  for (float& n : noise) n = rng.unit() - 0.5f;

  double previous = 1.0;
  for (float amplitude : {0.02f, 0.05f, 0.1f, 0.2f, 0.4f}) {
    Image noisy = clean;
    for (std::size_t i = 0; i < noisy.pixels.size(); ++i) noisy.pixels[i] += amplitude * noise[i];
    const double value = ssim(clean, noisy).mean_ssim;
    EXPECT_LT(value, previous) << "noise amplitude " << amplitude;
    EXPECT_GT(value, 0.0);
    previous = value;
  }
}

TEST(Ssim, MeanShiftLowersOnlyTheLuminanceTerm) {
  // Adding a constant leaves variances and covariance unchanged, so the
  // contrast-structure factor stays 1 and each local SSIM is the luminance
  // term (2 mu_x mu_y + C1) / (mu_x^2 + mu_y^2 + C1) of the local means.
  const Image a = pattern_image(32, 28);
  Image shifted = a;
  for (float& value : shifted.pixels) value += 0.25f;
  const SsimResult result = ssim(a, shifted);
  EXPECT_LT(result.mean_ssim, 1.0 - 1e-3);
  for (int y = 0; y < result.map.height; ++y) {
    for (int x = 0; x < result.map.width; ++x) {
      const LocalStatistics s = reference_statistics(a, shifted, x, y);
      // Float pixels make the shift exact only to ~1e-7; the variances agree
      // that closely, so the structure term is 1 to well within 1e-4.
      const double structure = (2 * s.covariance + kC2) / (s.variance_x + s.variance_y + kC2);
      EXPECT_NEAR(structure, 1.0, 1e-4);
      EXPECT_NEAR(result.map.at(x, y, 0), reference_luminance_term(s), 1e-4) << "at " << x << "," << y;
      EXPECT_LT(result.map.at(x, y, 0), 1.0f);
    }
  }
}

TEST(Ssim, RejectsMismatchedSizes) {
  try {
    ssim(Image(64, 36, 3), Image(32, 18, 3));
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("images differ in size: 64x36 vs 32x18"), std::string::npos)
        << error.what();
  }
}

TEST(Ssim, RejectsImagesSmallerThanTheWindow) {
  EXPECT_THROW(ssim(Image(10, 20, 1), Image(10, 20, 1)), std::invalid_argument);
  EXPECT_THROW(ssim(Image(20, 10, 3), Image(20, 10, 3)), std::invalid_argument);
  EXPECT_NO_THROW(ssim(Image(11, 11, 1), Image(11, 11, 1)));
}

}  // namespace
}  // namespace fovlab::metrics
