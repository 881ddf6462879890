// The sampling models on a pre-rendered frame (renderer/foveated_sampling/frame_sampler.h): each
// listed sample reads what the CPU reference reads; a model that samples every pixel gives the
// frame back; the display path encodes the linear result.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "core/colour.h"
#include "core/input_error.h"
#include "core/prng.h"
#include "foveation/display_geometry.h"
#include "renderer/foveated_sampling/frame_sampler.h"
#include "renderer/present/device_frame.h"
#include "renderer/vk/buffer.h"
#include "renderer/vk/context.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

using test::VulkanTest;

// Not a multiple of 4 (or of sigma): any frame size works.
constexpr int kWidth = 90, kHeight = 51;

DisplayGeometry small_display() { return display_from_size(kWidth, kHeight, 250.0, 141.7, 400.0); }

// Noise: every pixel differs from its neighbours, so a read from the wrong place shows.
Image noise_frame(int channels = 3) {
  Pcg32 random(20261202);
  Image frame(kWidth, kHeight, channels);
  for (float& value : frame.pixels) value = float(random.uniform(0.0, 4.0));  // linear light, above 1 too
  return frame;
}

SamplingMap map_of(SamplingModel model, double gaze_x, double gaze_y) {
  SamplingSettings settings;
  settings.model = model;
  settings.outer_pixel_size_px = 6.0;
  return make_sampling_map(settings, small_display(), gaze_x, gaze_y);
}

const SamplingModel kModels[] = {SamplingModel::rectangular, SamplingModel::hyperbolic, SamplingModel::linear,
                                 SamplingModel::kernel_log_polar};
struct Gaze {
  double x, y;
};
const Gaze kGazes[] = {{45, 25}, {0, 0}, {90, 51}, {-30, 70}, {std::nan(""), std::nan("")}};

