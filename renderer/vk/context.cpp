#include "renderer/vk/context.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/input_error.h"
#include "renderer/vk/check.h"

namespace fovlab::vk {

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
constexpr uint32_t kApiVersion = VK_API_VERSION_1_1;          // the least a device must offer
constexpr uint32_t kInstanceApiVersion = VK_API_VERSION_1_3;  // the most fovlab uses (driver properties)

std::string version_string(uint32_t version) {
  return std::to_string(VK_API_VERSION_MAJOR(version)) + "." + std::to_string(VK_API_VERSION_MINOR(version)) +
         "." + std::to_string(VK_API_VERSION_PATCH(version));
}

std::string type_name(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
  }
}

// Higher is preferred: real GPUs first, the CPU rasteriser last.
int type_preference(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
    default: return 0;
  }
}

bool has_layer(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  return std::any_of(layers.begin(), layers.end(),
                     [&](const VkLayerProperties& layer) { return std::strcmp(layer.layerName, name) == 0; });
}

bool has_device_extension(VkPhysicalDevice device, const char* name) {
  uint32_t count = 0;
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> extensions(count);
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, extensions.data());
  return std::any_of(extensions.begin(), extensions.end(),
                     [&](const VkExtensionProperties& e) { return std::strcmp(e.extensionName, name) == 0; });
}

std::vector<VkQueueFamilyProperties> queue_families(VkPhysicalDevice device) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  families.resize(count);
  return families;
}

// The first queue family that can run compute work, or -1.
int compute_queue_family(VkPhysicalDevice device) {
  const std::vector<VkQueueFamilyProperties> families = queue_families(device);
  for (uint32_t i = 0; i < families.size(); ++i) {
    if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) return static_cast<int>(i);
  }
  return -1;
}

DeviceDescription describe(VkPhysicalDevice device, uint32_t index) {
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
  description.preference = type_preference(properties.properties.deviceType);
  description.api_version = version_string(properties.properties.apiVersion);
  if (has_driver_properties) description.driver = std::string(driver.driverName) + " " + driver.driverInfo;
  if (properties.properties.apiVersion < kApiVersion) {
    description.unusable_reason = "needs Vulkan 1.1";
  } else if (compute_queue_family(device) < 0) {
    description.unusable_reason = "no compute queue";
  } else if (!has_device_extension(device, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME)) {
    description.unusable_reason = "no VK_KHR_push_descriptor";
  }
  description.usable = description.unusable_reason.empty();
  return description;
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance instance) {
  uint32_t count = 0;
  VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, nullptr));
  std::vector<VkPhysicalDevice> devices(count);
  VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, devices.data()));
  devices.resize(count);
  return devices;
}

