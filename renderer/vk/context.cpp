#include "renderer/vk/context.h"

#include <cstdlib>
#include <cstring>

#include "core/input_error.h"
#include "renderer/vk/check.h"
#include "renderer/vk/instance_support.h"

namespace fovlab::vk {

namespace {

constexpr uint32_t kApiVersion = VK_API_VERSION_1_1;          // the least a device must offer
constexpr uint32_t kInstanceApiVersion = VK_API_VERSION_1_3;  // the most fovlab uses (driver properties)

std::string version_string(uint32_t version) {
  return std::to_string(VK_API_VERSION_MAJOR(version)) + "." + std::to_string(VK_API_VERSION_MINOR(version)) + "." +
         std::to_string(VK_API_VERSION_PATCH(version));
}

std::string type_name(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      return "CPU";
    default:
      return "other";
  }
}

// The first queue family that can run compute work (and present to `surface` when there is one), or -1.
int compute_queue_family(VkPhysicalDevice device, VkSurfaceKHR surface) {
  const std::vector<VkQueueFamilyProperties> families = queue_families(device);
  for (uint32_t i = 0; i < families.size(); ++i) {
    if (!(families[i].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
    VkBool32 presents = VK_TRUE;
    if (surface && vkGetPhysicalDeviceSurfaceSupportKHR(device, i, surface, &presents) != VK_SUCCESS)
      presents = VK_FALSE;
    if (presents) return static_cast<int>(i);
  }
  return -1;
}

// `present_to` and `surface`: also whether the device can present to the window.
DeviceDescription describe(VkPhysicalDevice device, uint32_t index, const SurfaceRequest* present_to = nullptr,
                           VkSurfaceKHR surface = VK_NULL_HANDLE) {
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  VkPhysicalDeviceProperties basic{};
  vkGetPhysicalDeviceProperties(device, &basic);
  const bool has_driver_properties = basic.apiVersion >= VK_API_VERSION_1_2;
  if (has_driver_properties) properties.pNext = &driver;
  vkGetPhysicalDeviceProperties2(device, &properties);

  DeviceDescription description;
  description.index = index;
  description.name = properties.properties.deviceName;
  description.type = type_name(properties.properties.deviceType);
  description.preference = device_type_preference(properties.properties.deviceType);
  description.api_version = version_string(properties.properties.apiVersion);
  if (has_driver_properties) description.driver = std::string(driver.driverName) + " " + driver.driverInfo;
  if (properties.properties.apiVersion < kApiVersion) {
    description.unusable_reason = "needs Vulkan 1.1";
  } else if (compute_queue_family(device, VK_NULL_HANDLE) < 0) {
    description.unusable_reason = "no compute queue";
  } else if (!has_device_extension(device, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME)) {
    description.unusable_reason = "no VK_KHR_push_descriptor";
  } else if (surface && !has_device_extension(device, VK_KHR_SWAPCHAIN_EXTENSION_NAME)) {
    description.unusable_reason = "no VK_KHR_swapchain";
  } else if (surface && compute_queue_family(device, surface) < 0) {
    description.unusable_reason = "cannot present to the window from a compute queue";
  } else if (surface && present_to->unmet_need) {
    description.unusable_reason = present_to->unmet_need(device, surface);
  }
  description.usable = description.unusable_reason.empty();
  return description;
}

VkInstance create_instance(bool validation, const std::vector<const char*>& window_extensions = {},
                           const VulkanCreator* creator = nullptr) {
  VkApplicationInfo application{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  application.pApplicationName = "fovlab";
  application.apiVersion = kInstanceApiVersion;
  std::vector<const char*> layers;
  std::vector<const char*> extensions = window_extensions;
  if (validation) {
    enable_validation(layers, extensions);
  }
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pApplicationInfo = &application;
  info.enabledLayerCount = static_cast<uint32_t>(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  if (creator != nullptr) return creator->create_instance(info);
  VkInstance instance = VK_NULL_HANDLE;
  VkResult result = vkCreateInstance(&info, nullptr, &instance);
  if (result == VK_ERROR_INCOMPATIBLE_DRIVER) {
    throw InputError("no Vulkan driver found; expected a GPU driver or Mesa lavapipe (mesa-vulkan-drivers)");
  }
  if (result == VK_ERROR_EXTENSION_NOT_PRESENT && !window_extensions.empty()) {
    throw InputError(
        "window: no Vulkan driver can present to a window (VK_ERROR_EXTENSION_NOT_PRESENT); expected a "
        "GPU driver or Mesa lavapipe (mesa-vulkan-drivers)");
  }
  VK_CHECK(result);
  return instance;
}

// Descriptions of every device, in enumeration order; throws InputError when there is none.
std::vector<DeviceDescription> describe_all(const std::vector<VkPhysicalDevice>& devices,
                                            const SurfaceRequest* present_to = nullptr,
                                            VkSurfaceKHR surface = VK_NULL_HANDLE) {
  std::vector<DeviceDescription> descriptions;
  for (uint32_t i = 0; i < devices.size(); ++i) descriptions.push_back(describe(devices[i], i, present_to, surface));
  if (descriptions.empty()) {
    throw InputError("no Vulkan device found; expected a GPU or Mesa lavapipe (mesa-vulkan-drivers)");
  }
  return descriptions;
}

DeviceDescription choose_device(const std::vector<VkPhysicalDevice>& devices, const std::string& selector,
                                const std::string& flag, const SurfaceRequest* present_to, VkSurfaceKHR surface) {
  const std::vector<DeviceDescription> descriptions = describe_all(devices, present_to, surface);
  std::string names;
  for (const DeviceDescription& d : descriptions) {
    names += (d.index ? ", " : "") + std::to_string(d.index) + " '" + d.name + "'" +
             (surface && !d.usable ? " (" + d.unusable_reason + ")" : "");
  }
  if (!selector.empty()) {
    for (const DeviceDescription& d : descriptions) {
      if (!device_selector_matches(selector, d.index, d.name)) continue;
      if (!d.usable)
        throw InputError(flag + " " + selector + ": '" + d.name + "' cannot be used: " + d.unusable_reason);
      return d;
    }
    throw InputError(flag + " " + selector + ": no such device; expected an index or part of a name among " + names);
  }
  const DeviceDescription* best = nullptr;
  for (const DeviceDescription& d : descriptions) {
    if (d.usable && (!best || d.preference > best->preference)) best = &d;
  }
  if (!best && surface)
    throw InputError("window: no Vulkan device can render and present to the window among " + names);
  if (!best)
    throw InputError("no usable Vulkan device among " + names + "; fovlab needs compute and VK_KHR_push_descriptor");
  return *best;
}

}  // namespace

bool validation_requested_by_default() {
  if (const char* value = std::getenv("FOVLAB_VALIDATION"); value && *value) return std::strcmp(value, "0") != 0;
#ifdef NDEBUG
  return false;
#else
  return true;
#endif
}

std::vector<DeviceDescription> list_devices() {
  VkInstance instance = create_instance(false);
  try {
    std::vector<DeviceDescription> descriptions = describe_all(physical_devices(instance));
    vkDestroyInstance(instance, nullptr);
    return descriptions;
  } catch (...) {
    vkDestroyInstance(instance, nullptr);
    throw;
  }
}

bool is_preferred_device(const DeviceDescription& device) {
  for (const DeviceDescription& other : list_devices())
    if (other.usable && other.preference > device.preference) return false;
  return true;
}

Context::Context(const ContextOptions& options) : validation_log_(std::make_unique<ValidationLog>("")) {
  const SurfaceRequest* present_to = options.present_to ? &*options.present_to : nullptr;
  const VulkanCreator* creator = options.created_by ? &*options.created_by : nullptr;
  instance = create_instance(options.validation,
                             present_to ? present_to->instance_extensions : std::vector<const char*>{}, creator);
  try {
    if (options.validation) {
      messenger_ = create_validation_messenger(instance, validation_messenger_info(validation_log_.get()));
    }
    if (present_to) surface = present_to->create_surface(instance);

    std::vector<VkPhysicalDevice> devices = physical_devices(instance);
    if (creator != nullptr) {
      const VkPhysicalDevice given = creator->choose_physical_device(instance);
      uint32_t index = 0;
      while (index < devices.size() && devices[index] != given) ++index;
      if (index == devices.size()) throw InputError("the Vulkan device chosen for fovlab is not one of its instance's");
      description = describe(given, index, present_to, surface);
      if (!description.usable)
        throw InputError("the Vulkan device chosen for fovlab, '" + description.name + "', cannot be used: " +
                         description.unusable_reason);
    } else {
      description = choose_device(devices, options.device_selector, options.device_flag, present_to, surface);
    }
    if (options.require_gpu && description.type == "CPU")
      throw InputError("--require-gpu: the Vulkan device chosen, '" + description.name +
                       "', renders on the CPU; expected a GPU (run on a GPU node, or leave out --require-gpu to "
                       "render on the CPU)");
    physical_device = devices[description.index];
    queue_family = static_cast<uint32_t>(compute_queue_family(physical_device, surface));
    vkGetPhysicalDeviceMemoryProperties(physical_device, &memory_properties);

    VkPhysicalDeviceProperties properties;
    vkGetPhysicalDeviceProperties(physical_device, &properties);
    timestamp_valid_bits = queue_families(physical_device)[queue_family].timestampValidBits;
    if (timestamp_valid_bits > 0) timestamp_period_ns = static_cast<double>(properties.limits.timestampPeriod);
    max_storage_buffer_bytes = properties.limits.maxStorageBufferRange;
    max_image_side_3d = properties.limits.maxImageDimension3D;

    std::vector<const char*> extensions{VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
    if (surface) extensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    device = create_device(physical_device, queue_family, extensions,
                           creator != nullptr ? creator->create_device : nullptr);
    vkGetDeviceQueue(device, queue_family, 0, &queue);
    cmd_push_descriptor_set =
        reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(vkGetDeviceProcAddr(device, "vkCmdPushDescriptorSetKHR"));

    command_pool = create_command_pool(device, queue_family);
  } catch (...) {
    release();
    throw;
  }
}

Context::~Context() { release(); }

void Context::release() {
  if (device) {
    vkDeviceWaitIdle(device);
    if (command_pool) vkDestroyCommandPool(device, command_pool, nullptr);
    vkDestroyDevice(device, nullptr);
    device = VK_NULL_HANDLE;
  }
  if (surface) {
    vkDestroySurfaceKHR(instance, surface, nullptr);
    surface = VK_NULL_HANDLE;
  }
  if (messenger_) {
    destroy_validation_messenger(instance, messenger_);
    messenger_ = VK_NULL_HANDLE;
  }
  if (instance) {
    vkDestroyInstance(instance, nullptr);
    instance = VK_NULL_HANDLE;
  }
}

}  // namespace fovlab::vk
