// Zone-buffer upsampling (issue 6, Polychronakis et al. 2021 section 3.1): the filters' kernels, the double-precision
// CPU reference, and the GPU passes against it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/prng.h"
#include "bench/openimageio_resize.h"
#include "renderer/upsampling/upsample_filter.h"
#include "renderer/upsampling/upsampler.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

using test::VulkanTest;

constexpr UpsampleFilter kFilters[] = {UpsampleFilter::lanczos3, UpsampleFilter::bilinear, UpsampleFilter::nearest};

// Linear-light noise with a few bright spots (path-traced buffers have fireflies), 3 channels.
Image noisy_image(int width, int height, uint64_t seed) {
  Pcg32 random(seed);
  Image image(width, height, 3);
  for (float& value : image.pixels) value = static_cast<float>(random.uniform()) * 2.0f;
  for (int i = 0; i < 5; ++i)
    image.at(int(random.below(uint32_t(width))), int(random.below(uint32_t(height))), 1) = 40.0f;
  return image;
}

TEST(UpsampleFilter, KernelsAndNames) {
  EXPECT_EQ(upsample_kernel(UpsampleFilter::lanczos3, 0.0), 1.0);
  for (int k = 1; k <= 3; ++k) EXPECT_NEAR(upsample_kernel(UpsampleFilter::lanczos3, k), 0.0, 1e-15);
  EXPECT_EQ(upsample_kernel(UpsampleFilter::lanczos3, 3.2), 0.0);
  EXPECT_LT(upsample_kernel(UpsampleFilter::lanczos3, 1.5), 0.0) << "the negative lobe that rings";
  EXPECT_EQ(upsample_kernel(UpsampleFilter::bilinear, 0.25), 0.75);
  EXPECT_EQ(upsample_kernel(UpsampleFilter::nearest, -0.5), 1.0);
  EXPECT_EQ(upsample_kernel(UpsampleFilter::nearest, 0.5), 0.0);
  for (UpsampleFilter filter : kFilters) EXPECT_EQ(parse_upsample_filter(upsample_filter_name(filter)), filter);
  EXPECT_FALSE(parse_upsample_filter("bicubic").has_value());
}

// A constant stays constant (weights sum to 1, borders included); nearest repeats each pixel
// factor x factor times; bilinear keeps a linear ramp linear away from the borders.
TEST(UpsampleFilter, ReferenceKeepsConstantsRampsAndPixels) {
  Image constant(7, 5, 1);
  std::fill(constant.pixels.begin(), constant.pixels.end(), 0.3f);
  for (UpsampleFilter filter : kFilters)
    for (int factor : {2, 4})
      for (float value : upsample_reference(constant, factor, filter).pixels) ASSERT_NEAR(value, 0.3f, 1e-6);

  const Image source = noisy_image(6, 4, 3);
  const Image nearest = upsample_reference(source, 4, UpsampleFilter::nearest);
  ASSERT_EQ(nearest.width, 24);
  ASSERT_EQ(nearest.height, 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 24; ++x) ASSERT_EQ(nearest.at(x, y, 2), source.at(x / 4, y / 4, 2));

  Image ramp(8, 1, 1);
  for (int x = 0; x < 8; ++x) ramp.at(x, 0, 0) = float(x);
  const Image bilinear = upsample_reference(ramp, 2, UpsampleFilter::bilinear);
  for (int x = 1; x < 15; ++x) EXPECT_NEAR(bilinear.at(x, 0, 0), (x + 0.5) / 2.0 - 0.5, 1e-6);
  const Image lanczos = upsample_reference(ramp, 2, UpsampleFilter::lanczos3);
  // Normalised Lanczos-3 is not exactly linear-preserving: at quarter-pixel offsets the first moment
  // of its six weights is off by 0.0198 pixel, so a ramp of slope 1 bends by that much (and by
  // nothing at the input's own pixel centres' midpoints).
  for (int x = 6; x < 10; ++x)
    EXPECT_NEAR(lanczos.at(x, 0, 0), (x + 0.5) / 2.0 - 0.5, 0.0199) << "nearly linear inside";
  EXPECT_GT(std::fabs(lanczos.at(6, 0, 0) - 2.75), 0.019);
}

// The baseline `fovlab upsample --against-oiio` times is the same filter: OpenImageIO's lanczos3
// resize, as called, agrees with the reference everywhere, borders included (both clamp), to float
// precision. Fireflies included, so a kernel of another width would show (it did: an explicit width
// of 6 put pixels out of order and differed by 0.7 on values below 1).
TEST(UpsampleFilter, OpenImageIOResizeIsTheSameLanczos3) {
  const Image source = noisy_image(21, 13, 9);
  const float range = *std::max_element(source.pixels.begin(), source.pixels.end());
  for (int factor : {2, 4}) {
    const Image expected = upsample_reference(source, factor, UpsampleFilter::lanczos3);
    const Image oiio = bench::resize_with_openimageio(source, factor);
    ASSERT_EQ(oiio.width, expected.width);
    ASSERT_EQ(oiio.height, expected.height);
    double worst = 0.0;
    for (size_t i = 0; i < expected.pixels.size(); ++i)
      worst = std::max(worst, double(std::fabs(oiio.pixels[i] - expected.pixels[i])));
    EXPECT_LT(worst / range, 1e-4) << "factor " << factor;
  }
}

// The GPU's float passes agree with the double-precision reference within 1e-4 relative to the
// image's range, for every filter, both factors, 1 to 4 channels and odd sizes.
TEST_F(VulkanTest, GpuUpsamplingMatchesTheReference) {
  Upsampler upsampler(context());
  for (int channels : {1, 3, 4}) {
    Image source = noisy_image(37, 23, uint64_t(channels));
    if (channels != 3) {
      Image reshaped(37, 23, channels);
      for (size_t p = 0; p < reshaped.pixel_count(); ++p)
        for (int c = 0; c < channels; ++c)
          reshaped.pixels[p * size_t(channels) + size_t(c)] = source.pixels[p * 3 + size_t(c % 3)];
      source = reshaped;
    }
    const float range = *std::max_element(source.pixels.begin(), source.pixels.end());
    for (UpsampleFilter filter : kFilters) {
      for (int factor : {2, 4}) {
        const Image expected = upsample_reference(source, factor, filter);
        const UpsampleResult gpu = upsampler.upsample(source, factor, filter);
        ASSERT_EQ(gpu.image.width, expected.width);
        ASSERT_EQ(gpu.image.height, expected.height);
        ASSERT_EQ(gpu.image.channels, channels);
        double worst = 0.0;
        for (size_t i = 0; i < expected.pixels.size(); ++i)
          worst = std::max(worst, double(std::fabs(gpu.image.pixels[i] - expected.pixels[i])));
        EXPECT_LT(worst / range, 1e-4) << upsample_filter_name(filter) << " x" << factor << ", " << channels
                                       << " channels";
      }
    }
  }
}

}  // namespace
}  // namespace fovlab
