#pragma once
// Instance and device helpers of the renderer's Context:
// the validation layer and its messenger, layer and extension checks, the device choice rules, and
// creation of a one-queue device and its command pool.
#include <vulkan/vulkan.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace fovlab::vk {

// Where a validation messenger reports: each warning or error is printed to stderr as
// "fovlab: <label> validation error|warning: <message>" ("fovlab: validation ..." when the label
// is empty) and counted.
struct ValidationLog {
  explicit ValidationLog(const char* label_text) : label(label_text) {}
  const char* label;  // a string with static storage ("" or e.g. "window")
  std::atomic<uint32_t> messages{0};
};

bool has_instance_layer(const char* name);
bool has_device_extension(VkPhysicalDevice device, const char* name);

// Adds the Khronos validation layer and VK_EXT_debug_utils to an instance's lists; throws
// InputError when the layer is not installed.
void enable_validation(std::vector<const char*>& layers, std::vector<const char*>& extensions);

// Warnings and errors of every type, reported to `log` (which must outlive the messenger).
VkDebugUtilsMessengerCreateInfoEXT validation_messenger_info(ValidationLog* log);
VkDebugUtilsMessengerEXT create_validation_messenger(VkInstance instance,
                                                     const VkDebugUtilsMessengerCreateInfoEXT& info);
void destroy_validation_messenger(VkInstance instance, VkDebugUtilsMessengerEXT messenger);

std::vector<VkPhysicalDevice> physical_devices(VkInstance instance);
std::vector<VkQueueFamilyProperties> queue_families(VkPhysicalDevice device);

// A logical device with one queue (priority 1) of `queue_family` and the given device extensions;
// made by `create` from that create info when it is given (context.h: VulkanCreator).
VkDevice create_device(VkPhysicalDevice physical_device, uint32_t queue_family,
                       const std::vector<const char*>& extensions,
                       const std::function<VkDevice(VkPhysicalDevice, const VkDeviceCreateInfo&)>& create = nullptr);
// A command pool on `queue_family` whose buffers can be reset one by one.
VkCommandPool create_command_pool(VkDevice device, uint32_t queue_family);

// Higher is preferred: discrete 4, integrated 3, virtual 2, CPU 1, other 0.
int device_type_preference(VkPhysicalDeviceType type);
std::string lower_case(std::string text);
// Whether a --device selector picks the device at `index` named `name`: an all-digit selector is
// an index, anything else a case-insensitive part of the name.
bool device_selector_matches(const std::string& selector, uint32_t index, const std::string& name);

}  // namespace fovlab::vk