class FrameSamplerTest : public VulkanTest {
 protected:
  // The colours of the first `count` entries of the last call's sample buffer.
  std::vector<float> sample_colours(const FrameSampler& sampler) {
    const VkDeviceSize bytes = VkDeviceSize(sampler.passes().sample_capacity()) * 4 * sizeof(float);
    vk::Buffer readback(context(), bytes, vk::MemoryUse::host_readback);
    vk::OneTimeCommands commands(context());
    const VkBufferCopy region{0, 0, bytes};
    vkCmdCopyBuffer(commands.handle(), sampler.passes().sample_colours(), readback.handle(), 1, &region);
    vk::memory_barrier(commands.handle(), VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    commands.submit_and_wait();
    readback.invalidate();
    std::vector<float> colours(bytes / sizeof(float));
    std::memcpy(colours.data(), readback.mapped(), bytes);
    return colours;
  }
};

// Every listed sample holds the frame's mean over its footprint as the CPU reference computes it
// (to float rounding), for every model and gaze, on and off the screen; the samples are those the
// map's reference shades; every pixel of the result is finite.
TEST_F(FrameSamplerTest, EachSampleReadsTheReferenceMeanOverItsFootprint) {
  FrameSampler sampler(context());
  const Image frame = noise_frame();
  sampler.set_frame(frame);
  for (SamplingModel model : kModels) {
    for (const Gaze& gaze : kGazes) {
      const std::string where =
          std::string(sampling_model_name(model)) + " gaze " + std::to_string(gaze.x) + "," + std::to_string(gaze.y);
      const SamplingMap map = map_of(model, gaze.x, gaze.y);
      const FrameSamplingResult result = sampler.resample(map, ResampleFilter::bilinear, true);
      const double expected = double(shaded_samples(map));
      EXPECT_NEAR(double(result.shaded_samples), expected, 1.0 + 1e-3 * expected) << where;
      const std::vector<float> colours = sample_colours(sampler);
      double worst = 0.0, wide_footprints = 0;
      for (const ListedSample& sample : sampler.passes().listed_samples(uint32_t(result.shaded_samples))) {
        const std::array<float, 3> reference = footprint_mean(frame, sample);
        ASSERT_EQ(colours[size_t(sample.entry) * 4 + 3], 1.0f) << where << ": a listed sample left unread";
        for (int c = 0; c < 3; ++c)
          worst =
              std::max(worst, double(std::abs(colours[size_t(sample.entry) * 4 + size_t(c)] - reference[size_t(c)])));
        if (sample.footprint_px > 2.0f) ++wide_footprints;
      }
      EXPECT_LT(worst, 1e-4) << where;
      if (model != SamplingModel::linear) {
        EXPECT_GT(wide_footprints, 0) << where << ": no sample averages a wide footprint";
      }
      for (float value : result.colour_linear.pixels) ASSERT_TRUE(std::isfinite(value)) << where;
    }
  }
}

// The reference itself: a one-pixel footprint on a pixel centre is that pixel; between centres,
// the bilinear read; a wide footprint the plain mean of the pixels it covers; clipped at the edges.
TEST(FootprintMean, IsTheAreaWeightedMean) {
  Image frame(4, 3, 1);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) frame.at(x, y, 0) = float(10 * y + x);
  EXPECT_FLOAT_EQ(footprint_mean(frame, {2.5f, 1.5f, 1.0f, 0})[0], 12.0f);
  EXPECT_FLOAT_EQ(footprint_mean(frame, {2.75f, 1.5f, 1.0f, 0})[0], 12.25f);  // bilinear in x
  EXPECT_FLOAT_EQ(footprint_mean(frame, {2.0f, 1.5f, 2.0f, 0})[0], 11.5f);    // columns 1 and 2 of row 1
  EXPECT_FLOAT_EQ(footprint_mean(frame, {0.0f, 0.0f, 2.0f, 0})[0], 0.0f);     // clipped to pixel (0, 0)
  EXPECT_FLOAT_EQ(footprint_mean(frame, {-5.0f, 8.0f, 1.0f, 0})[0], 20.0f);   // off the frame: the nearest pixel
  EXPECT_FLOAT_EQ(footprint_mean(frame, {2.0f, 1.5f, 100.0f, 0})[0], 11.5f);  // the whole frame's mean
  EXPECT_FLOAT_EQ(footprint_mean(frame, {2.5f, 1.5f, 0.25f, 0})[0], 12.0f);   // footprints under a pixel: one pixel
  // Not numbers (no map makes them): the first pixel, a one-pixel footprint; never a NaN colour.
  const float nan = std::nanf("");
  EXPECT_FLOAT_EQ(footprint_mean(frame, {nan, nan, nan, 0})[0], 0.0f);
  EXPECT_FLOAT_EQ(footprint_mean(frame, {2.5f, 1.5f, nan, 0})[0], 12.0f);
  EXPECT_FLOAT_EQ(footprint_mean(frame, {1e30f, -1e30f, 1.0f, 0})[0], 3.0f);  // far off: the nearest pixel, (3, 0)
}

// The linear model with p_min 1 samples every pixel at its centre with a one-pixel footprint:
// the frame comes back exactly, whatever the gaze.
TEST_F(FrameSamplerTest, SamplingEveryPixelGivesTheFrameBack) {
  FrameSampler sampler(context());
  const Image frame = noise_frame();
  sampler.set_frame(frame);
  SamplingSettings settings;
  settings.model = SamplingModel::linear;
  settings.min_probability = 1.0;
  for (const Gaze& gaze : kGazes) {
    const FrameSamplingResult result =
        sampler.resample(make_sampling_map(settings, small_display(), gaze.x, gaze.y), ResampleFilter::bilinear);
    EXPECT_EQ(result.shaded_samples, uint64_t(kWidth) * kHeight);
    double worst = 0.0;
    for (size_t i = 0; i < frame.pixels.size(); ++i)
      worst = std::max(worst, double(std::abs(result.colour_linear.pixels[i] - frame.pixels[i])));
    EXPECT_LT(worst, 1e-5) << "gaze " << gaze.x << "," << gaze.y;
  }
}

