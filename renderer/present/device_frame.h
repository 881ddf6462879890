#pragma once
// A frame as a display shows it, kept on the device that made it: packed RGBA8, sRGB-encoded, one
// uint a pixel (R in the low byte, alpha 255), row-major, top row first. The sRGB8 encoder writes
// it (srgb8_encoder.h) and a presenter on the same device composes it onto the swapchain image
// without a copy through the host (display/window_presenter.h).
#include <vulkan/vulkan.h>

#include "core/rgba8_frame.h"

namespace fovlab {

namespace vk {
class Buffer;
class Context;
}  // namespace vk

struct DeviceRgba8Frame {
  const vk::Context* context = nullptr;  // the device holding `buffer`
  VkBuffer buffer = VK_NULL_HANDLE;      // at least width * height * 4 bytes; owned by whoever wrote it
  int width = 0;
  int height = 0;

  explicit operator bool() const { return buffer != VK_NULL_HANDLE; }
};

// The frame's bytes copied into `to`, a buffer on the frame's device of at least width * height * 4
// bytes: one copy submitted on that device and waited for, after the renderer's writes of the frame;
// `for_host` also makes the copy visible to reads from the host (a read-back).
void copy_device_frame(const DeviceRgba8Frame& frame, const vk::Buffer& to, bool for_host);

// The frame's bytes on the host: one copy into a host-visible buffer, submitted on the frame's
// device and waited for. Throws std::invalid_argument for an empty frame.
Rgba8Frame read_back(const DeviceRgba8Frame& frame);
// The same through `scratch`, a host-readback buffer of the frame's device kept by the caller for
// the next frame (replaced when it is too small or of another device).
Rgba8Frame read_back(const DeviceRgba8Frame& frame, vk::Buffer& scratch);

}  // namespace fovlab
