#pragma once
// One Vulkan context for the whole test binary (the validation layer is slow to load), with the
// validation layer on; every test fails if the layer reported anything while it ran.
#include <gtest/gtest.h>

#include <memory>

#include "renderer/vk/context.h"

namespace fovlab::test {

inline vk::Context& shared_context() {
  static std::unique_ptr<vk::Context> context = std::make_unique<vk::Context>(vk::ContextOptions{"", true});
  return *context;
}

class VulkanTest : public ::testing::Test {
 protected:
  void SetUp() override { messages_before_ = shared_context().validation_message_count(); }
  void TearDown() override {
    EXPECT_EQ(shared_context().validation_message_count(), messages_before_) << "Vulkan validation messages";
  }
  vk::Context& context() { return shared_context(); }

 private:
  uint32_t messages_before_ = 0;
};

}  // namespace fovlab::test
