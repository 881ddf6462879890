#include "display/window_presenter.h"

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
#include "renderer/vk/submission.h"

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

// Iconified, or a framebuffer of no pixels: there is nothing to present to.
bool window_minimised(GLFWwindow* window) {
  int width = 0, height = 0;
  glfwGetFramebufferSize(window, &width, &height);
  return glfwGetWindowAttrib(window, GLFW_ICONIFIED) || width <= 0 || height <= 0;
}

void sleep_s(double seconds) {
  if (seconds > 0) std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
}

}  // namespace

WindowPresenter::WindowPresenter(const WindowPresenterOptions& options) : options_(options) {
  if (options_.width_px <= 0 || options_.height_px <= 0) {
    throw std::invalid_argument("window: frame size must be positive, got " + std::to_string(options_.width_px) + "x" +
                                std::to_string(options_.height_px));
  }
  try {
    create_window();
    if (!options_.headset_mirror) {  // a mirror's context comes with attach()
      create_context();
      create_swapchain();
    }
  } catch (...) {
    release();
    throw;
  }
  clock_origin_s_ = glfwGetTime();
}

WindowPresenter::~WindowPresenter() { release(); }

void check_window_can_open(const std::string& flag) {
  std::lock_guard<std::mutex> lock(glfw_mutex);
  if (glfwInit()) {
    // Only asked: GLFW is left as it was (running while a window of this process is open).
    if (glfw_users == 0) glfwTerminate();
    return;
  }
  const char* display = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  if ((!display || !*display) && (!wayland || !*wayland))
    throw InputError(flag +
                     ": cannot open a window (no display: DISPLAY is not set; run on the desktop, or under xvfb-run)");
  throw InputError(flag + ": cannot open a window on display " + std::string(display ? display : wayland) + " (" +
                   glfw_error_description() + ")");
}

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
    throw InputError(
        "window: GLFW finds no Vulkan loader (expected libvulkan1 and a driver such as mesa-vulkan-drivers)");
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

vk::SurfaceRequest WindowPresenter::surface_request() {
  uint32_t glfw_extension_count = 0;
  const char** glfw_extensions = glfwGetRequiredInstanceExtensions(&glfw_extension_count);
  if (!glfw_extensions) {
    throw InputError("window: Vulkan cannot present to this display (" + glfw_error_description() + ")");
  }
  vk::SurfaceRequest request;
  request.instance_extensions.assign(glfw_extensions, glfw_extensions + glfw_extension_count);
  request.create_surface = [this](VkInstance instance) {
    VkSurfaceKHR surface = VK_NULL_HANDLE;
    VK_CHECK(glfwCreateWindowSurface(instance, window_, nullptr, &surface));
    return surface;
  };
  request.unmet_need = [](VkPhysicalDevice device, VkSurfaceKHR surface) {
    return choose_format(surface_formats(device, surface)) ? std::string()
                                                           : std::string("no 8-bit RGBA/BGRA surface format");
  };
  return request;
}

void WindowPresenter::create_context() {
  own_context_ = std::make_unique<vk::Context>(
      vk::ContextOptions{options_.device_selector, options_.validation, surface_request(), options_.device_flag});
  context_ = own_context_.get();
  create_present_objects();
}

void WindowPresenter::attach(vk::Context& context) {
  if (!options_.headset_mirror || context_)
    throw std::logic_error("window: attach() takes a headset mirror's context, once");
  if (!context.surface) throw std::logic_error("window: attach(): the context was made without this window's surface");
  context_ = &context;
  try {
    create_present_objects();
    create_swapchain();
  } catch (...) {
    release();
    throw;
  }
}

