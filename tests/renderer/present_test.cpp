// renderer/present: the frame composer against a CPU reference of the placement (integer scale,
// centring, crop, letterbox, byte order), and the sphere tracer's display output (the one sRGB8
// encoder) against the CPU's encoding of its linear colour.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/colour.h"
#include "renderer/present/device_frame.h"
#include "renderer/present/frame_compose.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "renderer/vk/buffer.h"
#include "renderer/vk/context.h"
#include "renderer/vk/submission.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

using test::VulkanTest;

TEST(PlaceFrame, ScalesByTheLargestWholeFactorCentresAndCrops) {
  const FramePlacement fits = place_frame(100, 50, 320, 180);  // x3 = 300x150 at (10, 15)
  EXPECT_EQ(fits.scale, 3);
  EXPECT_EQ(fits.dst_x, 10);
  EXPECT_EQ(fits.dst_y, 15);
  EXPECT_EQ(fits.src_x, 0);
  EXPECT_EQ(fits.shown_width, 300);
  EXPECT_EQ(fits.shown_height, 150);
  const FramePlacement exact = place_frame(320, 180, 320, 180);
  EXPECT_EQ(exact.scale, 1);
  EXPECT_EQ(exact.dst_x, 0);
  EXPECT_EQ(exact.shown_width, 320);
  const FramePlacement larger = place_frame(400, 100, 320, 180);  // wider than the image: its centre
  EXPECT_EQ(larger.scale, 1);
  EXPECT_EQ(larger.src_x, 40);
  EXPECT_EQ(larger.dst_x, 0);
  EXPECT_EQ(larger.shown_width, 320);
  EXPECT_EQ(larger.dst_y, 40);
  EXPECT_EQ(larger.shown_height, 100);
}

// Distinct bytes in every channel of every pixel, alpha 255.
std::vector<uint32_t> pattern(int width, int height) {
  std::vector<uint32_t> texels(size_t(width) * size_t(height));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      texels[size_t(y) * size_t(width) + size_t(x)] =
          uint32_t(x * 7 + 1) | uint32_t(y * 13 + 2) << 8 | uint32_t((x + y) * 3 + 5) << 16 | 0xff000000u;
  return texels;
}

// What the composer must write, from place_frame and the frame alone.
std::vector<uint32_t> reference(const std::vector<uint32_t>& frame, int frame_width, int frame_height, int image_width,
                                int image_height, bool bgra) {
  const FramePlacement place = place_frame(frame_width, frame_height, image_width, image_height);
  std::vector<uint32_t> image(size_t(image_width) * size_t(image_height), 0xff000000u);
  for (int y = place.dst_y; y < place.dst_y + place.shown_height; ++y)
    for (int x = place.dst_x; x < place.dst_x + place.shown_width; ++x) {
      const int fx = (x - place.dst_x + place.src_x) / place.scale, fy = (y - place.dst_y + place.src_y) / place.scale;
      uint32_t rgba = frame[size_t(fy) * size_t(frame_width) + size_t(fx)];
      if (bgra) rgba = (rgba & 0xff00ff00u) | (rgba & 0xffu) << 16 | (rgba >> 16 & 0xffu);
      image[size_t(y) * size_t(image_width) + size_t(x)] = rgba;
    }
  return image;
}

TEST_F(VulkanTest, FrameComposerMatchesItsPlacement) {
  const FrameComposer composer(context());
  struct Case {
    int frame_width, frame_height, image_width, image_height;
    bool bgra;
  };
  for (const Case c : {Case{5, 3, 17, 11, true}, Case{5, 3, 17, 11, false}, Case{16, 9, 16, 9, true},
                       Case{20, 10, 8, 6, false}, Case{7, 30, 40, 12, true}}) {
    const std::vector<uint32_t> frame = pattern(c.frame_width, c.frame_height);
    vk::Buffer frame_buffer(context(), frame.size() * 4, vk::MemoryUse::host_upload);
    std::memcpy(frame_buffer.mapped(), frame.data(), frame.size() * 4);
    frame_buffer.flush();
    const size_t image_pixels = size_t(c.image_width) * size_t(c.image_height);
    vk::Buffer image_buffer(context(), image_pixels * 4, vk::MemoryUse::host_readback);
    vk::OneTimeCommands commands(context());
    composer.record(commands.handle(), frame_buffer.handle(), c.frame_width, c.frame_height, image_buffer.handle(),
                    c.image_width, c.image_height, c.bgra);
    vk::memory_barrier(commands.handle(), VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    commands.submit_and_wait();
    image_buffer.invalidate();
    std::vector<uint32_t> image(image_pixels);
    std::memcpy(image.data(), image_buffer.mapped(), image_pixels * 4);
    const std::vector<uint32_t> expected =
        reference(frame, c.frame_width, c.frame_height, c.image_width, c.image_height, c.bgra);
    for (size_t i = 0; i < image_pixels; ++i)
      ASSERT_EQ(image[i], expected[i]) << c.frame_width << "x" << c.frame_height << " into " << c.image_width << "x"
                                       << c.image_height << (c.bgra ? " BGRA" : " RGBA") << ", pixel " << i;
  }
  EXPECT_EQ(context().validation_message_count(), 0u);
}

// The frame a session shows (TraceOutputs::display, encoded on the device) is the linear colour of
// the same render (TraceOutputs::all) encoded by core/colour.h's encode_srgb and rounded, up to one
// step where float rounding lands on the other side of a half step (a handful of channels).
TEST_F(VulkanTest, SphereTracerDisplayOutputIsItsColourEncodedToSrgb8) {
  SphereTracer tracer(context(), load_scene("primitives"));
  for (const TraceMethod method : {TraceMethod::ground_truth, TraceMethod::inverted_pyramid}) {
    SphereTraceSettings settings;
    settings.method = method;
    settings.width = 96;
    settings.height = 54;
    const SphereTraceResult linear = tracer.render(settings);
    settings.outputs = TraceOutputs::display;
    const SphereTraceResult shown = tracer.render(settings);
    EXPECT_TRUE(shown.colour_linear.pixels.empty());
    ASSERT_TRUE(shown.display);
    EXPECT_EQ(shown.display.context, &context());
    const Rgba8Frame bytes = read_back(shown.display);
    ASSERT_EQ(bytes.width, 96);
    ASSERT_EQ(bytes.height, 54);
    size_t off_by_one = 0;
    for (size_t pixel = 0; pixel < linear.colour_linear.pixel_count(); ++pixel) {
      for (size_t c = 0; c < 3; ++c) {
        const long expected = std::lround(encode_srgb(linear.colour_linear.pixels[pixel * 3 + c]) * 255.0f);
        const long got = bytes.rgba[pixel * 4 + c];
        ASSERT_LE(std::labs(got - expected), 1) << method_name(method) << " pixel " << pixel << " channel " << c;
        off_by_one += got != expected;
      }
      ASSERT_EQ(bytes.rgba[pixel * 4 + 3], 255);
    }
    EXPECT_LE(off_by_one, linear.colour_linear.pixel_count() * 3 / 100) << method_name(method);
  }
  EXPECT_EQ(context().validation_message_count(), 0u);
}

}  // namespace
}  // namespace fovlab
