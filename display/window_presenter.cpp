#include "display/window_presenter.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "core/input_error.h"
#include "renderer/vk/check.h"
#include "renderer/vk/instance_support.h"

namespace fovlab {

namespace {

// glfwInit/glfwTerminate are process-wide: the last presenter to go terminates GLFW.
std::mutex glfw_mutex;
int glfw_users = 0;

std::string glfw_error_description() {
  const char* description = nullptr;
  glfwGetError(&description);
  return description ? description : "no description";
}

// 8-bit four-channel formats whose bytes a copy stores unchanged. _UNORM first: the bytes are
// already sRGB-encoded and the SRGB_NONLINEAR colour space tells the display so. An _SRGB format
// would do too for a copy (copies never convert; only shader writes and sampling encode/decode),
// so it is the fallback.
struct FormatChoice {
  VkFormat format;
  bool bgra;
};
constexpr FormatChoice kFormats[] = {
    {VK_FORMAT_B8G8R8A8_UNORM, true},
    {VK_FORMAT_R8G8B8A8_UNORM, false},
    {VK_FORMAT_B8G8R8A8_SRGB, true},
    {VK_FORMAT_R8G8B8A8_SRGB, false},
};

std::vector<VkSurfaceFormatKHR> surface_formats(VkPhysicalDevice device, VkSurfaceKHR surface) {
  uint32_t count = 0;
  if (vkGetPhysicalDeviceSurfaceFormatsKHR(device, surface, &count, nullptr) != VK_SUCCESS) return {};
  std::vector<VkSurfaceFormatKHR> formats(count);
  if (vkGetPhysicalDeviceSurfaceFormatsKHR(device, surface, &count, formats.data()) != VK_SUCCESS) return {};
  formats.resize(count);
  return formats;
}

// The preferred format the surface offers, or nullopt.
std::optional<std::pair<VkSurfaceFormatKHR, bool>> choose_format(const std::vector<VkSurfaceFormatKHR>& formats) {
  if (formats.size() == 1 && formats[0].format == VK_FORMAT_UNDEFINED) {  // "anything"
    return std::make_pair(VkSurfaceFormatKHR{VK_FORMAT_B8G8R8A8_UNORM, VK_COLOR_SPACE_SRGB_NONLINEAR_KHR}, true);
  }
  for (const FormatChoice& choice : kFormats) {
    for (const VkSurfaceFormatKHR& offered : formats) {
      if (offered.format == choice.format && offered.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) {
        return std::make_pair(offered, choice.bgra);
      }
    }
  }
  return std::nullopt;
}

void sleep_s(double seconds) {
  if (seconds > 0) std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
}

}  // namespace

WindowPresenter::WindowPresenter(const WindowPresenterOptions& options)
    : options_(options), validation_log_(std::make_unique<vk::ValidationLog>("window")) {
  if (options_.width_px <= 0 || options_.height_px <= 0) {
    throw std::invalid_argument("window: frame size must be positive, got " + std::to_string(options_.width_px) + "x" +
                                std::to_string(options_.height_px));
  }
  try {
    create_window();
    create_instance();
    choose_device();
    create_swapchain();
  } catch (...) {
    release();
    throw;
  }
  clock_origin_s_ = glfwGetTime();
}

WindowPresenter::~WindowPresenter() { release(); }

void WindowPresenter::create_window() {
  {
    std::lock_guard<std::mutex> lock(glfw_mutex);
    if (!glfwInit()) {
      const char* display = std::getenv("DISPLAY");
      const char* wayland = std::getenv("WAYLAND_DISPLAY");
      if ((!display || !*display) && (!wayland || !*wayland)) {
        throw InputError("window: cannot open a window (no display; use --headless or run under xvfb-run)");
      }
      throw InputError("window: cannot open a window on display " + std::string(display ? display : wayland) + " (" +
                       glfw_error_description() + "; use --headless or run under xvfb-run)");
    }
    ++glfw_users;
    glfw_initialised_ = true;
  }
  if (!glfwVulkanSupported()) {
    throw InputError("window: GLFW finds no Vulkan loader (expected libvulkan1 and a driver such as mesa-vulkan-drivers)");
  }

  GLFWmonitor* monitor = glfwGetPrimaryMonitor();
  const GLFWvidmode* mode = monitor ? glfwGetVideoMode(monitor) : nullptr;
  if (mode && mode->refreshRate > 0) refresh_hz_ = mode->refreshRate;

  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
  if (options_.fullscreen) {
    if (!mode) throw InputError("window: --fullscreen: no monitor found");
    // The current video mode: no mode switch.
    glfwWindowHint(GLFW_RED_BITS, mode->redBits);
    glfwWindowHint(GLFW_GREEN_BITS, mode->greenBits);
    glfwWindowHint(GLFW_BLUE_BITS, mode->blueBits);
    glfwWindowHint(GLFW_REFRESH_RATE, mode->refreshRate);
    window_ = glfwCreateWindow(mode->width, mode->height, options_.title.c_str(), monitor, nullptr);
  } else {
    window_ = glfwCreateWindow(options_.width_px, options_.height_px, options_.title.c_str(), nullptr, nullptr);
  }
  if (!window_) throw InputError("window: cannot create a window (" + glfw_error_description() + ")");
  glfwSetWindowUserPointer(window_, this);
  glfwSetKeyCallback(window_, &WindowPresenter::key_callback);
  // Not every driver reports a resized surface as out of date (Mesa's software X11 path does not).
  glfwSetFramebufferSizeCallback(window_, [](GLFWwindow* window, int, int) {
    if (auto* self = static_cast<WindowPresenter*>(glfwGetWindowUserPointer(window))) self->swapchain_stale_ = true;
  });
}

void WindowPresenter::create_instance() {
  uint32_t glfw_extension_count = 0;
  const char** glfw_extensions = glfwGetRequiredInstanceExtensions(&glfw_extension_count);
  if (!glfw_extensions) {
    throw InputError("window: Vulkan cannot present to this display (" + glfw_error_description() + ")");
  }
  std::vector<const char*> extensions(glfw_extensions, glfw_extensions + glfw_extension_count);
  std::vector<const char*> layers;
  VkDebugUtilsMessengerCreateInfoEXT debug_info = vk::validation_messenger_info(validation_log_.get());
  if (options_.validation) vk::enable_validation(layers, extensions);
  VkApplicationInfo application{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  application.pApplicationName = "fovlab window";
  application.apiVersion = VK_API_VERSION_1_1;
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pNext = options_.validation ? &debug_info : nullptr;  // also reports on instance creation
  info.pApplicationInfo = &application;
  info.enabledLayerCount = static_cast<uint32_t>(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  const VkResult result = vkCreateInstance(&info, nullptr, &instance_);
  if (result == VK_ERROR_INCOMPATIBLE_DRIVER || result == VK_ERROR_EXTENSION_NOT_PRESENT) {
    throw InputError("window: no Vulkan driver can present to a window (" + std::string(vk::result_name(result)) +
                     "); expected a GPU driver or Mesa lavapipe (mesa-vulkan-drivers)");
  }
  VK_CHECK(result);
  if (options_.validation) messenger_ = vk::create_validation_messenger(instance_, debug_info);
  VK_CHECK(glfwCreateWindowSurface(instance_, window_, nullptr, &surface_));
}

void WindowPresenter::choose_device() {
  const std::vector<VkPhysicalDevice> devices = vk::physical_devices(instance_);

  struct Candidate {
    uint32_t index;
    std::string name;
    int preference;
    int queue_family = -1;
    std::string unusable_reason;
  };
  std::vector<Candidate> candidates;
  for (uint32_t i = 0; i < devices.size(); ++i) {
    VkPhysicalDeviceProperties properties;
    vkGetPhysicalDeviceProperties(devices[i], &properties);
    Candidate candidate{i, properties.deviceName, vk::device_type_preference(properties.deviceType)};
    if (!vk::has_device_extension(devices[i], VK_KHR_SWAPCHAIN_EXTENSION_NAME)) {
      candidate.unusable_reason = "no VK_KHR_swapchain";
    } else {
      const std::vector<VkQueueFamilyProperties> families = vk::queue_families(devices[i]);
      // vkCmdClearColorImage needs a graphics or compute queue; graphics preferred.
      for (uint32_t f = 0; f < families.size(); ++f) {
        if (!(families[f].queueFlags & (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT))) continue;
        VkBool32 supported = VK_FALSE;
        if (vkGetPhysicalDeviceSurfaceSupportKHR(devices[i], f, surface_, &supported) != VK_SUCCESS || !supported) continue;
        const bool graphics = families[f].queueFlags & VK_QUEUE_GRAPHICS_BIT;
        if (candidate.queue_family < 0 || graphics) candidate.queue_family = static_cast<int>(f);
        if (graphics) break;
      }
      if (candidate.queue_family < 0) {
        candidate.unusable_reason = "cannot present to this window";
      } else if (!choose_format(surface_formats(devices[i], surface_))) {
        candidate.unusable_reason = "no 8-bit RGBA/BGRA surface format";
      }
    }
    candidates.push_back(candidate);
  }

  std::string names;
  for (const Candidate& c : candidates) {
    names += (c.index ? ", " : "") + std::to_string(c.index) + " '" + c.name + "'" +
             (c.unusable_reason.empty() ? "" : " (" + c.unusable_reason + ")");
  }
  const Candidate* chosen = nullptr;
  const std::string& selector = options_.device_selector;
  if (!selector.empty()) {
    for (const Candidate& c : candidates) {
      if (!vk::device_selector_matches(selector, c.index, c.name)) continue;
      if (!c.unusable_reason.empty()) {
        throw InputError("window: device " + selector + ": '" + c.name + "' " + c.unusable_reason);
      }
      chosen = &c;
      break;
    }
    if (!chosen) throw InputError("window: device " + selector + ": no such device among " + names);
  } else {
    for (const Candidate& c : candidates) {
      if (c.unusable_reason.empty() && (!chosen || c.preference > chosen->preference)) chosen = &c;
    }
    if (!chosen) {
      throw InputError("window: no Vulkan device can present to the window" +
                       (names.empty() ? std::string(" (no device)") : " among " + names));
    }
  }

  physical_device_ = devices[chosen->index];
  device_name_ = chosen->name;
  queue_family_ = static_cast<uint32_t>(chosen->queue_family);
  vkGetPhysicalDeviceMemoryProperties(physical_device_, &memory_properties_);

  device_ = vk::create_device(physical_device_, queue_family_, VK_KHR_SWAPCHAIN_EXTENSION_NAME);
  vkGetDeviceQueue(device_, queue_family_, 0, &queue_);

  command_pool_ = vk::create_command_pool(device_, queue_family_);
  VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  allocate.commandPool = command_pool_;
  allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocate.commandBufferCount = 1;
  VK_CHECK(vkAllocateCommandBuffers(device_, &allocate, &command_buffer_));
  VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  fence_info.flags = VK_FENCE_CREATE_SIGNALED_BIT;
  VK_CHECK(vkCreateFence(device_, &fence_info, nullptr, &frame_fence_));
  VkSemaphoreCreateInfo semaphore_info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  VK_CHECK(vkCreateSemaphore(device_, &semaphore_info, nullptr, &image_available_));
}

void WindowPresenter::create_swapchain() {
  VkSurfaceCapabilitiesKHR caps;
  VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(physical_device_, surface_, &caps));
  VkExtent2D extent = caps.currentExtent;
  if (extent.width == std::numeric_limits<uint32_t>::max()) {
    int width = 0, height = 0;
    glfwGetFramebufferSize(window_, &width, &height);
    extent.width = std::clamp(static_cast<uint32_t>(std::max(width, 0)), caps.minImageExtent.width, caps.maxImageExtent.width);
    extent.height =
        std::clamp(static_cast<uint32_t>(std::max(height, 0)), caps.minImageExtent.height, caps.maxImageExtent.height);
  }
  VkSwapchainKHR old = swapchain_;
  swapchain_ = VK_NULL_HANDLE;
  extent_ = extent;
  if (extent.width == 0 || extent.height == 0) {  // minimised: nothing to present to until it comes back
    if (old) vkDestroySwapchainKHR(device_, old, nullptr);
    swapchain_stale_ = true;
    return;
  }

  const auto format = choose_format(surface_formats(physical_device_, surface_));
  if (!format) throw std::runtime_error("window: the surface offers no 8-bit RGBA/BGRA format");
  format_ = format->first.format;
  colour_space_ = format->first.colorSpace;
  format_is_bgra_ = format->second;
  if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT)) {
    throw std::runtime_error("window: swapchain images of '" + device_name_ + "' cannot be copied into");
  }
  can_read_back_ = options_.screenshots && (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT);