void WindowPresenter::create_present_objects() {
  composer_ = std::make_unique<FrameComposer>(*context_);
  const VkDevice device = context_->device;
  VkCommandBufferAllocateInfo allocate{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  allocate.commandPool = context_->command_pool;
  allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  allocate.commandBufferCount = 1;
  VK_CHECK(vkAllocateCommandBuffers(device, &allocate, &command_buffer_));
  VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  fence_info.flags = VK_FENCE_CREATE_SIGNALED_BIT;
  VK_CHECK(vkCreateFence(device, &fence_info, nullptr, &frame_fence_));
  VkSemaphoreCreateInfo semaphore_info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  VK_CHECK(vkCreateSemaphore(device, &semaphore_info, nullptr, &image_available_));
}

void WindowPresenter::create_swapchain() {
  VkSurfaceCapabilitiesKHR caps;
  VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(context_->physical_device, context_->surface, &caps));
  VkExtent2D extent = caps.currentExtent;
  if (extent.width == std::numeric_limits<uint32_t>::max()) {
    int width = 0, height = 0;
    glfwGetFramebufferSize(window_, &width, &height);
    extent.width =
        std::clamp(static_cast<uint32_t>(std::max(width, 0)), caps.minImageExtent.width, caps.maxImageExtent.width);
    extent.height =
        std::clamp(static_cast<uint32_t>(std::max(height, 0)), caps.minImageExtent.height, caps.maxImageExtent.height);
  }
  VkSwapchainKHR old = swapchain_;
  swapchain_ = VK_NULL_HANDLE;
  extent_ = extent;
  if (extent.width == 0 || extent.height == 0) {  // minimised: nothing to present to until it comes back
    if (old) vkDestroySwapchainKHR(context_->device, old, nullptr);
    swapchain_stale_ = true;
    return;
  }

  const auto format = choose_format(surface_formats(context_->physical_device, context_->surface));
  if (!format) throw std::runtime_error("window: the surface offers no 8-bit RGBA/BGRA format");
  format_ = format->first.format;
  colour_space_ = format->first.colorSpace;
  format_is_bgra_ = format->second;
  if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT)) {
    throw std::runtime_error("window: swapchain images of '" + context_->description.name + "' cannot be copied into");
  }
  can_read_back_ = options_.screenshots && (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT);

  uint32_t mode_count = 0;
  VK_CHECK(
      vkGetPhysicalDeviceSurfacePresentModesKHR(context_->physical_device, context_->surface, &mode_count, nullptr));
  std::vector<VkPresentModeKHR> modes(mode_count);
  VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(context_->physical_device, context_->surface, &mode_count,
                                                     modes.data()));
  present_mode_ = VK_PRESENT_MODE_FIFO_KHR;  // always supported
  if (!options_.vsync || options_.headset_mirror) {
    for (VkPresentModeKHR wanted : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR}) {
      if (std::find(modes.begin(), modes.end(), wanted) != modes.end()) {
        present_mode_ = wanted;
        break;
      }
    }
  }

  VkCompositeAlphaFlagBitsKHR composite = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
  if (!(caps.supportedCompositeAlpha & composite)) {
    for (VkCompositeAlphaFlagBitsKHR bit :
         {VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR, VK_COMPOSITE_ALPHA_PRE_MULTIPLIED_BIT_KHR,
          VK_COMPOSITE_ALPHA_POST_MULTIPLIED_BIT_KHR}) {
      if (caps.supportedCompositeAlpha & bit) {
        composite = bit;
        break;
      }
    }
  }

  VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
  info.surface = context_->surface;
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
  const VkResult result = vkCreateSwapchainKHR(context_->device, &info, nullptr, &swapchain_);
  if (old) vkDestroySwapchainKHR(context_->device, old, nullptr);
  VK_CHECK(result);

  uint32_t image_count = 0;
  VK_CHECK(vkGetSwapchainImagesKHR(context_->device, swapchain_, &image_count, nullptr));
  images_.resize(image_count);
  VK_CHECK(vkGetSwapchainImagesKHR(context_->device, swapchain_, &image_count, images_.data()));
  images_.resize(image_count);
  VkSemaphoreCreateInfo semaphore_info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  render_finished_.assign(image_count, VK_NULL_HANDLE);
  for (VkSemaphore& semaphore : render_finished_)
    VK_CHECK(vkCreateSemaphore(context_->device, &semaphore_info, nullptr, &semaphore));

  const VkDeviceSize bytes = VkDeviceSize{extent.width} * extent.height * 4;
  if (composed_.size_bytes() < bytes) {
    composed_ = vk::Buffer();
    composed_ = vk::Buffer(*context_, bytes, vk::MemoryUse::device_local);
  }
  composed_extent_ = {0, 0};  // holds no frame at this extent yet
  if (can_read_back_ && readback_.size_bytes() < bytes) {
    readback_ = vk::Buffer();
    readback_ = vk::Buffer(*context_, bytes, vk::MemoryUse::host_readback);
  }
  swapchain_stale_ = false;
}

