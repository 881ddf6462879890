#pragma once
// The Vulkan instance, the chosen physical device and one compute queue.
//
// Device choice: a discrete GPU, else an integrated or virtual GPU, else a CPU device (Mesa
// lavapipe), unless --device names one by index or by a case-insensitive part of its name.
// Validation: the Khronos validation layer is enabled in Debug builds and whenever the
// environment sets FOVLAB_VALIDATION=1 (every test does); FOVLAB_VALIDATION=0 turns it off.
// Each warning or error the layer reports is printed to stderr and counted.
#include <vulkan/vulkan.h>

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "renderer/vk/instance_support.h"

namespace fovlab::vk {

struct DeviceDescription {
  uint32_t index = 0;  // position in vkEnumeratePhysicalDevices
  std::string name;
  std::string type;         // "discrete GPU", "integrated GPU", "virtual GPU", "CPU", "other"
  int preference = 0;       // automatic choice takes the highest: discrete > integrated > virtual > CPU
  std::string api_version;  // e.g. "1.3.230"
  std::string driver;       // driver name and info, when the device reports them
  bool usable = false;      // has a compute queue and the features fovlab needs
  std::string unusable_reason;
};

// A context that also presents to a window (display/window_presenter.h): the instance gets the
// window system's extensions, the surface is made on it, and only a device with a queue family that
// both computes and presents to that surface (and VK_KHR_swapchain) is usable; that family is the
// context's one queue, so frames go from the renderer's buffers to the swapchain on one device.
struct SurfaceRequest {
  std::vector<const char*> instance_extensions;            // e.g. glfwGetRequiredInstanceExtensions
  std::function<VkSurfaceKHR(VkInstance)> create_surface;  // the context owns and destroys the result
  // Further needs of the presenter on a candidate device: empty when met, else why not (e.g. "no
  // 8-bit RGBA/BGRA surface format"), shown in the device error.
  std::function<std::string(VkPhysicalDevice, VkSurfaceKHR)> unmet_need;
};

// Vulkan created by someone else from the context's own create infos: the OpenXR runtime, through
// XR_KHR_vulkan_enable2 (display/openxr/openxr_session.h). The context builds its instance and
// device create infos as it always does (the validation layer included) and hands them to these in
// place of vkCreateInstance and vkCreateDevice; the physical device is the creator's choice, and
// must be usable. The context owns what they return and destroys it as its own.
struct VulkanCreator {
  std::function<VkInstance(const VkInstanceCreateInfo&)> create_instance;
  std::function<VkPhysicalDevice(VkInstance)> choose_physical_device;
  std::function<VkDevice(VkPhysicalDevice, const VkDeviceCreateInfo&)> create_device;
};

struct ContextOptions {
  std::string device_selector;  // empty: automatic; an index ("0") or part of a name ("llvmpipe")
  bool validation = false;
  std::optional<SurfaceRequest> present_to;  // none: compute only
  std::string device_flag = "--device";      // names device_selector in errors
  // Refuse a CPU renderer (lavapipe) with InputError naming --require-gpu: a cluster task meant for
  // a GPU node does not quietly render a hundred times slower on a node without one.
  bool require_gpu = false;
  std::optional<VulkanCreator> created_by;  // none: the context creates its own instance and device
};

// Validation on by default in Debug builds; FOVLAB_VALIDATION=0/1 overrides either way.
bool validation_requested_by_default();

class Context {
 public:
  explicit Context(const ContextOptions& options);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  uint32_t queue_family = 0;
  VkCommandPool command_pool = VK_NULL_HANDLE;
  DeviceDescription description;
  VkPhysicalDeviceMemoryProperties memory_properties{};
  double timestamp_period_ns = 0.0;  // 0 when the queue cannot write timestamps
  uint32_t timestamp_valid_bits = 0;
  VkDeviceSize max_storage_buffer_bytes = 0;  // maxStorageBufferRange: the largest buffer one binding sees
  uint32_t max_image_side_3d = 0;             // maxImageDimension3D: the largest side of a 3-D image
  PFN_vkCmdPushDescriptorSetKHR cmd_push_descriptor_set = nullptr;
  VkSurfaceKHR surface = VK_NULL_HANDLE;  // made for ContextOptions::present_to; the queue presents to it

  bool validation_enabled() const { return messenger_ != VK_NULL_HANDLE; }
  // Warnings and errors reported by the validation layer since the context was created.
  uint32_t validation_message_count() const { return validation_log_->messages.load(); }

 private:
  void release();  // destroys whatever was created, in reverse order; safe to call twice
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  std::unique_ptr<ValidationLog> validation_log_;
};

// Every physical device the loader sees, usable or not. Throws InputError when there is none.
std::vector<DeviceDescription> list_devices();

// Whether `device` is the one a compute-only context would choose with no --device: no usable
// device is preferred to it (a window's context may have had to settle for a lesser one, e.g. a
// CPU device when the GPU cannot present to a virtual display).
bool is_preferred_device(const DeviceDescription& device);

}  // namespace fovlab::vk