  uint32_t mode_count = 0;
  VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(physical_device_, surface_, &mode_count, nullptr));
  std::vector<VkPresentModeKHR> modes(mode_count);
  VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(physical_device_, surface_, &mode_count, modes.data()));
  present_mode_ = VK_PRESENT_MODE_FIFO_KHR;  // always supported
  if (!options_.vsync) {
    for (VkPresentModeKHR wanted : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR}) {
      if (std::find(modes.begin(), modes.end(), wanted) != modes.end()) {
        present_mode_ = wanted;
        break;
      }
    }
  }

  VkCompositeAlphaFlagBitsKHR composite = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
  if (!(caps.supportedCompositeAlpha & composite)) {
    for (VkCompositeAlphaFlagBitsKHR bit : {VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR, VK_COMPOSITE_ALPHA_PRE_MULTIPLIED_BIT_KHR,
                                            VK_COMPOSITE_ALPHA_POST_MULTIPLIED_BIT_KHR}) {
      if (caps.supportedCompositeAlpha & bit) {
        composite = bit;
        break;
      }
    }
  }

  VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
  info.surface = surface_;
  // The fewest images: the acquire then blocks on flips soonest, which paces present() (latency).
  info.minImageCount = std::max(caps.minImageCount, 2u);
  if (caps.maxImageCount > 0) info.minImageCount = std::min(info.minImageCount, caps.maxImageCount);
  info.imageFormat = format_;
  info.imageColorSpace = colour_space_;
  info.imageExtent = extent;
  info.imageArrayLayers = 1;
  info.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT | (can_read_back_ ? VK_IMAGE_USAGE_TRANSFER_SRC_BIT : 0);
  info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.preTransform = caps.currentTransform;
  info.compositeAlpha = composite;
  info.presentMode = present_mode_;
  info.clipped = VK_FALSE;  // every pixel is kept, so a screenshot is the whole frame even when covered
  info.oldSwapchain = old;
  const VkResult result = vkCreateSwapchainKHR(device_, &info, nullptr, &swapchain_);
  if (old) vkDestroySwapchainKHR(device_, old, nullptr);
  VK_CHECK(result);

  uint32_t image_count = 0;
  VK_CHECK(vkGetSwapchainImagesKHR(device_, swapchain_, &image_count, nullptr));
  images_.resize(image_count);
  VK_CHECK(vkGetSwapchainImagesKHR(device_, swapchain_, &image_count, images_.data()));
  images_.resize(image_count);
  VkSemaphoreCreateInfo semaphore_info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  render_finished_.assign(image_count, VK_NULL_HANDLE);
  for (VkSemaphore& semaphore : render_finished_) VK_CHECK(vkCreateSemaphore(device_, &semaphore_info, nullptr, &semaphore));

  if (can_read_back_) {
    const VkDeviceSize bytes = VkDeviceSize{extent.width} * extent.height * 4;
    if (readback_.size < bytes) {
      destroy_host_buffer(readback_);
      readback_ = create_host_buffer(bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
    }
  }
  swapchain_stale_ = false;
}

