// Vulkan core: device choice, buffers, push-descriptor compute pipelines, barriers, timestamps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "core/input_error.h"
#include "renderer/shaders/embedded_shaders.h"
#include "renderer/vk/buffer.h"
#include "renderer/vk/compute_pipeline.h"
#include "tests/renderer/vulkan_test_fixture.h"
#include "renderer/vk/submission.h"

namespace fovlab {
namespace {

using test::VulkanTest;

TEST_F(VulkanTest, ContextHasValidationAndAUsableDevice) {
  EXPECT_TRUE(context().validation_enabled());
  EXPECT_TRUE(context().description.usable);
  EXPECT_FALSE(context().description.name.empty());
  EXPECT_NE(context().cmd_push_descriptor_set, nullptr);
}

TEST(VulkanDevices, ListsAtLeastOneDeviceAndRejectsUnknownSelectors) {
  const std::vector<vk::DeviceDescription> devices = vk::list_devices();
  ASSERT_FALSE(devices.empty());
  EXPECT_THROW(vk::Context(vk::ContextOptions{"no-such-device-name", false}), InputError);
  EXPECT_THROW(vk::Context(vk::ContextOptions{"99", false}), InputError);
  vk::Context by_index(vk::ContextOptions{std::to_string(devices.front().index), false});
  EXPECT_EQ(by_index.description.name, devices.front().name);
}

// Runs the built-in min-filter shader on a depth grid and reads the result back.
std::vector<float> gpu_min_filter(vk::Context& context, const std::vector<float>& depth, uint32_t width,
                                  uint32_t height, int radius, std::vector<vk::PassTime>* passes) {
  const VkDeviceSize bytes = depth.size() * sizeof(float);
  vk::Buffer upload(context, bytes, vk::MemoryUse::host_upload);
  std::memcpy(upload.mapped(), depth.data(), bytes);
  upload.flush();
  vk::Buffer input(context, bytes, vk::MemoryUse::device_local);
  vk::Buffer output(context, bytes, vk::MemoryUse::device_local);
  vk::Buffer readback(context, bytes, vk::MemoryUse::host_readback);
  vk::ComputePipeline pipeline(context, shaders::min_filter_spirv, 2, 12);

  vk::OneTimeCommands commands(context);
  VkCommandBuffer cmd = commands.handle();
  vk::PassTimer timer(context, 1);
  timer.reset(cmd);
  VkBufferCopy whole{0, 0, bytes};
  vkCmdCopyBuffer(cmd, upload.handle(), input.handle(), 1, &whole);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
  struct {
    uint32_t size[2];
    int32_t radius;
  } params{{width, height}, radius};
  const VkBuffer buffers[] = {input.handle(), output.handle()};
  timer.begin(cmd, "min_filter");
  pipeline.dispatch_2d(cmd, buffers, &params, width, height);
  timer.end(cmd);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
  vkCmdCopyBuffer(cmd, output.handle(), readback.handle(), 1, &whole);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                     VK_ACCESS_HOST_READ_BIT);
  commands.submit_and_wait();
  if (passes) *passes = timer.results();
  readback.invalidate();
  std::vector<float> result(depth.size());
  std::memcpy(result.data(), readback.mapped(), bytes);
  return result;
}

TEST_F(VulkanTest, MinFilterMatchesACpuNeighbourhoodMinimum) {
  const uint32_t width = 13, height = 9;  // not multiples of the 8x8 workgroup
  std::vector<float> depth(width * height);
  uint32_t state = 12345;
  for (float& value : depth) {
    state = state * 1664525u + 1013904223u;
    value = static_cast<float>(state >> 8) / 65536.0f;
  }
  for (int radius : {0, 1, 2}) {
    std::vector<vk::PassTime> passes;
    const std::vector<float> gpu = gpu_min_filter(context(), depth, width, height, radius, &passes);
    for (int y = 0; y < int(height); ++y) {
      for (int x = 0; x < int(width); ++x) {
        float expected = depth[size_t(y) * width + size_t(x)];
        for (int dy = -radius; dy <= radius; ++dy) {
          for (int dx = -radius; dx <= radius; ++dx) {
            const int nx = std::clamp(x + dx, 0, int(width) - 1);
            const int ny = std::clamp(y + dy, 0, int(height) - 1);
            expected = std::min(expected, depth[size_t(ny) * width + size_t(nx)]);
          }
        }
        ASSERT_EQ(gpu[size_t(y) * width + size_t(x)], expected) << "radius " << radius << " at " << x << "," << y;
      }
    }
    ASSERT_EQ(passes.size(), 1u);
    EXPECT_EQ(passes[0].name, "min_filter");
    if (context().timestamp_period_ns > 0) {
      EXPECT_GT(passes[0].gpu_ms, 0.0);
    }
  }
}

TEST_F(VulkanTest, BuffersMoveWithoutDoubleFree) {
  vk::Buffer a(context(), 256, vk::MemoryUse::device_local);
  const VkBuffer handle = a.handle();
  vk::Buffer b = std::move(a);
  EXPECT_EQ(b.handle(), handle);
  EXPECT_EQ(a.handle(), VK_NULL_HANDLE);  // NOLINT(bugprone-use-after-move): moved-from state is part of the contract
  b = vk::Buffer(context(), 64, vk::MemoryUse::host_readback);
  EXPECT_NE(b.mapped(), nullptr);
  EXPECT_EQ(b.size_bytes(), 64u);
}

}  // namespace
}  // namespace fovlab
