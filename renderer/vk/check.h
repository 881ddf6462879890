#pragma once
// VK_CHECK: turns a failed Vulkan call into an exception naming the call and the result code.
#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>

namespace fovlab::vk {

const char* result_name(VkResult result);

[[noreturn]] void throw_vulkan_error(const char* call, VkResult result);

}  // namespace fovlab::vk

#define VK_CHECK(call)                                                                             \
  do {                                                                                             \
    VkResult vk_check_result_ = (call);                                                            \
    if (vk_check_result_ != VK_SUCCESS) ::fovlab::vk::throw_vulkan_error(#call, vk_check_result_); \
  } while (false)