// Semaphores and images of the swapchain; the swapchain itself stays when it is handed to the next
// one as oldSwapchain.
void WindowPresenter::destroy_swapchain(bool keep_handle_for_recreation) {
  for (VkSemaphore semaphore : render_finished_) vkDestroySemaphore(device_, semaphore, nullptr);
  render_finished_.clear();
  images_.clear();
  if (!keep_handle_for_recreation && swapchain_) {
    vkDestroySwapchainKHR(device_, swapchain_, nullptr);
    swapchain_ = VK_NULL_HANDLE;
  }
}

void WindowPresenter::recreate_swapchain() {
  VK_CHECK(vkDeviceWaitIdle(device_));
  destroy_swapchain(true);
  create_swapchain();
}

void WindowPresenter::release() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    destroy_host_buffer(staging_);
    destroy_host_buffer(readback_);
    destroy_swapchain(false);
    if (image_available_) vkDestroySemaphore(device_, image_available_, nullptr);
    if (frame_fence_) vkDestroyFence(device_, frame_fence_, nullptr);
    if (command_pool_) vkDestroyCommandPool(device_, command_pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
    device_ = VK_NULL_HANDLE;
  }
  if (surface_) {
    vkDestroySurfaceKHR(instance_, surface_, nullptr);
    surface_ = VK_NULL_HANDLE;
  }
  if (messenger_) {
    vk::destroy_validation_messenger(instance_, messenger_);
    messenger_ = VK_NULL_HANDLE;
  }
  if (instance_) {
    vkDestroyInstance(instance_, nullptr);
    instance_ = VK_NULL_HANDLE;
  }
  if (window_) {
    glfwDestroyWindow(window_);
    window_ = nullptr;
  }
  if (glfw_initialised_) {
    std::lock_guard<std::mutex> lock(glfw_mutex);
    if (--glfw_users == 0) glfwTerminate();
    glfw_initialised_ = false;
  }
}