// What a session shows is the linear result encoded to sRGB8 (one level for float rounding at a
// half step), alpha 255; a new frame replaces the old one (the buffers are kept).
TEST_F(FrameSamplerTest, DisplayFrameIsTheEncodedLinearFrame) {
  FrameSampler sampler(context());
  Image frame = noise_frame(4);
  for (int round = 0; round < 2; ++round) {
    for (size_t i = 0; i < frame.pixels.size(); ++i) frame.pixels[i] *= round == 0 ? 0.25f : 0.5f;
    sampler.set_frame(frame);
    for (SamplingModel model : kModels) {
      for (ResampleFilter filter : {ResampleFilter::bilinear, ResampleFilter::lanczos2}) {
        const SamplingMap map = map_of(model, 30, 20);
        const Image linear = sampler.resample(map, filter).colour_linear;
        const Rgba8Frame shown = read_back(sampler.display_frame_on_device(map, filter));
        ASSERT_EQ(shown.rgba.size(), size_t(kWidth) * kHeight * 4);
        int worst = 0;
        for (int p = 0; p < kWidth * kHeight; ++p) {
          for (int c = 0; c < 3; ++c)
            worst = std::max(
                worst, std::abs(int(shown.rgba[size_t(p) * 4 + size_t(c)]) -
                                int(std::lround(255.0f * encode_srgb(linear.pixels[size_t(p) * 3 + size_t(c)])))));
          ASSERT_EQ(shown.rgba[size_t(p) * 4 + 3], 255);
        }
        EXPECT_LE(worst, 1) << sampling_model_name(model) << " " << resample_filter_name(filter);
      }
    }
  }
}

// A map of another screen is a programming error; a frame too large for the device, bad input.
TEST_F(FrameSamplerTest, RefusesAMapOfAnotherScreen) {
  FrameSampler sampler(context());
  sampler.set_frame(noise_frame());
  SamplingSettings settings;
  DisplayGeometry other = display_from_size(kWidth + 1, kHeight, 250.0, 141.7, 400.0);
  EXPECT_THROW(sampler.resample(make_sampling_map(settings, other, 10, 10), ResampleFilter::bilinear),
               std::invalid_argument);
  EXPECT_THROW(sampler.set_frame(Image(0, 0, 3)), InputError);
}

// Equalised for equal shaded samples on a headset-like (Ye et al. 2022's 238x264 mm at 100 mm, at
// 180x200) and a desktop geometry (24 inches at 300 mm, 160x90): the GPU shades the samples the CPU
// count (shaded_samples) says for every model, so the count tests/foveation/equal_samples_test.cpp
// equalises is the renderer's.
TEST_F(FrameSamplerTest, EqualisedMapsShadeTheSamplesTheCpuCounts) {
  FrameSampler sampler(context());
  for (const DisplayGeometry& display :
       {display_from_size(180, 200, 238.0, 264.0, 100.0), display_from_diagonal(160, 90, 24.0, 300.0)}) {
    Pcg32 random(20261205);
    Image frame(display.width_px, display.height_px, 3);
    for (float& value : frame.pixels) value = float(random.uniform(0.0, 1.0));
    sampler.set_frame(frame);
    uint64_t rmfr_shaded = 0;
    for (SamplingModel model : kModels) {
      SamplingSettings settings;
      settings.model = model;
      settings.equalise = Equalise::samples;
      const SamplingMap map = make_sampling_map(settings, display, std::nan(""), std::nan(""));
      const std::string where = std::string(sampling_model_name(model)) + " " + std::to_string(display.width_px) +
                                "x" + std::to_string(display.height_px);
      const uint64_t shaded = sampler.resample(map, ResampleFilter::bilinear).shaded_samples;
      const double expected = double(shaded_samples(map));
      EXPECT_NEAR(double(shaded), expected, 1.0 + 1e-3 * expected) << where;
      if (model == SamplingModel::rectangular) rmfr_shaded = shaded;
      // At these sizes one column of a layer or buffer is over 1 % of the samples: within 3 %.
      EXPECT_NEAR(double(shaded) / double(rmfr_shaded), 1.0, 0.03) << where;
    }
  }
}

}  // namespace
}  // namespace fovlab