// Semaphores and images of the swapchain; the swapchain itself stays when it is handed to the next
// one as oldSwapchain.
void WindowPresenter::destroy_swapchain(bool keep_handle_for_recreation) {
  for (VkSemaphore semaphore : render_finished_) vkDestroySemaphore(context_->device, semaphore, nullptr);
  render_finished_.clear();
  images_.clear();
  if (!keep_handle_for_recreation && swapchain_) {
    vkDestroySwapchainKHR(context_->device, swapchain_, nullptr);
    swapchain_ = VK_NULL_HANDLE;
  }
}

void WindowPresenter::recreate_swapchain() {
  VK_CHECK(vkDeviceWaitIdle(context_->device));
  destroy_swapchain(true);
  create_swapchain();
}

void WindowPresenter::release() {
  if (context_) {
    const VkDevice device = context_->device;
    vkDeviceWaitIdle(device);
    upload_ = vk::Buffer();
    composed_ = vk::Buffer();
    readback_ = vk::Buffer();
    destroy_swapchain(false);
    if (image_available_) vkDestroySemaphore(device, image_available_, nullptr);
    if (frame_fence_) vkDestroyFence(device, frame_fence_, nullptr);
    if (command_buffer_) vkFreeCommandBuffers(device, context_->command_pool, 1, &command_buffer_);
    image_available_ = VK_NULL_HANDLE;
    frame_fence_ = VK_NULL_HANDLE;
    command_buffer_ = VK_NULL_HANDLE;
    composer_.reset();
    own_context_.reset();  // the device, the surface and the instance (a mirror's stay: the headset's)
    context_ = nullptr;
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

double WindowPresenter::now_s() { return glfwGetTime() - clock_origin_s_; }

WindowPresenter::ComposeSource WindowPresenter::upload(const Rgba8Frame& frame) {
  if (upload_.size_bytes() < frame.rgba.size()) {
    upload_ = vk::Buffer();
    upload_ = vk::Buffer(*context_, frame.rgba.size(), vk::MemoryUse::host_upload);
  }
  // The previous compose reading upload_ has finished: present_source waits for its fence.
  std::memcpy(upload_.mapped(), frame.rgba.data(), frame.rgba.size());
  upload_.flush();
  return ComposeSource{upload_.handle(), frame.width, frame.height};
}

double WindowPresenter::present(const Rgba8Frame& frame) {
  if (frame.width <= 0 || frame.height <= 0 ||
      frame.rgba.size() != static_cast<size_t>(frame.width) * static_cast<size_t>(frame.height) * 4) {
    throw std::invalid_argument("window: present: frame of " + std::to_string(frame.width) + "x" +
                                std::to_string(frame.height) + " holds " + std::to_string(frame.rgba.size()) +
                                " bytes; expected width * height * 4");
  }
  VK_CHECK(vkWaitForFences(context_->device, 1, &frame_fence_, VK_TRUE, UINT64_MAX));
  if (&frame != &last_frame_) last_frame_ = frame;
  last_device_frame_ = DeviceRgba8Frame{};
  return present_source(upload(last_frame_), true);
}

double WindowPresenter::present(const DeviceRgba8Frame& frame) {
  if (!frame || frame.width <= 0 || frame.height <= 0)
    throw std::invalid_argument("window: present: no frame on a device");
  if (frame.context != context_) {  // rendered on another device: through the host, timed
    const auto start = std::chrono::steady_clock::now();
    Rgba8Frame bytes = read_back(frame);
    VK_CHECK(vkWaitForFences(context_->device, 1, &frame_fence_, VK_TRUE, UINT64_MAX));
    last_frame_ = std::move(bytes);
    const ComposeSource source = upload(last_frame_);
    cross_device_copies_.frames += 1;
    cross_device_copies_.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    last_device_frame_ = DeviceRgba8Frame{};
    return present_source(source, true);
  }
  last_frame_ = Rgba8Frame{};
  last_device_frame_ = frame;
  return present_source(ComposeSource{frame.buffer, frame.width, frame.height}, true);
}

double WindowPresenter::present_source(const ComposeSource& source, bool recompose) {
  pump_events();
  has_presented_ = true;
  last_width_ = source.width;
  last_height_ = source.height;

  const VkDevice device = context_->device;
  VK_CHECK(vkWaitForFences(device, 1, &frame_fence_, VK_TRUE, UINT64_MAX));
  // A mirror is never waited for: minimised, it is not even recreated (that waits for the device);
  // with no image free at once, this frame is not shown in it.
  const bool never_wait = options_.headset_mirror;
  last_present_shown_ = false;
  if (never_wait && window_minimised(window_)) return now_s();
  uint32_t image_index = 0;
  for (int attempt = 0;; ++attempt) {
    if (swapchain_stale_ || !swapchain_) recreate_swapchain();
    if (!swapchain_) {  // minimised: nothing is shown
      last_present_read_back_ = false;
      last_present_s_ = now_s();
      return last_present_s_;
    }
    const VkResult acquired = vkAcquireNextImageKHR(device, swapchain_, never_wait ? 0 : UINT64_MAX, image_available_,
                                                    VK_NULL_HANDLE, &image_index);
    if (acquired == VK_SUCCESS) break;
    if (never_wait && (acquired == VK_NOT_READY || acquired == VK_TIMEOUT)) return now_s();
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
  const bool compose =
      recompose || composed_extent_.width != extent_.width || composed_extent_.height != extent_.height;

  const VkImage image = images_[image_index];
  auto image_barrier = [&](VkImageLayout from, VkImageLayout to, VkAccessFlags src_access, VkAccessFlags dst_access,
                           VkPipelineStageFlags src_stage, VkPipelineStageFlags dst_stage) {
    vk::image_layout_barrier(command_buffer_, image, from, to, src_stage, src_access, dst_stage, dst_access);
  };

  VK_CHECK(vkResetCommandBuffer(command_buffer_, 0));
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VK_CHECK(vkBeginCommandBuffer(command_buffer_, &begin));
  if (compose) {
    // The frame (written by the renderer's earlier submission, or by the host) into the image's
    // pixels; the compose does not touch the swapchain image, so it may run before the acquire's
    // semaphore is signalled.
    vk::memory_barrier(command_buffer_, VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_ACCESS_HOST_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    composer_->record(command_buffer_, source.buffer, source.width, source.height, composed_.handle(),
                      static_cast<int>(extent_.width), static_cast<int>(extent_.height), format_is_bgra_);
    vk::memory_barrier(command_buffer_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
  }
  // The acquire semaphore is waited at the transfer stage; the barrier chains on it.
  image_barrier(VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 0, VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
  VkBufferImageCopy copy{};
  copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  copy.imageExtent = {extent_.width, extent_.height, 1};
  vkCmdCopyBufferToImage(command_buffer_, composed_.handle(), image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
  if (can_read_back_) {
    image_barrier(VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                  VK_ACCESS_TRANSFER_WRITE_BIT, VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                  VK_PIPELINE_STAGE_TRANSFER_BIT);
    vkCmdCopyImageToBuffer(command_buffer_, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback_.handle(), 1, &copy);
    vk::memory_barrier(command_buffer_, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    image_barrier(VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, 0, 0,
                  VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
  } else {
    image_barrier(VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_ACCESS_TRANSFER_WRITE_BIT,
                  0, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
  }
  VK_CHECK(vkEndCommandBuffer(command_buffer_));

  VK_CHECK(vkResetFences(device, 1, &frame_fence_));
  const VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.waitSemaphoreCount = 1;
  submit.pWaitSemaphores = &image_available_;
  submit.pWaitDstStageMask = &wait_stage;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &command_buffer_;
  submit.signalSemaphoreCount = 1;
  submit.pSignalSemaphores = &render_finished_[image_index];
  VK_CHECK(vkQueueSubmit(context_->queue, 1, &submit, frame_fence_));
  composed_extent_ = extent_;

  VkPresentInfoKHR present_info{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  present_info.waitSemaphoreCount = 1;
  present_info.pWaitSemaphores = &render_finished_[image_index];
  present_info.swapchainCount = 1;
  present_info.pSwapchains = &swapchain_;
  present_info.pImageIndices = &image_index;
  const VkResult presented = vkQueuePresentKHR(context_->queue, &present_info);
  if (presented == VK_SUBOPTIMAL_KHR || presented == VK_ERROR_OUT_OF_DATE_KHR) {
    swapchain_stale_ = true;
  } else if (presented != VK_SUCCESS) {
    vk::throw_vulkan_error("vkQueuePresentKHR", presented);
  }
  VK_CHECK(vkWaitForFences(device, 1, &frame_fence_, VK_TRUE, UINT64_MAX));
  double presented_s = now_s();
  // A FIFO swapchain that did not block (software presentation: lavapipe on X11, Xvfb) would let
  // presents run faster than the display; pace to one refresh period after the previous present.
  const double period_s = 1.0 / refresh_hz_;
  if (!never_wait && present_mode_ == VK_PRESENT_MODE_FIFO_KHR && last_present_s_ >= 0 &&
      presented_s - last_present_s_ < 0.5 * period_s) {
    sleep_s(last_present_s_ + period_s - presented_s);
    presented_s = now_s();
  }
  last_present_s_ = presented_s;
  last_present_shown_ = true;
  last_present_read_back_ = can_read_back_;
  readback_extent_ = extent_;
  readback_is_bgra_ = format_is_bgra_;
  if (swapchain_stale_) recreate_swapchain();
  return last_present_s_;
}

// Re-presents what is on screen: the composed pixels when the swapchain kept its extent, else the
// last frame composed again.
double WindowPresenter::present_again() {
  if (last_device_frame_)
    return present_source(ComposeSource{last_device_frame_.buffer, last_width_, last_height_}, false);
  return present_source(ComposeSource{upload_.handle(), last_width_, last_height_}, false);
}

bool WindowPresenter::screenshot_is_readback() const { return last_present_read_back_; }

Rgba8Frame WindowPresenter::screenshot() const {
  if (!has_presented_) return Rgba8Frame{};
  if (!last_present_read_back_) return last_device_frame_ ? read_back(last_device_frame_) : last_frame_;
  Rgba8Frame shot(static_cast<int>(readback_extent_.width), static_cast<int>(readback_extent_.height));
  readback_.invalidate();
  std::memcpy(shot.rgba.data(), readback_.mapped(), shot.rgba.size());
  if (readback_is_bgra_) {
    for (size_t i = 0; i < shot.rgba.size(); i += 4) std::swap(shot.rgba[i], shot.rgba[i + 2]);
  }
  return shot;
}

void WindowPresenter::pump_events() {
  glfwPollEvents();
  // A headset's mirror takes the keyboard only: the headset's runtime gives the controllers (an
  // Xbox controller there would otherwise answer twice, through OpenXR and through GLFW).
  if (!options_.headset_mirror) poll_gamepads();
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
      present_again();
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
  const int frame_width = has_presented_ ? last_width_ : options_.width_px;
  const int frame_height = has_presented_ ? last_height_ : options_.height_px;
  if (extent_.width == 0 || extent_.height == 0) return std::nullopt;
  const FramePlacement layout =
      place_frame(frame_width, frame_height, static_cast<int>(extent_.width), static_cast<int>(extent_.height));
  const double frame_x = (x - layout.dst_x + layout.src_x) / layout.scale;
  const double frame_y = (y - layout.dst_y + layout.src_y) / layout.scale;
  if (x < layout.dst_x || y < layout.dst_y || x >= layout.dst_x + layout.shown_width ||
      y >= layout.dst_y + layout.shown_height || frame_x < 0 || frame_y < 0 || frame_x >= frame_width ||
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