WindowPresenter::HostBuffer WindowPresenter::create_host_buffer(VkDeviceSize size, VkBufferUsageFlags usage,
                                                                bool prefer_cached) {
  HostBuffer result;
  result.size = size;
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VK_CHECK(vkCreateBuffer(device_, &info, nullptr, &result.buffer));
  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(device_, result.buffer, &requirements);
  // Host-coherent always (no flush/invalidate); cached too where offered for buffers the CPU reads.
  const VkMemoryPropertyFlags required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  int chosen = -1;
  for (int pass = prefer_cached ? 0 : 1; pass < 2 && chosen < 0; ++pass) {
    const VkMemoryPropertyFlags wanted = required | (pass == 0 ? VK_MEMORY_PROPERTY_HOST_CACHED_BIT : 0);
    for (uint32_t i = 0; i < memory_properties_.memoryTypeCount; ++i) {
      if ((requirements.memoryTypeBits & (1u << i)) &&
          (memory_properties_.memoryTypes[i].propertyFlags & wanted) == wanted) {
        chosen = static_cast<int>(i);
        break;
      }
    }
  }
  if (chosen < 0) {
    vkDestroyBuffer(device_, result.buffer, nullptr);
    throw std::runtime_error("window: '" + device_name_ + "' has no host-visible coherent memory");
  }
  VkMemoryAllocateInfo allocate{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  allocate.allocationSize = requirements.size;
  allocate.memoryTypeIndex = static_cast<uint32_t>(chosen);
  VkResult allocated = vkAllocateMemory(device_, &allocate, nullptr, &result.memory);
  if (allocated != VK_SUCCESS) {
    vkDestroyBuffer(device_, result.buffer, nullptr);
    VK_CHECK(allocated);
  }
  VK_CHECK(vkBindBufferMemory(device_, result.buffer, result.memory, 0));
  VK_CHECK(vkMapMemory(device_, result.memory, 0, VK_WHOLE_SIZE, 0, &result.mapped));
  return result;
}

void WindowPresenter::destroy_host_buffer(HostBuffer& buffer) {
  if (buffer.buffer) vkDestroyBuffer(device_, buffer.buffer, nullptr);
  if (buffer.memory) vkFreeMemory(device_, buffer.memory, nullptr);  // unmaps
  buffer = HostBuffer{};
}

WindowPresenter::Layout WindowPresenter::layout_for(int frame_width, int frame_height) const {
  Layout layout;
  const int image_width = static_cast<int>(extent_.width), image_height = static_cast<int>(extent_.height);
  layout.scale = std::max(1, std::min(image_width / frame_width, image_height / frame_height));
  layout.scaled_width = frame_width * layout.scale;
  layout.scaled_height = frame_height * layout.scale;
  auto place = [](int scaled, int image, int& src, int& dst, int& size) {
    if (scaled <= image) {
      src = 0;
      dst = (image - scaled) / 2;
      size = scaled;
    } else {  // larger than the screen: its centre
      src = (scaled - image) / 2;
      dst = 0;
      size = image;
    }
  };
  place(layout.scaled_width, image_width, layout.src_x, layout.dst_x, layout.copy_width);
  place(layout.scaled_height, image_height, layout.src_y, layout.dst_y, layout.copy_height);
  layout.covers_image = layout.copy_width == image_width && layout.copy_height == image_height;
  return layout;
}

double WindowPresenter::now_s() { return glfwGetTime() - clock_origin_s_; }

double WindowPresenter::present(const Rgba8Frame& frame) {
  if (frame.width <= 0 || frame.height <= 0 ||
      frame.rgba.size() != static_cast<size_t>(frame.width) * static_cast<size_t>(frame.height) * 4) {
    throw std::invalid_argument("window: present: frame of " + std::to_string(frame.width) + "x" +
                                std::to_string(frame.height) + " holds " + std::to_string(frame.rgba.size()) +
                                " bytes; expected width * height * 4");
  }
  pump_events();
  if (&frame != &last_frame_) last_frame_ = frame;
  has_presented_ = true;

  VK_CHECK(vkWaitForFences(device_, 1, &frame_fence_, VK_TRUE, UINT64_MAX));
  uint32_t image_index = 0;
  for (int attempt = 0;; ++attempt) {
    if (swapchain_stale_ || !swapchain_) recreate_swapchain();
    if (!swapchain_) {  // minimised: nothing is shown
      last_present_read_back_ = false;
      last_present_s_ = now_s();
      return last_present_s_;
    }
    const VkResult acquired =
        vkAcquireNextImageKHR(device_, swapchain_, UINT64_MAX, image_available_, VK_NULL_HANDLE, &image_index);
    if (acquired == VK_SUCCESS) break;
    if (acquired == VK_SUBOPTIMAL_KHR) {  // usable this time; recreated after the present
      swapchain_stale_ = true;
      break;
    }
    if (acquired == VK_ERROR_OUT_OF_DATE_KHR && attempt < 3) {
      swapchain_stale_ = true;
      continue;
    }
    vk::throw_vulkan_error("vkAcquireNextImageKHR", acquired);
  }

  // The frame, integer-scaled and in the swapchain's byte order, into the staging buffer.
  const Layout layout = layout_for(frame.width, frame.height);
  const VkDeviceSize staging_bytes =
      static_cast<VkDeviceSize>(layout.scaled_width) * static_cast<VkDeviceSize>(layout.scaled_height) * 4;
  if (staging_.size < staging_bytes) {
    destroy_host_buffer(staging_);
    staging_ = create_host_buffer(staging_bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, false);
  }
  {
    uint8_t* out = static_cast<uint8_t*>(staging_.mapped);
    const size_t scaled_row_bytes = static_cast<size_t>(layout.scaled_width) * 4;
    const int s = layout.scale;
    for (int y = 0; y < frame.height; ++y) {
      const uint8_t* in = frame.rgba.data() + static_cast<size_t>(y) * static_cast<size_t>(frame.width) * 4;
      uint8_t* row = out + static_cast<size_t>(y) * static_cast<size_t>(s) * scaled_row_bytes;
      if (s == 1 && !format_is_bgra_) {
        std::memcpy(row, in, scaled_row_bytes);
      } else {
        uint8_t* p = row;
        for (int x = 0; x < frame.width; ++x, in += 4) {
          const uint8_t r = format_is_bgra_ ? in[2] : in[0], b = format_is_bgra_ ? in[0] : in[2];
          for (int k = 0; k < s; ++k, p += 4) {
            p[0] = r;
            p[1] = in[1];
            p[2] = b;
            p[3] = in[3];
          }
        }
      }
      for (int k = 1; k < s; ++k) std::memcpy(row + static_cast<size_t>(k) * scaled_row_bytes, row, scaled_row_bytes);
    }
  }

  const VkImage image = images_[image_index];
  const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  auto image_barrier = [&](VkImageLayout from, VkImageLayout to, VkAccessFlags src_access, VkAccessFlags dst_access,
                           VkPipelineStageFlags src_stage, VkPipelineStageFlags dst_stage) {
    VkImageMemoryBarrier barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    barrier.srcAccessMask = src_access;
    barrier.dstAccessMask = dst_access;
    barrier.oldLayout = from;
    barrier.newLayout = to;
    barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.image = image;
    barrier.subresourceRange = range;
    vkCmdPipelineBarrier(command_buffer_, src_stage, dst_stage, 0, 0, nullptr, 0, nullptr, 1, &barrier);
  };

  VK_CHECK(vkResetCommandBuffer(command_buffer_, 0));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_CHECK(vkBeginCommandBuffer(command_buffer_, &begin));
  // The acquire semaphore is waited at the transfer stage; the barrier chains on it.
  image_barrier(VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0, VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
  if (!layout.covers_image) {  // letterbox
    const VkClearColorValue black{{0.0f, 0.0f, 0.0f, 1.0f}};
    vkCmdClearColorImage(command_buffer_, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &black, 1, &range);
    image_barrier(VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                  VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                  VK_PIPELINE_STAGE_TRANSFER_BIT);
  }
  VkBufferImageCopy upload{};
  upload.bufferOffset =
      (static_cast<VkDeviceSize>(layout.src_y) * static_cast<VkDeviceSize>(layout.scaled_width) +
       static_cast<VkDeviceSize>(layout.src_x)) * 4;
  upload.bufferRowLength = static_cast<uint32_t>(layout.scaled_width);
  upload.bufferImageHeight = static_cast<uint32_t>(layout.scaled_height);
  upload.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  upload.imageOffset = {layout.dst_x, layout.dst_y, 0};
  upload.imageExtent = {static_cast<uint32_t>(layout.copy_width), static_cast<uint32_t>(layout.copy_height), 1};
  vkCmdCopyBufferToImage(command_buffer_, staging_.buffer, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &upload);
  if (can_read_back_) {
    image_barrier(VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                  VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                  VK_PIPELINE_STAGE_TRANSFER_BIT);
    VkBufferImageCopy download{};
    download.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    download.imageExtent = {extent_.width, extent_.height, 1};
    vkCmdCopyImageToBuffer(command_buffer_, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback_.buffer, 1, &download);
    VkBufferMemoryBarrier to_host{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER};
    to_host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    to_host.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    to_host.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    to_host.buffer = readback_.buffer;
    to_host.size = VK_WHOLE_SIZE;
    vkCmdPipelineBarrier(command_buffer_, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 0, nullptr, 1,
                         &to_host, 0, nullptr);
    image_barrier(VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, 0, 0,
                  VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
  } else {
    image_barrier(VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_ACCESS_TRANSFER_WRITE_BIT,
                  0, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
  }
  VK_CHECK(vkEndCommandBuffer(command_buffer_));

  VK_CHECK(vkResetFences(device_, 1, &frame_fence_));
  const VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.waitSemaphoreCount = 1;
  submit.pWaitSemaphores = &image_available_;
  submit.pWaitDstStageMask = &wait_stage;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &command_buffer_;
  submit.signalSemaphoreCount = 1;
  submit.pSignalSemaphores = &render_finished_[image_index];
  VK_CHECK(vkQueueSubmit(queue_, 1, &submit, frame_fence_));

  VkPresentInfoKHR present_info{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  present_info.waitSemaphoreCount = 1;
  present_info.pWaitSemaphores = &render_finished_[image_index];
  present_info.swapchainCount = 1;
  present_info.pSwapchains = &swapchain_;
  present_info.pImageIndices = &image_index;
  const VkResult presented = vkQueuePresentKHR(queue_, &present_info);
  if (presented == VK_SUBOPTIMAL_KHR || presented == VK_ERROR_OUT_OF_DATE_KHR) {
    swapchain_stale_ = true;
  } else if (presented != VK_SUCCESS) {
    vk::throw_vulkan_error("vkQueuePresentKHR", presented);
  }
  VK_CHECK(vkWaitForFences(device_, 1, &frame_fence_, VK_TRUE, UINT64_MAX));
  double presented_s = now_s();
  // A FIFO swapchain that did not block (software presentation: lavapipe on X11, Xvfb) would let
  // presents run faster than the display; pace to one refresh period after the previous present.
  const double period_s = 1.0 / refresh_hz_;
  if (present_mode_ == VK_PRESENT_MODE_FIFO_KHR && last_present_s_ >= 0 &&
      presented_s - last_present_s_ < 0.5 * period_s) {
    sleep_s(last_present_s_ + period_s - presented_s);
    presented_s = now_s();
  }
  last_present_s_ = presented_s;
  last_present_read_back_ = can_read_back_;
  readback_extent_ = extent_;
  readback_is_bgra_ = format_is_bgra_;
  if (swapchain_stale_) recreate_swapchain();
  return last_present_s_;
}

bool WindowPresenter::screenshot_is_readback() const { return last_present_read_back_; }

Rgba8Frame WindowPresenter::screenshot() const {
  if (!has_presented_) return Rgba8Frame{};
  if (!last_present_read_back_) return last_frame_;
  Rgba8Frame shot(static_cast<int>(readback_extent_.width), static_cast<int>(readback_extent_.height));
  std::memcpy(shot.rgba.data(), readback_.mapped, shot.rgba.size());
  if (readback_is_bgra_) {
    for (size_t i = 0; i < shot.rgba.size(); i += 4) std::swap(shot.rgba[i], shot.rgba[i + 2]);
  }
  return shot;
}

void WindowPresenter::pump_events() {
  glfwPollEvents();
  poll_gamepads();
}

void WindowPresenter::poll_gamepads() {
  for (int joystick = GLFW_JOYSTICK_1; joystick <= GLFW_JOYSTICK_LAST; ++joystick) {
    auto& previous = gamepad_buttons_[static_cast<size_t>(joystick)];
    GLFWgamepadstate state;
    if (!glfwJoystickIsGamepad(joystick) || !glfwGetGamepadState(joystick, &state)) {
      previous.fill(GLFW_RELEASE);
      continue;
    }
    double time_s = -1.0;
    for (const auto& [button, name] : glfw_gamepad_buttons()) {
      const auto b = static_cast<size_t>(button);
      if (state.buttons[b] == GLFW_PRESS && previous[b] != GLFW_PRESS) {
        if (time_s < 0) time_s = now_s();
        events_.push_back(InputEvent{time_s, name});
      }
    }
    std::copy(std::begin(state.buttons), std::end(state.buttons), previous.begin());
  }
}

void WindowPresenter::key_callback(GLFWwindow* window, int key, int scancode, int action, int) {
  auto* self = static_cast<WindowPresenter*>(glfwGetWindowUserPointer(window));
  if (!self || action != GLFW_PRESS || key == GLFW_KEY_UNKNOWN) return;  // repeats are not presses
  self->on_key(key, glfwGetKeyName(key, scancode));
}

void WindowPresenter::on_key(int key, const char* layout_name) {
  const std::string name = glfw_key_name(key, layout_name);
  if (name.empty()) return;
  const double time_s = now_s();
  events_.push_back(InputEvent{time_s, name});
  if (name == "escape" && escape_detector_.press(time_s)) escape_close_ = true;
}

std::vector<InputEvent> WindowPresenter::poll_input() {
  pump_events();
  std::vector<InputEvent> events(events_.begin(), events_.end());
  events_.clear();
  return events;
}

void WindowPresenter::wait_until(double time_s) {
  const double period_s = 1.0 / refresh_hz_;
  for (;;) {
    pump_events();
    const double now = now_s();
    if (now >= time_s) return;
    const double remaining = time_s - now;
    if (has_presented_ && remaining >= period_s && now - last_present_s_ >= 0.5 * period_s) {
      present(last_frame_);
    } else {
      sleep_s(std::min(remaining, 0.001));
    }
  }
}

std::optional<std::pair<double, double>> WindowPresenter::cursor_px() {
  pump_events();
  if (!glfwGetWindowAttrib(window_, GLFW_HOVERED)) return std::nullopt;
  double x = 0, y = 0;
  glfwGetCursorPos(window_, &x, &y);
  int window_width = 0, window_height = 0, framebuffer_width = 0, framebuffer_height = 0;
  glfwGetWindowSize(window_, &window_width, &window_height);
  glfwGetFramebufferSize(window_, &framebuffer_width, &framebuffer_height);
  if (window_width <= 0 || window_height <= 0 || framebuffer_width <= 0 || framebuffer_height <= 0) return std::nullopt;
  x *= static_cast<double>(framebuffer_width) / window_width;  // screen coordinates to pixels
  y *= static_cast<double>(framebuffer_height) / window_height;
  const int frame_width = has_presented_ ? last_frame_.width : options_.width_px;
  const int frame_height = has_presented_ ? last_frame_.height : options_.height_px;
  if (extent_.width == 0 || extent_.height == 0) return std::nullopt;
  const Layout layout = layout_for(frame_width, frame_height);
  const double frame_x = (x - layout.dst_x + layout.src_x) / layout.scale;
  const double frame_y = (y - layout.dst_y + layout.src_y) / layout.scale;
  if (x < layout.dst_x || y < layout.dst_y || x >= layout.dst_x + layout.copy_width ||
      y >= layout.dst_y + layout.copy_height || frame_x < 0 || frame_y < 0 || frame_x >= frame_width ||
      frame_y >= frame_height) {
    return std::nullopt;
  }
  return std::make_pair(frame_x, frame_y);
}

bool WindowPresenter::close_requested() {
  pump_events();
  return glfwWindowShouldClose(window_) || escape_close_;
}

}  // namespace fovlab