VkInstance create_instance(bool validation) {
  VkApplicationInfo application{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  application.pApplicationName = "fovlab";
  application.apiVersion = kInstanceApiVersion;
  std::vector<const char*> layers;
  std::vector<const char*> extensions;
  if (validation) {
    if (!has_layer(kValidationLayer)) {
      throw InputError(std::string("validation requested but ") + kValidationLayer +
                       " is not installed; expected the Debian package vulkan-validationlayers");
    }
    layers.push_back(kValidationLayer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pApplicationInfo = &application;
  info.enabledLayerCount = static_cast<uint32_t>(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  VkInstance instance = VK_NULL_HANDLE;
  VkResult result = vkCreateInstance(&info, nullptr, &instance);
  if (result == VK_ERROR_INCOMPATIBLE_DRIVER) {
    throw InputError("no Vulkan driver found; expected a GPU driver or Mesa lavapipe (mesa-vulkan-drivers)");
  }
  VK_CHECK(result);
  return instance;
}

VKAPI_ATTR VkBool32 VKAPI_CALL on_validation_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                     VkDebugUtilsMessageTypeFlagsEXT,
                                                     const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                     void* user_data) {
  const bool is_error = severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  std::fprintf(stderr, "fovlab: validation %s: %s\n", is_error ? "error" : "warning", data->pMessage);
  static_cast<std::atomic<uint32_t>*>(user_data)->fetch_add(1);
  return VK_FALSE;
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// Descriptions of every device, in enumeration order; throws InputError when there is none.
std::vector<DeviceDescription> describe_all(const std::vector<VkPhysicalDevice>& devices) {
  std::vector<DeviceDescription> descriptions;
  for (uint32_t i = 0; i < devices.size(); ++i) descriptions.push_back(describe(devices[i], i));
  if (descriptions.empty()) {
    throw InputError("no Vulkan device found; expected a GPU or Mesa lavapipe (mesa-vulkan-drivers)");
  }
  return descriptions;
}

DeviceDescription choose_device(const std::vector<VkPhysicalDevice>& devices, const std::string& selector) {
  const std::vector<DeviceDescription> descriptions = describe_all(devices);
  std::string names;
  for (const DeviceDescription& d : descriptions) {
    names += (d.index ? ", " : "") + std::to_string(d.index) + " '" + d.name + "'";
  }
  if (!selector.empty()) {
    const bool is_index = std::all_of(selector.begin(), selector.end(), [](unsigned char c) { return std::isdigit(c); });
    for (const DeviceDescription& d : descriptions) {
      const bool match = is_index ? std::to_string(d.index) == selector
                                  : lower(d.name).find(lower(selector)) != std::string::npos;
      if (!match) continue;
      if (!d.usable) throw InputError("--device " + selector + ": '" + d.name + "' cannot be used: " + d.unusable_reason);
      return d;
    }
    throw InputError("--device " + selector + ": no such device; expected an index or part of a name among " + names);
  }
  const DeviceDescription* best = nullptr;
  for (const DeviceDescription& d : descriptions) {
    if (d.usable && (!best || d.preference > best->preference)) best = &d;
  }
  if (!best) throw InputError("no usable Vulkan device among " + names + "; fovlab needs compute and VK_KHR_push_descriptor");
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

Context::Context(const ContextOptions& options)
    : validation_messages_(std::make_unique<std::atomic<uint32_t>>(0)) {
  instance = create_instance(options.validation);
  try {
    if (options.validation) {
      VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
      info.messageSeverity =
          VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
      info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                         VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
      info.pfnUserCallback = on_validation_message;
      info.pUserData = validation_messages_.get();
      auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
      VK_CHECK(create(instance, &info, nullptr, &messenger_));
    }

    std::vector<VkPhysicalDevice> devices = physical_devices(instance);
    description = choose_device(devices, options.device_selector);
    physical_device = devices[description.index];
    queue_family = static_cast<uint32_t>(compute_queue_family(physical_device));
    vkGetPhysicalDeviceMemoryProperties(physical_device, &memory_properties);

    VkPhysicalDeviceProperties properties;
    vkGetPhysicalDeviceProperties(physical_device, &properties);
    timestamp_valid_bits = queue_families(physical_device)[queue_family].timestampValidBits;
    if (timestamp_valid_bits > 0) timestamp_period_ns = static_cast<double>(properties.limits.timestampPeriod);
    max_storage_buffer_bytes = properties.limits.maxStorageBufferRange;

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queue_info{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queue_info.queueFamilyIndex = queue_family;
    queue_info.queueCount = 1;
    queue_info.pQueuePriorities = &priority;
    const char* extensions[] = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
    VkDeviceCreateInfo device_info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    device_info.queueCreateInfoCount = 1;
    device_info.pQueueCreateInfos = &queue_info;
    device_info.enabledExtensionCount = 1;
    device_info.ppEnabledExtensionNames = extensions;
    VK_CHECK(vkCreateDevice(physical_device, &device_info, nullptr, &device));
    vkGetDeviceQueue(device, queue_family, 0, &queue);
    cmd_push_descriptor_set =
        reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(vkGetDeviceProcAddr(device, "vkCmdPushDescriptorSetKHR"));

    VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool_info.queueFamilyIndex = queue_family;
    VK_CHECK(vkCreateCommandPool(device, &pool_info, nullptr, &command_pool));
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
  if (messenger_) {
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
    destroy(instance, messenger_, nullptr);
    messenger_ = VK_NULL_HANDLE;
  }
  if (instance) {
    vkDestroyInstance(instance, nullptr);
    instance = VK_NULL_HANDLE;
  }
}

}  // namespace fovlab::vk
